// One set of scene rules: for every rule of validate(), a
// scene built in code and the same scene written as JSON are accepted or
// rejected alike, and a rejection names the same field — validate()'s Scene
// path in code, the file's JSON path from the loader — with the same problem.
//
// Each row changes one value of a valid scene to one side of a rule (both
// sides of every threshold). The JSON is written from the changed Scene
// itself, numbers with 17 significant digits (they read back as the same
// doubles), so the two sides differ only in how they reach validate().
#include "scene_loader.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <string>
#include <vector>

using namespace octray;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A valid scene using every kind of value the rules speak of.
Scene base_scene() {
    Scene s;
    s.camera.eye = {0, 1, 6};
    s.camera.width = 64;
    s.camera.height = 48;
    s.background = {0.1, 0.2, 0.3};
    s.ambient = AmbientLight{{1, 0.5, 0.25}, 0.75};
    s.directional_lights = {{{1, 2, 2}, {1, 1, 1}, 2.0, false}, {{0, 1, 0}, {1, 0.9, 0.8}, 1.0, true}};
    s.point_lights = {{{-3, 4, 3}, {1, 1, 1}, 3.0, Attenuation::inverse_square, true},
                      {{3, 4, 3}, {0.5, 0.5, 1}, 1.0, Attenuation::none, false}};
    s.materials = {{"red", 0.2, 0.6, {1, 0, 0}}, {"green", 0.3, 0.7, {0, 1, 0}}};
    s.objects = {{Sphere{{0, 0, 0}, 1}, 0},
                 {Plane{{0, -1, 0}, {0, 3, 0}}, 1},
                 {Disk{{2, 0, 0}, {0, 0, 2}, 0.5}, 0},
                 {Rectangle{{-2, -1, -1}, {1, 0, 0}, {0, 1, 0}}, 1},
                 {Box{{1, -1, 1}, {2, 0, 2}}, 0},
                 {Triangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, 1}};
    s.render = {ToneMap::saturate, {0, 1, 0}, 2.2};
    return s;
}

// JSON has no infinity: a literal that overflows a double stands for it.
std::string num(double d) {
    if (std::isinf(d)) return d > 0 ? "1e999" : "-1e999";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", d);
    return buf;
}
std::string vec(const Vec3d& v) { return "[" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + "]"; }
std::string field(const char* key, const std::string& value) { return std::string("\"") + key + "\": " + value; }
std::string str(const char* s) { return std::string("\"") + s + "\""; }

std::string shape_json(const Shape& shape) {
    return std::visit(
        [](const auto& s) {
            using S = std::decay_t<decltype(s)>;
            if constexpr (std::is_same_v<S, Sphere>) return field("center", vec(s.center)) + ", " + field("radius", num(s.radius));
            else if constexpr (std::is_same_v<S, Plane>) return field("point", vec(s.point)) + ", " + field("normal", vec(s.normal));
            else if constexpr (std::is_same_v<S, Disk>)
                return field("center", vec(s.center)) + ", " + field("normal", vec(s.normal)) + ", " + field("radius", num(s.radius));
            else if constexpr (std::is_same_v<S, Rectangle>)
                return field("corner", vec(s.corner)) + ", " + field("a", vec(s.a)) + ", " + field("b", vec(s.b));
            else if constexpr (std::is_same_v<S, Box>) return field("min", vec(s.min)) + ", " + field("max", vec(s.max));
            else return field("vertices", "[" + vec(s.v0) + ", " + vec(s.v1) + ", " + vec(s.v2) + "]");
        },
        shape);
}

// The scene as JSON. The file's one `lights` array holds the point and
// directional lights interleaved, point first: point_lights[0] is lights[0],
// directional_lights[0] lights[1], point_lights[1] lights[2],
// directional_lights[1] lights[3].
std::string to_json(const Scene& s) {
    const Camera& c = s.camera;
    std::string j = "{" + field("camera", "{" + field("type", str(camera_type_name(c.type))) + ", " +
                                              field("eye", vec(c.eye)) + ", " + field("look_at", vec(c.look_at)) + ", " +
                                              field("up", vec(c.up)) + ", " +
                                              (c.type == CameraType::pinhole ? field("fov_y", num(c.fov_y))
                                                                             : field("height_world", num(c.height_world))) +
                                              ", " + field("width", std::to_string(c.width)) + ", " +
                                              field("height", std::to_string(c.height)) + "}");
    j += ", " + field("background", vec(s.background));
    if (s.ambient) j += ", " + field("ambient", "{" + field("color", vec(s.ambient->color)) + ", " + field("ls", num(s.ambient->ls)) + "}");
    std::vector<std::string> lights;
    for (std::size_t i = 0; i < std::max(s.point_lights.size(), s.directional_lights.size()); ++i) {
        if (i < s.point_lights.size()) {
            const PointLight& l = s.point_lights[i];
            lights.push_back("{" + field("type", str("point")) + ", " + field("position", vec(l.position)) + ", " +
                             field("color", vec(l.color)) + ", " + field("ls", num(l.ls)) + ", " +
                             field("attenuation", str(attenuation_name(l.attenuation))) + ", " +
                             field("shadows", l.shadows ? "true" : "false") + "}");
        }
        if (i < s.directional_lights.size()) {
            const DirectionalLight& l = s.directional_lights[i];
            lights.push_back("{" + field("type", str("directional")) + ", " + field("direction", vec(l.direction)) + ", " +
                             field("color", vec(l.color)) + ", " + field("ls", num(l.ls)) + ", " +
                             field("shadows", l.shadows ? "true" : "false") + "}");
        }
    }
    std::string list;
    for (const std::string& l : lights) list += (list.empty() ? "" : ", ") + l;
    j += ", " + field("lights", "[" + list + "]");
    list.clear();
    for (const Material& m : s.materials)
        list += (list.empty() ? "" : ", ") + str(m.name.c_str()) + ": {" + field("type", str("matte")) + ", " +
                field("ka", num(m.ka)) + ", " + field("kd", num(m.kd)) + ", " + field("cd", vec(m.cd)) + "}";
    j += ", " + field("materials", "{" + list + "}");
    list.clear();
    for (const Object& o : s.objects)
        list += (list.empty() ? "" : ", ") + std::string("{") + field("type", str(primitive_type_name(primitive_type(o.shape)))) +
                ", " + shape_json(o.shape) + ", " + field("material", str(s.materials.at(std::size_t(o.material)).name.c_str())) + "}";
    j += ", " + field("objects", "[" + list + "]");
    j += ", " + field("render", "{" + field("tonemap", str(tonemap_name(s.render.tonemap))) + ", " +
                                    field("clamp_color", vec(s.render.clamp_color)) + ", " + field("gamma", num(s.render.gamma)) +
                                    "}");
    return j + "}";
}

struct Verdict {
    bool accepted = true;
    std::string path, problem;  // when rejected
};

Verdict in_code(const Scene& s) {
    try {
        validate(s);
    } catch (const InvalidScene& e) {
        return {false, e.path(), e.problem()};
    }
    return {};
}

Verdict in_json(const Scene& s) {
    const std::string prefix = "t.json: ";
    try {
        parse_scene(to_json(s), "t.json");
    } catch (const SceneError& e) {
        const std::string msg = e.what();
        REQUIRE(msg.rfind(prefix, 0) == 0);
        const std::size_t colon = msg.find(": ", prefix.size());
        REQUIRE(colon != std::string::npos);
        return {false, msg.substr(prefix.size(), colon - prefix.size()), msg.substr(colon + 2)};
    }
    return {};
}

// The rule a problem states, without the value found: the file spells an
// infinity 1e999 where the Scene holds inf.
std::string rule_of(const std::string& problem) { return problem.substr(0, problem.find(", got ")); }

// One side of one rule: `change` applied to the base scene; `scene_path` is
// where validate() must say the problem is ("" = accepted), `json_path` where
// the loader must say it is.
struct Row {
    const char* what;
    std::function<void(Scene&)> change;
    const char* scene_path;
    const char* json_path;
};

// up at angle ~`sine` from the view direction (0, 1, 6): the view's unit
// vector plus `sine` times a unit vector across it.
Vec3d up_at(double sine) { return unit_direction({0, 1, 6}) + Vec3d{sine, 0, 0}; }

const std::vector<Row>& rows() {
    static const std::vector<Row> table = {
        {"the base scene", [](Scene&) {}, "", ""},
        // camera
        {"eye infinite", [](Scene& s) { s.camera.eye.x = kInf; }, "camera.eye[0]", "camera.eye[0]"},
        {"up zero", [](Scene& s) { s.camera.up = {0, 0, 0}; }, "camera.up", "camera.up"},
        {"up of length 1e-300", [](Scene& s) { s.camera.up = {0, 1e-300, 0}; }, "", ""},
        {"up of length 1e300", [](Scene& s) { s.camera.up = {0, 1e300, 0}; }, "", ""},
        {"up 1e-7 from the view (sine < 1e-6)", [](Scene& s) { s.camera.up = up_at(1e-7); }, "camera.up", "camera.up"},
        {"up 1e-5 from the view", [](Scene& s) { s.camera.up = up_at(1e-5); }, "", ""},
        {"look_at at the eye", [](Scene& s) { s.camera.look_at = s.camera.eye; }, "camera.look_at", "camera.look_at"},
        {"eye - look_at overflows",
         [](Scene& s) { s.camera.eye = {1e308, 0, 0}, s.camera.look_at = {-1e308, 0, 0}; }, "camera.look_at", "camera.look_at"},
        {"fov_y 0", [](Scene& s) { s.camera.fov_y = 0; }, "camera.fov_y", "camera.fov_y"},
        {"fov_y 180", [](Scene& s) { s.camera.fov_y = 180; }, "camera.fov_y", "camera.fov_y"},
        {"fov_y 179.9", [](Scene& s) { s.camera.fov_y = 179.9; }, "", ""},
        {"orthographic, height_world 0",
         [](Scene& s) { s.camera.type = CameraType::orthographic, s.camera.height_world = 0; }, "camera.height_world",
         "camera.height_world"},
        {"orthographic, height_world 3.5",
         [](Scene& s) { s.camera.type = CameraType::orthographic, s.camera.height_world = 3.5; }, "", ""},
        {"width 0", [](Scene& s) { s.camera.width = 0; }, "camera.width", "camera.width"},
        {"width 16384", [](Scene& s) { s.camera.width = 16384; }, "", ""},
        {"height 16385", [](Scene& s) { s.camera.height = 16385; }, "camera.height", "camera.height"},
        // colours and intensities
        {"background below 0", [](Scene& s) { s.background.x = -0.1; }, "background[0]", "background[0]"},
        {"background above 1 (HDR)", [](Scene& s) { s.background.x = 5; }, "", ""},
        {"ambient ls below 0", [](Scene& s) { s.ambient->ls = -0.5; }, "ambient.ls", "ambient.ls"},
        {"ambient ls 0", [](Scene& s) { s.ambient->ls = 0; }, "", ""},
        {"ambient colour below 0", [](Scene& s) { s.ambient->color.y = -1; }, "ambient.color[1]", "ambient.color[1]"},
        // lights: validate's two arrays are the file's one
        {"directional light zero", [](Scene& s) { s.directional_lights[1].direction = {0, 0, 0}; },
         "directional_lights[1].direction", "lights[3].direction"},
        {"directional light of length 3e300", [](Scene& s) { s.directional_lights[1].direction = {1e300, 2e300, 2e300}; }, "",
         ""},
        {"directional ls below 0", [](Scene& s) { s.directional_lights[0].ls = -1; }, "directional_lights[0].ls",
         "lights[1].ls"},
        {"directional colour below 0", [](Scene& s) { s.directional_lights[1].color.z = -0.5; },
         "directional_lights[1].color[2]", "lights[3].color[2]"},
        {"point ls below 0", [](Scene& s) { s.point_lights[0].ls = -1; }, "point_lights[0].ls", "lights[0].ls"},
        {"point position infinite", [](Scene& s) { s.point_lights[1].position.y = -kInf; }, "point_lights[1].position[1]",
         "lights[2].position[1]"},
        {"point colour above 1 (HDR)", [](Scene& s) { s.point_lights[1].color = {8, 2, 1}; }, "", ""},
        // materials: validate's array is the file's object keyed by name
        {"ka below 0", [](Scene& s) { s.materials[1].ka = -0.1; }, "materials[1].ka", "materials.green.ka"},
        {"kd below 0", [](Scene& s) { s.materials[0].kd = -1; }, "materials[0].kd", "materials.red.kd"},
        {"kd 0", [](Scene& s) { s.materials[0].kd = 0; }, "", ""},
        {"cd below 0", [](Scene& s) { s.materials[1].cd.y = -1; }, "materials[1].cd[1]", "materials.green.cd[1]"},
        // objects (a material index out of range has no JSON form: the file names materials)
        {"sphere radius 0", [](Scene& s) { std::get<Sphere>(s.objects[0].shape).radius = 0; }, "objects[0].radius",
         "objects[0].radius"},
        {"sphere radius 1e-30", [](Scene& s) { std::get<Sphere>(s.objects[0].shape).radius = 1e-30; }, "", ""},
        {"sphere centre infinite", [](Scene& s) { std::get<Sphere>(s.objects[0].shape).center.z = kInf; },
         "objects[0].center[2]", "objects[0].center[2]"},
        {"plane normal zero", [](Scene& s) { std::get<Plane>(s.objects[1].shape).normal = {0, 0, 0}; }, "objects[1].normal",
         "objects[1].normal"},
        {"disk normal of length 1e-300", [](Scene& s) { std::get<Disk>(s.objects[2].shape).normal = {0, 0, 1e-300}; }, "",
         ""},
        {"disk radius below 0", [](Scene& s) { std::get<Disk>(s.objects[2].shape).radius = -0.5; }, "objects[2].radius",
         "objects[2].radius"},
        {"rectangle a zero", [](Scene& s) { std::get<Rectangle>(s.objects[3].shape).a = {0, 0, 0}; }, "objects[3].a",
         "objects[3].a"},
        {"rectangle a, b at sine 1e-10", [](Scene& s) { std::get<Rectangle>(s.objects[3].shape).b = {1, 1e-10, 0}; },
         "objects[3]", "objects[3]"},
        {"rectangle a, b at sine 1e-8", [](Scene& s) { std::get<Rectangle>(s.objects[3].shape).b = {1, 1e-8, 0}; }, "", ""},
        {"rectangle of size 1e-8", [](Scene& s) { std::get<Rectangle>(s.objects[3].shape) = {{0, 0, 0}, {1e-8, 0, 0}, {0, 1e-8, 1e-9}}; },
         "", ""},
        {"box flat in y", [](Scene& s) { std::get<Box>(s.objects[4].shape).max.y = -1; }, "objects[4]", "objects[4]"},
        {"triangle collinear", [](Scene& s) { std::get<Triangle>(s.objects[5].shape) = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}; },
         "objects[5]", "objects[5]"},
        // A right angle at v0 but a width of 1e-10 against a length of 1: zero area for the longest edge.
        {"triangle needle, right angle at v0",
         [](Scene& s) { std::get<Triangle>(s.objects[5].shape) = {{0, 0, 0}, {1, 0, 0}, {0, 1e-10, 0}}; }, "objects[5]",
         "objects[5]"},
        {"triangle of width 1e-8 against length 1",
         [](Scene& s) { std::get<Triangle>(s.objects[5].shape) = {{0, 0, 0}, {1, 0, 0}, {0, 1e-8, 0}}; }, "", ""},
        {"triangle of size 1e-9",
         [](Scene& s) { std::get<Triangle>(s.objects[5].shape) = {{0, 0, 0}, {1e-9, 0, 0}, {0, 1e-9, 0}}; }, "", ""},
        {"triangle vertex infinite", [](Scene& s) { std::get<Triangle>(s.objects[5].shape).v2.x = kInf; },
         "objects[5].vertices[2][0]", "objects[5].vertices[2][0]"},
        // render
        {"gamma 0", [](Scene& s) { s.render.gamma = 0; }, "render.gamma", "render.gamma"},
        {"gamma below 0", [](Scene& s) { s.render.gamma = -1; }, "render.gamma", "render.gamma"},
        {"clamp colour above 1 (a display colour)", [](Scene& s) { s.render.clamp_color.y = 2; }, "render.clamp_color[1]",
         "render.clamp_color[1]"},
        {"clamp colour 1", [](Scene& s) { s.render.clamp_color = {1, 1, 1}; }, "", ""},
    };
    return table;
}

}  // namespace

TEST_CASE("every rule: a scene built in code and the same scene in JSON are judged alike") {
    REQUIRE(rows().size() >= 40);
    int rejected = 0;
    for (const Row& row : rows()) {
        CAPTURE(row.what);
        Scene s = base_scene();
        row.change(s);
        const Verdict code = in_code(s), json = in_json(s);
        INFO("code: " << code.path << ": " << code.problem);
        INFO("json: " << json.path << ": " << json.problem);
        const bool reject = *row.scene_path != '\0';
        CHECK(code.accepted == !reject);
        CHECK(json.accepted == !reject);
        if (!reject) continue;
        ++rejected;
        CHECK(code.path == row.scene_path);
        CHECK(json.path == row.json_path);
        CHECK(rule_of(json.problem) == rule_of(code.problem));
        CHECK(!rule_of(code.problem).empty());
    }
    CHECK(rejected >= 30);
}

TEST_CASE("the JSON writer of this test round-trips the base scene") {
    // Guards the table above: were the writer to drop or alter a value, both
    // sides would no longer see the same scene.
    const Scene s = base_scene();
    const Scene back = parse_scene(to_json(s), "t.json");
    REQUIRE(back.directional_lights.size() == 2);
    REQUIRE(back.point_lights.size() == 2);
    REQUIRE(back.objects.size() == s.objects.size());
    CHECK(back.point_lights[0].position.x == s.point_lights[0].position.x);
    CHECK(back.point_lights[0].attenuation == Attenuation::inverse_square);
    CHECK(back.directional_lights[1].shadows);
    CHECK(back.materials[1].name == "green");
    CHECK(back.objects[5].material == 1);
    CHECK(std::get<Disk>(back.objects[2].shape).radius == 0.5);
    CHECK(back.render.gamma == 2.2);
    CHECK(back.render.tonemap == ToneMap::saturate);
    // Directions come back normalized (docs/scene-format.md), everything else as written.
    CHECK(std::get<Plane>(back.objects[1].shape).normal.y == 1.0);
    CHECK(back.directional_lights[0].direction.x == unit_direction({1, 2, 2}).x);
}

TEST_CASE("InvalidScene splits its message into path and problem") {
    const InvalidScene e("objects[3].radius", "must be > 0, got -1");
    CHECK(std::string(e.what()) == "objects[3].radius: must be > 0, got -1");
    CHECK(e.path() == "objects[3].radius");
    CHECK(e.problem() == "must be > 0, got -1");
    const std::invalid_argument& base = e;  // still what compile() was documented to throw
    CHECK(std::string(base.what()) == e.what());
}

TEST_CASE("the primitive limit counts objects and mesh triangles together") {
    Scene s = base_scene();
    const std::size_t triangles = kMaxPrimitives - s.objects.size() + 1;  // one primitive too many
    Mesh m;
    m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    m.indices.resize(3 * triangles);
    for (std::size_t t = 0; t < triangles; ++t) m.indices[3 * t] = 0, m.indices[3 * t + 1] = 1, m.indices[3 * t + 2] = 2;
    s.meshes.push_back(std::move(m));
    try {
        validate(s);
        FAIL("a scene over the primitive limit was accepted");
    } catch (const InvalidScene& e) {
        CHECK(e.path() == "objects");
        CHECK(e.problem() == "too many primitives: 16777216 objects and mesh triangles (limit 16777215)");
    }
    s.meshes[0].indices.resize(3 * (triangles - 1));  // exactly at the limit: valid
    CHECK_NOTHROW(validate(s));
}
