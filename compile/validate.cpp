// compile/validate.cpp — the one set of authoring-scene rules (scene.hpp).
//
// Scenes built in code and scenes read from JSON are judged here alike: the
// loader (io/scene_loader.cpp) checks only the JSON's shape and reports
// these messages at the file's JSON path. Messages name the Scene path
// ("point_lights[0].ls") and say what is wrong and what was found.
#include <octray/scene.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <type_traits>

namespace octray {
namespace {

// Relative tolerances for "degenerate": sines of angles this small make the
// camera basis, a rectangle's dual basis or a triangle numerically meaningless.
constexpr double kParallelSine = 1e-6;
constexpr double kDegenerateSine = 1e-9;

// Shortest decimal that reads back as the same double, so "got 0.1" is not
// "got 0.100000" or "got 0.10000000000000001".
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

// A Scene path ("objects[3].radius") as a chain of parts on the stack,
// spelled out only when something fails: a valid scene of a million objects
// builds no strings.
struct Path {
    const Path* parent = nullptr;
    const char* member = nullptr;  // ".radius", or a root name; null: the index
    long index = 0;

    Path(const char* root) : member(root) {}  // NOLINT: implicit from a root name
    Path(const Path& p, const char* m) : parent(&p), member(m) {}
    Path(const Path& p, long i) : parent(&p), index(i) {}
    std::string str() const {
        std::string s = parent ? parent->str() : std::string();
        return member ? s + member : s + "[" + std::to_string(index) + "]";
    }
};
double component(const Vec3d& v, int k) { return k == 0 ? v.x : k == 1 ? v.y : v.z; }
double length(const Vec3d& v) { return std::sqrt(dot(v, v)); }
bool is_zero(const Vec3d& v) { return v.x == 0 && v.y == 0 && v.z == 0; }
bool is_finite(const Vec3d& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

[[noreturn]] void fail(const Path& path, const std::string& what) { throw InvalidScene(path.str(), what); }

void finite(const Path& path, double v) {
    if (!std::isfinite(v)) fail(path, "must be finite, got " + format_number(v));
}
void finite(const Path& path, const Vec3d& v) {
    for (int k = 0; k < 3; ++k) finite(Path(path, k), component(v, k));
}
void non_negative(const Path& path, double v) {
    finite(path, v);
    if (v < 0) fail(path, "must be >= 0, got " + format_number(v));
}
void positive(const Path& path, double v) {
    finite(path, v);
    if (!(v > 0)) fail(path, "must be > 0, got " + format_number(v));
}
// HDR colours are unbounded above; a display colour (max = 1) is not.
void colour(const Path& path, const Vec3d& c, double max = INFINITY) {
    for (int k = 0; k < 3; ++k) {
        const double x = component(c, k);
        finite(Path(path, k), x);
        if (x < 0) fail(Path(path, k), "colour components must be >= 0, got " + format_number(x));
        if (x > max)
            fail(Path(path, k), "colour components must be <= " + format_number(max) + ", got " + format_number(x));
    }
}
// Any finite, non-zero vector: every path uses unit_direction() of it.
void direction(const Path& path, const Vec3d& d) {
    finite(path, d);
    if (is_zero(d)) fail(path, "must not be zero-length");
}
void image_size(const Path& path, int n) {
    if (n < 1 || n > kMaxImageSide)
        fail(path, "must be in [1, " + std::to_string(kMaxImageSide) + "], got " + std::to_string(n));
}

void camera(const Camera& c) {
    finite("camera.eye", c.eye), finite("camera.look_at", c.look_at);
    direction("camera.up", c.up);
    if (c.type == CameraType::pinhole && !(c.fov_y > 0 && c.fov_y < 180))
        fail("camera.fov_y", "must be in (0, 180) degrees, got " + format_number(c.fov_y));
    if (c.type == CameraType::orthographic) positive("camera.height_world", c.height_world);
    image_size("camera.width", c.width), image_size("camera.height", c.height);
    const Vec3d view = c.eye - c.look_at;
    if (is_zero(view)) fail("camera.look_at", "must differ from eye");
    if (!is_finite(view)) fail("camera.look_at", "eye - look_at overflows (coordinates too large)");
    if (length(cross(unit_direction(c.up), unit_direction(view))) < kParallelSine)
        fail("camera.up", "is parallel to the view direction (eye - look_at)");
}

void rectangle(const Path& p, const Rectangle& r) {
    finite(Path(p, ".corner"), r.corner);
    direction(Path(p, ".a"), r.a), direction(Path(p, ".b"), r.b);
    if (length(cross(unit_direction(r.a), unit_direction(r.b))) < kDegenerateSine)
        fail(p, "is degenerate: a and b are parallel (|a x b| ~ 0 relative to |a||b|)");
}

void box(const Path& p, const Box& b) {
    finite(Path(p, ".min"), b.min), finite(Path(p, ".max"), b.max);
    for (int k = 0; k < 3; ++k) {
        const double lo = component(b.min, k), hi = component(b.max, k);
        if (!(lo < hi)) {
            const std::string a(1, "xyz"[k]);
            fail(p, "is degenerate: min." + a + " = " + format_number(lo) + " is not < max." + a + " = " +
                        format_number(hi));
        }
    }
}

// Zero area relative to the longest edge: collinear or coincident vertices.
void triangle(const Path& p, const Triangle& t) {
    const Path vertices(p, ".vertices");
    finite(Path(vertices, 0L), t.v0), finite(Path(vertices, 1L), t.v1), finite(Path(vertices, 2L), t.v2);
    Vec3d e[3] = {t.v1 - t.v0, t.v2 - t.v0, t.v2 - t.v1};
    double m = 0;
    for (const Vec3d& v : e) m = std::max({m, std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
    if (!std::isfinite(m)) fail(p, "is degenerate: vertex differences overflow (coordinates too large)");
    if (m > 0) {
        for (Vec3d& v : e) v = v * (1 / m);  // scale-free from here on
        const double longest2 = std::max({dot(e[0], e[0]), dot(e[1], e[1]), dot(e[2], e[2])});
        if (length(cross(e[0], e[1])) >= kDegenerateSine * longest2) return;
    }
    fail(p, "is degenerate: zero area relative to its edge lengths (collinear or coincident vertices)");
}

void shape(const Path& p, const Shape& shape) {
    std::visit(
        [&](const auto& s) {
            using S = std::decay_t<decltype(s)>;
            if constexpr (std::is_same_v<S, Sphere>) {
                finite(Path(p, ".center"), s.center), positive(Path(p, ".radius"), s.radius);
            } else if constexpr (std::is_same_v<S, Plane>) {
                finite(Path(p, ".point"), s.point), direction(Path(p, ".normal"), s.normal);
            } else if constexpr (std::is_same_v<S, Disk>) {
                finite(Path(p, ".center"), s.center), direction(Path(p, ".normal"), s.normal), positive(Path(p, ".radius"), s.radius);
            } else if constexpr (std::is_same_v<S, Rectangle>) {
                rectangle(p, s);
            } else if constexpr (std::is_same_v<S, Box>) {
                box(p, s);
            } else {
                triangle(p, s);
            }
        },
        shape);
}

void occlusion(const Path& path, const AmbientOcclusion& o, bool ambient) {
    if (!ambient) fail(path, "needs an ambient light (Scene::ambient) to occlude");
    if (o.samples < 1 || o.samples > AmbientOcclusion::kMaxSamples)
        fail(Path(path, ".samples"), "must be in [1, " + std::to_string(AmbientOcclusion::kMaxSamples) + "], got " +
                                    std::to_string(o.samples));
    positive(Path(path, ".distance"), o.distance);
    non_negative(Path(path, ".min_amount"), o.min_amount);
    if (o.min_amount > 1) fail(Path(path, ".min_amount"), "must be in [0, 1], got " + format_number(o.min_amount));
}

}  // namespace

InvalidScene::InvalidScene(const std::string& path, const std::string& problem)
    : std::invalid_argument(path + ": " + problem), path_size_(path.size()) {}
std::string InvalidScene::path() const { return std::string(what(), path_size_); }
std::string InvalidScene::problem() const { return std::string(what() + path_size_ + 2); }

namespace {

void mesh(const Path& p, const Mesh& m, const Scene& scene) {
    if (m.material < 0 || std::size_t(m.material) >= scene.materials.size())
        fail(Path(p, ".material"), "index " + std::to_string(m.material) + ", but there are " +
                                  std::to_string(scene.materials.size()) + " materials");
    if (m.indices.size() % 3 != 0)
        fail(Path(p, ".indices"), "must hold three per triangle, got " + std::to_string(m.indices.size()));
    if (m.indices.empty()) fail(p, "has no triangles");
    for (std::size_t v = 0; v < m.vertices.size(); ++v)
        if (!std::isfinite(m.vertices[v].x) || !std::isfinite(m.vertices[v].y) || !std::isfinite(m.vertices[v].z))
            fail(Path(Path(p, ".vertices"), long(v)), "must be finite");
    for (std::size_t k = 0; k < m.indices.size(); ++k)
        if (m.indices[k] >= m.vertices.size())
            fail(Path(Path(p, ".indices"), long(k)), "index " + std::to_string(m.indices[k]) + " out of range (" +
                                                                std::to_string(m.vertices.size()) + " vertices)");
    for (std::size_t k = 0; k < m.indices.size(); k += 3) {
        const Vec3d& a = m.vertices[m.indices[k]];
        const Vec3d n = cross(m.vertices[m.indices[k + 1]] - a, m.vertices[m.indices[k + 2]] - a);
        if (n.x == 0 && n.y == 0 && n.z == 0)
            fail(Path(Path(p, ".indices"), long(k)), "triangle " + std::to_string(k / 3) + " has zero area");
    }
}

}  // namespace

Vec3d unit_direction(const Vec3d& v) {
    // m = 2^e * [1, 2): scaling by 2^-e is exact and brings the largest component to [1, 2).
    const double m = std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
    if (!(m > 0) || !std::isfinite(m)) {  // zero, infinite or NaN: ilogb has no usable exponent
        const double nan = std::numeric_limits<double>::quiet_NaN();
        return {nan, nan, nan};
    }
    // 2^-e from m's exponent bits where both are normal (every mesh triangle's
    // normal comes here: the library calls cost more than the rest); a
    // product by a power of two rounds as scalbn does, so the bits agree.
    std::uint64_t bits;
    std::memcpy(&bits, &m, sizeof bits);
    const int biased = int(bits >> 52);  // m > 0: no sign bit
    Vec3d s;
    if (biased >= 1 && biased <= 2045) {
        const std::uint64_t inverse = std::uint64_t(2046 - biased) << 52;  // 2^-(biased - 1023)
        double k;
        std::memcpy(&k, &inverse, sizeof k);
        s = {v.x * k, v.y * k, v.z * k};
    } else {
        const int e = std::ilogb(m);
        s = {std::scalbn(v.x, -e), std::scalbn(v.y, -e), std::scalbn(v.z, -e)};
    }
    const double len = std::sqrt(dot(s, s));
    return {s.x / len, s.y / len, s.z / len};
}

void validate(const Scene& scene) {
    const Path directional_lights_root("directional_lights"), point_lights_root("point_lights"),
        materials_root("materials"), objects_root("objects");
    camera(scene.camera);
    colour("background", scene.background);
    if (scene.ambient) colour("ambient.color", scene.ambient->color), non_negative("ambient.ls", scene.ambient->ls);
    if (scene.ambient_occlusion) occlusion("ambient_occlusion", *scene.ambient_occlusion, scene.ambient.has_value());
    for (std::size_t i = 0; i < scene.directional_lights.size(); ++i) {
        const Path p(directional_lights_root, long(i));
        const DirectionalLight& l = scene.directional_lights[i];
        direction(Path(p, ".direction"), l.direction), colour(Path(p, ".color"), l.color), non_negative(Path(p, ".ls"), l.ls);
    }
    for (std::size_t i = 0; i < scene.point_lights.size(); ++i) {
        const Path p(point_lights_root, long(i));
        const PointLight& l = scene.point_lights[i];
        finite(Path(p, ".position"), l.position), colour(Path(p, ".color"), l.color), non_negative(Path(p, ".ls"), l.ls);
    }
    if (scene.materials.size() > kMaxMaterials)
        fail("materials", "too many: " + std::to_string(scene.materials.size()) + " (limit " +
                              std::to_string(kMaxMaterials) + ")");
    if (const std::size_t n = scene.objects.size() + scene.mesh_triangle_count(); n > kMaxPrimitives)
        fail("objects", "too many primitives: " + std::to_string(n) + " objects and mesh triangles (limit " +
                            std::to_string(kMaxPrimitives) + ")");
    for (std::size_t i = 0; i < scene.materials.size(); ++i) {
        const Path p(materials_root, long(i));
        const Material& m = scene.materials[i];
        non_negative(Path(p, ".ka"), m.ka), non_negative(Path(p, ".kd"), m.kd), colour(Path(p, ".cd"), m.cd);
    }
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        const Path p(objects_root, long(i));
        const Object& o = scene.objects[i];
        if (o.material < 0 || std::size_t(o.material) >= scene.materials.size())
            fail(Path(p, ".material"), "index " + std::to_string(o.material) + ", but there are " +
                                      std::to_string(scene.materials.size()) + " materials");
        shape(p, o.shape);
    }
    for (std::size_t i = 0; i < scene.meshes.size(); ++i) mesh(Path(Path("meshes"), long(i)), scene.meshes[i], scene);
    positive("render.gamma", scene.render.gamma);
    colour("render.clamp_color", scene.render.clamp_color, 1.0);
}

}  // namespace octray
