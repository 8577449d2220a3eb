// kernels/validate.cpp — the authoring-scene invariants, checked for scenes
// built in code (the JSON loader checks the same rules with file positions).
#include <octray/scene.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace octray {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) { throw std::invalid_argument(path + ": " + what); }

void finite(const std::string& path, double v) {
    if (!std::isfinite(v)) fail(path, "must be finite, got " + std::to_string(v));
}
void finite(const std::string& path, const Vec3d& v) {
    finite(path + "[0]", v.x), finite(path + "[1]", v.y), finite(path + "[2]", v.z);
}
void non_negative(const std::string& path, double v) {
    finite(path, v);
    if (v < 0) fail(path, "must be >= 0, got " + std::to_string(v));
}
void colour(const std::string& path, const Vec3d& c) {
    non_negative(path + "[0]", c.x), non_negative(path + "[1]", c.y), non_negative(path + "[2]", c.z);
}
void positive(const std::string& path, double v) {
    finite(path, v);
    if (!(v > 0)) fail(path, "must be > 0, got " + std::to_string(v));
}
void direction(const std::string& path, const Vec3d& d) {
    finite(path, d);
    if (!(length_squared(d) > 0) || !std::isfinite(length_squared(d))) fail(path, "must be a non-zero, finite direction");
}
// |a x b| small against |a||b|: the two edges are (nearly) parallel.
void spans_area(const std::string& path, const Vec3d& a, const Vec3d& b) {
    const double area2 = length_squared(cross(a, b)), scale2 = length_squared(a) * length_squared(b);
    if (!(area2 > 1e-24 * scale2)) fail(path, "is degenerate (zero area)");
}

}  // namespace

Vec3d unit_direction(const Vec3d& v) {
    // m = 2^e * [1, 2): scaling by 2^-e is exact and brings the largest component to [1, 2).
    const int e = std::ilogb(std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}));
    const Vec3d s{std::scalbn(v.x, -e), std::scalbn(v.y, -e), std::scalbn(v.z, -e)};
    const double len = std::sqrt(dot(s, s));
    return {s.x / len, s.y / len, s.z / len};
}

void validate(const Scene& scene) {
    const Camera& c = scene.camera;
    finite("camera.eye", c.eye), finite("camera.look_at", c.look_at);
    direction("camera.up", c.up);
    const Vec3d view = c.eye - c.look_at;
    direction("camera.look_at (eye - look_at)", view);
    spans_area("camera.up (parallel to the view direction)", c.up, view);
    if (c.type == CameraType::pinhole && !(c.fov_y > 0 && c.fov_y < 180))
        fail("camera.fov_y", "must be in (0, 180) degrees, got " + std::to_string(c.fov_y));
    if (c.type == CameraType::orthographic) positive("camera.height_world", c.height_world);
    if (c.width < 1 || c.width > 16384) fail("camera.width", "must be in [1, 16384], got " + std::to_string(c.width));
    if (c.height < 1 || c.height > 16384) fail("camera.height", "must be in [1, 16384], got " + std::to_string(c.height));

    colour("background", scene.background);
    if (scene.ambient) colour("ambient.color", scene.ambient->color), non_negative("ambient.ls", scene.ambient->ls);
    for (std::size_t i = 0; i < scene.directional_lights.size(); ++i) {
        const std::string p = "directional_lights[" + std::to_string(i) + "]";
        const DirectionalLight& l = scene.directional_lights[i];
        direction(p + ".direction", l.direction), colour(p + ".color", l.color), non_negative(p + ".ls", l.ls);
    }
    for (std::size_t i = 0; i < scene.point_lights.size(); ++i) {
        const std::string p = "point_lights[" + std::to_string(i) + "]";
        const PointLight& l = scene.point_lights[i];
        finite(p + ".position", l.position), colour(p + ".color", l.color), non_negative(p + ".ls", l.ls);
    }
    for (std::size_t i = 0; i < scene.materials.size(); ++i) {
        const std::string p = "materials[" + std::to_string(i) + "]";
        const Material& m = scene.materials[i];
        non_negative(p + ".ka", m.ka), non_negative(p + ".kd", m.kd), colour(p + ".cd", m.cd);
    }
    for (std::size_t i = 0; i < scene.objects.size(); ++i) {
        const std::string p = "objects[" + std::to_string(i) + "]";
        const Object& o = scene.objects[i];
        if (o.material < 0 || std::size_t(o.material) >= scene.materials.size())
            fail(p + ".material", "index " + std::to_string(o.material) + ", but there are " +
                                      std::to_string(scene.materials.size()) + " materials");
        std::visit(
            [&](const auto& s) {
                using S = std::decay_t<decltype(s)>;
                if constexpr (std::is_same_v<S, Sphere>) {
                    finite(p + ".center", s.center), positive(p + ".radius", s.radius);
                } else if constexpr (std::is_same_v<S, Plane>) {
                    finite(p + ".point", s.point), direction(p + ".normal", s.normal);
                } else if constexpr (std::is_same_v<S, Disk>) {
                    finite(p + ".center", s.center), direction(p + ".normal", s.normal);
                    positive(p + ".radius", s.radius);
                } else if constexpr (std::is_same_v<S, Rectangle>) {
                    finite(p + ".corner", s.corner), finite(p + ".a", s.a), finite(p + ".b", s.b);
                    spans_area(p, s.a, s.b);
                } else if constexpr (std::is_same_v<S, Box>) {
                    finite(p + ".min", s.min), finite(p + ".max", s.max);
                    if (!(s.min.x < s.max.x && s.min.y < s.max.y && s.min.z < s.max.z))
                        fail(p, "is degenerate: min must be < max on every axis");
                } else {
                    finite(p + ".vertices[0]", s.v0), finite(p + ".vertices[1]", s.v1), finite(p + ".vertices[2]", s.v2);
                    spans_area(p, s.v1 - s.v0, s.v2 - s.v0);
                }
            },
            o.shape);
    }
    if (!(scene.render.gamma > 0) || !std::isfinite(scene.render.gamma))
        fail("render.gamma", "must be > 0, got " + std::to_string(scene.render.gamma));
    colour("render.clamp_color", scene.render.clamp_color);
}

}  // namespace octray
