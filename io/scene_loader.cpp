// io/scene_loader.cpp — read scene JSON into an octray::Scene.
//
// The JSON's shape (types, required and unknown fields, names of types,
// materials and enums) is checked here; value ranges, finiteness and
// degenerate geometry are octray::validate()'s (kernels/validate.cpp), the one
// set of rules a scene built in code meets too. Its message is reported at the
// JSON path of the offending value.
#include "scene_loader.hpp"

#include "model_loader.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <set>
#include <utility>
#include <vector>

namespace octray {
namespace {

// ordered_json keeps the materials in file order: material index = position.
using Json = nlohmann::ordered_json;
using Names = std::vector<std::string>;

std::string member(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }
std::string element(const std::string& path, std::size_t i) { return path + "[" + std::to_string(i) + "]"; }

// An enum's name table (scene.hpp) as a list of allowed strings.
template <std::size_t N>
Names names_of(const char* const (&table)[N]) {
    return Names(table, table + N);
}

std::string join(const Names& names) {
    std::string out;
    for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
    return out;
}

// A value as the file spells it (numbers by nlohmann's shortest round-trip form).
std::string describe(const Json& v) {
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

    std::string json_path(const std::string& scene_path, const Scene& scene) const {
        static const std::string occlusion = "ambient_occlusion";  // the file's ambient.occlusion
        if (scene_path.compare(0, occlusion.size(), occlusion) == 0)
            return "ambient.occlusion" + scene_path.substr(occlusion.size());
        const auto open = scene_path.find('['), close = scene_path.find(']');
        if (open == std::string::npos || close == std::string::npos || close < open) return scene_path;
        const std::string head = scene_path.substr(0, open), rest = scene_path.substr(close + 1);
        const std::size_t i = std::stoul(scene_path.substr(open + 1, close - open - 1));
        if (head == "materials") return member("materials", scene.materials.at(i).name) + rest;
        if (head == "directional_lights") return element("lights", directional.at(i)) + rest;
        if (head == "point_lights") return element("lights", point.at(i)) + rest;
        if (head == "meshes") return element("objects", mesh.at(i)) + rest;
        return scene_path;  // camera, background, ambient, objects, render: the same in both
    }
};

// DESIGN.md: the loader stores directions normalized (every path would
// normalize them the same way anyway: scene.hpp, unit_direction).
void normalize_directions(Scene& s) {
    s.camera.up = unit_direction(s.camera.up);
    for (DirectionalLight& l : s.directional_lights) l.direction = unit_direction(l.direction);
    for (Object& o : s.objects) {
        if (Plane* p = std::get_if<Plane>(&o.shape)) p->normal = unit_direction(p->normal);
        if (Disk* d = std::get_if<Disk>(&o.shape)) d->normal = unit_direction(d->normal);
    }
}

// Reads one document; every check names the file and the JSON path it failed on.
class Reader {
public:
    explicit Reader(std::string file) : file_(std::move(file)) {}

    [[noreturn]] void fail(const std::string& path, std::string problem) const {
        // The message contract is one line; user strings may hold newlines.
        std::replace(problem.begin(), problem.end(), '\n', ' ');
        throw SceneError(file_ + ": " + (path.empty() ? "(root)" : path) + ": " + problem);
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

    Camera camera(const Json& j, const std::string& path) const {
        Camera cam;
        cam.type = static_cast<CameraType>(type_of(j, path, "camera", names_of(kCameraTypeNames)));
        const bool pinhole = cam.type == CameraType::pinhole;
        const Names fields = pinhole ? Names{"type", "eye", "look_at", "up", "fov_y", "width", "height"}
                                     : Names{"type", "eye", "look_at", "up", "height_world", "width", "height"};
        const std::string what = pinhole ? "a pinhole camera" : "an orthographic camera";
        reject_unknown(j, path, what, fields);
        auto req = [&](const char* key) -> const Json& { return required(j, path, key, what); };
        cam.eye = vec3(req("eye"), member(path, "eye"));
        cam.look_at = vec3(req("look_at"), member(path, "look_at"));
        cam.up = vec3(req("up"), member(path, "up"));
        if (pinhole) cam.fov_y = number(req("fov_y"), member(path, "fov_y"));
        else cam.height_world = number(req("height_world"), member(path, "height_world"));
        cam.width = integer(req("width"), member(path, "width"));
        cam.height = integer(req("height"), member(path, "height"));
        return cam;
    }

    std::vector<Material> materials(const Json& j, const std::string& path) const {
        expect_object(j, path);
        std::vector<Material> out;
        for (const auto& item : j.items()) {
            const std::string mpath = member(path, item.key());
            type_of(item.value(), mpath, "material", {"matte"});
            const std::string what = "a matte material";
            reject_unknown(item.value(), mpath, what, {"type", "ka", "kd", "cd"});
            Material m;
            m.name = item.key();
            m.ka = number(required(item.value(), mpath, "ka", what), member(mpath, "ka"));
            m.kd = number(required(item.value(), mpath, "kd", what), member(mpath, "kd"));
            m.cd = vec3(required(item.value(), mpath, "cd", what), member(mpath, "cd"));
            out.push_back(std::move(m));
        }
        return out;
    }

    AmbientLight ambient(const Json& j, const std::string& path) const {
        expect_object(j, path);
        reject_unknown(j, path, "ambient", {"color", "ls", "occlusion"});
        AmbientLight a;
        if (auto* c = optional(j, "color")) a.color = vec3(*c, member(path, "color"));
        if (auto* ls = optional(j, "ls")) a.ls = number(*ls, member(path, "ls"));
        return a;
    }

    AmbientOcclusion occlusion(const Json& j, const std::string& path) const {
        expect_object(j, path);
        reject_unknown(j, path, "occlusion", {"samples", "distance", "min_amount"});
        AmbientOcclusion o;
        if (auto* v = optional(j, "samples")) o.samples = integer(*v, member(path, "samples"));
        if (auto* v = optional(j, "distance")) o.distance = number(*v, member(path, "distance"));
        if (auto* v = optional(j, "min_amount")) o.min_amount = number(*v, member(path, "min_amount"));
        return o;
    }

    void lights(const Json& j, const std::string& path, Scene& scene, SourceMap& source) const {
        if (!j.is_array()) fail(path, "must be an array, got " + describe(j));
        for (std::size_t i = 0; i < j.size(); ++i) {
            const Json& l = j[i];
            const std::string lpath = element(path, i);
            const bool directional = type_of(l, lpath, "light", {"directional", "point"}) == 0;
            const std::string what = directional ? "a directional light" : "a point light";
            reject_unknown(l, lpath, what,
                           directional ? Names{"type", "direction", "color", "ls", "shadows"}
                                       : Names{"type", "position", "color", "ls", "attenuation", "shadows"});
            Vec3d color_v{1, 1, 1};
            double ls = 1.0;
            bool shadows = false;
            if (auto* c = optional(l, "color")) color_v = vec3(*c, member(lpath, "color"));
            if (auto* v = optional(l, "ls")) ls = number(*v, member(lpath, "ls"));
            if (auto* v = optional(l, "shadows")) shadows = boolean(*v, member(lpath, "shadows"));
            if (directional) {
                DirectionalLight d;
                d.direction = vec3(required(l, lpath, "direction", what), member(lpath, "direction"));
                d.color = color_v;
                d.ls = ls;
                d.shadows = shadows;
                scene.directional_lights.push_back(d);
                source.directional.push_back(i);
            } else {
                PointLight p;
                p.position = vec3(required(l, lpath, "position", what), member(lpath, "position"));
                p.color = color_v;
                p.ls = ls;
                p.shadows = shadows;
                if (auto* v = optional(l, "attenuation"))
                    p.attenuation = static_cast<Attenuation>(
                        one_of(*v, member(lpath, "attenuation"), "attenuation", names_of(kAttenuationNames)));
                scene.point_lights.push_back(p);
                source.point.push_back(i);
            }
        }
    }

    Shape shape(const Json& o, const std::string& path, PrimitiveType type) const {
        const std::string what = std::string("a ") + primitive_type_name(type);
        auto req = [&](const char* key) -> const Json& { return required(o, path, key, what); };
        auto vec = [&](const char* key) { return vec3(req(key), member(path, key)); };
        auto radius = [&] { return number(req("radius"), member(path, "radius")); };
        switch (type) {
            case PrimitiveType::sphere: {
                Sphere s;
                s.center = vec("center");
                s.radius = radius();
                return s;
            }
            case PrimitiveType::plane: return Plane{vec("point"), vec("normal")};
            case PrimitiveType::disk: {
                Disk d;
                d.center = vec("center");
                d.normal = vec("normal");
                d.radius = radius();
                return d;
            }
            case PrimitiveType::rectangle: return Rectangle{vec("corner"), vec("a"), vec("b")};
            case PrimitiveType::box: return Box{vec("min"), vec("max")};
            case PrimitiveType::triangle: {
                const std::string vpath = member(path, "vertices");
                const Json& vs = req("vertices");
                if (!vs.is_array() || vs.size() != 3)
                    fail(vpath, "must be an array of 3 points ([x,y,z]), got " + describe(vs));
                return Triangle{vec3(vs[0], element(vpath, 0)), vec3(vs[1], element(vpath, 1)), vec3(vs[2], element(vpath, 2))};
            }
        }
        fail(path, "internal error: unhandled primitive type");
    }

    // A mesh object (DESIGN.md, meshes): its model file read by load_model.
    Mesh mesh(const Json& o, const std::string& opath) const {
        reject_unknown(o, opath, "a mesh", {"type", "file", "material", "transform"});
        const std::string fpath = member(opath, "file");
        const std::string file = string(required(o, opath, "file", "a mesh"), fpath);
        MeshTransform transform;
        if (auto* v = optional(o, "transform")) transform = mesh_transform(*v, member(opath, "transform"));
        // Relative to the scene file's folder.
        std::string resolved = file;
        const auto slash = file_.rfind('/');
        if (!file.empty() && file[0] != '/' && slash != std::string::npos) resolved = file_.substr(0, slash + 1) + file;
        try {
            MeshData data = load_model(resolved, transform);
            Mesh m;
            m.vertices = std::move(data.vertices);
            m.indices = std::move(data.indices);
            m.dropped_degenerate = data.dropped_degenerate;
            return m;
        } catch (const ModelError& e) {
            fail(fpath, file + ": " + e.what());
        }
    }

    MeshTransform mesh_transform(const Json& j, const std::string& path) const {
        expect_object(j, path);
        reject_unknown(j, path, "a transform", {"translate", "rotate_deg", "scale", "matrix"});
        MeshTransform t;
        auto check = [&](const std::string& key, const std::string& problem) {
            if (!problem.empty()) fail(member(path, key), problem);
        };
        if (auto* v = optional(j, "matrix")) {
            for (const char* key : {"translate", "rotate_deg", "scale"})
                if (optional(j, key)) fail(member(path, key), "not with \"matrix\": give one or the other");
            const std::string mpath = member(path, "matrix");
            if (!v->is_array() || v->size() != 16) fail(mpath, "must be an array of 16 numbers (row-major), got " + describe(*v));
            Matrix4d m{};
            for (std::size_t i = 0; i < 16; ++i) m[i] = number((*v)[i], element(mpath, i));
            check("matrix", matrix_problem(m));
            return MeshTransform::from_matrix(m);
        }
        if (auto* v = optional(j, "translate")) t.translate = vec3(*v, member(path, "translate")), check("translate", translate_problem(t.translate));
        if (auto* v = optional(j, "rotate_deg")) t.rotate_deg = vec3(*v, member(path, "rotate_deg")), check("rotate_deg", rotate_deg_problem(t.rotate_deg));
        if (auto* v = optional(j, "scale")) t.scale = number(*v, member(path, "scale")), check("scale", scale_problem(t.scale));
        return t;
    }

    std::vector<Object> objects(const Json& j, const std::string& path, const std::vector<Material>& mats,
                                std::vector<Mesh>& meshes, SourceMap& source) const {
        if (!j.is_array()) fail(path, "must be an array, got " + describe(j));
        static const std::vector<Names> fields{
            {"type", "center", "radius", "material"},         {"type", "point", "normal", "material"},
            {"type", "center", "normal", "radius", "material"}, {"type", "corner", "a", "b", "material"},
            {"type", "min", "max", "material"},               {"type", "vertices", "material"}};
        Names material_names;
        for (const auto& m : mats) material_names.push_back(m.name);

        std::vector<Object> out;
        // The primitive limit (scene.hpp) checked as meshes come in, before a
        // scene too large to compile loads more models.
        std::size_t primitives = 0;
        auto count = [&](std::size_t n, const std::string& at) {
            primitives += n;
            if (primitives > kMaxPrimitives)
                fail(at, "too many primitives: more than " + std::to_string(kMaxPrimitives) +
                             " objects and mesh triangles (the limit)");
        };
        for (std::size_t i = 0; i < j.size(); ++i) {
            const Json& o = j[i];
            const std::string opath = element(path, i);
            Names types = names_of(kPrimitiveTypeNames);
            types.push_back("mesh");
            const std::size_t type_index = type_of(o, opath, "object", types);
            const bool is_mesh = type_index == std::size_t(kPrimitiveTypeCount);
            const auto type = static_cast<PrimitiveType>(is_mesh ? 0 : type_index);
            const std::string what = is_mesh ? std::string("a mesh") : std::string("a ") + primitive_type_name(type);
            Object obj;
            Mesh m;
            if (is_mesh) {
                m = mesh(o, opath);
                count(m.triangle_count(), member(opath, "file"));
            } else {
                count(1, opath);
                reject_unknown(o, opath, what, fields[static_cast<std::size_t>(type)]);
                obj.shape = shape(o, opath, type);
            }
            const std::string mpath = member(opath, "material");
            const std::string name = string(required(o, opath, "material", what), mpath);
            auto it = std::find(material_names.begin(), material_names.end(), name);
            if (it == material_names.end())
                fail(mpath, "unknown material \"" + name + "\" (" +
                                (material_names.empty() ? std::string("no materials are defined")
                                                        : "defined: " + join(material_names)) +
                                ")");
            if (is_mesh) {
                m.material = static_cast<int>(it - material_names.begin());
                meshes.push_back(std::move(m));
                source.mesh.push_back(i);
                continue;
            }
            obj.material = static_cast<int>(it - material_names.begin());
            out.push_back(std::move(obj));
        }
        return out;
    }

    RenderSettings render(const Json& j, const std::string& path) const {
        expect_object(j, path);
        reject_unknown(j, path, "render", {"tonemap", "clamp_color", "gamma"});
        RenderSettings r;
        if (auto* v = optional(j, "tonemap"))
            r.tonemap = static_cast<ToneMap>(
                one_of(*v, member(path, "tonemap"), "tonemap", names_of(kToneMapNames)));
        if (auto* v = optional(j, "clamp_color")) r.clamp_color = vec3(*v, member(path, "clamp_color"));
        if (auto* v = optional(j, "gamma")) r.gamma = number(*v, member(path, "gamma"));
        return r;
    }

    Scene scene(const Json& root) const {
        expect_object(root, "");
        reject_unknown(root, "", "a scene",
                       {"camera", "background", "ambient", "lights", "materials", "objects", "render"});
        Scene s;
        SourceMap source;
        s.camera = camera(required(root, "", "camera", "a scene"), "camera");
        if (auto* v = optional(root, "background")) s.background = vec3(*v, "background");
        if (auto* v = optional(root, "ambient")) {
            s.ambient = ambient(*v, "ambient");
            if (auto* o = optional(*v, "occlusion")) s.ambient_occlusion = occlusion(*o, "ambient.occlusion");
        }
        if (auto* v = optional(root, "lights")) lights(*v, "lights", s, source);
        s.materials = materials(required(root, "", "materials", "a scene"), "materials");
        s.objects = objects(required(root, "", "objects", "a scene"), "objects", s.materials, s.meshes, source);
        if (auto* v = optional(root, "render")) s.render = render(*v, "render");
        // The values: the rules every scene meets, stated once (validate()).
        try {
            validate(s);
        } catch (const InvalidScene& e) {
            fail(source.json_path(e.path(), s), e.problem());
        }
        normalize_directions(s);
        return s;
    }

private:
    std::string file_;
};


// A SAX handler that builds the document with nlohmann's own DOM builder and
// tracks the JSON path being parsed: nlohmann keeps the last of duplicate keys
// without a word, so a repeated key is rejected here, and a number that
// overflows a double is reported at its path. (The callback parser does the
// same with a per-event callback, but its cost grows faster than the file:
// 12 s for 262,144 objects.)
class PathTracker {
public:
    using Dom = nlohmann::detail::json_sax_dom_parser<Json>;
    PathTracker(const Reader& reader, Json& root) : reader_(reader), dom_(root, true) {}

    bool null() { return value(dom_.null()); }
    bool boolean(bool v) { return value(dom_.boolean(v)); }
    bool number_integer(Json::number_integer_t v) { return value(dom_.number_integer(v)); }
    bool number_unsigned(Json::number_unsigned_t v) { return value(dom_.number_unsigned(v)); }
    bool number_float(Json::number_float_t v, const Json::string_t& s) { return value(dom_.number_float(v, s)); }
    bool string(Json::string_t& v) { return value(dom_.string(v)); }
    bool binary(Json::binary_t& v) { return value(dom_.binary(v)); }
    bool start_object(std::size_t n) {
        frames_.push_back({false, 0, {}, {}});
        return dom_.start_object(n);
    }
    bool key(Json::string_t& k) {
        Frame& top = frames_.back();
        top.key = k;
        if (!top.keys.insert(k).second) reader_.fail(current_path(), "duplicate field");
        return dom_.key(k);
    }
    bool end_object() { return close(dom_.end_object()); }
    bool start_array(std::size_t n) {
        frames_.push_back({true, 0, {}, {}});
        return dom_.start_array(n);
    }
    bool end_array() { return close(dom_.end_array()); }
    template <class Exception>
    bool parse_error(std::size_t position, const std::string& last_token, const Exception& ex) {
        return dom_.parse_error(position, last_token, ex);  // throws ex
    }

    // The path of the value being parsed now (the one a lexer error is about).
    std::string current_path() const {
        std::string path;
        for (const auto& f : frames_) path = f.array ? element(path, f.index) : member(path, f.key);
        return path;
    }

private:
    struct Frame {
        bool array;
        std::size_t index;  // array: elements completed so far
        std::string key;    // object: the key being parsed
        std::set<std::string> keys;
    };

    bool value(bool ok) {
        element_done();
        return ok;
    }
    bool close(bool ok) {
        frames_.pop_back();
        element_done();
        return ok;
    }
    void element_done() {
        if (!frames_.empty() && frames_.back().array) ++frames_.back().index;
    }

    const Reader& reader_;
    Dom dom_;
    std::vector<Frame> frames_;
};

// "[json.exception.parse_error.101] parse error at line 1, column 2: syntax
// error ..." -> "syntax error ..."; our own line/column replace nlohmann's.
std::string parse_problem(const std::string& what) {
    auto pos = what.find("syntax error");
    if (pos == std::string::npos) {
        pos = what.find("] ");
        pos = pos == std::string::npos ? 0 : pos + 2;
    }
    return what.substr(pos);
}

}  // namespace

Scene parse_scene(const std::string& json_text, const std::string& file_name_for_messages) {
    const Reader reader(file_name_for_messages);
    Json root;
    PathTracker tracker(reader, root);
    try {
        Json::sax_parse(json_text, &tracker);
    } catch (const Json::out_of_range& e) {
        // nlohmann refuses literals like 1e400 ("number overflow parsing '1e400'").
        std::string what = e.what();
        const auto open = what.find('\''), close = what.rfind('\'');
        const std::string literal = open < close && close != std::string::npos ? what.substr(open + 1, close - open - 1) : "";
        reader.fail(tracker.current_path(), "must be finite, got " + (literal.empty() ? what : literal) + " (overflows a double)");
    } catch (const Json::parse_error& e) {
        // e.byte counts characters read, so the offending one is at e.byte - 1.
        const std::size_t end = std::min<std::size_t>(e.byte == 0 ? 0 : e.byte - 1, json_text.size());
        std::size_t line = 1, line_start = 0;
        for (std::size_t i = 0; i < end; ++i) {
            if (json_text[i] == '\n') {
                ++line;
                line_start = i + 1;
            }
        }
        std::string problem = parse_problem(e.what());
        std::replace(problem.begin(), problem.end(), '\n', ' ');
        throw SceneError(file_name_for_messages + ": line " + std::to_string(line) + ", column " +
                         std::to_string(end - line_start + 1) + ": " + problem);
    }
    return reader.scene(root);
}

Scene load_scene(const std::string& path) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) throw SceneError(path + ": cannot open: " + std::strerror(errno));
    std::error_code ec;
    if (const std::uintmax_t size = std::filesystem::file_size(path, ec); !ec && size > kMaxSceneFileBytes) {
        std::fclose(f);
        throw SceneError(path + ": file too large: " + std::to_string(size) + " bytes (limit " +
                         std::to_string(kMaxSceneFileBytes) + ")");
    }
    std::string text;
    char buf[1 << 16];
    std::size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) text.append(buf, n);
    const bool failed = std::ferror(f) != 0;
    const int err = errno;  // fopen succeeds on a directory; the read fails with EISDIR
    std::fclose(f);
    if (failed) throw SceneError(path + ": cannot read: " + std::strerror(err));
    return parse_scene(text, path);
}

}  // namespace octray
