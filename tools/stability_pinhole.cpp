// tools/stability_pinhole.cpp — small spheres seen through a pinhole camera:
// every ray from one eye, in a direction rounded to float (a camera kernel's
// ray: ~u per component, never exact as an orthographic camera's down an
// axis). The normal is checked against the reference's on the same float ray,
// so the rounding of the direction is an input here, and what is left is
// the kernels' own error: a few u, with the one 1/cos of h near the outline
// (precision.hpp, sphere_normal_bound), whatever t/r and the ray's angle.
#include "stability_check.hpp"

#include <cmath>
#include <random>
#include <vector>

namespace octray::stability::detail {

namespace {

// A camera eye that is not exact in float's coarse grid (scenes/default.json's).
Vec3d eye() { return fl(Vec3d{0, 2.4, 8}); }

}  // namespace

// A sphere of radius 0.04 at 12 units, 55 degrees off the view axis of a
// 120-degree pinhole (t/r = 300), seen from two eyes; rays through its centre
// and out to 0.99999 of its radius (cos = 0.0045), in three directions each.
Measure pinhole_wide_outline(const Tracer& tr) {
    Measure m;
    const double off = 55 * kPi / 180;
    for (const Vec3d& o : {Vec3d{0, 0, 0}, eye()})
        for (double around : {0.5, 2.6}) {
            const Vec3d axis{std::sin(off) * std::cos(around), std::sin(off) * std::sin(around), -std::cos(off)};
            const Vec3d c = fl(o + axis * 12.0);
            const double r = fl(0.04);
            merge(m, measure_frame(tr, scene_of({Sphere{c, r}}),
                                   sphere_probe(o, c, r, {0.0, 0.5, 0.9, 0.99, 0.999, 0.9999, 0.99999})));
        }
    return m;
}

// 400 spheres of radius 1e-3 at 100 to 100.05 units inside a 3-degree cone
// (t/r = 1e5), from a float eye; rays at 64 of them, across their disks and
// near their outlines (others may be hit first: whatever is hit is checked).
Measure pinhole_far_field(const Tracer& tr) {
    std::mt19937 rng(19);
    const Vec3d o = eye();
    const double half = std::tan(1.5 * kPi / 180);
    std::vector<Shape> shapes;
    std::vector<Sphere> aimed;
    for (int k = 0; k < 400; ++k) {
        const double dist = uniform(rng, 100, 100.05);
        const Vec3d c = fl(o + Vec3d{uniform(rng, -half, half) * dist, uniform(rng, -half, half) * dist * 0.75, -dist});
        const Sphere sp{c, fl(1e-3)};
        shapes.push_back(sp);
        if (k < 64) aimed.push_back(sp);
    }
    std::vector<Lane> lanes;
    for (const Sphere& sp : aimed)
        for (const Lane& l : sphere_probe(o, sp.center, sp.radius, {0.3, 0.9, 0.99, 0.999})) lanes.push_back(l);
    return measure_frame(tr, scene_of(std::move(shapes)), lanes);
}

}  // namespace octray::stability::detail
