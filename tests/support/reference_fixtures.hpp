// tests/support/reference_fixtures.hpp — what the reference tests (test_reference*.cpp)
// share: tolerances, the vector and t checks, and the pole scene and 5x3 camera
// their hand-worked values start from.
#pragma once

#include <octray/reference.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <limits>
#include <optional>

namespace reference_fixtures {

using namespace octray;
using namespace octray::reference;

inline constexpr double kInf = std::numeric_limits<double>::infinity();
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Relative tolerance 1e-12 (doctest's Approx also allows 1e-12 absolute near 0).
inline doctest::Approx near(double x) { return doctest::Approx(x).epsilon(1e-12); }

#define CHECK_VEC(a, b)                                   \
    do {                                                  \
        const Vec3d a_ = (a), b_ = (b);                   \
        CHECK(a_.x == near(b_.x));                        \
        CHECK(a_.y == near(b_.y));                        \
        CHECK(a_.z == near(b_.z));                        \
    } while (0)

// The next double above x: the first value past a boundary.
inline double up(double x) { return std::nextafter(x, kInf); }

inline std::optional<double> hit(const Shape& s, Vec3d o, Vec3d d, double tmin = 0.0, double tmax = kInf) {
    return intersect(s, Ray{o, d}, tmin, tmax);
}

// Checks an intersection parameter: present and equal to t.
#define CHECK_T(result, t)               \
    do {                                 \
        const auto r_ = (result);        \
        REQUIRE(r_.has_value());         \
        CHECK(*r_ == near(t));           \
    } while (0)

inline const Vec3d kDown{0, 0, -1};  // the most common test direction: along -z

// Unit sphere at the origin, matte ka=0.25 kd=0.65 cd=(1,0.5,0.25); the view
// ray from (0,0,5) along -z hits the pole p=(0,0,1) with n=(0,0,1).
inline Scene pole_scene() {
    Scene s;
    s.materials.push_back({"m", 0.25, 0.65, {1, 0.5, 0.25}});
    s.objects.push_back({Sphere{{0, 0, 0}, 1.0}, 0});
    return s;
}
inline const Ray kPoleRay{{0, 0, 5}, kDown};
inline const Vec3d kCd{1, 0.5, 0.25};

inline Vec3d shade_ray(const Scene& s, const Ray& r) { return shade(s, r, trace(s, r)); }

// The 5x3 camera most tests use: looking at the origin, up +y, fov 90
// (tan 45deg = 1) or height_world 2 (half height 1), so both types share sx, sy.
inline Camera camera_5x3(CameraType type, const Vec3d& eye) {
    Camera cam;
    cam.type = type;
    cam.eye = eye;
    cam.fov_y = 90;
    cam.height_world = 2;
    cam.width = 5;
    cam.height = 3;
    return cam;
}

}  // namespace reference_fixtures
