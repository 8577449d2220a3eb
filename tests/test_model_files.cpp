// tests/test_model_files.cpp — io/model_loader on files the tests write into a
// temporary folder: missing, unknown, broken, truncated and corrupted files are
// ModelErrors, not crashes; degenerate triangles are dropped and counted; shared
// vertices are merged by exact position; the triangle and file-size limits hold.
#include "model_fixtures.hpp"
#include "model_loader.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace octray;
using namespace model_fixtures;

namespace {

const char* const kPlyHeader3 =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n";

// s with its one occurrence of `from` replaced (the test's own fixture must have it).
void replace_once(std::string& s, const std::string& from, const std::string& to) {
    const std::size_t at = s.find(from);
    REQUIRE(at != std::string::npos);
    s.replace(at, from.size(), to);
}

}  // namespace

TEST_CASE("model_loader: broken files written by the test") {
    TempDir dir;
    CHECK(load_error((dir.path / "nothere.obj").string()) == "cannot open: No such file or directory");
    fs::create_directories(dir.path / "folder.ply");
    CHECK(load_error((dir.path / "folder.ply").string()) == "cannot open: Is a directory");
    CHECK(load_error(dir.write("cube.stl", "solid x\nendsolid x\n")) ==
          "unknown model format '.stl' (expected .gltf, .glb, .obj or .ply)");
    CHECK(load_error(dir.write("noext", "v 0 0 0\n")) == "unknown model format '' (expected .gltf, .glb, .obj or .ply)");
    CHECK(load_error(dir.write("text.glb", "this is a text file, not a model\n")) ==
          "unreadable glTF: not a binary glTF file (no 'glTF' magic)");
    CHECK(load_error(dir.write("text.gltf", "{\"not\": \"gltf\"}\n")) ==
          "unreadable glTF: no \"asset\" object (glTF 2.0 requires one)");
    CHECK(load_error(dir.write("v1.gltf", "{\"asset\": {\"version\": \"1.0\"}}\n")) ==
          "glTF 1.0 is not supported (glTF 2.0 only)");

    CHECK(load_error(dir.write("oor.ply", std::string(kPlyHeader3) + "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"))
              .find("index 7 out of range (3 vertices)") != std::string::npos);
    CHECK(load_error(dir.write("nan.ply", std::string(kPlyHeader3) + "0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n")) ==
          "vertex 1 is not finite: (nan, 0, 0)");
    CHECK(load_error(dir.write("inf.ply", std::string(kPlyHeader3) + "0 0 0\n1 0 0\n0 -inf 0\n3 0 1 2\n")) ==
          "vertex 2 is not finite: (0, -inf, 0)");
    CHECK(load_error(dir.write("oor.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"))
              .find("index 9 out of range (3 vertices)") != std::string::npos);
    CHECK(load_error(dir.write("lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\np 1\n")) == "no triangles");
    CHECK(load_error(dir.write("empty.obj", "")) == "no triangles");
}

TEST_CASE("model_loader: truncated and corrupted .glb, .ply and .obj files are errors, not crashes") {
    if (!have_models()) return;
    TempDir dir;
    const std::string sources[] = {model("glTF2/BoxTextured-glTF-Binary/BoxTextured.glb"),
                                   model("PLY/cube_binary.ply"), model("PLY/cube.ply"), model("OBJ/box.obj")};
    int refused = 0, loaded = 0;
    for (const std::string& src : sources) {
        const std::string bytes = read_bytes(src);
        const std::string ext = fs::path(src).extension().string();
        REQUIRE(bytes.size() > 100);
        // Every length up to 64 bytes, then every 37th, then the last 16.
        std::vector<std::size_t> lengths;
        for (std::size_t n = 0; n < bytes.size(); n += (n < 64 ? 1 : 37)) lengths.push_back(n);
        for (std::size_t n = bytes.size() - 16; n < bytes.size(); ++n) lengths.push_back(n);
        for (std::size_t n : lengths) {
            CAPTURE(src);
            CAPTURE(n);
            const std::string err = load_error(dir.write("cut" + ext, bytes.substr(0, n)));
            (err.empty() ? loaded : refused)++;
        }
        // Flip one byte at a time, at 97 places spread over the file (fixed, so repeatable).
        for (int k = 0; k < 97; ++k) {
            std::string bad = bytes;
            const std::size_t at = (bytes.size() * std::size_t(k)) / 97;
            bad[at] = char(bad[at] ^ 0x5A);
            CAPTURE(src);
            CAPTURE(at);
            const std::string err = load_error(dir.write("flip" + ext, bad));
            (err.empty() ? loaded : refused)++;
        }
    }
    // The truncated .glb files are all refused (a .glb must be whole).
    MESSAGE(refused << " refused, " << loaded << " loaded (a corrupted byte in a number still loads)");
    const std::string glb = read_bytes(sources[0]);
    for (std::size_t n : {std::size_t(0), std::size_t(12), std::size_t(20), std::size_t(200), glb.size() / 2,
                          glb.size() - 1}) {
        CAPTURE(n);
        CHECK(load_error(dir.write("half.glb", glb.substr(0, n))).rfind("unreadable glTF: ", 0) == 0);
    }
}

TEST_CASE("model_loader: degenerate triangles are dropped and counted") {
    TempDir dir;
    // Four triangles: two real ones, one with a repeated vertex, one with three collinear
    // vertices (exactly: (0,0,0), (1,1,1), (2,2,2)).
    const std::string obj =
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 1\nv 2 2 2\nv 0 0 1\n"
        "f 1 2 3\nf 1 2 2\nf 1 4 5\nf 1 3 6\n";
    const MeshData m = load_model(dir.write("degenerate.obj", obj));
    CHECK(m.triangle_count() == 2);
    CHECK(m.dropped_degenerate == 2);
    CHECK(m.vertices.size() == 4);  // vertex 5 (2,2,2) and 4 (1,1,1) are used by no kept triangle
    CHECK(m.faces == std::vector<std::uint32_t>{0, 3});  // the file's numbers of the kept triangles
    CHECK(m.face_of(1) == 3);
    CHECK(load_error(dir.write("all_degenerate.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 1 1 2\n")) ==
          "no triangles (all 2 have zero area)");

    // A real one: OBJ/spider.obj has 1368 triangles, 56 of which repeat a position (counted
    // from the file's "v" and "f" lines by a separate script, not by the reader).
    if (!have_models()) return;
    const MeshData spider = load_model(model("OBJ/spider.obj"));
    CHECK(spider.triangle_count() == 1368 - 56);
    CHECK(spider.dropped_degenerate == 56);
    REQUIRE(spider.faces.size() == spider.triangle_count());
    CHECK(std::is_sorted(spider.faces.begin(), spider.faces.end()));
    CHECK(std::adjacent_find(spider.faces.begin(), spider.faces.end()) == spider.faces.end());
    CHECK(spider.faces.back() < 1368);
}

TEST_CASE("model_loader: shared vertices by exact position, across meshes") {
    TempDir dir;
    // Two OBJ groups (two meshes) sharing an edge, one vertex written twice.
    const std::string obj =
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 1 0 0\n"
        "g a\nf 1 2 3\ng b\nf 5 4 3\n";
    const MeshData m = load_model(dir.write("shared.obj", obj));
    REQUIRE(m.triangle_count() == 2);
    CHECK(m.vertices.size() == 4);
    CHECK(m.faces.empty());              // none dropped: no face map
    CHECK(m.indices[1] == m.indices[3]);  // (1,0,0) once
    CHECK(m.indices[2] == m.indices[5]);  // (0,1,0) once
}

TEST_CASE("model_loader: the triangle limit and the file-size limit are checked before building") {
    TempDir dir;
    // A glTF 2.0 file whose one mesh has 2^16 triangles (all index 0: degenerate, but they
    // count) and is used by 256 nodes: 2^24 triangles, one over the limit.
    const std::uint32_t tris = 1u << 16, nodes = 256;
    REQUIRE(std::uint64_t(tris) * nodes > kMaxModelTriangles);
    REQUIRE(std::uint64_t(tris) * (nodes - 1) <= kMaxModelTriangles);
    std::string bin(std::size_t(tris) * 3 * 2, '\0');  // uint16 indices, all 0
    const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    bin.append(reinterpret_cast<const char*>(pos), sizeof pos);
    dir.write("many.bin", bin);
    std::string node_list, node_refs;
    for (std::uint32_t i = 0; i < nodes; ++i) {
        node_list += std::string(i ? "," : "") + "{\"mesh\":0}";
        node_refs += std::string(i ? "," : "") + std::to_string(i);
    }
    const std::string gltf =
        "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[" + node_refs + "]}],\"nodes\":[" +
        node_list +
        "],\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":1},\"indices\":0,\"mode\":4}]}],"
        "\"buffers\":[{\"uri\":\"many.bin\",\"byteLength\":" + std::to_string(bin.size()) + "}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":" + std::to_string(tris * 6) +
        "},{\"buffer\":0,\"byteOffset\":" + std::to_string(tris * 6) + ",\"byteLength\":36}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5123,\"count\":" + std::to_string(tris * 3) +
        ",\"type\":\"SCALAR\"},{\"bufferView\":1,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\","
        "\"min\":[0,0,0],\"max\":[1,1,0]}]}";
    CHECK(load_error(dir.write("many.gltf", gltf)) == "too many triangles: more than 16777215 (the limit)");

    // Sparse files just over kMaxModelFileBytes: the model itself, and a glTF buffer.
    const std::string big = (dir.path / "big.ply").string();
    { std::ofstream touch(big); }
    fs::resize_file(big, kMaxModelFileBytes + 1);
    CHECK(load_error(big) == "file too large: 2147483649 bytes (limit 2147483648)");
    fs::rename(big, dir.path / "many.bin");
    const std::string err = load_error((dir.path / "many.gltf").string());
    CHECK(err.rfind("file too large: ", 0) == 0);
    CHECK(err.find("many.bin is 2147483649 bytes") != std::string::npos);
}

// The hostile files of tests/bad_scenes/hostile/ (the CLI tests run them through a scene):
// each refused with its reason, before anything of the size it claims is allocated. That
// last part is what the fuzz and ASan builds watch (an allocation of gigabytes fails
// there); here, that the claims are large and the files are not.
TEST_CASE("model_loader: hostile files are refused before allocation") {
    const fs::path dir = fs::path(OCTRAY_TEST_SOURCE_DIR) / "bad_scenes" / "hostile";
    struct Case {
        const char* file;
        const char* reason;
    };
    const Case cases[] = {
        {"huge_vertex_count.ply", "vertex count 2147483648 does not fit"},
        {"huge_accessor_count.gltf", "accessor 0: 2000000000 elements of 12 bytes run past buffer view 0 (12 bytes)"},
        {"index_out_of_range.obj", "index 4 out of range (3 vertices)"},
        {"negative_index.obj", "index -4 out of range (3 vertices)"},
        {"data_uri_gigabytes.gltf", "buffers[0]: byteLength 4000000000 but its data URI holds 12 bytes"},
        {"buffer_outside_folder.gltf", "is outside the model's folder"},
    };
    for (const Case& c : cases) {
        const fs::path file = dir / c.file;
        CAPTURE(file.string());
        REQUIRE(fs::exists(file));
        CHECK(fs::file_size(file) <= 400);
        const std::string err = load_error(file.string());
        CHECK_MESSAGE(err.find(c.reason) != std::string::npos, err);
        CHECK(err.find('\n') == std::string::npos);
    }
    TempDir tmp;
    // An absolute URI, and one that climbs out through a subfolder: both refused by name.
    const std::string absolute = read_bytes((dir / "buffer_outside_folder.gltf").string());
    std::string abs_copy = absolute;
    replace_once(abs_copy, "../../../../../../etc/passwd", "/etc/passwd");
    CHECK(load_error(tmp.write("abs.gltf", abs_copy)).find("'/etc/passwd' is outside the model's folder") !=
          std::string::npos);
    std::string climb = absolute;
    replace_once(climb, "../../../../../../etc/passwd", "sub/../../x.bin");
    CHECK(load_error(tmp.write("climb.gltf", climb)).find("'sub/../../x.bin' is outside the model's folder") !=
          std::string::npos);
    // Percent-encoded dots are dots (tinygltf decodes them).
    std::string encoded = absolute;
    replace_once(encoded, "../../../../../../etc/passwd", "%2e%2e/x.bin");
    CHECK(load_error(tmp.write("encoded.gltf", encoded)).find("is outside the model's folder") != std::string::npos);
    // JSON nested past the depth bound, in "extras" (which tinygltf converts recursively).
    std::string deep = "{\"asset\":{\"version\":\"2.0\"},\"extras\":" + std::string(5000, '[') +
                       std::string(5000, ']') + "}";
    CHECK(load_error(tmp.write("deep.gltf", deep)).find("nested deeper than") != std::string::npos);
    // A required extension that encodes the geometry.
    CHECK(load_error(tmp.write("draco.gltf", "{\"asset\":{\"version\":\"2.0\"},\"extensionsRequired\":"
                                               "[\"KHR_draco_mesh_compression\"]}")) ==
          "glTF extension KHR_draco_mesh_compression is not supported (it encodes the geometry)");
    // A node graph that is not a tree: node 1 under node 0 twice.
    std::string dag = read_bytes((dir / "huge_accessor_count.gltf").string());
    replace_once(dag, "\"count\": 2000000000", "\"count\": 1");
    replace_once(dag, "\"nodes\": [{\"mesh\": 0}]", "\"nodes\": [{\"children\": [1, 1]}, {\"mesh\": 0}]");
    CHECK(load_error(tmp.write("dag.gltf", dag)) == "unreadable glTF: node 1 is reached twice (glTF nodes form trees)");
}
