// io/scene_loader.hpp — scene JSON (docs/scene-format.md) -> octray::Scene.
//
// The loader checks the JSON's shape itself: types, required fields, unknown
// fields (a typo must not be silently ignored), type and material names. Value
// ranges, finiteness and degenerate geometry are judged by octray::validate()
// (scene.hpp), the same rules a scene built in code meets, and reported at the
// JSON path of the offending value. It normalizes every direction (light
// `direction`, `normal`, camera `up`) with octray::unit_direction.
//
// Required: camera (type; eye, look_at, up, width, height; fov_y for pinhole,
// height_world for orthographic), materials (object: name -> {type "matte",
// ka, kd, cd}), objects (array; every object's geometry, type and material).
// Optional, with the defaults of docs/scene-format.md / scene.hpp: background, ambient
// (absent = no ambient light; color, ls), lights (a light needs type and
// direction or position; color, ls, shadows, attenuation are optional),
// render (tonemap, clamp_color, gamma).
#pragma once

#include <octray/scene.hpp>

#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace octray {

// what() is one line: "FILE: JSON_PATH: problem", e.g.
// "scenes/x.json: objects[3].radius: must be > 0, got -1", or for a syntax
// error "FILE: line L, column C: syntax error ...".
class SceneError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// The largest scene file load_scene() reads. Parsing holds the JSON document
// in memory, about 9 bytes per byte of text: some 10 GB at this limit.
inline constexpr std::uintmax_t kMaxSceneFileBytes = std::uintmax_t(1) << 30;  // 1 GiB

// Reads and parses `path`. A file that cannot be read gives
// "FILE: cannot open: <OS reason>"; one larger than kMaxSceneFileBytes,
// "FILE: file too large: N bytes (limit 1073741824)", unread.
Scene load_scene(const std::string& path);

// Parses JSON text; `file_name_for_messages` only prefixes error messages.
Scene parse_scene(const std::string& json_text, const std::string& file_name_for_messages);

// A mesh object's triangles given in memory instead of a model file: the
// vertices, and three indices per triangle (the Python module's
// octray.Scene(dict) with "vertices" and "indices" arrays).
struct MeshArrays {
    std::vector<Vec3d> vertices;
    std::vector<std::uint32_t> indices;
};

// Where a parsed scene's parts came from in the JSON, for a caller that
// reports hits in the JSON's own terms (the Python module's geometry_id and
// primitive_id: docs/python.md) or must know what a geometry-only scene left out.
struct SceneSources {
    bool camera = true;     // false: the JSON had no camera; Scene::camera is Camera{}, a placeholder
    bool materials = true;  // false: the JSON had no materials; Scene::materials is one Material{}, every object's
    std::vector<std::size_t> objects;  // the "objects" index of each Scene::objects entry
    std::vector<std::size_t> meshes;   // the "objects" index of each Scene::meshes entry
    // Per Scene mesh: the number, among the triangles its file or arrays gave,
    // of each triangle kept (MeshData::faces); empty when none was dropped.
    std::vector<std::vector<std::uint32_t>> mesh_faces;
};

struct ParseOptions {
    // A scene for ray casting alone may leave out "camera" and "materials"
    // (its objects then name no material): SceneSources says which it left
    // out, and the Scene holds placeholders that compile() accepts. Off (the
    // CLI's contract): both are required.
    bool geometry_only = false;
    SceneSources* sources = nullptr;  // filled when given
};

// A scene held in memory rather than in a file: the same reader, the same
// rules, the same messages. `name_for_messages` prefixes them (empty: the
// message is "JSON_PATH: problem" alone); a relative model "file" is read from
// `base_dir` (empty: the working directory). A mesh object whose index in
// "objects" is a key of `arrays` takes its triangles from there: its JSON has
// "vertices" and "indices" (their values are not read) and no "file"; a
// "transform" applies as to a file. validate() then judges the arrays as any
// mesh (finite vertices, indices in range) and reports at
// objects[i].vertices[v] or objects[i].indices[k]; where those hold, a
// zero-area triangle (after the transform) is dropped and counted as a model
// file's is (Mesh::dropped_degenerate, SceneSources::mesh_faces), and a mesh
// whose every triangle has zero area is an error at objects[i].indices.
Scene parse_scene(const std::string& json_text, const std::string& name_for_messages, const std::string& base_dir,
                  const std::map<std::size_t, MeshArrays>& arrays, const ParseOptions& options = {});

// load_scene, and where the scene's parts came from (the CLI's contract:
// camera and materials required).
Scene load_scene(const std::string& path, SceneSources* sources);

}  // namespace octray
