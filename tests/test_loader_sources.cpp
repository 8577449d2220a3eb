// Scene loader, what a ray caster needs besides the Scene (SceneSources,
// ParseOptions): geometry-only scenes, where each primitive came from in the
// JSON, zero-area triangles of meshes given as arrays dropped and numbered.
#include "scene_loader.hpp"

#include <doctest/doctest.h>

#include <map>
#include <string>
#include <vector>

using octray::MeshArrays;
using octray::ParseOptions;
using octray::parse_scene;
using octray::Scene;
using octray::SceneError;
using octray::SceneSources;

namespace {

std::string error_of(const std::string& json, const std::map<std::size_t, MeshArrays>& arrays = {},
                     bool geometry_only = false) {
    ParseOptions options;
    options.geometry_only = geometry_only;
    try {
        parse_scene(json, "", "", arrays, options);
    } catch (const SceneError& e) {
        return e.what();
    }
    return "";
}

// A unit square as two triangles, with zero-area triangles at places 1 and 3:
// the caller's faces 0, 2 and 4 are kept.
MeshArrays square_with_slivers() {
    MeshArrays m;
    m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 2, 0}};
    m.indices = {0, 1, 2, /**/ 1, 1, 2, /**/ 1, 3, 2, /**/ 0, 3, 4, /**/ 0, 1, 3};
    return m;
}

}  // namespace

TEST_CASE("loader: a geometry-only scene leaves out the camera and the materials, the CLI's does not") {
    const std::string json = R"({"objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1},
                                            {"type": "mesh", "vertices": 0, "indices": 0},
                                            {"type": "box", "min": [0, 0, 0], "max": [1, 1, 1]}]})";
    std::map<std::size_t, MeshArrays> arrays{{1, square_with_slivers()}};
    SceneSources sources;
    ParseOptions options;
    options.geometry_only = true;
    options.sources = &sources;
    const Scene s = parse_scene(json, "", "", arrays, options);
    CHECK_FALSE(sources.camera);
    CHECK_FALSE(sources.materials);
    REQUIRE(s.materials.size() == 1);  // the placeholder every object uses
    CHECK(s.objects.at(0).material == 0);
    CHECK(s.meshes.at(0).material == 0);
    CHECK(sources.objects == std::vector<std::size_t>{0, 2});
    CHECK(sources.meshes == std::vector<std::size_t>{1});
    REQUIRE(s.meshes.at(0).triangle_count() == 3);
    CHECK(s.meshes[0].dropped_degenerate == 2);
    CHECK(sources.mesh_faces.at(0) == std::vector<std::uint32_t>{0, 2, 4});
    CHECK(s.meshes[0].indices == std::vector<std::uint32_t>{0, 1, 2, 1, 3, 2, 0, 1, 3});

    // The CLI's contract: both required; with options off, too.
    CHECK(error_of(json, arrays) == "camera: missing required field of a scene");
    // A material named in a scene without materials is unknown; one left out
    // in a scene with materials is missing.
    CHECK(error_of(R"({"objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "m"}]})", {},
                   true) == "objects[0].material: unknown material \"m\" (no materials are defined)");
    CHECK(error_of(R"({"materials": {"m": {"type": "matte", "ka": 0, "kd": 1, "cd": [1, 1, 1]}},
                       "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1}]})",
                   {}, true) == "objects[0].material: missing required field of a sphere");
}

TEST_CASE("loader: array meshes, zero-area triangles dropped where the arrays are otherwise valid") {
    const std::string json = R"({"objects": [{"type": "mesh", "vertices": 0, "indices": 0}]})";
    MeshArrays m = square_with_slivers();
    m.indices.at(13) = 9;  // out of range, after a zero-area triangle: reported at its own place
    CHECK(error_of(json, {{0, m}}, true) == "objects[0].indices[13]: index 9 out of range (5 vertices)");
    MeshArrays flat;
    flat.vertices = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
    flat.indices = {0, 1, 2, 0, 0, 1};
    CHECK(error_of(json, {{0, flat}}, true) == "objects[0].indices: no triangles (all 2 have zero area)");
    // None dropped: no face map (the identity).
    MeshArrays clean;
    clean.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    clean.indices = {0, 1, 2};
    SceneSources sources;
    ParseOptions options;
    options.geometry_only = true;
    options.sources = &sources;
    parse_scene(json, "", "", {{0, clean}}, options);
    REQUIRE(sources.mesh_faces.size() == 1);
    CHECK(sources.mesh_faces[0].empty());
}

TEST_CASE("loader: an object's error names its place in the file's objects, meshes before it or not") {
    const std::string json = R"({"camera": {"type": "pinhole", "eye": [0, 0, 5], "look_at": [0, 0, 0],
                                            "up": [0, 1, 0], "fov_y": 60, "width": 8, "height": 4},
        "materials": {"m": {"type": "matte", "ka": 0, "kd": 1, "cd": [1, 1, 1]}},
        "objects": [{"type": "mesh", "vertices": 0, "indices": 0, "material": "m"},
                    {"type": "sphere", "center": [0, 0, 0], "radius": -1, "material": "m"}]})";
    MeshArrays clean;
    clean.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    clean.indices = {0, 1, 2};
    CHECK(error_of(json, {{0, clean}}) == "objects[1].radius: must be > 0, got -1");
}
