// tests/test_model_loader.cpp — io/model_loader on real models: one of each
// format, glTF node transforms, every glTF, OBJ and PLY file of assimp-testmodels,
// and its broken files. Counts are checked against what assimp itself reports
// through a different path (its PreTransformVertices step, float), or against
// counts read off the file by eye, as each test says. Files the tests write:
// test_model_files.cpp.
#include "model_fixtures.hpp"
#include "model_loader.hpp"

#include <octray/constants.hpp>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <doctest/doctest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <set>
#include <string>
#include <tuple>
#include <vector>

namespace fs = std::filesystem;
using namespace octray;
using namespace model_fixtures;

namespace {

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

double extent_of(const Bounds& b) {
    return std::max({1.0, b.hi.x - b.lo.x, b.hi.y - b.lo.y, b.hi.z - b.lo.z});
}

// Files assimp 5.2 reads that octray refuses, with the reason octray gives. All but
// the Draco file are refused on purpose (the assimp-based loader refused them too).
const std::map<std::string, std::string> kOnlyAssimpReads = {
    {"OBJ/number_formats.obj", "no triangles (all 1 have zero area)"},  // its one face is collinear
    {"glTF/BoxTextured-glTF/BoxTextured.gltf", "glTF 1.0 is not supported"},
    {"glTF/BoxTextured-glTF-Embedded/BoxTextured.gltf", "glTF 1.0 is not supported"},
    {"glTF/BoxTextured-glTF-MaterialsCommon/BoxTextured.gltf", "glTF 1.0 is not supported"},
    {"glTF/CesiumMilkTruck/CesiumMilkTruck.gltf", "no asset.version"},  // glTF 1.0 without the field
    {"glTF/IncorrectVertexArrays/Cube_v1.gltf", "glTF 1.0 is not supported"},
    {"glTF/TwoBoxes/TwoBoxes.gltf", "glTF 1.0 is not supported"},
    {"glTF2/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", "vertex 0 is not finite"},
    {"glTF2/IndexOutOfRange/IndexOutOfRange.gltf", "index 255 out of range (24 vertices)"},  // assimp drops the faces
    {"glTF2/draco/2CylinderEngine.gltf", "KHR_draco_mesh_compression is not supported"},  // the one loss
};
// Files octray reads that assimp 5.2 refuses: fields of the wrong JSON type where no
// geometry depends on them (tinygltf ignores them; assimp refuses the file).
const std::set<std::string> kOnlyOctrayReads = {
    "glTF2/issue_3269/texcoord_crash.gltf", "glTF2/wrongTypes/badExtension.gltf", "glTF2/wrongTypes/badNumber.gltf",
    "glTF2/wrongTypes/badObject.gltf",     "glTF2/wrongTypes/badString.gltf",    "glTF2/wrongTypes/badUint.gltf",
};

}  // namespace

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
        // assimp rounds every coordinate to float; octray's readers keep a text file's
        // decimals in double (binary files hold floats, read exactly by both): a
        // coordinate differs by at most half a float ulp of the largest magnitude.
        const double magnitude = std::max({std::fabs(b.lo.x), std::fabs(b.lo.y), std::fabs(b.lo.z),
                                           std::fabs(b.hi.x), std::fabs(b.hi.y), std::fabs(b.hi.z)});
        check_bounds(b, ref.bounds, c.nodes ? 1e-6 * extent : 0x1p-24 * magnitude);
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

// Every glTF 2, OBJ and PLY file of assimp-testmodels through octray's readers and through
// assimp (the reader octray used before; docs/reliability.md): where both read triangles,
// the counts and bounds agree; where only one reads a file, the file and the reason are
// on the lists below. With OCTRAY_MODEL_TABLE=<file> set, the comparison is written there
// as a Markdown table (docs/reliability.md's).
TEST_CASE("model_loader: every glTF, OBJ and PLY file of assimp-testmodels, against assimp") {
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
    std::ostringstream table;
    table << "| file | octray | assimp 5.2 |\n|---|---|---|\n";
    int loaded = 0, refused = 0, same = 0;
    for (const fs::path& f : files) {
        const std::string rel = fs::relative(f, kModels).string();
        CAPTURE(rel);
        Reference ref;
        const bool assimp_reads = assimp_reference(f.string(), ref) && ref.triangles > 0;
        std::string ours;
        try {
            const MeshData m = load_model(f.string());
            ++loaded;
            REQUIRE(m.triangle_count() > 0);
            Bounds got;
            for (const Vec3d& v : m.vertices) {
                REQUIRE((std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)));
                got.add(v);
            }
            ours = std::to_string(m.triangle_count() + m.dropped_degenerate) + " triangles";
            if (assimp_reads) {
                CHECK(m.triangle_count() + m.dropped_degenerate == ref.triangles);
                if (m.dropped_degenerate == 0) check_bounds(got, ref.bounds, 1e-5 * extent_of(got));
                if (m.triangle_count() + m.dropped_degenerate == ref.triangles) ++same;
            } else {
                CHECK_MESSAGE(kOnlyOctrayReads.count(rel) == 1, "octray reads what assimp does not");
            }
        } catch (const ModelError& e) {
            ++refused;
            ours = std::string("refused: ") + e.what();
            if (assimp_reads) {
                const auto expected = kOnlyAssimpReads.find(rel);
                CHECK_MESSAGE(expected != kOnlyAssimpReads.end(), "assimp reads what octray refuses: " << e.what());
                if (expected != kOnlyAssimpReads.end()) CHECK(ours.find(expected->second) != std::string::npos);
            }
        }
        table << "| " << rel << " | " << ours << " | "
              << (assimp_reads ? std::to_string(ref.triangles) + " triangles" : std::string("no triangles or refused"))
              << " |\n";
    }
    MESSAGE(files.size() << " files: " << loaded << " loaded, " << refused << " refused with a ModelError; " << same
                         << " with assimp's triangle count");
    if (const char* out = std::getenv("OCTRAY_MODEL_TABLE")) std::ofstream(out) << table.str();
}

TEST_CASE("model_loader: broken and unsupported files from assimp-testmodels") {
    if (!have_models()) return;
    CHECK(load_error(model("glTF2/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb")).find("is not finite") !=
          std::string::npos);
    CHECK(load_error(model("glTF2/IndexOutOfRange/IndexOutOfRange.gltf")) ==
          "mesh 0 primitive 0: index 255 out of range (24 vertices)");
    CHECK(load_error(model("glTF2/IndexOutOfRange/AllIndicesOutOfRange.gltf")) ==
          "mesh 0 primitive 0: index 65535 out of range (24 vertices)");
    CHECK(load_error(model("glTF2/MissingBin/BoxTextured.gltf")) == "unreadable glTF: File not found : BoxTextured0.bin");
    CHECK(load_error(model("glTF2/RecursiveNodes/RecursiveNodes.gltf")) ==
          "unreadable glTF: node 0 is reached twice (glTF nodes form trees)");
    CHECK(load_error(model("glTF/TwoBoxes/TwoBoxes.gltf")) == "glTF 1.0 is not supported (glTF 2.0 only)");
    CHECK(load_error(model("glTF/BoxTextured-glTF-Binary/BoxTextured.glb")) ==
          "glTF 1.0 binary is not supported (glTF 2.0 only)");
    // Points and lines only.
    for (const char* f : {"OBJ/testpoints.obj", "OBJ/testline.obj", "OBJ/point_cloud.obj", "PLY/points.ply",
                          "glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_00.gltf",
                          "glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_01.gltf",
                          "glTF2/TestNoRootNode/SceneWithoutNodes.gltf"}) {
        CAPTURE(f);
        CHECK(load_error(model(f)) == "no triangles");
    }
    CHECK(load_error(model("invalid/empty.obj")) == "no triangles");
    CHECK(load_error(model("invalid/empty.ply")) == "not a ply file: no 'ply' line at the start");
    CHECK(load_error(model("invalid/malformed.obj")) == "face 1 (line 23): index 12 out of range (8 vertices)");
    CHECK(load_error(model("invalid/OutOfMemory.off")) ==
          "unknown model format '.off' (expected .gltf, .glb, .obj or .ply)");
}
