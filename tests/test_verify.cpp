// The paths agree on scenes built in code, where nothing has normalized the
// directions (scene.hpp: every path uses unit_direction()), measured with
// `octray verify`'s own comparison (harness/verify.hpp).
#include "verify.hpp"

#include <octray/reference.hpp>

#include <doctest/doctest.h>

#include <cmath>

using namespace octray;

namespace {

// A sphere on a plane, lit by directional lights of length sqrt(6) and 0.25
// (one casting shadows) and a point light; the plane's normal has length 3.
Scene non_unit_scene() {
    Scene s;
    s.camera.eye = {0, 1.5, 5};
    s.camera.width = 64;
    s.camera.height = 48;
    s.ambient = AmbientLight{{1, 1, 1}, 0.1};
    s.directional_lights.push_back({{1, 2, 1}, {1, 1, 1}, 1.5, true});
    s.directional_lights.push_back({{0, 0, 0.25}, {0.5, 0.7, 1}, 0.8, false});
    s.point_lights.push_back({{-2, 3, 2}, {1, 0.9, 0.8}, 6.0, Attenuation::inverse_square, false});
    s.materials.push_back({"red", 0.25, 0.65, {1, 0.2, 0.2}});
    s.materials.push_back({"grey", 0.25, 0.65, {0.7, 0.7, 0.7}});
    s.objects.push_back({Sphere{{0, 0, 0}, 1}, 0});
    s.objects.push_back({Plane{{0, -1, 0}, {0, 3, 0}}, 1});
    return s;
}

}  // namespace

TEST_CASE("unit_direction: v / |v|, scale-free") {
    // (1, 2, 2) has length 3.
    const Vec3d third{1.0 / 3, 2.0 / 3, 2.0 / 3};
    for (double scale : {1.0, 1e-300, 1e300, 0x1p-1070, 0.1}) {
        CAPTURE(scale);
        const Vec3d u = unit_direction(Vec3d{1, 2, 2} * scale);
        CHECK(u.x == doctest::Approx(third.x).epsilon(1e-15));
        CHECK(u.y == doctest::Approx(third.y).epsilon(1e-15));
        CHECK(u.z == doctest::Approx(third.z).epsilon(1e-15));
    }
    // In the normal range it is v / sqrt(v.v), bit for bit (what the reference always did).
    const Vec3d v{0.3, -1.7, 2.9};
    const double len = std::sqrt(dot(v, v));
    const Vec3d u = unit_direction(v);
    CHECK(u.x == v.x / len);
    CHECK(u.y == v.y / len);
    CHECK(u.z == v.z / len);
    CHECK(std::isnan(unit_direction({0, 0, 0}).x));
}

TEST_CASE("a hand-built scene with non-unit directions: reference and kernels agree") {
    const Scene scene = non_unit_scene();
    const ReferenceRender ref = render_reference(scene);
    const PacketScene packet = compile(scene);
    for (Path path : {Path::scalar, Path::simd}) {
        CAPTURE(path_name(path));
        const PacketRender out = render_packet(select_kernel(packet, path), packet);
        const Agreement a = compare(ref, out.radiance, out.primitive);
        INFO("max |L - L_ref| / S " << a.max_scaled << ", mismatched " << a.mismatched << " of " << a.lanes);
        CHECK(a.compared > a.lanes / 2);  // the sphere and the plane fill most of the image
        CHECK(a.within(Tolerance{}));
    }
}

TEST_CASE("the reference reads a direction's length as nothing") {
    // Doubling a direction (a power of two: unit_direction gives the same bits)
    // or normalizing it by hand leaves the reference's image as it was.
    const Scene scene = non_unit_scene();
    Scene doubled = scene, normalized = scene;
    for (DirectionalLight& l : doubled.directional_lights) l.direction = l.direction * 2.0;
    for (DirectionalLight& l : normalized.directional_lights) l.direction = unit_direction(l.direction);
    const Image<double> base = reference::render(scene), twice = reference::render(doubled),
                        unit = reference::render(normalized);
    REQUIRE(base.rgb.size() == unit.rgb.size());
    double lit = 0;
    for (std::size_t k = 0; k < base.rgb.size(); ++k) {
        CHECK(twice.rgb[k] == base.rgb[k]);
        CHECK(unit.rgb[k] == doctest::Approx(base.rgb[k]).epsilon(1e-14));
        lit += base.rgb[k];
    }
    CHECK(lit > 0);
}
