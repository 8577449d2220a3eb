// Scene loader: every shipped scene loads, defaults and normalization are
// applied, and each class of bad input is rejected with a one-line message
// "FILE: JSON_PATH: problem" naming the exact path.
#include "scene_loader.hpp"

#include <doctest/doctest.h>

#include "scene_files.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

using octray::parse_scene;
using octray::Scene;
using octray::SceneError;

namespace {

// A valid scene using every feature; bad inputs are single textual edits of it.
const std::string kBase = R"({
  "camera": {"type": "pinhole", "eye": [0, 1, 6], "look_at": [0, 0, 0], "up": [0, 2, 0],
             "fov_y": 45, "width": 64, "height": 48},
  "background": [0.1, 0.2, 0.3],
  "ambient": {"color": [1, 0.5, 0.25], "ls": 0.75},
  "lights": [
    {"type": "directional", "direction": [1, 2, 2], "color": [1, 1, 1], "ls": 2.0},
    {"type": "point", "position": [-3, 4, 3], "color": [1, 0.9, 0.8], "ls": 3.0,
     "attenuation": "inverse_square", "shadows": true}
  ],
  "materials": {
    "red": {"type": "matte", "ka": 0.2, "kd": 0.6, "cd": [1, 0, 0]},
    "green": {"type": "matte", "ka": 0.3, "kd": 0.7, "cd": [0, 1, 0]}
  },
  "objects": [
    {"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "red"},
    {"type": "plane", "point": [0, -1, 0], "normal": [0, 3, 0], "material": "green"},
    {"type": "disk", "center": [2, 0, 0], "normal": [0, 0, 2], "radius": 0.5, "material": "red"},
    {"type": "rectangle", "corner": [-2, -1, -1], "a": [1, 0, 0], "b": [0, 1, 0], "material": "green"},
    {"type": "box", "min": [1, -1, 1], "max": [2, 0, 2], "material": "red"},
    {"type": "triangle", "vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "material": "green"}
  ],
  "render": {"tonemap": "saturate", "clamp_color": [0, 1, 0], "gamma": 2.2}
})";

// Only the required parts: everything else takes its default.
const std::string kMinimal = R"({
  "camera": {"type": "pinhole", "eye": [0, 0, 5], "look_at": [0, 0, 0], "up": [0, 1, 0],
             "fov_y": 60, "width": 8, "height": 4},
  "materials": {},
  "objects": []
})";

// kBase with `from` (which must occur exactly once) replaced by `to`.
std::string edit(const std::string& from, const std::string& to, const std::string& text = kBase) {
    const auto pos = text.find(from);
    REQUIRE_MESSAGE(pos != std::string::npos, "edit target not found: " << from);
    REQUIRE_MESSAGE(text.find(from, pos + 1) == std::string::npos, "edit target not unique: " << from);
    return text.substr(0, pos) + to + text.substr(pos + from.size());
}

std::string load_error(const std::string& text) {
    try {
        parse_scene(text, "t.json");
    } catch (const SceneError& e) {
        const std::string msg = e.what();
        CHECK_MESSAGE(msg.find('\n') == std::string::npos, "message is not one line: " << msg);
        return msg;
    }
    FAIL("scene was accepted but should have been rejected");
    return {};
}

// The message starts with exactly "t.json: PATH: " and contains `problem`.
void expect_error(const std::string& text, const std::string& path, const std::string& problem) {
    const std::string msg = load_error(text);
    INFO("message: " << msg);
    CHECK(msg.rfind("t.json: " + path + ": ", 0) == 0);
    CHECK(msg.find(problem) != std::string::npos);
}

bool near(const octray::Vec3d& a, const octray::Vec3d& b, double tol = 1e-15) {
    return std::fabs(a.x - b.x) <= tol && std::fabs(a.y - b.y) <= tol && std::fabs(a.z - b.z) <= tol;
}

}  // namespace

TEST_CASE("every scene in scenes/ loads") {
    int count = 0;
    for (const std::string& file : scene_files()) {
        INFO(file);
        CHECK_NOTHROW(octray::load_scene(file));
        ++count;
    }
    CHECK(count >= 16);
}

TEST_CASE("default.json shows every feature the README picture promises") {
    const Scene s = octray::load_scene(OCTRAY_SOURCE_DIR "/scenes/default.json");
    bool has[octray::kPrimitiveTypeCount] = {};
    for (const auto& o : s.objects) has[static_cast<int>(octray::primitive_type(o.shape))] = true;
    for (int t = 0; t < octray::kPrimitiveTypeCount; ++t) CHECK_MESSAGE(has[t], octray::primitive_type_name(static_cast<octray::PrimitiveType>(t)));
    CHECK(s.ambient.has_value());
    CHECK(s.directional_lights.size() >= 2);
    CHECK(s.point_lights.size() >= 2);
    int attenuated = 0;
    for (const auto& p : s.point_lights) attenuated += p.attenuation == octray::Attenuation::inverse_square;
    CHECK(attenuated >= 1);
    CHECK(s.camera.type == octray::CameraType::pinhole);
    CHECK(s.camera.width == 320);
    CHECK(s.camera.height == 240);
}

TEST_CASE("a full scene is read field by field") {
    const Scene s = parse_scene(kBase, "t.json");
    CHECK(s.camera.eye.z == 6);
    CHECK(s.camera.fov_y == 45);
    CHECK(s.camera.width == 64);
    CHECK(s.camera.height == 48);
    CHECK(near(s.background, {0.1, 0.2, 0.3}));
    REQUIRE(s.ambient.has_value());
    CHECK(near(s.ambient->color, {1, 0.5, 0.25}));
    CHECK(s.ambient->ls == 0.75);
    REQUIRE(s.directional_lights.size() == 1);
    CHECK(s.directional_lights[0].ls == 2.0);
    CHECK_FALSE(s.directional_lights[0].shadows);
    REQUIRE(s.point_lights.size() == 1);
    CHECK(near(s.point_lights[0].position, {-3, 4, 3}));
    CHECK(s.point_lights[0].attenuation == octray::Attenuation::inverse_square);
    CHECK(s.point_lights[0].shadows);
    REQUIRE(s.materials.size() == 2);
    CHECK(s.materials[1].name == "green");
    CHECK(s.materials[1].ka == 0.3);
    CHECK(s.materials[1].kd == 0.7);
    REQUIRE(s.objects.size() == 6);
    for (int i = 0; i < 6; ++i) CHECK(static_cast<int>(octray::primitive_type(s.objects[i].shape)) == i);
    CHECK(s.objects[0].material == 0);
    CHECK(s.objects[1].material == 1);
    CHECK(std::get<octray::Sphere>(s.objects[0].shape).radius == 1);
    CHECK(std::get<octray::Disk>(s.objects[2].shape).radius == 0.5);
    CHECK(near(std::get<octray::Box>(s.objects[4].shape).max, {2, 0, 2}));
    CHECK(near(std::get<octray::Triangle>(s.objects[5].shape).v2, {0, 1, 0}));
    CHECK(s.render.tonemap == octray::ToneMap::saturate);
    CHECK(near(s.render.clamp_color, {0, 1, 0}));
    CHECK(s.render.gamma == 2.2);
}

TEST_CASE("material indices follow the file order, not name order") {
    const Scene s = parse_scene(edit(R"("materials": {})",
                                     R"("materials": {"zeta": {"type": "matte", "ka": 0, "kd": 1, "cd": [1, 1, 1]},
                                                      "alpha": {"type": "matte", "ka": 0, "kd": 1, "cd": [1, 1, 1]}})",
                                     edit(R"("objects": [])",
                                          R"("objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "alpha"}])",
                                          kMinimal)),
                                "t.json");
    REQUIRE(s.materials.size() == 2);
    CHECK(s.materials[0].name == "zeta");
    CHECK(s.materials[1].name == "alpha");
    CHECK(s.objects[0].material == 1);
}

TEST_CASE("defaults: absent optional parts take docs/scene-format.md's values") {
    const Scene s = parse_scene(kMinimal, "t.json");
    CHECK(near(s.background, {0, 0, 0}));
    CHECK_FALSE(s.ambient.has_value());
    CHECK(s.directional_lights.empty());
    CHECK(s.point_lights.empty());
    CHECK(s.render.tonemap == octray::ToneMap::max_to_one);
    CHECK(near(s.render.clamp_color, {1, 0, 0}));
    CHECK(s.render.gamma == 1.0);

    // Lights and ambient with only their required fields.
    const Scene l = parse_scene(edit(R"("materials": {})", R"("ambient": {},
        "lights": [{"type": "directional", "direction": [0, 1, 0]}, {"type": "point", "position": [1, 2, 3]}],
        "render": {},
        "materials": {})", kMinimal), "t.json");
    REQUIRE(l.ambient.has_value());
    CHECK(near(l.ambient->color, {1, 1, 1}));
    CHECK(l.ambient->ls == 1.0);
    REQUIRE(l.directional_lights.size() == 1);
    CHECK(near(l.directional_lights[0].color, {1, 1, 1}));
    CHECK(l.directional_lights[0].ls == 1.0);
    CHECK_FALSE(l.directional_lights[0].shadows);
    REQUIRE(l.point_lights.size() == 1);
    CHECK(l.point_lights[0].attenuation == octray::Attenuation::none);
    CHECK_FALSE(l.point_lights[0].shadows);
    CHECK(l.point_lights[0].ls == 1.0);
    CHECK(l.render.tonemap == octray::ToneMap::max_to_one);
}

TEST_CASE("directions, normals and up are normalized") {
    const Scene s = parse_scene(kBase, "t.json");
    CHECK(near(s.camera.up, {0, 1, 0}));
    CHECK(near(s.directional_lights[0].direction, {1.0 / 3, 2.0 / 3, 2.0 / 3}));
    CHECK(near(std::get<octray::Plane>(s.objects[1].shape).normal, {0, 1, 0}));
    CHECK(near(std::get<octray::Disk>(s.objects[2].shape).normal, {0, 0, 1}));
    // Huge and tiny components normalize without overflow or underflow.
    const Scene big = parse_scene(edit(R"("direction": [1, 2, 2])", R"("direction": [1e300, 2e300, 2e300])"), "t.json");
    CHECK(near(big.directional_lights[0].direction, {1.0 / 3, 2.0 / 3, 2.0 / 3}));
    const Scene tiny = parse_scene(edit(R"("direction": [1, 2, 2])", R"("direction": [1e-300, 2e-300, 2e-300])"), "t.json");
    CHECK(near(tiny.directional_lights[0].direction, {1.0 / 3, 2.0 / 3, 2.0 / 3}));
}

TEST_CASE("syntax errors report line and column") {
    const std::string msg = load_error("{\n  \"a\": 1,\n  \"b\": ]\n}");
    INFO(msg);
    CHECK(msg.rfind("t.json: line 3, column 8: syntax error", 0) == 0);

    const std::string empty = load_error("");
    INFO(empty);
    CHECK(empty.rfind("t.json: line 1, column 1: syntax error", 0) == 0);

    const std::string trailing = load_error(kBase + "\n x");
    INFO(trailing);
    CHECK(trailing.find("syntax error") != std::string::npos);
    CHECK(trailing.find("line 25, column 2") != std::string::npos);
}

TEST_CASE("missing required fields are named") {
    expect_error(edit(R"("fov_y": 45, )", ""), "camera.fov_y", "missing required field");
    expect_error(edit(R"("type": "pinhole", )", ""), "camera.type", "missing required field");
    expect_error(edit(R"("radius": 1, )", ""), "objects[0].radius", "missing required field of a sphere");
    expect_error(edit(R"(, "radius": 0.5)", ""), "objects[2].radius", "missing required field of a disk");
    expect_error(edit(R"(, "material": "red"},)" "\n" R"(    {"type": "plane")", R"(},)" "\n" R"(    {"type": "plane")"),
                 "objects[0].material", "missing required field");
    expect_error(edit(R"("direction": [1, 2, 2], )", ""), "lights[0].direction", "missing required field of a directional light");
    expect_error(edit(R"("position": [-3, 4, 3], )", ""), "lights[1].position", "missing required field of a point light");
    expect_error(edit(R"("ka": 0.2, )", ""), "materials.red.ka", "missing required field");
    expect_error(edit(R"("objects": [])", R"("objs": [])", kMinimal), "objs", "unknown field");
    expect_error(edit(R"(,
  "objects": [])", "", kMinimal), "objects", "missing required field");
    expect_error(edit(R"("materials": {},)", "", kMinimal), "materials", "missing required field");
    expect_error(edit(R"("type": "pinhole")", R"("type": "orthographic")"), "camera.fov_y", "unknown field");
    expect_error(edit(R"("fov_y": 45, )", "", edit(R"("type": "pinhole")", R"("type": "orthographic")")),
                 "camera.height_world", "missing required field of an orthographic camera");
}

TEST_CASE("wrong JSON types are rejected") {
    expect_error(edit(R"("eye": [0, 1, 6])", R"("eye": "origin")"), "camera.eye", "must be an array of 3 numbers, got a string");
    expect_error(edit(R"("eye": [0, 1, 6])", R"("eye": [0, 1])"), "camera.eye", "must be an array of 3 numbers, got an array of 2");
    expect_error(edit(R"("eye": [0, 1, 6])", R"("eye": [0, "1", 6])"), "camera.eye[1]", "must be a number, got a string");
    expect_error(edit(R"("width": 64)", R"("width": "64")"), "camera.width", "must be a number");
    expect_error(edit(R"("ls": 2.0)", R"("ls": true)"), "lights[0].ls", "must be a number, got true");
    expect_error(edit(R"("shadows": true)", R"("shadows": 1)"), "lights[1].shadows", "must be true or false, got 1");
    expect_error(edit(R"("material": "red"},)" "\n" R"(    {"type": "plane")", R"("material": 0},)" "\n" R"(    {"type": "plane")"),
                 "objects[0].material", "must be a string, got 0");
    expect_error(edit(R"("gamma": 2.2)", R"("gamma": null)"), "render.gamma", "must be a number, got null");
    expect_error(edit(R"("vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]])", R"("vertices": [[0, 0, 0], [1, 0, 0]])"),
                 "objects[5].vertices", "must be an array of 3 points");
    expect_error(edit(R"([0, 1, 0]], "material")", R"([0, 1]], "material")"), "objects[5].vertices[2]", "must be an array of 3 numbers");
    expect_error(edit(R"("objects": [])", R"("objects": {})", kMinimal), "objects", "must be an array, got an object");
    expect_error(edit(R"("materials": {})", R"("materials": [])", kMinimal), "materials", "must be an object, got an array of 0");
    expect_error(edit(R"("materials": {})", R"("lights": {}, "materials": {})", kMinimal), "lights", "must be an array");
    expect_error(edit(R"("objects": [])", R"("objects": [42])", kMinimal), "objects[0]", "must be an object, got 42");
    expect_error("[1, 2]", "(root)", "must be an object");
    expect_error(R"({"camera": 3, "materials": {}, "objects": []})", "camera", "must be an object, got 3");
}

TEST_CASE("unknown types list the allowed ones") {
    expect_error(edit(R"("type": "pinhole")", R"("type": "fisheye")"), "camera.type",
                 "unknown camera type \"fisheye\" (allowed: pinhole, orthographic)");
    expect_error(edit(R"("type": "directional")", R"("type": "spot")"), "lights[0].type",
                 "unknown light type \"spot\" (allowed: directional, point)");
    expect_error(edit(R"("red": {"type": "matte")", R"("red": {"type": "phong")"), "materials.red.type",
                 "unknown material type \"phong\" (allowed: matte)");
    expect_error(edit(R"("type": "box")", R"("type": "cone")"), "objects[4].type",
                 "unknown object type \"cone\" (allowed: sphere, plane, disk, rectangle, box, triangle, mesh)");
}

TEST_CASE("an unknown material name lists the defined ones") {
    expect_error(edit(R"("material": "red"},)" "\n" R"(    {"type": "plane")", R"("material": "blue"},)" "\n" R"(    {"type": "plane")"),
                 "objects[0].material", "unknown material \"blue\" (defined: red, green)");
    expect_error(edit(R"("objects": [])", R"("objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1, "material": "x"}])", kMinimal),
                 "objects[0].material", "no materials are defined");
}

TEST_CASE("unknown fields are rejected, not ignored") {
    expect_error(edit(R"("radius": 1,)", R"("raduis": 1,)"), "objects[0].raduis", "unknown field (a sphere has: type, center, radius, material)");
    expect_error(edit(R"("lights": [)", R"("lihgts": [)"), "lihgts", "unknown field");
    expect_error(edit(R"("gamma": 2.2)", R"("gama": 2.2)"), "render.gama", "unknown field (render has: tonemap, clamp_color, gamma)");
    expect_error(edit(R"("ls": 0.75})", R"("intensity": 0.75})"), "ambient.intensity", "unknown field");
    expect_error(edit(R"("cd": [1, 0, 0]})", R"("cd": [1, 0, 0], "ks": 0.5})"), "materials.red.ks", "unknown field");
    expect_error(edit(R"("ls": 2.0})", R"("ls": 2.0, "attenuation": "none"})"), "lights[0].attenuation",
                 "unknown field (a directional light has");
    expect_error(edit(R"("width": 64)", R"("widht": 64)"), "camera.widht", "unknown field");
}

TEST_CASE("duplicate fields are rejected") {
    expect_error(edit(R"("radius": 0.5)", R"("radius": 0.5, "radius": 2)"), "objects[2].radius", "duplicate field");
    expect_error(edit(R"("gamma": 2.2)", R"("gamma": 2.2, "gamma": 1)"), "render.gamma", "duplicate field");
}

TEST_CASE("zero-length directions are rejected") {
    expect_error(edit(R"("up": [0, 2, 0])", R"("up": [0, 0, 0])"), "camera.up", "must not be zero-length");
    expect_error(edit(R"("direction": [1, 2, 2])", R"("direction": [0, 0, 0])"), "lights[0].direction", "must not be zero-length");
    expect_error(edit(R"("normal": [0, 3, 0])", R"("normal": [0, 0, 0])"), "objects[1].normal", "must not be zero-length");
    expect_error(edit(R"("normal": [0, 0, 2])", R"("normal": [0, -0.0, 0])"), "objects[2].normal", "must not be zero-length");
}

TEST_CASE("camera: up parallel to the view direction, eye equal to look_at") {
    expect_error(edit(R"("up": [0, 2, 0])", R"("up": [0, -1, -6])"), "camera.up", "parallel to the view direction");
    expect_error(edit(R"("up": [0, 2, 0])", R"("up": [0, 1e-9, 1])", edit(R"("eye": [0, 1, 6])", R"("eye": [0, 0, 6])")),
                 "camera.up", "parallel");
    expect_error(edit(R"("look_at": [0, 0, 0])", R"("look_at": [0, 1, 6])"), "camera.look_at", "must differ from eye");
    // Not parallel, merely oblique: accepted.
    CHECK_NOTHROW(parse_scene(edit(R"("up": [0, 2, 0])", R"("up": [0, 1, 1])"), "t.json"));
}

TEST_CASE("non-positive radius") {
    expect_error(edit(R"("radius": 1,)", R"("radius": -1,)"), "objects[0].radius", "must be > 0, got -1");
    expect_error(edit(R"("radius": 0.5)", R"("radius": 0)"), "objects[2].radius", "must be > 0, got 0");
}

TEST_CASE("non-finite numbers (overflowing literals) are rejected") {
    expect_error(edit(R"("center": [0, 0, 0], "radius": 1,)", R"("center": [0, 1e400, 0], "radius": 1,)"),
                 "objects[0].center[1]", "must be finite, got 1e400");
    expect_error(edit(R"("ls": 3.0)", R"("ls": -1e999)"), "lights[1].ls", "must be finite, got -1e999");
    expect_error(edit(R"("fov_y": 45)", R"("fov_y": 1e309)"), "camera.fov_y", "must be finite");
}

TEST_CASE("degenerate rectangle") {
    // validate()'s wording (tests/test_packet.cpp pins "objects[0]: is degenerate" for a scene built in code).
    expect_error(edit(R"("b": [0, 1, 0])", R"("b": [-2, 0, 0])"), "objects[3]", "is degenerate: a and b are parallel");
    expect_error(edit(R"("b": [0, 1, 0])", R"("b": [1, 1e-12, 0])"), "objects[3]", "is degenerate");
    expect_error(edit(R"("a": [1, 0, 0])", R"("a": [0, 0, 0])"), "objects[3].a", "must not be zero-length");
    // Small is not degenerate: the test is relative to |a||b|.
    CHECK_NOTHROW(parse_scene(edit(R"("a": [1, 0, 0], "b": [0, 1, 0])", R"("a": [1e-8, 0, 0], "b": [0, 1e-8, 1e-9])"), "t.json"));
}

TEST_CASE("degenerate triangle") {
    const std::string tri = R"("vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0]])";
    expect_error(edit(tri, R"("vertices": [[0, 0, 0], [1, 1, 1], [2, 2, 2]])"), "objects[5]", "is degenerate: zero area");
    expect_error(edit(tri, R"("vertices": [[1, 2, 3], [1, 2, 3], [0, 1, 0]])"), "objects[5]", "is degenerate: zero area");
    expect_error(edit(tri, R"("vertices": [[5, 5, 5], [5, 5, 5], [5, 5, 5]])"), "objects[5]", "zero area");
    // A needle whose width is 1e-12 of its length is degenerate ...
    expect_error(edit(tri, R"("vertices": [[0, 0, 0], [1, 0, 0], [0.5, 1e-12, 0]])"), "objects[5]", "is degenerate: zero area");
    // ... but a tiny well-shaped triangle is fine.
    CHECK_NOTHROW(parse_scene(edit(tri, R"("vertices": [[0, 0, 0], [1e-9, 0, 0], [0, 1e-9, 0]])"), "t.json"));
}

TEST_CASE("degenerate box") {
    expect_error(edit(R"("max": [2, 0, 2])", R"("max": [2, -1, 2])"), "objects[4]", "is degenerate: min.y = -1 is not < max.y = -1");
    expect_error(edit(R"("max": [2, 0, 2])", R"("max": [0, 0, 2])"), "objects[4]", "is degenerate: min.x = 1 is not < max.x = 0");
}

TEST_CASE("image size out of range") {
    expect_error(edit(R"("width": 64)", R"("width": 0)"), "camera.width", "must be in [1, 16384], got 0");
    expect_error(edit(R"("height": 48)", R"("height": 16385)"), "camera.height", "must be in [1, 16384], got 16385");
    expect_error(edit(R"("width": 64)", R"("width": 64.5)"), "camera.width", "must be an integer, got 64.5");
    expect_error(edit(R"("width": 64)", R"("width": -3)"), "camera.width", "must be in [1, 16384]");
    CHECK(parse_scene(edit(R"("width": 64)", R"("width": 16384)"), "t.json").camera.width == 16384);
}

TEST_CASE("camera angles and sizes") {
    expect_error(edit(R"("fov_y": 45)", R"("fov_y": 0)"), "camera.fov_y", "must be in (0, 180) degrees, got 0");
    expect_error(edit(R"("fov_y": 45)", R"("fov_y": 180)"), "camera.fov_y", "must be in (0, 180) degrees, got 180");
    const std::string ortho = edit(R"("type": "pinhole")", R"("type": "orthographic")", edit(R"("fov_y": 45)", R"("height_world": 0)"));
    expect_error(ortho, "camera.height_world", "must be > 0, got 0");
    const Scene s = parse_scene(edit(R"("height_world": 0)", R"("height_world": 3.5)", ortho), "t.json");
    CHECK(s.camera.type == octray::CameraType::orthographic);
    CHECK(s.camera.height_world == 3.5);
}

TEST_CASE("gamma must be positive") {
    expect_error(edit(R"("gamma": 2.2)", R"("gamma": 0)"), "render.gamma", "must be > 0, got 0");
    expect_error(edit(R"("gamma": 2.2)", R"("gamma": -1)"), "render.gamma", "must be > 0, got -1");
}

TEST_CASE("negative coefficients and colour components") {
    expect_error(edit(R"("ka": 0.2)", R"("ka": -0.1)"), "materials.red.ka", "must be >= 0, got -0.1");
    expect_error(edit(R"("kd": 0.7)", R"("kd": -1)"), "materials.green.kd", "must be >= 0, got -1");
    expect_error(edit(R"("ls": 0.75)", R"("ls": -0.5)"), "ambient.ls", "must be >= 0, got -0.5");
    expect_error(edit(R"("ls": 2.0)", R"("ls": -2)"), "lights[0].ls", "must be >= 0");
    expect_error(edit(R"("cd": [0, 1, 0])", R"("cd": [0, -1, 0])"), "materials.green.cd[1]", "colour components must be >= 0, got -1");
    expect_error(edit(R"("color": [1, 0.9, 0.8])", R"("color": [1, 0.9, -0.8])"), "lights[1].color[2]", "must be >= 0");
    expect_error(edit(R"("background": [0.1, 0.2, 0.3])", R"("background": [-0.1, 0.2, 0.3])"), "background[0]", "must be >= 0");
    expect_error(edit(R"("color": [1, 0.5, 0.25])", R"("color": [1, -0.5, 0.25])"), "ambient.color[1]", "must be >= 0");
    expect_error(edit(R"("clamp_color": [0, 1, 0])", R"("clamp_color": [0, 2, 0])"), "render.clamp_color[1]", "must be <= 1, got 2");
    // HDR colours above 1 are legal everywhere except the display clamp colour.
    CHECK_NOTHROW(parse_scene(edit(R"("cd": [0, 1, 0])", R"("cd": [0, 3, 0])"), "t.json"));
}

TEST_CASE("attenuation and tonemap must be known names") {
    expect_error(edit(R"("attenuation": "inverse_square")", R"("attenuation": "linear")"), "lights[1].attenuation",
                 "unknown attenuation \"linear\" (allowed: none, inverse_square)");
    expect_error(edit(R"("tonemap": "saturate")", R"("tonemap": "reinhard")"), "render.tonemap",
                 "unknown tonemap \"reinhard\" (allowed: max_to_one, clamp_to_color, saturate)");
    expect_error(edit(R"("tonemap": "saturate")", R"("tonemap": 1)"), "render.tonemap", "must be a string");
    CHECK(parse_scene(edit(R"("tonemap": "saturate")", R"("tonemap": "clamp_to_color")"), "t.json").render.tonemap ==
          octray::ToneMap::clamp_to_color);
}

TEST_CASE("a file that cannot be read names the file and the OS reason") {
    const std::string path = OCTRAY_SOURCE_DIR "/scenes/does-not-exist.json";
    try {
        octray::load_scene(path);
        FAIL("missing file was accepted");
    } catch (const SceneError& e) {
        CHECK(std::string(e.what()) == path + ": cannot open: No such file or directory");
    }
    try {
        octray::load_scene(OCTRAY_SOURCE_DIR "/scenes");
        FAIL("a directory was accepted");
    } catch (const SceneError& e) {
        CHECK(std::string(e.what()).find("Is a directory") != std::string::npos);
    }
}

TEST_CASE("a scene file over the size limit is refused unread") {
    // A sparse file: no disk, no memory; load_scene must not try to read it.
    const std::filesystem::path big = std::filesystem::temp_directory_path() / "octray_test_big_scene.json";
    { std::ofstream touch(big); }
    std::filesystem::resize_file(big, octray::kMaxSceneFileBytes + 1);
    try {
        octray::load_scene(big.string());
        FAIL("a file over the limit was accepted");
    } catch (const SceneError& e) {
        CHECK(std::string(e.what()) == big.string() + ": file too large: 1073741825 bytes (limit 1073741824)");
    }
    std::filesystem::remove(big);
}
