// tools/scene_loader.cpp — validate scene JSON and build an octray::Scene.
#include "scene_loader.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>
#include <set>
#include <utility>
#include <vector>

namespace octray {
namespace {

// ordered_json keeps the materials in file order: material index = position.
using Json = nlohmann::ordered_json;
using Names = std::vector<std::string>;

// Relative tolerances for "degenerate": sines of angles this small make the
// camera basis, a rectangle or a triangle numerically meaningless.
constexpr double kParallelSine = 1e-6;
constexpr double kDegenerateSine = 1e-9;

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

// Shortest decimal that reads back as the same double, so "got 0.1" is not
// "got 0.10000000000000001".
std::string format_number(double d) {
    if (std::isinf(d)) return d > 0 ? "inf" : "-inf";
    if (std::isnan(d)) return "nan";
    char buf[40];
    if (d == std::floor(d) && std::fabs(d) < 1e15) {  // integers as such: "180", not "1.8e+02"
        std::snprintf(buf, sizeof buf, "%.0f", d);
        return buf;
    }
    for (int precision = 1; precision <= 17; ++precision) {
        std::snprintf(buf, sizeof buf, "%.*g", precision, d);
        if (std::strtod(buf, nullptr) == d) break;
    }
    return buf;
}

std::string describe(const Json& v) {
    switch (v.type()) {
        case Json::value_t::null: return "null";
        case Json::value_t::boolean: return v.get<bool>() ? "true" : "false";
        case Json::value_t::string: return "a string (\"" + v.get<std::string>() + "\")";
        case Json::value_t::array: return "an array of " + std::to_string(v.size());
        case Json::value_t::object: return "an object";
        default: return v.is_number() ? format_number(v.get<double>()) : v.type_name();
    }
}

// Scale-free normalization: dividing by the largest component first keeps the
// squared length from overflowing or underflowing.
std::optional<Vec3d> normalized(const Vec3d& v) {
    const double m = std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
    if (!(m > 0) || !std::isfinite(m)) return std::nullopt;
    const Vec3d s{v.x / m, v.y / m, v.z / m};
    const double len = std::sqrt(dot(s, s));
    return Vec3d{s.x / len, s.y / len, s.z / len};
}

double length(const Vec3d& v) { return std::sqrt(dot(v, v)); }

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

    double number(const Json& v, const std::string& path) const {
        if (!v.is_number()) fail(path, "must be a number, got " + describe(v));
        const double d = v.get<double>();
        if (!std::isfinite(d)) fail(path, "must be finite, got " + format_number(d));
        return d;
    }

    double positive(const Json& v, const std::string& path) const {
        const double d = number(v, path);
        if (!(d > 0)) fail(path, "must be > 0, got " + format_number(d));
        return d;
    }

    double non_negative(const Json& v, const std::string& path) const {
        const double d = number(v, path);
        if (d < 0) fail(path, "must be >= 0, got " + format_number(d));
        return d;
    }

    int integer_in(const Json& v, const std::string& path, int lo, int hi) const {
        const double d = number(v, path);
        if (d != std::floor(d)) fail(path, "must be an integer, got " + format_number(d));
        if (d < lo || d > hi)
            fail(path, "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + format_number(d));
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

    Vec3d color(const Json& v, const std::string& path, double max = INFINITY) const {
        const Vec3d c = vec3(v, path);
        const double comps[3] = {c.x, c.y, c.z};
        for (std::size_t i = 0; i < 3; ++i) {
            if (comps[i] < 0) fail(element(path, i), "colour components must be >= 0, got " + format_number(comps[i]));
            if (comps[i] > max)
                fail(element(path, i), "colour components must be <= " + format_number(max) + ", got " + format_number(comps[i]));
        }
        return c;
    }

    Vec3d direction(const Json& v, const std::string& path) const {
        const auto n = normalized(vec3(v, path));
        if (!n) fail(path, "must not be zero-length");
        return *n;
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
        cam.up = direction(req("up"), member(path, "up"));
        if (pinhole) {
            cam.fov_y = number(req("fov_y"), member(path, "fov_y"));
            if (!(cam.fov_y > 0 && cam.fov_y < 180))
                fail(member(path, "fov_y"), "must be in (0, 180) degrees, got " + format_number(cam.fov_y));
        } else {
            cam.height_world = positive(req("height_world"), member(path, "height_world"));
        }
        constexpr int kMaxSize = 16384;
        cam.width = integer_in(req("width"), member(path, "width"), 1, kMaxSize);
        cam.height = integer_in(req("height"), member(path, "height"), 1, kMaxSize);

        const Vec3d view = cam.eye - cam.look_at;
        if (view.x == 0 && view.y == 0 && view.z == 0) fail(member(path, "look_at"), "must differ from eye");
        const auto w = normalized(view);
        if (!w) fail(member(path, "look_at"), "eye - look_at overflows (coordinates too large)");
        if (length(cross(cam.up, *w)) < kParallelSine)
            fail(member(path, "up"), "is parallel to the view direction (eye - look_at)");
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
            m.ka = non_negative(required(item.value(), mpath, "ka", what), member(mpath, "ka"));
            m.kd = non_negative(required(item.value(), mpath, "kd", what), member(mpath, "kd"));
            m.cd = color(required(item.value(), mpath, "cd", what), member(mpath, "cd"));
            out.push_back(std::move(m));
        }
        return out;
    }

    AmbientLight ambient(const Json& j, const std::string& path) const {
        expect_object(j, path);
        reject_unknown(j, path, "ambient", {"color", "ls"});
        AmbientLight a;
        if (auto* c = optional(j, "color")) a.color = color(*c, member(path, "color"));
        if (auto* ls = optional(j, "ls")) a.ls = non_negative(*ls, member(path, "ls"));
        return a;
    }

    void lights(const Json& j, const std::string& path, Scene& scene) const {
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
            if (auto* c = optional(l, "color")) color_v = color(*c, member(lpath, "color"));
            if (auto* v = optional(l, "ls")) ls = non_negative(*v, member(lpath, "ls"));
            if (auto* v = optional(l, "shadows")) shadows = boolean(*v, member(lpath, "shadows"));
            if (directional) {
                DirectionalLight d;
                d.direction = direction(required(l, lpath, "direction", what), member(lpath, "direction"));
                d.color = color_v;
                d.ls = ls;
                d.shadows = shadows;
                scene.directional_lights.push_back(d);
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
            }
        }
    }

    Shape shape(const Json& o, const std::string& path, PrimitiveType type) const {
        const std::string what = std::string("a ") + primitive_type_name(type);
        auto req = [&](const char* key) -> const Json& { return required(o, path, key, what); };
        auto point = [&](const char* key) { return vec3(req(key), member(path, key)); };
        auto dir = [&](const char* key) { return direction(req(key), member(path, key)); };
        auto radius = [&] { return positive(req("radius"), member(path, "radius")); };
        switch (type) {
            case PrimitiveType::sphere: {
                Sphere s;
                s.center = point("center");
                s.radius = radius();
                return s;
            }
            case PrimitiveType::plane: return Plane{point("point"), dir("normal")};
            case PrimitiveType::disk: {
                Disk d;
                d.center = point("center");
                d.normal = dir("normal");
                d.radius = radius();
                return d;
            }
            case PrimitiveType::rectangle: {
                Rectangle r{point("corner"), point("a"), point("b")};
                const auto a = normalized(r.a), b = normalized(r.b);
                if (!a) fail(member(path, "a"), "degenerate rectangle: a must not be zero-length");
                if (!b) fail(member(path, "b"), "degenerate rectangle: b must not be zero-length");
                if (length(cross(*a, *b)) < kDegenerateSine)
                    fail(path, "degenerate rectangle: a and b are parallel (|a x b| ~ 0 relative to |a||b|)");
                return r;
            }
            case PrimitiveType::box: {
                Box b{point("min"), point("max")};
                const double lo[3] = {b.min.x, b.min.y, b.min.z}, hi[3] = {b.max.x, b.max.y, b.max.z};
                for (int axis = 0; axis < 3; ++axis) {
                    if (!(lo[axis] < hi[axis])) {
                        const std::string a(1, "xyz"[axis]);
                        fail(path, "degenerate box: min." + a + " = " + format_number(lo[axis]) + " is not < max." + a +
                                       " = " + format_number(hi[axis]));
                    }
                }
                return b;
            }
            case PrimitiveType::triangle: {
                const std::string vpath = member(path, "vertices");
                const Json& vs = req("vertices");
                if (!vs.is_array() || vs.size() != 3)
                    fail(vpath, "must be an array of 3 points ([x,y,z]), got " + describe(vs));
                Triangle t{vec3(vs[0], element(vpath, 0)), vec3(vs[1], element(vpath, 1)), vec3(vs[2], element(vpath, 2))};
                check_triangle(t, vpath);
                return t;
            }
        }
        fail(path, "internal error: unhandled primitive type");
    }

    // Zero area relative to the longest edge: collinear or coincident vertices.
    void check_triangle(const Triangle& t, const std::string& path) const {
        Vec3d e[3] = {t.v1 - t.v0, t.v2 - t.v0, t.v2 - t.v1};
        double m = 0;
        for (const auto& v : e) m = std::max({m, std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
        if (!std::isfinite(m)) fail(path, "vertex differences overflow (coordinates too large)");
        if (m > 0) {
            for (auto& v : e) v = Vec3d{v.x / m, v.y / m, v.z / m};  // scale-free from here on
            const double longest2 = std::max({dot(e[0], e[0]), dot(e[1], e[1]), dot(e[2], e[2])});
            if (length(cross(e[0], e[1])) >= kDegenerateSine * longest2) return;
        }
        fail(path, "degenerate triangle: zero area relative to its edge lengths (collinear or coincident vertices)");
    }

    std::vector<Object> objects(const Json& j, const std::string& path, const std::vector<Material>& mats) const {
        if (!j.is_array()) fail(path, "must be an array, got " + describe(j));
        static const std::vector<Names> fields{
            {"type", "center", "radius", "material"},         {"type", "point", "normal", "material"},
            {"type", "center", "normal", "radius", "material"}, {"type", "corner", "a", "b", "material"},
            {"type", "min", "max", "material"},               {"type", "vertices", "material"}};
        Names material_names;
        for (const auto& m : mats) material_names.push_back(m.name);

        std::vector<Object> out;
        for (std::size_t i = 0; i < j.size(); ++i) {
            const Json& o = j[i];
            const std::string opath = element(path, i);
            const auto type = static_cast<PrimitiveType>(type_of(o, opath, "object", names_of(kPrimitiveTypeNames)));
            const std::string what = std::string("a ") + primitive_type_name(type);
            reject_unknown(o, opath, what, fields[static_cast<std::size_t>(type)]);
            Object obj;
            obj.shape = shape(o, opath, type);
            const std::string mpath = member(opath, "material");
            const std::string name = string(required(o, opath, "material", what), mpath);
            auto it = std::find(material_names.begin(), material_names.end(), name);
            if (it == material_names.end())
                fail(mpath, "unknown material \"" + name + "\" (" +
                                (material_names.empty() ? std::string("no materials are defined")
                                                        : "defined: " + join(material_names)) +
                                ")");
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
        // clamp_color is a display colour, written as is: it must already be in [0, 1].
        if (auto* v = optional(j, "clamp_color")) r.clamp_color = color(*v, member(path, "clamp_color"), 1.0);
        if (auto* v = optional(j, "gamma")) r.gamma = positive(*v, member(path, "gamma"));
        return r;
    }

    Scene scene(const Json& root) const {
        expect_object(root, "");
        reject_unknown(root, "", "a scene",
                       {"camera", "background", "ambient", "lights", "materials", "objects", "render"});
        Scene s;
        s.camera = camera(required(root, "", "camera", "a scene"), "camera");
        if (auto* v = optional(root, "background")) s.background = color(*v, "background");
        if (auto* v = optional(root, "ambient")) s.ambient = ambient(*v, "ambient");
        if (auto* v = optional(root, "lights")) lights(*v, "lights", s);
        s.materials = materials(required(root, "", "materials", "a scene"), "materials");
        s.objects = objects(required(root, "", "objects", "a scene"), "objects", s.materials);
        if (auto* v = optional(root, "render")) s.render = render(*v, "render");
        return s;
    }

private:
    std::string file_;
};

// Parser callback that tracks the JSON path being parsed: nlohmann keeps the
// last of duplicate keys without a word, so a repeated key is rejected here,
// and a number that overflows a double is reported at its path.
class PathTracker {
public:
    explicit PathTracker(const Reader& reader) : reader_(reader) {}

    bool operator()(int /*depth*/, nlohmann::json::parse_event_t event, Json& parsed) {
        using E = nlohmann::json::parse_event_t;
        switch (event) {
            case E::object_start: frames_.push_back({false, 0, {}, {}}); break;
            case E::array_start: frames_.push_back({true, 0, {}, {}}); break;
            case E::key: {
                Frame& top = frames_.back();
                top.key = parsed.get<std::string>();
                if (!top.keys.insert(top.key).second) reader_.fail(current_path(), "duplicate field");
                break;
            }
            case E::object_end:
            case E::array_end:
                frames_.pop_back();
                element_done();
                break;
            case E::value: element_done(); break;
        }
        return true;
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

    void element_done() {
        if (!frames_.empty() && frames_.back().array) ++frames_.back().index;
    }

    const Reader& reader_;
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
    PathTracker tracker(reader);
    try {
        root = Json::parse(json_text, [&tracker](int depth, nlohmann::json::parse_event_t event, Json& parsed) {
            return tracker(depth, event, parsed);
        });
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
