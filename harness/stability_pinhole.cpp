// harness/stability_pinhole.cpp — small spheres seen through a pinhole camera:
// every ray from one eye, in a direction no orthographic camera's axis is.
// Two kinds of input. Float: eye, centres and directions rounded to float,
// the reference tracing those same floats, so what is left is the kernels'
// own error. Double: eye, centres and directions as authored in double, the
// rays carried as float + residual (the camera kernel's rays) and the
// centres' residuals kept by compile(), the reference tracing the doubles;
// rounded alone they would move a hit by ~u t, a normal by ~u t / r. Either
// way the normal is a few u, with the one 1/cos of h near the outline
// (precision.hpp, sphere_normal_bound), whatever t/r and the ray's angle.
#include "stability_check.hpp"

#include <cmath>
#include <random>
#include <vector>

namespace octray::stability::detail {

namespace {

// scenes/default.json's camera eye: 2.4 is not a float.
const Vec3d kEye{0, 2.4, 8};

Vec3d as_float(const Vec3d& v) { return fl(v); }
Vec3d as_double(const Vec3d& v) { return v; }

// A sphere of radius 0.04 at 12 units, 55 degrees off the view axis of a
// 120-degree pinhole (t/r = 300), seen from two eyes; rays through its centre
// and out to 0.99999 of its radius (cos = 0.0045), in three directions each.
Measure wide_outline(const Tracer& tr, bool exact) {
    Measure m;
    const double off = 55 * kPi / 180;
    const auto input = exact ? as_double : as_float;
    for (const Vec3d& o : {Vec3d{0, 0, 0}, input(kEye)})
        for (double around : {0.5, 2.6}) {
            const Vec3d axis{std::sin(off) * std::cos(around), std::sin(off) * std::sin(around), -std::cos(off)};
            const Vec3d c = input(o + axis * 12.0);
            const double r = fl(0.04);
            merge(m, measure_frame(tr, scene_of({Sphere{c, r}}),
                                   sphere_probe(o, c, r, {0.0, 0.5, 0.9, 0.99, 0.999, 0.9999, 0.99999},
                                                exact ? toward_exact : toward)));
        }
    return m;
}

// 400 spheres of radius 1e-3 at 100 to 100.05 units inside a 3-degree cone
// (t/r = 1e5), from default.json's eye; rays at 64 of them, across their
// disks and near their outlines (others may be hit first: whatever is hit is
// checked).
Measure far_field(const Tracer& tr, bool exact) {
    std::mt19937 rng(19);
    const auto input = exact ? as_double : as_float;
    const Vec3d o = input(kEye);
    const double half = std::tan(1.5 * kPi / 180);
    std::vector<Shape> shapes;
    std::vector<Sphere> aimed;
    for (int k = 0; k < 400; ++k) {
        const double dist = uniform(rng, 100, 100.05);
        const Vec3d c = input(o + Vec3d{uniform(rng, -half, half) * dist, uniform(rng, -half, half) * dist * 0.75, -dist});
        const Sphere sp{c, fl(1e-3)};
        shapes.push_back(sp);
        if (k < 64) aimed.push_back(sp);
    }
    std::vector<Lane> lanes;
    for (const Sphere& sp : aimed)
        for (const Lane& l : sphere_probe(o, sp.center, sp.radius, {0.3, 0.9, 0.99, 0.999}, exact ? toward_exact : toward))
            lanes.push_back(l);
    return measure_frame(tr, scene_of(std::move(shapes)), lanes);
}

}  // namespace

Measure pinhole_wide_outline(const Tracer& tr) { return wide_outline(tr, false); }
Measure pinhole_far_field(const Tracer& tr) { return far_field(tr, false); }
Measure pinhole_wide_outline_double(const Tracer& tr) { return wide_outline(tr, true); }
Measure pinhole_far_field_double(const Tracer& tr) { return far_field(tr, true); }

}  // namespace octray::stability::detail
