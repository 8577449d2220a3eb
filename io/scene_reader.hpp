// io/scene_reader.hpp — the pieces of the scene JSON reader that its two
// files share (scene_loader.cpp: the document, camera, materials, lights and
// render settings; scene_objects.cpp: objects, shapes and meshes): JSON values
// read and checked at their JSON path. Internal to io/.
#pragma once

#include "model_loader.hpp"
#include "scene_loader.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <climits>
#include <map>
#include <cmath>
#include <string>
#include <vector>

namespace octray::scene_json {

// ordered_json keeps the materials in file order: material index = position.
using Json = nlohmann::ordered_json;
using Names = std::vector<std::string>;

inline std::string member(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }
inline std::string element(const std::string& path, std::size_t i) { return path + "[" + std::to_string(i) + "]"; }

// An enum's name table (scene.hpp) as a list of allowed strings.
template <std::size_t N>
Names names_of(const char* const (&table)[N]) {
    return Names(table, table + N);
}

inline std::string join(const Names& names) {
    std::string out;
    for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
    return out;
}

// A value as the file spells it (numbers by nlohmann's shortest round-trip form).
inline std::string describe(const Json& v) {
    switch (v.type()) {
        case Json::value_t::null: return "null";
        case Json::value_t::boolean: return v.get<bool>() ? "true" : "false";
        case Json::value_t::string: return "a string (\"" + v.get<std::string>() + "\")";
        case Json::value_t::array: return "an array of " + std::to_string(v.size());
        case Json::value_t::object: return "an object";
        default: return v.is_number() ? v.dump() : v.type_name();
    }
}

// Where the Scene's lights and materials stand in the file. validate() names
// Scene paths; some differ from the file's: the file's one `lights` array is
// split into directional_lights and point_lights, materials are an object
// keyed by name, not an array, and ambient.occlusion is Scene::ambient_occlusion.
struct SourceMap {
    std::vector<std::size_t> directional, point;  // the `lights` index of each Scene light
    std::vector<std::size_t> mesh;                // the `objects` index of each Scene mesh
    std::vector<std::size_t> object;              // the `objects` index of each Scene object
    std::vector<std::vector<std::uint32_t>> faces;  // per Scene mesh: SceneSources::mesh_faces

    std::string json_path(const std::string& scene_path, const Scene& scene) const;
};

// Reads one document; every check names the file and the JSON path it failed on.
class Reader {
public:
    explicit Reader(std::string file) : file_(std::move(file)), base_dir_(folder_of(file_)) {}
    // A scene held in memory (parse_scene with arrays): model files relative to
    // `base_dir`, mesh arrays by object index.
    // geometry_only: ParseOptions::geometry_only.
    Reader(std::string name, std::string base_dir, const std::map<std::size_t, MeshArrays>* arrays,
           bool geometry_only = false)
        : file_(std::move(name)), base_dir_(std::move(base_dir)), arrays_(arrays), geometry_only_(geometry_only) {
        if (!base_dir_.empty() && base_dir_.back() != '/') base_dir_ += '/';
    }

    [[noreturn]] void fail(const std::string& path, std::string problem) const {
        // The message contract is one line; user strings may hold newlines.
        std::replace(problem.begin(), problem.end(), '\n', ' ');
        throw SceneError((file_.empty() ? "" : file_ + ": ") + (path.empty() ? "(root)" : path) + ": " + problem);
    }

    void expect_object(const Json& v, const std::string& path) const {
        if (!v.is_object()) fail(path, "must be an object, got " + describe(v));
    }

    // Rejects any field not in `allowed`: a misspelt optional field would
    // otherwise be silently replaced by its default.
    void reject_unknown(const Json& obj, const std::string& path, const std::string& what, const Names& allowed) const {
        for (const auto& item : obj.items()) {
            if (std::find(allowed.begin(), allowed.end(), item.key()) == allowed.end())
                fail(member(path, item.key()), "unknown field (" + what + " has: " + join(allowed) + ")");
        }
    }

    const Json& required(const Json& obj, const std::string& path, const std::string& key, const std::string& what) const {
        auto it = obj.find(key);
        if (it == obj.end()) fail(member(path, key), "missing required field of " + what);
        return *it;
    }

    static const Json* optional(const Json& obj, const std::string& key) {
        auto it = obj.find(key);
        return it == obj.end() ? nullptr : &*it;
    }

    // A JSON number is always finite (the parser refuses literals that overflow).
    double number(const Json& v, const std::string& path) const {
        if (!v.is_number()) fail(path, "must be a number, got " + describe(v));
        return v.get<double>();
    }

    int integer(const Json& v, const std::string& path) const {
        const double d = number(v, path);
        if (d != std::floor(d)) fail(path, "must be an integer, got " + describe(v));
        if (d < INT_MIN || d > INT_MAX) fail(path, "must be an integer in the range of int, got " + describe(v));
        return static_cast<int>(d);
    }

    bool boolean(const Json& v, const std::string& path) const {
        if (!v.is_boolean()) fail(path, "must be true or false, got " + describe(v));
        return v.get<bool>();
    }

    std::string string(const Json& v, const std::string& path) const {
        if (!v.is_string()) fail(path, "must be a string, got " + describe(v));
        return v.get<std::string>();
    }

    // Index of the string `v` in `allowed`; `what` names the kind ("light type").
    std::size_t one_of(const Json& v, const std::string& path, const std::string& what, const Names& allowed) const {
        const std::string s = string(v, path);
        auto it = std::find(allowed.begin(), allowed.end(), s);
        if (it == allowed.end()) fail(path, "unknown " + what + " \"" + s + "\" (allowed: " + join(allowed) + ")");
        return static_cast<std::size_t>(it - allowed.begin());
    }

    Vec3d vec3(const Json& v, const std::string& path) const {
        if (!v.is_array() || v.size() != 3) fail(path, "must be an array of 3 numbers, got " + describe(v));
        return {number(v[0], element(path, 0)), number(v[1], element(path, 1)), number(v[2], element(path, 2))};
    }

    // Top-level value: the type field, checked before anything else so the
    // allowed-field list below can depend on it.
    std::size_t type_of(const Json& obj, const std::string& path, const std::string& kind, const Names& types) const {
        expect_object(obj, path);
        return one_of(required(obj, path, "type", "a " + kind), member(path, "type"), kind + " type", types);
    }

    // The document's parts: scene_loader.cpp. `sources`: filled when given.
    Scene scene(const Json& root, SceneSources* sources = nullptr) const;
    Camera camera(const Json& j, const std::string& path) const;
    std::vector<Material> materials(const Json& j, const std::string& path) const;
    AmbientLight ambient(const Json& j, const std::string& path) const;
    AmbientOcclusion occlusion(const Json& j, const std::string& path) const;
    void lights(const Json& j, const std::string& path, Scene& scene, SourceMap& source) const;
    RenderSettings render(const Json& j, const std::string& path) const;

    // Objects: scene_objects.cpp. `mats` null: the scene has no materials (a
    // geometry-only one): no object names one, each gets material 0.
    std::vector<Object> objects(const Json& j, const std::string& path, const std::vector<Material>* mats,
                                std::vector<Mesh>& meshes, SourceMap& source) const;
    Shape shape(const Json& o, const std::string& path, PrimitiveType type) const;
    // A mesh from its model file (load_model); `faces`: MeshData::faces.
    Mesh mesh(const Json& o, const std::string& opath, std::vector<std::uint32_t>& faces) const;
    // The mesh object `index` of "objects": from `arrays_` where it is a key
    // (zero-area triangles dropped as load_model drops them), else mesh().
    Mesh mesh_at(const Json& o, const std::string& opath, std::size_t index, std::vector<std::uint32_t>& faces) const;
    MeshTransform mesh_transform(const Json& j, const std::string& path) const;
    void drop_zero_area(Mesh& m, std::vector<std::uint32_t>& faces, const std::string& opath) const;

private:
    // The folder of a scene file, with its '/' (empty: none named, the working directory).
    static std::string folder_of(const std::string& file) {
        const auto slash = file.rfind('/');
        return slash == std::string::npos ? std::string() : file.substr(0, slash + 1);
    }

    std::string file_;
    std::string base_dir_;  // where relative model files are read from
    const std::map<std::size_t, MeshArrays>* arrays_ = nullptr;
    bool geometry_only_ = false;
};

}  // namespace octray::scene_json
