// tests/test_model_obj.cpp — read_obj (io/obj_reader.cpp): small OBJ texts written here,
// with the expected triangles worked out by hand, and every .obj of assimp-testmodels.
#include <doctest/doctest.h>
#include <unistd.h>

#include "model_fixtures.hpp"
#include "model_formats.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

namespace {

using namespace octray;
using namespace octray::model_formats;

using Tri = std::array<Vec3d, 3>;

// A mesh's triangles as positions: independent of how the reader numbers vertices.
std::vector<Tri> triangles_of(const RawMesh& m) {
    std::vector<Tri> out;
    for (std::size_t t = 0; t + 2 < m.triangles.size(); t += 3)
        out.push_back({m.positions.at(m.triangles[t]), m.positions.at(m.triangles[t + 1]),
                       m.positions.at(m.triangles[t + 2])});
    return out;
}

bool same(const Vec3d& a, const Vec3d& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
bool same(const Tri& a, const Tri& b) { return same(a[0], b[0]) && same(a[1], b[1]) && same(a[2], b[2]); }

// The ModelError message of reading `text`, or "" when it reads.
std::string error_of(const std::string& text) { return model_fixtures::read_error(read_obj, text); }

std::size_t triangle_total(const RawModel& m) {
    std::size_t n = 0;
    for (const RawMesh& mesh : m.meshes) n += mesh.triangles.size() / 3;
    return n;
}

// Vertex k (1-based) of the squares below: (k, 10k, 100k), all distinct.
Vec3d P(int k) { return {double(k), 10.0 * k, 100.0 * k}; }
std::string vertices(int n) {
    std::string s;
    for (int k = 1; k <= n; ++k)
        s += "v " + std::to_string(k) + " " + std::to_string(10 * k) + " " + std::to_string(100 * k) + "\n";
    return s;
}

}  // namespace

TEST_CASE("read_obj: one triangle, positions as written") {
    const RawModel m = read_obj("v 0 0 0\nv 1.5 0 0\nv 0 -2 0.25\nf 1 2 3\n");
    REQUIRE(m.meshes.size() == 1);
    REQUIRE(m.instances.size() == 1);
    CHECK(m.instances[0].mesh == 0);
    const auto t = triangles_of(m.meshes[0]);
    REQUIRE(t.size() == 1);
    CHECK(same(t[0], Tri{Vec3d{0, 0, 0}, Vec3d{1.5, 0, 0}, Vec3d{0, -2, 0.25}}));
}

TEST_CASE("read_obj: quads and n-gons fanned (v0, vi, vi+1); faces of fewer than 3 skipped") {
    const RawModel m = read_obj(vertices(5) + "f 1 2 3 4\nf 5 4 3 2 1\nf 1 2\nf 3\n");
    REQUIRE(m.meshes.size() == 1);
    const auto t = triangles_of(m.meshes[0]);
    REQUIRE(t.size() == 5);
    CHECK(same(t[0], Tri{P(1), P(2), P(3)}));
    CHECK(same(t[1], Tri{P(1), P(3), P(4)}));
    CHECK(same(t[2], Tri{P(5), P(4), P(3)}));
    CHECK(same(t[3], Tri{P(5), P(3), P(2)}));
    CHECK(same(t[4], Tri{P(5), P(2), P(1)}));
}

TEST_CASE("read_obj: a face of 300 vertices (more than tinyobjloader's unsigned char count)") {
    std::string f = "f";
    for (int k = 1; k <= 300; ++k) f += " " + std::to_string(k);
    const RawModel m = read_obj(vertices(300) + f + "\nf 1 2 3\n");
    REQUIRE(m.meshes.size() == 1);
    const auto t = triangles_of(m.meshes[0]);
    REQUIRE(t.size() == 298 + 1);
    for (int i = 0; i < 298; ++i) CHECK(same(t[i], Tri{P(1), P(i + 2), P(i + 3)}));
    CHECK(same(t[298], Tri{P(1), P(2), P(3)}));
}

TEST_CASE("read_obj: negative indices count back from the vertices so far") {
    const RawModel m = read_obj(vertices(3) + "f -3 -2 -1\n" +
                                "v 7 0 0\nv 0 7 0\nv 0 0 7\nf -1 -2 -3\nf -6 1 -1\n");
    const auto t = triangles_of(m.meshes.at(0));
    REQUIRE(t.size() == 3);
    CHECK(same(t[0], Tri{P(1), P(2), P(3)}));
    CHECK(same(t[1], Tri{Vec3d{0, 0, 7}, Vec3d{0, 7, 0}, Vec3d{7, 0, 0}}));
    CHECK(same(t[2], Tri{P(1), P(1), Vec3d{0, 0, 7}}));
}

TEST_CASE("read_obj: v/vt/vn, v//vn and v/vt corners use the position index") {
    const std::string text = vertices(4) +
                             "vt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n"
                             "f 1/1/1 2/2/1 3/3/1\nf 2//1 3//1 4//1\nf 4/3 3/2 1/1\nf -1/-1/-1 -2/-2/-1 -3/-3/-1\n";
    const RawModel m = read_obj(text);
    const auto t = triangles_of(m.meshes.at(0));
    REQUIRE(t.size() == 4);
    CHECK(same(t[0], Tri{P(1), P(2), P(3)}));
    CHECK(same(t[1], Tri{P(2), P(3), P(4)}));
    CHECK(same(t[2], Tri{P(4), P(3), P(1)}));
    CHECK(same(t[3], Tri{P(4), P(3), P(2)}));
}

TEST_CASE("read_obj: each group and object is a mesh, named, with only the vertices it uses") {
    const RawModel m =
        read_obj(vertices(6) + "f 1 2 3\ng wheel\nf 4 5 6\nf 4 6 1\no body\nf 2 3 4\ng \nf 1 2 3 4\n");
    REQUIRE(m.meshes.size() == 4);
    CHECK(m.meshes[0].name == "");
    CHECK(m.meshes[1].name == "wheel");
    CHECK(m.meshes[2].name == "body");
    CHECK(m.meshes[0].positions.size() == 3);
    CHECK(m.meshes[1].positions.size() == 4);
    CHECK(m.meshes[2].positions.size() == 3);
    CHECK(m.meshes[3].positions.size() == 4);
    CHECK(same(triangles_of(m.meshes[1]).at(1), Tri{P(4), P(6), P(1)}));
    CHECK(same(triangles_of(m.meshes[2]).at(0), Tri{P(2), P(3), P(4)}));
    CHECK(triangles_of(m.meshes[3]).size() == 2);
    REQUIRE(m.instances.size() == 4);
    for (std::uint32_t i = 0; i < 4; ++i) CHECK(m.instances[i].mesh == i);
}

TEST_CASE("read_obj: points and lines are left out") {
    const RawModel m = read_obj(vertices(4) + "p 1 2\nl 1 2 3 4\nf 1 2 3\np 4\nl 2 3\n");
    CHECK(triangle_total(m) == 1);
    const RawModel none = read_obj(vertices(4) + "p 1 2 3\nl 1 2 3 4\n");
    CHECK(triangle_total(none) == 0);
    CHECK_THROWS_WITH_AS(collect_model(none, {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, "Wavefront OBJ"),
                         "no triangles", ModelError);
}

TEST_CASE("read_obj: indices out of range name the face, the index as written and the vertex count") {
    const std::string six_faces = "f 1 2 3\nf 1 2 3\nf 1 2 3\nf 1 2 3\nf 1 2 3\nf 1 2 3\n";
    CHECK(error_of(vertices(8) + six_faces + "f 1 2 -12\n") == "face 7 (line 15): index -12 out of range (8 vertices)");
    CHECK(error_of(vertices(8) + "f 1 2 9\n") == "face 1 (line 9): index 9 out of range (8 vertices)");
    CHECK(error_of(vertices(8) + "f 1 0 2\n") == "face 1 (line 9): index 0 out of range (8 vertices)");
    // Relative indices count the vertices before the face, not the file's.
    CHECK(error_of(vertices(2) + "f 1 2 -3\n" + vertices(5)) == "face 1 (line 3): index -3 out of range (2 vertices)");
    // A forward reference is in range when the file has the vertex.
    CHECK(error_of("f 1 2 3\n" + vertices(3)).empty());
    // Lines and points are not read, so their indices are not checked.
    CHECK(error_of(vertices(3) + "l 1 99\np -7\nf 1 2 3\n").empty());
}

TEST_CASE("read_obj: indices beyond int are refused, not wrapped") {
    CHECK(error_of(vertices(3) + "f 99999999999999999999 1 2\n") ==
          "face 1 (line 4): index 99999999999999999999 out of range (3 vertices)");
    CHECK(error_of(vertices(3) + "f 1 2 -2147483649\n") ==
          "face 1 (line 4): index -2147483649 out of range (3 vertices)");
    CHECK(error_of(vertices(3) + "f 1 2 -2147483648\n") ==
          "face 1 (line 4): index -2147483648 out of range (3 vertices)");
    CHECK(error_of(vertices(3) + "f 1 2 4294967297\n") ==
          "face 1 (line 4): index 4294967297 out of range (3 vertices)");
    CHECK(error_of(vertices(3) + "f 1/99999999999 2 3\n").find("out of range") != std::string::npos);
}

TEST_CASE("read_obj: mtllib is never opened, usemtl is ignored") {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("octray_obj_mtl_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path mtl = dir / "red.mtl";
    std::ofstream(mtl) << "newmtl red\nKd 1 0 0\n";
    const std::string tri = vertices(3) + "f 1 2 3\n";
    for (const std::string& lib : {mtl.string(), std::string("../../etc/passwd"), std::string("/etc/passwd"),
                                  (dir / "missing.mtl").string(), dir.string()}) {
        CAPTURE(lib);
        const RawModel m = read_obj("mtllib " + lib + "\nusemtl red\n" + tri + "usemtl root\nf 3 2 1\n");
        REQUIRE(m.meshes.size() == 1);  // usemtl does not split the mesh
        CHECK(triangle_total(m) == 2);
    }
    fs::remove_all(dir);
}

TEST_CASE("read_obj: an empty file, comments only, or no faces read as no triangles") {
    for (const std::string& text : {std::string(), std::string("# nothing\n"), std::string("\n\r\n\r"),
                                   vertices(3), std::string("g a\no b\n")}) {
        CAPTURE(text);
        const RawModel m = read_obj(text);
        CHECK(triangle_total(m) == 0);
        CHECK_THROWS_WITH_AS(collect_model(m, {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, "Wavefront OBJ"),
                             "no triangles", ModelError);
    }
}

TEST_CASE("read_obj: nan, inf and 1e999 coordinates are passed through") {
    const RawModel m = read_obj("v nan 0 0\nv 1 -INF 0\nv 0 0 1e999\nv 0 0 -1e-999\nf 1 2 3 4\n");
    REQUIRE(m.meshes.size() == 1);
    const auto t = triangles_of(m.meshes[0]);
    REQUIRE(t.size() == 2);
    CHECK(std::isnan(t[0][0].x));
    CHECK(t[0][1].y == -std::numeric_limits<double>::infinity());
    CHECK(t[0][2].z == std::numeric_limits<double>::infinity());
    CHECK(t[1][2].z == 0.0);
    CHECK_THROWS_AS(collect_model(m, {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}, "Wavefront OBJ"), ModelError);
}

TEST_CASE("read_obj: coordinates are kept in double") {
    const RawModel m = read_obj("v 0.1 0.3 -123456.789\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const Vec3d p = triangles_of(m.meshes.at(0)).at(0)[0];
    // float would be off by about 1e-9 (0.1), 1e-8 (0.3) and 4e-3 (123456.789).
    CHECK(std::fabs(p.x - 0.1) < 1e-16);
    CHECK(std::fabs(p.y - 0.3) < 1e-16);
    CHECK(std::fabs(p.z + 123456.789) < 1e-10);
}

TEST_CASE("read_obj: bad vertex lines are refused") {
    CHECK(error_of("v 1 2\nv 0 0 0\nv 1 1 1\nf 1 2 3\n") == "line 1: 'v' needs 3 coordinates");
    CHECK(error_of("v 1 2 abc\n") == "line 1: coordinate 'abc' is not a number");
    CHECK(error_of("v 1 2 1ex\n") == "line 1: coordinate '1ex' is not a number");
    CHECK(error_of("v 1 2 -\n") == "line 1: coordinate '-' is not a number");
    // tinyobjloader reads a number's start, as assimp does: "3.1+e2" is 3.1.
    const RawModel lax = read_obj("v 3x 3.1+e2 2.e1\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    CHECK(same(triangles_of(lax.meshes.at(0)).at(0)[0], Vec3d{3, 3.1, 20}));
    // tinyobjloader's exponent would overflow an int: refused before it parses.
    CHECK(error_of("v 1e2147483649 0 0\n").find("exponent too large") != std::string::npos);
    CHECK(error_of("v 0 0 0 1 1e2147483648 0\n").find("exponent too large") != std::string::npos);
    CHECK(error_of("v 1e0000000000000000000999 0 0\n").empty());  // leading zeros are not digits of size
    CHECK(error_of("v 1 2 3 1\nv 1 2 3 0.5 0.5 0.5\n").empty());     // w, and colours
}

TEST_CASE("read_obj: CRLF, lone CR, tabs, leading spaces and comments") {
    const RawModel m = read_obj("# c\r\n  v\t0 0 0\r\nv 1 0 0\rv 0 1 0\r\n\t f 1 2 3 \r\n#f 3 2 1\n");
    const auto t = triangles_of(m.meshes.at(0));
    REQUIRE(t.size() == 1);
    CHECK(same(t[0], Tri{Vec3d{0, 0, 0}, Vec3d{1, 0, 0}, Vec3d{0, 1, 0}}));
    // tinyobjloader takes a comment after a face's corners for a corner (atoi gives 0).
    CHECK(error_of(vertices(3) + "f 1 2 3 # tail\n") == "face 1 (line 4): '# tail' is not an index");
}

TEST_CASE("read_obj: NUL bytes, binary garbage and long lines read or throw ModelError") {
    std::string with_nul = vertices(3) + "f 1 2 3";
    with_nul += '\0';
    with_nul += " 9999\nf 3 2 1\n";
    const RawModel m = read_obj(with_nul);  // tinyobjloader's lines end at a NUL
    CHECK(triangle_total(m) == 2);

    std::uint64_t state = 0x9E3779B97F4A7C15ull;
    auto next = [&] {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        return state;
    };
    const char alphabet[] = "vfgolp0123456789-+./ e\t\n\r#nai\0x";
    for (int round = 0; round < 300; ++round) {
        std::string text = round % 2 ? vertices(4) : "";
        const std::size_t n = next() % 400;
        for (std::size_t i = 0; i < n; ++i)
            text += round % 3 ? alphabet[next() % (sizeof alphabet - 1)] : static_cast<char>(next() & 0xFF);
        try {
            read_obj(text);
        } catch (const ModelError&) {
        }
    }
    const std::string long_comment = "#" + std::string(1 << 20, 'x') + "\n";
    CHECK(triangle_total(read_obj(long_comment + vertices(3) + "f 1 2 3\n")) == 1);
    CHECK(error_of("v " + std::string(5000, '1') + " 0 0\n").find("too long") != std::string::npos);
    std::string big_face = "f";
    for (int k = 0; k < 100000; ++k) big_face += " 1 2";
    CHECK(triangle_total(read_obj(vertices(2) + big_face + "\n")) == 199998);
}

#ifdef OCTRAY_ASSIMP_MODELS
TEST_CASE("read_obj: every .obj of assimp-testmodels reads or throws ModelError") {
    namespace fs = std::filesystem;
    const fs::path dir = fs::path(OCTRAY_ASSIMP_MODELS) / "OBJ";
    if (!fs::exists(dir)) return;
    int files = 0, read = 0;
    for (const auto& e : fs::directory_iterator(dir)) {
        if (e.path().extension() != ".obj") continue;
        CAPTURE(e.path().string());
        std::ifstream in(e.path(), std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        ++files;
        try {
            const RawModel m = read_obj(bytes);
            for (const RawMesh& mesh : m.meshes)
                for (const std::uint32_t i : mesh.triangles) REQUIRE(i < mesh.positions.size());
            ++read;
        } catch (const ModelError& err) {
            const std::string what = e.path().filename().string() + ": " + err.what();
            MESSAGE(what);
        }
    }
    CHECK(files > 10);
    CHECK(read > files / 2);
}
#endif
