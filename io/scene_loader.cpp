// io/scene_loader.cpp — read scene JSON into an octray::Scene.
//
// The JSON's shape (types, required and unknown fields, names of types,
// materials and enums) is checked here; value ranges, finiteness and
// degenerate geometry are octray::validate()'s (compile/validate.cpp), the one
// set of rules a scene built in code meets too. Its message is reported at the
// JSON path of the offending value.
#include "scene_loader.hpp"

#include "scene_reader.hpp"

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
namespace scene_json {

std::string SourceMap::json_path(const std::string& scene_path, const Scene& scene) const {
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
    // Scene::objects leaves the meshes out: its index k is the file's only
    // when no mesh comes before it.
    if (head == "objects" && i < object.size()) return element("objects", object[i]) + rest;
    return scene_path;  // camera, background, ambient, render: the same in both
}

namespace {

// docs/scene-format.md: the loader stores directions normalized (every path would
// normalize them the same way anyway: scene.hpp, unit_direction).
void normalize_directions(Scene& s) {
    s.camera.up = unit_direction(s.camera.up);
    for (DirectionalLight& l : s.directional_lights) l.direction = unit_direction(l.direction);
    for (Object& o : s.objects) {
        if (Plane* p = std::get_if<Plane>(&o.shape)) p->normal = unit_direction(p->normal);
        if (Disk* d = std::get_if<Disk>(&o.shape)) d->normal = unit_direction(d->normal);
    }
}

}  // namespace

Camera Reader::camera(const Json& j, const std::string& path) const {
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

std::vector<Material> Reader::materials(const Json& j, const std::string& path) const {
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

AmbientLight Reader::ambient(const Json& j, const std::string& path) const {
    expect_object(j, path);
    reject_unknown(j, path, "ambient", {"color", "ls", "occlusion"});
    AmbientLight a;
    if (auto* c = optional(j, "color")) a.color = vec3(*c, member(path, "color"));
    if (auto* ls = optional(j, "ls")) a.ls = number(*ls, member(path, "ls"));
    return a;
}

AmbientOcclusion Reader::occlusion(const Json& j, const std::string& path) const {
    expect_object(j, path);
    reject_unknown(j, path, "occlusion", {"samples", "distance", "min_amount"});
    AmbientOcclusion o;
    if (auto* v = optional(j, "samples")) o.samples = integer(*v, member(path, "samples"));
    if (auto* v = optional(j, "distance")) o.distance = number(*v, member(path, "distance"));
    if (auto* v = optional(j, "min_amount")) o.min_amount = number(*v, member(path, "min_amount"));
    return o;
}

void Reader::lights(const Json& j, const std::string& path, Scene& scene, SourceMap& source) const {
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

RenderSettings Reader::render(const Json& j, const std::string& path) const {
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

Scene Reader::scene(const Json& root, SceneSources* sources) const {
    expect_object(root, "");
    reject_unknown(root, "", "a scene",
                   {"camera", "background", "ambient", "lights", "materials", "objects", "render"});
    Scene s;
    SourceMap source;
    // A geometry-only scene may leave out the camera and the materials; the
    // Scene keeps its defaults (Camera{}, one Material{}) for compile().
    auto part = [&](const char* key) { return geometry_only_ ? optional(root, key) : &required(root, "", key, "a scene"); };
    const Json* camera_json = part("camera");
    if (camera_json) s.camera = camera(*camera_json, "camera");
    if (auto* v = optional(root, "background")) s.background = vec3(*v, "background");
    if (auto* v = optional(root, "ambient")) {
        s.ambient = ambient(*v, "ambient");
        if (auto* o = optional(*v, "occlusion")) s.ambient_occlusion = occlusion(*o, "ambient.occlusion");
    }
    if (auto* v = optional(root, "lights")) lights(*v, "lights", s, source);
    const Json* materials_json = part("materials");
    if (materials_json) s.materials = materials(*materials_json, "materials");
    s.objects = objects(required(root, "", "objects", "a scene"), "objects", materials_json ? &s.materials : nullptr,
                        s.meshes, source);
    if (!materials_json) s.materials.push_back(Material{});
    if (auto* v = optional(root, "render")) s.render = render(*v, "render");
    // The values: the rules every scene meets, stated once (validate()).
    try {
        validate(s);
    } catch (const InvalidScene& e) {
        fail(source.json_path(e.path(), s), e.problem());
    }
    normalize_directions(s);
    if (sources) {
        sources->camera = camera_json != nullptr;
        sources->materials = materials_json != nullptr;
        sources->objects = std::move(source.object);
        sources->meshes = std::move(source.mesh);
        sources->mesh_faces = std::move(source.faces);
    }
    return s;
}

}  // namespace scene_json

namespace {

using namespace scene_json;

// A SAX handler that builds the document with nlohmann's own DOM builder and
// tracks the JSON path being parsed: nlohmann keeps the last of duplicate keys
// without a word, so a repeated key is rejected here, and a number that
// overflows a double is reported at its path. (The callback parser does the
// same with a per-event callback, but its cost grows faster than the file:
// docs/history/performance-2026.md, scale.)
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

namespace {

Scene parse_with(const Reader& reader, const std::string& json_text, const std::string& file_name_for_messages,
                 SceneSources* sources = nullptr) {
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
        throw SceneError((file_name_for_messages.empty() ? "" : file_name_for_messages + ": ") + "line " +
                         std::to_string(line) + ", column " +
                         std::to_string(end - line_start + 1) + ": " + problem);
    }
    return reader.scene(root, sources);
}

}  // namespace

Scene parse_scene(const std::string& json_text, const std::string& file_name_for_messages) {
    return parse_with(Reader(file_name_for_messages), json_text, file_name_for_messages);
}

Scene parse_scene(const std::string& json_text, const std::string& name_for_messages, const std::string& base_dir,
                  const std::map<std::size_t, MeshArrays>& arrays, const ParseOptions& options) {
    return parse_with(Reader(name_for_messages, base_dir, &arrays, options.geometry_only), json_text,
                      name_for_messages, options.sources);
}

Scene load_scene(const std::string& path) { return load_scene(path, nullptr); }

Scene load_scene(const std::string& path, SceneSources* sources) {
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
    return parse_with(Reader(path), text, path, sources);
}

}  // namespace octray
