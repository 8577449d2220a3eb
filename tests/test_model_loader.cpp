// tests/test_model_loader.cpp — io/model_loader and io/mesh_generators.
//
// Real models come from Debian's assimp-testmodels (OCTRAY_ASSIMP_MODELS, found at
// configure time; tools/install-deps installs it). Counts are checked against what
// assimp itself reports through a different path (its PreTransformVertices step, float),
// or against counts read off the file by eye, as each test says. Broken files are written
// by the tests into a temporary folder.
#include "mesh_generators.hpp"
#include "model_loader.hpp"

#include <octray/constants.hpp>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <doctest/doctest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>
#include <string>
#include <tuple>
#include <vector>

namespace fs = std::filesystem;
using namespace octray;

namespace {

#ifdef OCTRAY_ASSIMP_MODELS
const std::string kModels = OCTRAY_ASSIMP_MODELS;
#else
const std::string kModels;
#endif

// The folder of assimp-testmodels, or "" (with a message and a warning) when absent.
bool have_models() {
    if (!kModels.empty() && fs::exists(kModels)) return true;
    MESSAGE("assimp-testmodels is not installed (tools/install-deps installs it): test skipped");
    WARN_MESSAGE(false, "real-model test skipped");
    return false;
}

std::string model(const std::string& rel) { return kModels + "/" + rel; }

// A fresh folder under the system's temporary folder, removed at the end of the test.
struct TempDir {
    fs::path path;
    TempDir() {
        static std::atomic<int> counter{0};
        path = fs::temp_directory_path() /
               ("octray-model-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
    std::string write(const std::string& name, const std::string& bytes) const {
        const fs::path p = path / name;
        std::ofstream(p, std::ios::binary) << bytes;
        return p.string();
    }
};

std::string read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The ModelError message of load_model(path, t), or "" when it loads.
std::string load_error(const std::string& path, const MeshTransform& t = {}) {
    try {
        load_model(path, t);
    } catch (const ModelError& e) {
        return e.what();
    }
    return "";
}

struct Bounds {
    Vec3d lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
             std::numeric_limits<double>::infinity()};
    Vec3d hi = -lo;
    void add(const Vec3d& p) {
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
};

Bounds bounds_of(const MeshData& m) {
    Bounds b;
    for (std::uint32_t i : m.indices) b.add(m.vertices[i]);
    return b;
}

// Every coordinate of both corners within tol.
void check_bounds(const Bounds& got, const Bounds& want, double tol) {
    const double g[6] = {got.lo.x, got.lo.y, got.lo.z, got.hi.x, got.hi.y, got.hi.z};
    const double w[6] = {want.lo.x, want.lo.y, want.lo.z, want.hi.x, want.hi.y, want.hi.z};
    for (int i = 0; i < 6; ++i) {
        CAPTURE(i);
        CHECK(std::fabs(g[i] - w[i]) <= tol);
    }
}

// What assimp reports for a file by itself: its own triangulation and PreTransformVertices
// (node transforms applied by assimp, in float), points and lines left out.
struct Reference {
    std::size_t triangles = 0;
    std::size_t positions = 0;  // distinct positions used by triangles
    Bounds bounds;
};

bool assimp_reference(const std::string& path, Reference& ref) {
    Assimp::Importer imp;
    const aiScene* s = imp.ReadFile(path, aiProcess_Triangulate | aiProcess_PreTransformVertices);
    if (!s) return false;
    std::set<std::tuple<float, float, float>> positions;
    for (unsigned m = 0; m < s->mNumMeshes; ++m) {
        const aiMesh* mesh = s->mMeshes[m];
        for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
            const aiFace& face = mesh->mFaces[f];
            if (face.mNumIndices != 3) continue;
            ++ref.triangles;
            for (unsigned k = 0; k < 3; ++k) {
                const aiVector3D& v = mesh->mVertices[face.mIndices[k]];
                positions.emplace(v.x, v.y, v.z);
                ref.bounds.add({v.x, v.y, v.z});
            }
        }
    }
    ref.positions = positions.size();
    return true;
}

}  // namespace

// ---- real models ----------------------------------------------------------------------

TEST_CASE("model_loader: one model of each format agrees with assimp's own counts") {
    if (!have_models()) return;
    struct Case {
        std::string file;
        std::string format;
        std::size_t triangles, vertices;  // read off the file, as the comment says
        bool nodes;                       // glTF node transforms: assimp applies them in float
    };
    const Case cases[] = {
        // Cubes: 8 corners; 6 quads ("f a b c d", "4 a b c d") or 12 triangles.
        {"OBJ/box.obj", "Wavefront OBJ", 12, 8, false},               // 8 "v", 6 quad "f"
        {"PLY/cube.ply", "PLY", 12, 8, false},                         // ascii: vertex 8, face 6 quads
        {"PLY/cube_binary.ply", "PLY", 12, 8, false},                  // binary: vertex 8, face 12
        // 36 indices into 24 vertices (the corners split by normal): 8 positions. The one
        // node matrix turns -90 degrees about x: 0 and ±1 only, exact in float too.
        {"glTF2/BoxTextured-glTF-Binary/BoxTextured.glb", "glTF 2.0", 12, 8, false},
        {"glTF2/BoxTextured-glTF/BoxTextured.gltf", "glTF 2.0", 12, 8, false},
        // Larger ones: only assimp's count.
        {"OBJ/spider.obj", "Wavefront OBJ", 0, 0, false},
        {"PLY/Wuson.ply", "PLY", 0, 0, false},
        {"glTF2/ClearCoat-glTF/ClearCoatTest.gltf", "glTF 2.0", 0, 0, true},
    };
    for (const Case& c : cases) {
        CAPTURE(c.file);
        const MeshData m = load_model(model(c.file));
        Reference ref;
        REQUIRE(assimp_reference(model(c.file), ref));
        CHECK(m.format == c.format);
        CHECK(m.indices.size() % 3 == 0);
        CHECK(m.triangle_count() + m.dropped_degenerate == ref.triangles);
        if (m.dropped_degenerate == 0) CHECK(m.vertices.size() == ref.positions);
        if (c.triangles) {
            CHECK(m.triangle_count() == c.triangles);
            CHECK(m.vertices.size() == c.vertices);
            CHECK(m.dropped_degenerate == 0);
        }
        for (std::uint32_t i : m.indices) REQUIRE(i < m.vertices.size());
        const Bounds b = bounds_of(m);
        const double extent = std::max({b.hi.x - b.lo.x, b.hi.y - b.lo.y, b.hi.z - b.lo.z});
        check_bounds(b, ref.bounds, c.nodes ? 1e-6 * extent : 0);  // else: the file's floats exactly
        MESSAGE(c.file << ": " << m.triangle_count() << " triangles, " << m.vertices.size() << " vertices, "
                       << m.dropped_degenerate << " degenerate dropped");
    }
}

TEST_CASE("model_loader: glTF node transforms are applied (instanced meshes under a node hierarchy)") {
    if (!have_models()) return;
    // 82 nodes, up to 3 deep, each with a matrix; mesh 0 is used by several nodes.
    const std::string file = model("glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb");
    const MeshData m = load_model(file);
    Reference ref;
    REQUIRE(assimp_reference(file, ref));
    CHECK(m.triangle_count() + m.dropped_degenerate == ref.triangles);
    const Bounds got = bounds_of(m);
    const double extent = std::max({got.hi.x - got.lo.x, got.hi.y - got.lo.y, got.hi.z - got.lo.z});
    check_bounds(got, ref.bounds, 1e-5 * extent);  // assimp composes in float, this loader in double

    // Without the node transforms the bounds are far from these: the check above has teeth.
    Assimp::Importer imp;
    const aiScene* raw = imp.ReadFile(file, 0);
    REQUIRE(raw);
    Bounds untransformed;
    for (unsigned i = 0; i < raw->mNumMeshes; ++i)
        for (unsigned v = 0; v < raw->mMeshes[i]->mNumVertices; ++v) {
            const aiVector3D& p = raw->mMeshes[i]->mVertices[v];
            untransformed.add({p.x, p.y, p.z});
        }
    CHECK(std::fabs(untransformed.lo.x - got.lo.x) + std::fabs(untransformed.hi.y - got.hi.y) > 0.01 * extent);
    MESSAGE("2CylinderEngine.glb: " << m.triangle_count() << " triangles, " << m.vertices.size() << " vertices, "
                                     << m.dropped_degenerate << " degenerate dropped");
}

TEST_CASE("model_loader: every glTF, OBJ and PLY file of assimp-testmodels loads or is a ModelError") {
    if (!have_models()) return;
    std::vector<fs::path> files;
    for (const auto& e : fs::recursive_directory_iterator(kModels)) {
        std::string ext = e.path().extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
        if (e.is_regular_file() && (ext == ".gltf" || ext == ".glb" || ext == ".obj" || ext == ".ply"))
            files.push_back(e.path());
    }
    std::sort(files.begin(), files.end());
    CHECK(files.size() > 50);
    int loaded = 0, refused = 0;
    for (const fs::path& f : files) {
        CAPTURE(f.string());
        try {
            const MeshData m = load_model(f.string());
            ++loaded;
            CHECK(m.triangle_count() > 0);
            for (const Vec3d& v : m.vertices) REQUIRE((std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)));
            Reference ref;
            if (assimp_reference(f.string(), ref)) CHECK(m.triangle_count() + m.dropped_degenerate == ref.triangles);
        } catch (const ModelError& e) {
            ++refused;
            CHECK(std::string(e.what()).size() > 0);
        }
    }
    MESSAGE(files.size() << " files: " << loaded << " loaded, " << refused << " refused with a ModelError");
}

TEST_CASE("model_loader: broken and unsupported files from assimp-testmodels") {
    if (!have_models()) return;
    CHECK(load_error(model("glTF2/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb")).find("is not finite") !=
          std::string::npos);
    CHECK(load_error(model("glTF2/IndexOutOfRange/IndexOutOfRange.gltf")).rfind("index out of range", 0) == 0);
    CHECK(load_error(model("glTF2/IndexOutOfRange/AllIndicesOutOfRange.gltf"))
              .rfind("unsupported or unreadable model file: ", 0) == 0);
    CHECK(load_error(model("glTF2/MissingBin/BoxTextured.gltf")).rfind("unsupported or unreadable model file: ", 0) ==
          0);
    CHECK(load_error(model("glTF2/RecursiveNodes/RecursiveNodes.gltf"))
              .rfind("unsupported or unreadable model file: ", 0) == 0);
    CHECK(load_error(model("glTF/TwoBoxes/TwoBoxes.gltf")) == "glTF 1.0 is not supported (glTF 2.0 only)");
    CHECK(load_error(model("glTF/BoxTextured-glTF-Binary/BoxTextured.glb"))
              .rfind("unsupported or unreadable model file: ", 0) == 0);
    // Points and lines only.
    for (const char* f : {"OBJ/testpoints.obj", "OBJ/testline.obj", "OBJ/point_cloud.obj", "PLY/points.ply",
                          "glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_00.gltf",
                          "glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_01.gltf",
                          "glTF2/TestNoRootNode/SceneWithoutNodes.gltf"}) {
        CAPTURE(f);
        CHECK(load_error(model(f)) == "no triangles");
    }
    for (const char* f : {"invalid/empty.obj", "invalid/empty.ply", "invalid/malformed.obj"}) {
        CAPTURE(f);
        CHECK(load_error(model(f)).rfind("unsupported or unreadable model file: ", 0) == 0);
    }
    CHECK(load_error(model("invalid/OutOfMemory.off")) ==
          "unknown model format '.off' (expected .gltf, .glb, .obj or .ply)");
}

// ---- files written here -----------------------------------------------------------------

namespace {

const char* const kPlyHeader3 =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n";

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
          "unsupported or unreadable model file: not a glTF 2.0 file");
    CHECK(load_error(dir.write("text.gltf", "{\"not\": \"gltf\"}\n")) ==
          "unsupported or unreadable model file: not a glTF 2.0 file");

    CHECK(load_error(dir.write("oor.ply", std::string(kPlyHeader3) + "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n")) ==
          "index 7 out of range (3 vertices)");
    CHECK(load_error(dir.write("nan.ply", std::string(kPlyHeader3) + "0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n")) ==
          "vertex 1 is not finite: (nan, 0, 0)");
    CHECK(load_error(dir.write("inf.ply", std::string(kPlyHeader3) + "0 0 0\n1 0 0\n0 -inf 0\n3 0 1 2\n")) ==
          "vertex 2 is not finite: (0, -inf, 0)");
    CHECK(load_error(dir.write("oor.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"))
              .rfind("unsupported or unreadable model file: ", 0) == 0);  // assimp's OBJ reader checks itself
    CHECK(load_error(dir.write("lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\np 1\n")) == "no triangles");
    CHECK(load_error(dir.write("empty.obj", "")).rfind("unsupported or unreadable model file: ", 0) == 0);
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
        CHECK(load_error(dir.write("half.glb", glb.substr(0, n))).rfind("unsupported or unreadable model file: ", 0) ==
              0);
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
    CHECK(load_error(dir.write("all_degenerate.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 1 1 2\n")) ==
          "no triangles (all 2 have zero area)");

    // A real one: OBJ/spider.obj has 1368 triangles, 56 of which repeat a position (counted
    // from the file's "v" and "f" lines by a separate script, not by assimp).
    if (!have_models()) return;
    const MeshData spider = load_model(model("OBJ/spider.obj"));
    CHECK(spider.triangle_count() == 1368 - 56);
    CHECK(spider.dropped_degenerate == 56);
}

TEST_CASE("model_loader: shared vertices by exact position, across meshes") {
    TempDir dir;
    // Two OBJ groups (two assimp meshes) sharing an edge, one vertex written twice.
    const std::string obj =
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 1 0 0\n"
        "g a\nf 1 2 3\ng b\nf 5 4 3\n";
    const MeshData m = load_model(dir.write("shared.obj", obj));
    REQUIRE(m.triangle_count() == 2);
    CHECK(m.vertices.size() == 4);
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

// ---- transforms -----------------------------------------------------------------------

TEST_CASE("MeshTransform: translate, rotate and scale of a unit cube give the analytic bounds") {
    TempDir dir;
    // The unit cube [0,1]^3 written here as 12 triangles (assimp-testmodels' PLY/cube.ply is
    // the same cube; this one does not need the package).
    const std::string cube = dir.write("cube.obj",
                                       "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                                       "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n");
    SUBCASE("identity") {
        const MeshData m = load_model(cube);
        CHECK(m.triangle_count() == 12);
        CHECK(m.vertices.size() == 8);
        Bounds want;
        want.lo = {0, 0, 0};
        want.hi = {1, 1, 1};
        check_bounds(bounds_of(m), want, 0);
    }
    SUBCASE("scale 2, 90 degrees about y, translate (1,2,3): exact") {
        // Scaled: [0,2]^3. About y by +90: (x, y, z) -> (z, y, -x): x in [0,2], z in [-2,0].
        const MeshData m = load_model(cube, MeshTransform::from_trs({1, 2, 3}, {0, 90, 0}, 2));
        Bounds want;
        want.lo = {1, 2, 1};
        want.hi = {3, 4, 3};
        check_bounds(bounds_of(m), want, 0);
    }
    SUBCASE("scale 1.5, 30 degrees about z, translate (-1, 0.5, 4)") {
        // (x, y) -> (x cos - y sin, x sin + y cos): x from -s sin to s cos, y from 0 to s (sin + cos).
        const double s = 1.5, sn = 0.5, cs = std::sqrt(3.0) / 2;
        const MeshData m = load_model(cube, MeshTransform::from_trs({-1, 0.5, 4}, {0, 0, 30}, s));
        Bounds want;
        want.lo = {-1 - s * sn, 0.5, 4};
        want.hi = {-1 + s * cs, 0.5 + s * (sn + cs), 4 + s};
        check_bounds(bounds_of(m), want, 1e-12);
    }
    SUBCASE("scale 0.75, (10, 20, 30) degrees: x first, then y, then z") {
        // Each corner turned one axis at a time, written out here without matrices.
        const double s = 0.75, d = kPi / 180;
        const Vec3d t{0.25, -3, 7};
        Bounds want;
        for (int c = 0; c < 8; ++c) {
            double x = s * (c & 1), y = s * ((c >> 1) & 1), z = s * ((c >> 2) & 1), u;
            u = y * std::cos(10 * d) - z * std::sin(10 * d); z = y * std::sin(10 * d) + z * std::cos(10 * d); y = u;
            u = z * std::cos(20 * d) - x * std::sin(20 * d); x = z * std::sin(20 * d) + x * std::cos(20 * d); z = u;
            u = x * std::cos(30 * d) - y * std::sin(30 * d); y = x * std::sin(30 * d) + y * std::cos(30 * d); x = u;
            want.add({x + t.x, y + t.y, z + t.z});
        }
        const MeshData m = load_model(cube, MeshTransform::from_trs(t, {10, 20, 30}, s));
        check_bounds(bounds_of(m), want, 1e-12);
    }
}

TEST_CASE("MeshTransform: the matrix form equals the translate/rotate/scale form") {
    TempDir dir;
    const std::string file = dir.write("tet.obj", "v 0.1 0.2 0.3\nv 1.7 -0.4 0.9\nv -0.6 1.3 0.5\nv 0.3 0.2 -1.1\n"
                                                  "f 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n");
    // Scale 2, +90 degrees about y, translate (1, 2, 3), written by hand:
    // (x, y, z) -> (2z + 1, 2y + 2, -2x + 3).
    const Matrix4d hand{0, 0, 2, 1, 0, 2, 0, 2, -2, 0, 0, 3, 0, 0, 0, 1};
    const MeshTransform trs = MeshTransform::from_trs({1, 2, 3}, {0, 90, 0}, 2);
    CHECK(trs.to_matrix() == hand);
    const MeshData a = load_model(file, trs);
    const MeshData b = load_model(file, MeshTransform::from_matrix(hand));
    REQUIRE(a.vertices.size() == b.vertices.size());
    CHECK(a.indices == b.indices);
    for (std::size_t i = 0; i < a.vertices.size(); ++i) {
        CHECK(a.vertices[i].x == b.vertices[i].x);
        CHECK(a.vertices[i].y == b.vertices[i].y);
        CHECK(a.vertices[i].z == b.vertices[i].z);
    }
    CHECK(a.vertices[0].x == 2 * 0.3f + 1.0);  // vertex 0 (0.1, 0.2, 0.3) as float, then mapped
    CHECK(a.vertices[0].y == 2 * 0.2f + 2.0);
    CHECK(a.vertices[0].z == -2 * 0.1f + 3.0);

    // A general one: the matrix of the TRS form, given as a matrix, maps every vertex alike.
    const MeshTransform general = MeshTransform::from_trs({-4, 0.5, 2}, {12.5, -70, 200}, 0.3);
    const MeshData c = load_model(file, general);
    const MeshData d = load_model(file, MeshTransform::from_matrix(general.to_matrix()));
    CHECK(c.indices == d.indices);
    for (std::size_t i = 0; i < c.vertices.size(); ++i) CHECK(c.vertices[i].x == d.vertices[i].x);
}

TEST_CASE("MeshTransform: validation") {
    CHECK(MeshTransform{}.problem().empty());
    CHECK(MeshTransform{}.to_matrix() == Matrix4d{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1});
    CHECK(scale_problem(1e-300).empty());
    CHECK(scale_problem(0) == "must be finite and > 0, got 0");
    CHECK(scale_problem(-1) == "must be finite and > 0, got -1");
    CHECK(scale_problem(std::nan("")) == "must be finite and > 0, got nan");
    CHECK(translate_problem({0, INFINITY, 0}) == "must be finite, got (0, inf, 0)");
    CHECK(rotate_deg_problem({0, 0, NAN}).rfind("must be finite", 0) == 0);
    CHECK(MeshTransform::from_trs({0, 0, 0}, {0, 0, 0}, -2).problem() == "scale: must be finite and > 0, got -2");

    CHECK(matrix_problem({1e-6, 0, 0, 5, 0, 1e-6, 0, 0, 0, 0, 1e-6, 0, 0, 0, 0, 1}).empty());  // tiny, fine
    CHECK(matrix_problem({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 1}) ==
          "must be affine (last row 0 0 0 1), got 0 0 1 1");
    CHECK(matrix_problem({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1}) ==
          "must be invertible (row 2 of the 3x3 part is zero)");
    CHECK(matrix_problem({1, 0, 0, 0, 0, 1, 0, 0, 1, 1, 1e-14, 0, 0, 0, 0, 1}).rfind("must be invertible", 0) == 0);
    CHECK(matrix_problem({1, 2, 3, 0, 4, 5, 6, 0, 7, 8, 9, 0, 0, 0, 0, 1}).rfind("must be invertible", 0) == 0);
    CHECK(matrix_problem({1, 0, 0, NAN, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}) == "must be finite, got nan");
    CHECK(MeshTransform::from_matrix({2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2}).problem() ==
          "matrix: must be affine (last row 0 0 0 1), got 0 0 0 2");

    TempDir dir;
    const std::string tri = dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    CHECK(load_error(tri, MeshTransform::from_trs({0, 0, 0}, {0, 0, 0}, 0)) ==
          "transform: scale: must be finite and > 0, got 0");
    CHECK(load_error(tri, MeshTransform::from_trs({0, 0, 0}, {0, 0, 0}, 1e308)).empty());
    // Valid, but it sends a vertex past the largest double.
    CHECK(load_error(tri, MeshTransform::from_trs({1e308, 0, 0}, {0, 0, 0}, 1e308)) ==
          "vertex 1 is not finite after the transform: (inf, 0, 0)");
}

// ---- generators and save_ply --------------------------------------------------------------

TEST_CASE("mesh_generators: uv_sphere and height_field") {
    const MeshData s = uv_sphere(6, 10);
    CHECK(s.vertices.size() == 5 * 10 + 2);
    CHECK(s.triangle_count() == 2 * 10 * 5);
    for (const Vec3d& v : s.vertices) CHECK(std::fabs(length_squared(v) - 1) < 1e-15);
    for (std::size_t t = 0; t < s.triangle_count(); ++t) {
        const Vec3d a = s.vertices[s.indices[3 * t]], b = s.vertices[s.indices[3 * t + 1]],
                    c = s.vertices[s.indices[3 * t + 2]];
        CAPTURE(t);
        CHECK(dot(cross(b - a, c - a), a + b + c) > 0);  // outward
    }
    const MeshData h = height_field(7);
    CHECK(h.vertices.size() == 64);
    CHECK(h.triangle_count() == 2 * 49);
    for (std::size_t t = 0; t < h.triangle_count(); ++t) {
        const Vec3d a = h.vertices[h.indices[3 * t]], b = h.vertices[h.indices[3 * t + 1]],
                    c = h.vertices[h.indices[3 * t + 2]];
        CHECK(cross(b - a, c - a).y > 0);  // facing +y
    }
    CHECK(h.vertices.front().x == -1);
    CHECK(h.vertices.back().z == 1);
    CHECK_THROWS_AS(uv_sphere(1, 10), std::invalid_argument);
    CHECK_THROWS_AS(uv_sphere(4, 2), std::invalid_argument);
    CHECK_THROWS_AS(height_field(0), std::invalid_argument);
}

TEST_CASE("save_ply: a generated mesh, written as binary PLY and loaded back, gives the same triangles") {
    TempDir dir;
    for (const MeshData& src : {uv_sphere(12, 24), height_field(9)}) {
        const std::string path = (dir.path / "mesh.ply").string();
        save_ply(src, path);
        CHECK(read_bytes(path).find("format binary_little_endian 1.0") != std::string::npos);
        const MeshData back = load_model(path);
        CHECK(back.format == "PLY");
        CHECK(back.dropped_degenerate == 0);
        REQUIRE(back.triangle_count() == src.triangle_count());
        CHECK(back.vertices.size() == src.vertices.size());
        auto as_float = [](const Vec3d& v) { return Vec3d{double(float(v.x)), double(float(v.y)), double(float(v.z))}; };
        for (std::size_t i = 0; i < src.indices.size(); ++i) {
            const Vec3d want = as_float(src.vertices[src.indices[i]]);
            const Vec3d got = back.vertices[back.indices[i]];
            CAPTURE(i);
            REQUIRE((got.x == want.x && got.y == want.y && got.z == want.z));
        }
    }
    MeshData bad = height_field(1);
    bad.vertices[0].x = 1e300;
    CHECK_THROWS_WITH_AS(save_ply(bad, (dir.path / "bad.ply").string()),
                         doctest::Contains("does not fit in float"), ModelError);
    bad = height_field(1);
    bad.indices[4] = 99;
    CHECK_THROWS_WITH_AS(save_ply(bad, (dir.path / "bad.ply").string()),
                         doctest::Contains("index 99 out of range (4 vertices)"), ModelError);
    CHECK_THROWS_AS(save_ply(MeshData{}, (dir.path / "empty.ply").string()), ModelError);
    CHECK_THROWS_AS(save_ply(height_field(1), (dir.path / "no" / "such" / "dir.ply").string()), ModelError);
}
