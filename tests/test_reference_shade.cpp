// tests/test_reference_shade.cpp — the oracle's shading checked against values
// worked out by hand (the arithmetic is in the comments) from the shading
// equations of docs/shading-model.md: background, ambient, directional and
// point lights, their sum, shadows, and the shadow-ray offset.
#include "reference_fixtures.hpp"
#include "reference/reference_parts.hpp"

#include <doctest/doctest.h>

#include <cmath>

using namespace octray;
using namespace octray::reference;
using namespace reference_fixtures;

// ---------------------------------------------------------------- shading ----

TEST_CASE("shade: miss is the background; no lights is black") {
    Scene s = pole_scene();
    s.background = {0.1, 0.2, 0.3};
    CHECK_VEC(shade_ray(s, {{5, 5, 5}, kDown}), Vec3d(0.1, 0.2, 0.3));
    CHECK_VEC(shade_ray(s, kPoleRay), Vec3d(0, 0, 0));  // no ambient, no lights: L = 0
}

TEST_CASE("shade: ambient term") {
    Scene s = pole_scene();
    s.ambient = AmbientLight{{1, 1, 1}, 1.0};
    // ka cd * (ls cl) = 0.25*(1,0.5,0.25) = (0.25, 0.125, 0.0625).
    CHECK_VEC(shade_ray(s, kPoleRay), Vec3d(0.25, 0.125, 0.0625));
    // cl=(1,0.5,2), ls=0.5: ls cl = (0.5,0.25,1); 0.25*(1*0.5, 0.5*0.25, 0.25*1) = (0.125, 0.03125, 0.0625).
    s.ambient = AmbientLight{{1, 0.5, 2}, 0.5};
    CHECK_VEC(shade_ray(s, kPoleRay), Vec3d(0.125, 0.03125, 0.0625));
}

TEST_CASE("shade: directional light, Lambertian term") {
    Scene s = pole_scene();
    s.ambient = AmbientLight{{1, 1, 1}, 1.0};
    // Straight at the pole, ls=2: n.l = 1; L = 0.25 cd + (0.65 cd/pi) * 2 * 1.
    s.directional_lights.push_back({{0, 0, 1}, {1, 1, 1}, 2.0, false});
    CHECK_VEC(shade_ray(s, kPoleRay), kCd * (0.25 + 1.3 / kPi));
    // At 60deg from the normal: l = (sin 60, 0, cos 60), n.l = 0.5 -> 0.65/pi * 2 * 0.5 = 0.65/pi.
    s.directional_lights[0].direction = {std::sqrt(3.0) / 2, 0, 0.5};
    CHECK_VEC(shade_ray(s, kPoleRay), kCd * (0.25 + 0.65 / kPi));
    // Coloured light cl=(0.5,1,2), ls=1, straight: (0.65/pi) * cd * cl = 0.65/pi * (0.5, 0.5, 0.5).
    s.ambient.reset();
    s.directional_lights[0] = {{0, 0, 1}, {0.5, 1, 2}, 1.0, false};
    CHECK_VEC(shade_ray(s, kPoleRay), Vec3d(0.5, 0.5, 0.5) * (0.65 / kPi));
    // From behind (n.l = -1) and grazing (n.l = 0): no contribution.
    s.directional_lights[0].direction = {0, 0, -1};
    CHECK_VEC(shade_ray(s, kPoleRay), Vec3d(0, 0, 0));
    s.directional_lights[0].direction = {1, 0, 0};
    CHECK_VEC(shade_ray(s, kPoleRay), Vec3d(0, 0, 0));
}

TEST_CASE("shade: point light, with and without inverse square") {
    Scene s = pole_scene();
    // Light at (0,0,3): p=(0,0,1), r=2, l=(0,0,1), n.l=1. ls=3: L = 0.65/pi * 3 * cd.
    s.point_lights.push_back({{0, 0, 3}, {1, 1, 1}, 3.0, Attenuation::none, false});
    CHECK_VEC(shade_ray(s, kPoleRay), kCd * (0.65 * 3 / kPi));
    // inverse_square: times 1/r^2 = 1/4.
    s.point_lights[0].attenuation = Attenuation::inverse_square;
    CHECK_VEC(shade_ray(s, kPoleRay), kCd * (0.65 * 3 / kPi / 4));
    // Light at (0,3,5): to light (0,3,4), r=5, l=(0,0.6,0.8), n.l=0.8; ls=10, cl=(1,0.5,0.5),
    // 1/r^2 = 1/25: ls cl n.l / r^2 = (10,5,5)*0.032 = (0.32,0.16,0.16); times cd ->
    // (0.32, 0.08, 0.04) * 0.65/pi.
    s.point_lights[0] = {{0, 3, 5}, {1, 0.5, 0.5}, 10.0, Attenuation::inverse_square, false};
    CHECK_VEC(shade_ray(s, kPoleRay), Vec3d(0.32, 0.08, 0.04) * (0.65 / kPi));
    // Without attenuation the same light gives 25 times that.
    s.point_lights[0].attenuation = Attenuation::none;
    CHECK_VEC(shade_ray(s, kPoleRay), Vec3d(8, 2, 1) * (0.65 / kPi));
    // Light level with the surface (n.l = 0) or below it: nothing.
    s.point_lights[0].position = {0, 2, 1};
    CHECK_VEC(shade_ray(s, kPoleRay), Vec3d(0, 0, 0));
    s.point_lights[0].position = {0, 0, -3};
    CHECK_VEC(shade_ray(s, kPoleRay), Vec3d(0, 0, 0));
    // A light exactly at the surface point has no direction: nothing, and no NaN.
    s.point_lights[0].position = {0, 0, 1};
    CHECK_VEC(shade_ray(s, kPoleRay), Vec3d(0, 0, 0));
}

TEST_CASE("shade: lights add up") {
    Scene s = pole_scene();
    s.ambient = AmbientLight{{1, 1, 1}, 1.0};                                       // 0.25
    s.directional_lights.push_back({{0, 0, 1}, {1, 1, 1}, 2.0, false});             // 0.65*2/pi
    s.point_lights.push_back({{0, 0, 3}, {1, 1, 1}, 4.0, Attenuation::inverse_square, false});  // 0.65*4/4/pi
    CHECK_VEC(shade_ray(s, kPoleRay), kCd * (0.25 + 0.65 * 3 / kPi));
}

// Plane y=-1 (normal +y); the view ray straight down at x=2 hits p=(2,-1,0), n=(0,1,0).
// A sphere at (0.5,0.5,0), r=0.5 sits on the line from p toward (-1,1,0): the line
// x+y=1 passes through its centre. It is not on the view ray (x=2).
namespace {

Scene blocker_scene() {
    Scene s;
    s.materials.push_back({"m", 0.25, 0.65, {1, 0.5, 0.25}});
    s.objects.push_back({Plane{{0, -1, 0}, {0, 1, 0}}, 0});
    s.objects.push_back({Sphere{{0.5, 0.5, 0}, 0.5}, 0});
    return s;
}
const Ray kBlockerView{{2, 5, 0}, {0, -1, 0}};

}  // namespace

TEST_CASE("shade: shadows on and off") {
    Scene s = blocker_scene();
    const Ray& view = kBlockerView;
    REQUIRE(trace(s, view).object == 0);
    const double r2 = 1 / std::sqrt(2.0);
    // Directional toward (-1,1,0)/sqrt2: n.l = 1/sqrt2; unshadowed L = 0.65/pi * cd / sqrt2.
    s.directional_lights.push_back({{-r2, r2, 0}, {1, 1, 1}, 1.0, false});
    CHECK_VEC(shade_ray(s, view), kCd * (0.65 / kPi * r2));
    s.directional_lights[0].shadows = true;
    CHECK_VEC(shade_ray(s, view), Vec3d(0, 0, 0));
    // Straight up nothing blocks, and the plane does not shadow itself: 0.65/pi * cd.
    s.directional_lights[0].direction = {0, 1, 0};
    CHECK_VEC(shade_ray(s, view), kCd * (0.65 / kPi));

    // Point light behind the sphere at (-1,2,0): to light (-3,3,0), n.l = 1/sqrt2; blocked.
    s.directional_lights.clear();
    s.point_lights.push_back({{-1, 2, 0}, {1, 1, 1}, 1.0, Attenuation::none, false});
    CHECK_VEC(shade_ray(s, view), kCd * (0.65 / kPi * r2));
    s.point_lights[0].shadows = true;
    CHECK_VEC(shade_ray(s, view), Vec3d(0, 0, 0));
    // Point light between p and the sphere, at (1.5,-0.5,0): the sphere is beyond r -> lit.
    s.point_lights[0].position = {1.5, -0.5, 0};
    CHECK_VEC(shade_ray(s, view), kCd * (0.65 / kPi * r2));
}

TEST_CASE("shade's parts: ambient_term, lambertian_brdf, shadowed") {
    const Material m{"m", 0.25, 0.65, {1, 0.5, 0.25}};
    Scene s = blocker_scene();
    CHECK_VEC(ambient_term(s, m), Vec3d(0, 0, 0));  // no ambient light
    // ls cl = 2 (1, 0.5, 2) = (2, 1, 4); ka cd * that = 0.25 (2, 0.5, 1) = (0.5, 0.125, 0.25).
    s.ambient = AmbientLight{{1, 0.5, 2}, 2.0};
    CHECK_VEC(ambient_term(s, m), Vec3d(0.5, 0.125, 0.25));
    CHECK_VEC(lambertian_brdf(m), kCd * (0.65 / kPi));

    // The blockers of "shadows on and off", asked directly.
    const Hit h = trace(s, kBlockerView);
    REQUIRE(h.object == 0);
    const double r2 = 1 / std::sqrt(2.0);
    DirectionalLight toward_sphere{{-r2, r2, 0}, {1, 1, 1}, 1.0, true};
    CHECK(shadowed(s, h, toward_sphere));
    toward_sphere.shadows = false;  // a light without shadows is never shadowed
    CHECK_FALSE(shadowed(s, h, toward_sphere));
    CHECK_FALSE(shadowed(s, h, DirectionalLight{{0, 1, 0}, {1, 1, 1}, 1.0, true}));  // nothing above p
    PointLight behind{{-1, 2, 0}, {1, 1, 1}, 1.0, Attenuation::none, true};
    CHECK(shadowed(s, h, behind));
    behind.position = {1.5, -0.5, 0};  // between p and the sphere
    CHECK_FALSE(shadowed(s, h, behind));
}

TEST_CASE("shade: a shadowed sphere's lit pole does not shadow itself") {
    Scene s = pole_scene();
    s.directional_lights.push_back({{0, 0, 1}, {1, 1, 1}, 1.0, true});
    s.point_lights.push_back({{0, 0, 3}, {1, 1, 1}, 1.0, Attenuation::none, true});
    CHECK_VEC(shade_ray(s, kPoleRay), kCd * (0.65 * 2 / kPi));
    // A far blocker along the directional light still blocks ("any hit"), the point light is not blocked.
    s.objects.push_back({Sphere{{0, 0, 1e6}, 1}, 0});
    CHECK_VEC(shade_ray(s, kPoleRay), kCd * (0.65 / kPi));
}

TEST_CASE("shade: convex objects never shadow themselves (shadow-ray offset)") {
    // A lone convex object cannot block its own light, so the image with shadows
    // on must equal the one with shadows off, pixel for pixel. Off-grid sizes and
    // a tilted plane make hit points land a rounding error below the surface.
    Scene s;
    s.materials.push_back({"m", 0.1, 0.8, {0.9, 0.7, 0.3}});
    s.camera = {CameraType::pinhole, {0.3, 1.7, 4.9}, {0.1, -0.2, 0.05}, {0, 1, 0}, 41, 0, 37, 29};
    s.directional_lights.push_back({{0.48, 0.6, 0.64}, {1, 1, 1}, 1.3, false});
    s.point_lights.push_back({{-2.1, 3.3, 1.7}, {1, 0.9, 0.8}, 7.0, Attenuation::inverse_square, false});
    const Shape shapes[] = {Sphere{{0.13, -0.21, 0.07}, 1.09},
                            Plane{{0.1, -0.7, 0.3}, {0.36, 0.8, 0.48}}};
    for (const Shape& shape : shapes) {
        s.objects = {{shape, 0}};
        s.directional_lights[0].shadows = s.point_lights[0].shadows = false;
        const Image<double> lit = render(s);
        s.directional_lights[0].shadows = s.point_lights[0].shadows = true;
        const Image<double> shadowed = render(s);
        REQUIRE(lit.rgb.size() == std::size_t(3 * 37 * 29));  // the whole image, not an empty one
        REQUIRE(shadowed.rgb.size() == lit.rgb.size());
        int differ = 0, on_object = 0;  // on the object: radiance > 0 (the background is black)
        for (std::size_t k = 0; k < lit.rgb.size(); ++k) differ += lit.rgb[k] != shadowed.rgb[k], on_object += lit.rgb[k] > 0;
        CHECK(on_object > 0);
        CHECK(differ == 0);
    }
}
