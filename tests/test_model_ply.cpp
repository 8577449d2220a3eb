// tests/test_model_ply.cpp — read_ply (io/ply_reader.cpp) on well-formed files in
// every encoding, and save_ply (io/ply_writer.cpp); test_model_ply_hostile.cpp has the
// files read_ply must refuse. The files come from tests/support/ply_files.hpp.
#include "ply_files.hpp"
#include "model_loader.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

using namespace octray;
using namespace octray::model_formats;
using namespace model_fixtures;
using namespace ply_files;

TEST_CASE("read_ply: the three encodings of one mesh read the same, polygons fanned") {
    // The binary layout spelled out once, so the writer above is checked too: vertex 4
    // (0.5, 2.25, -1.5) as little-endian floats, then the quad as uchar 4 and ints.
    const std::string le = make_ply({vertices(), faces()}, Enc::le);
    const std::string data = le.substr(le.find("end_header\n") + 11);
    const std::string v4 = data.substr(4 * 12, 12);
    CHECK(v4 == std::string("\x00\x00\x00\x3f\x00\x00\x10\x40\x00\x00\xc0\xbf", 12));
    CHECK(data.substr(5 * 12, 17) == std::string("\x04\x00\x00\x00\x00\x01\x00\x00\x00\x02\x00\x00\x00\x03\x00\x00\x00", 17));
    const std::string be = make_ply({vertices(), faces()}, Enc::be);
    CHECK(be.substr(be.find("end_header\n") + 11 + 4 * 12, 12) ==
          std::string("\x3f\x00\x00\x00\x40\x10\x00\x00\xbf\xc0\x00\x00", 12));

    for (const Enc enc : kEncodings)
        for (const char* type : {"float", "double", "float32", "float64"}) {
            INFO("encoding: " << std::string(enc_name(enc)));
            INFO("type: " << std::string(type));
            check_small_mesh(read_ply(make_ply({vertices(type), faces()}, enc)));
        }
    // Integer coordinates, and every integral count and index type.
    Elem ints{"vertex", {{"short", "x", ""}, {"int", "y", ""}, {"char", "z", ""}}, {}};
    for (const Vec3d& p : {Vec3d{0, 0, 0}, Vec3d{-300, 70000, -5}, Vec3d{1, 2, 3}, Vec3d{4, 5, 6}, Vec3d{7, 8, 9}})
        ints.rows.push_back({{p.x}, {p.y}, {p.z}});
    for (const Enc enc : kEncodings)
        for (const char* ct : {"uchar", "char", "ushort", "short", "uint", "int", "uint8", "int32"})
            for (const char* it : {"uchar", "char", "ushort", "short", "uint", "int", "uint32", "int16"}) {
                INFO("encoding: " << std::string(enc_name(enc)));
                INFO("count type: " << std::string(ct) << ", index type: " << std::string(it));
                const RawModel m = read_ply(make_ply({ints, faces(ct, it)}, enc));
                REQUIRE(m.meshes.size() == 1);
                CHECK(m.meshes[0].triangles == kTriangles);
                CHECK(m.meshes[0].positions[1].x == -300);
                CHECK(m.meshes[0].positions[1].y == 70000);
                CHECK(m.meshes[0].positions[1].z == -5);
            }
    // `vertex_index`, the other name.
    check_small_mesh(read_ply(make_ply({vertices(), faces("uchar", "int", "vertex_index")}, Enc::ascii)));
}

TEST_CASE("read_ply: \\r\\n line ends, faces before vertices, no face element") {
    for (const Enc enc : kEncodings) {
        INFO("encoding: " << std::string(enc_name(enc)));
        check_small_mesh(read_ply(make_ply({vertices(), faces()}, enc, "\r\n")));
        check_small_mesh(read_ply(make_ply({faces(), vertices()}, enc)));
        // No faces: the positions, no triangles; collect_model says so.
        const RawModel m = read_ply(make_ply({vertices()}, enc));
        REQUIRE(m.meshes.size() == 1);
        CHECK(m.meshes[0].positions.size() == kPositions.size());
        CHECK(m.meshes[0].triangles.empty());
        CHECK_THROWS_WITH_AS(collect_model(m, MeshTransform{}.to_matrix(), "PLY"), "no triangles", ModelError);
    }
    // Header words apart by tabs and runs of spaces, trailing spaces (assimp's cube.ply),
    // a line of no keyword passed over, obj_info; trailing bytes after the data ignored.
    const std::string h =
        "ply \nformat\tascii  1.0   \nobj_info made by hand\nCreated by Blender3D 247\nelement vertex 3\n"
        "property float x\nproperty float y\nproperty float z\nelement face 1\n"
        "property list uchar int vertex_indices\nend_header\n";
    const RawModel m = read_ply(h + "0 0 0\n+1 0 0\n0 1.0e0 0\n3 0 1 +2\nanything after\n");
    CHECK(m.meshes[0].triangles == std::vector<std::uint32_t>{0, 1, 2});
    CHECK(m.meshes[0].positions[1].x == 1);
    CHECK(m.meshes[0].positions[2].y == 1);
}

TEST_CASE("read_ply: other properties and elements, lists included, are skipped in every encoding") {
    Elem v{"vertex",
           {{"uchar", "red", ""}, {"double", "z", ""}, {"float", "weights", "uchar"}, {"short", "nx", ""},
            {"float", "x", ""}, {"uint", "flags", ""}, {"int", "y", ""}, {"double", "confidence", ""}},
           {}};
    for (std::size_t i = 0; i < kPositions.size(); ++i) {
        const Vec3d& p = kPositions[i];
        Row r = {{200}, {p.z}, {}, {-7}, {p.x}, {4000000000.0}, {0}, {0.25}};
        r[2].assign(i, 1.5);  // lists of 0 to 4 weights
        r[6] = {p.y == 2.25 ? 2.0 : p.y};  // y is an int here
        v.rows.push_back(r);
    }
    Elem f{"face", {{"uchar", "flags", ""}, {"int", "vertex_indices", "uchar"}, {"float", "texcoord", "int"}}, {}};
    for (const auto& face : kFaces) f.rows.push_back({{9}, face, std::vector<double>(2 * face.size(), 0.5)});
    Elem edge{"edge", {{"int", "vertex1", ""}, {"int", "vertex2", ""}, {"uint", "path", "ushort"}}, {}};
    for (int i = 0; i < 4; ++i) edge.rows.push_back({{double(i)}, {double(i + 1)}, std::vector<double>(i * 3, 99)});
    Elem material{"material", {{"float", "ambient", ""}, {"uchar", "name", "uint"}}, {{{0.5}, {65, 66}}, {{1}, {}}}};
    Elem empty{"nothing", {}, {{}, {}, {}}};  // properties none, rows three: no bytes

    std::vector<Vec3d> want = kPositions;
    want[4].y = 2;
    for (const Enc enc : kEncodings) {
        INFO("encoding: " << std::string(enc_name(enc)));
        check_mesh(read_ply(make_ply({material, v, edge, f, empty, material}, enc)), want, kTriangles);
    }
}

TEST_CASE("read_ply: save_ply's file reads back as the mesh rounded to float") {
    TempDir dir;
    MeshData src;
    src.vertices = {{0.1, 0.2, 0.3}, {1e10, -1.0 / 3, 2}, {-5, 7.125, 1e-30}, {3.14159265358979, 0, -2.5}};
    src.indices = {0, 1, 2, 2, 1, 3, 3, 0, 2};
    const std::string path = (dir.path / "round.ply").string();
    save_ply(src, path);
    const std::string bytes = read_bytes(path);
    // The layout save_ply promises: the header, then 12 bytes a vertex, 13 a triangle.
    const std::string h = "ply\nformat binary_little_endian 1.0\ncomment written by octray\nelement vertex 4\n"
                          "property float x\nproperty float y\nproperty float z\nelement face 3\n"
                          "property list uchar int vertex_indices\nend_header\n";
    REQUIRE(bytes.substr(0, h.size()) == h);
    CHECK(bytes.size() == h.size() + 4 * 12 + 3 * 13);
    std::vector<Vec3d> rounded;
    for (const Vec3d& v : src.vertices) rounded.push_back(round_to_float(v));
    CHECK(rounded[0].x != src.vertices[0].x);  // the rounding is real
    check_mesh(read_ply(bytes), rounded, src.indices);

    // What save_ply refuses, it refuses before creating the file.
    MeshData bad = src;
    bad.vertices[2].y = 1e300;
    const std::string bad_path = (dir.path / "bad.ply").string();
    CHECK_THROWS_WITH_AS(save_ply(bad, bad_path), doctest::Contains(": vertex 2 (-5, 1"), ModelError);
    CHECK_THROWS_WITH_AS(save_ply(bad, bad_path), doctest::Contains("does not fit in float"), ModelError);
    bad = src;
    bad.indices[7] = 4;
    const std::string oor = "cannot write " + bad_path + ": index 4 out of range (4 vertices)";
    CHECK_THROWS_WITH_AS(save_ply(bad, bad_path), oor.c_str(), ModelError);
    CHECK_FALSE(fs::exists(bad_path));
    CHECK_THROWS_WITH_AS(save_ply(src, (dir.path / "no" / "dir.ply").string()),
                         doctest::Contains("No such file or directory"), ModelError);
}

TEST_CASE("read_ply: assimp-testmodels' PLY files read or give a ModelError") {
    if (!have_models()) return;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(model("PLY")))
        if (e.is_regular_file() && e.path().extension() == ".ply") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    REQUIRE(!files.empty());
    std::size_t read = 0;
    for (const fs::path& p : files) {
        INFO("file: " << p.string());
        const std::string bytes = read_bytes(p.string());
        try {
            const RawModel m = read_ply(bytes);
            REQUIRE(m.meshes.size() == 1);
            MESSAGE(p.filename().string() << ": read, " << m.meshes[0].positions.size() << " vertices, "
                                          << m.meshes[0].triangles.size() / 3 << " triangles");
            ++read;
        } catch (const ModelError& e) {
            MESSAGE(p.filename().string() << ": ModelError: " << std::string(e.what()));
        }
    }
    CHECK(read > 0);
}
