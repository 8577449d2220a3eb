// tests/support/support.cpp — see support.hpp.
#include "support.hpp"

#include "scene_loader.hpp"

#include <cmath>

namespace octray::test {

float f(double x) { return float(round_to_float(x)); }

Vec3d fl(const Vec3d& v) { return round_to_float(v); }

Vec3d RandomRays::direction() {
    for (;;) {
        const Vec3d d = in_cube(1);
        const double l2 = dot(d, d);
        if (l2 > 1e-4 && l2 <= 1) return fl(d * (1 / std::sqrt(l2)));
    }
}

Shape random_shape(PrimitiveType type, RandomRays& r) {
    switch (type) {
    case PrimitiveType::sphere: return Sphere{fl(r.in_cube(1)), double(f(r.uniform(0.3, 2)))};
    case PrimitiveType::plane: return Plane{fl(r.in_cube(1)), r.direction()};
    case PrimitiveType::disk: return Disk{fl(r.in_cube(1)), r.direction(), double(f(r.uniform(0.3, 2)))};
    case PrimitiveType::rectangle: return Rectangle{fl(r.in_cube(1)), fl(r.in_cube(2)), fl(r.in_cube(2))};
    case PrimitiveType::box: {
        const Vec3d a = fl(r.in_cube(1.5)), e = fl(Vec3d{r.uniform(0.2, 2), r.uniform(0.2, 2), r.uniform(0.2, 2)});
        return Box{a, fl(a + e)};
    }
    case PrimitiveType::triangle: return Triangle{fl(r.in_cube(2)), fl(r.in_cube(2)), fl(r.in_cube(2))};
    }
    return Sphere{};
}

bool near_boundary(const Shape& shape, const reference::Ray& ray, double rel) {
    const bool base = reference::intersect(shape, ray, 0, 1e300).has_value();
    for (int axis = 0; axis < 3; ++axis)
        for (double sign : {-1.0, 1.0}) {
            Vec3d e;
            (axis == 0 ? e.x : axis == 1 ? e.y : e.z) = sign * rel;
            const double scale = 1 + std::sqrt(dot(ray.origin, ray.origin));
            const reference::Ray moved{ray.origin + e * scale, ray.direction};
            const reference::Ray turned{ray.origin, ray.direction + e};
            if (reference::intersect(shape, moved, 0, 1e300).has_value() != base) return true;
            if (reference::intersect(shape, turned, 0, 1e300).has_value() != base) return true;
        }
    return false;
}

void set_ray(RayPacket8& rp, int lane, const Vec3d& o, const Vec3d& d) {
    rp.ox[lane] = f(o.x), rp.oy[lane] = f(o.y), rp.oz[lane] = f(o.z);
    rp.dx[lane] = f(d.x), rp.dy[lane] = f(d.y), rp.dz[lane] = f(d.z);
    rp.tmin[lane] = 0, rp.tmax[lane] = INFINITY, rp.active[lane] = -1;
}

Scene one_object_scene(const Shape& shape) {
    Scene s;
    s.materials.push_back(Material{"m", 0.25, 0.65, {1, 1, 1}});
    s.objects.push_back(Object{shape, 0});
    return s;
}

Scene two_material_scene(const Vec3d& eye, int width, int height, const Vec3d& background) {
    Scene s;
    s.camera.eye = eye;
    s.camera.look_at = {0, 0, 0};
    s.camera.width = width;
    s.camera.height = height;
    s.background = background;
    s.materials = {Material{"a", 0.3, 0.6, {0.9, 0.4, 0.2}}, Material{"b", 0.2, 0.7, {0.2, 0.5, 0.9}}};
    return s;
}

Scene scene_with_features(unsigned bits, std::mt19937& rng) {
    Scene s = two_material_scene({0.3, 2.5, 7}, 48, 36, {0.1, 0.2, 0.3});
    auto u = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
    auto add = [&](Shape shape) { s.objects.push_back(Object{shape, int(s.objects.size() % 2)}); };
    if (bits & kSphere) add(Sphere{{u(-1, 1), u(0, 1), u(-1, 1)}, u(0.5, 1)});
    if (bits & kPlane) add(Plane{{0, -1, 0}, {0, 1, 0}});
    if (bits & kDisk) add(Disk{{-2, 0.5, -1}, {0.3, 0.2, 1}, 0.8});
    if (bits & kRectangle) add(Rectangle{{-1.5, -1, -2.5}, {3, 0, 0}, {0, 2.5, 0.3}});
    if (bits & kBox) add(Box{{1.2, -1, -0.5}, {2.2, 0.3, 0.5}});
    if (bits & kTriangle) add(Triangle{{0.5, -1, 1.5}, {2, -1, 2}, {1.2, 0.5, 1.8}});
    const bool shadows = (bits & kShadows) != 0;
    if (bits & kAmbient) s.ambient = AmbientLight{{1, 1, 1}, 0.4};
    if (bits & kOcclusion) s.ambient_occlusion = AmbientOcclusion{4, 1e30, 0.1};
    if (bits & kDirectional) s.directional_lights.push_back({{0.4, 0.8, 0.45}, {1, 0.9, 0.8}, 1.5, shadows});
    if (bits & kPoint) s.point_lights.push_back({{-3, 4, 3}, {1, 1, 1}, 1.2, Attenuation::none, shadows});
    if (bits & kPointAttenuated) s.point_lights.push_back({{2, 3, 3}, {1, 0.8, 0.6}, 25, Attenuation::inverse_square, shadows});
    for (DirectionalLight& l : s.directional_lights) l.direction = l.direction * (1 / std::sqrt(dot(l.direction, l.direction)));
    return s;
}

std::vector<Isa> simd_isas() {
    std::vector<Isa> isas;
    if (avx512_supported()) isas.push_back(Isa::avx512);
    if (simd_supported()) isas.push_back(Isa::avx2);
    if (isas.empty()) isas.push_back(Isa::best);  // the generic scalar unit
    return isas;
}

Scene load_repo_scene(const std::string& name) {
    return load_scene(std::string(OCTRAY_SOURCE_DIR) + "/scenes/" + name + ".json");
}

}  // namespace octray::test
