// The triangle hit's distance t against the double reference, in every
// precision mode on every ISA unit this CPU runs: the bound docs/accuracy.md
// states, on triangles far out, small and seen at grazing angles.
#include <doctest/doctest.h>

#include "precision_units.hpp"
#include "support.hpp"

#include <octray/kernels.hpp>
#include <octray/reference.hpp>

#include <algorithm>
#include <cmath>

using namespace octray;
using namespace octray::precision_test;

// Triangle hits, the watertight test's t (kernels/geometry/triangle.hpp): within
//     |t - t_ref| <= div_bound(mode) |t| + 8 u (|t| + S / |d|) / cos
// (S: the triangle's diameter, cos = |n.d| / |d|) on every unit and mode,
// for triangles 1 to 2^14 units out, 2^-12 to 1 of their distance across,
// rays from half to twice that distance away, aimed inside the triangle at
// cos from 1 down to 2^-10, |d| from 2^-4 to 2^4. Inputs float-exact; the
// reference is the double test.
TEST_CASE("triangle hits: t within the stated bound far out, small and at grazing angles, in every mode") {
    constexpr double u = kUnitRoundoff;
    constexpr double kBound = 8;
    for_each_unit_mode([&](const kernels::Unit& unit, Precision p) {
        CAPTURE(unit_name(unit, p));
        const Kernel k = unit.kernel(p, kAllFeatures, kAllFeatures);
        Rng rng(2026);
        auto unit_vec = [&]() {
            for (;;) {
                const Vec3d v{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
                const double l2 = dot(v, v);
                if (l2 > 1e-4 && l2 <= 1) return v * (1 / std::sqrt(l2));
            }
        };
        double worst = 0;
        int hits = 0, lanes = 0;
        for (int tri = 0; tri < 96; ++tri) {
            const double dist = std::exp2(rng.uniform(0, 14)), size = dist * std::exp2(rng.uniform(-12, 0));
            const Vec3d centre = unit_vec() * dist;
            const Triangle shape{test::fl(centre + unit_vec() * size), test::fl(centre + unit_vec() * size),
                                 test::fl(centre + unit_vec() * size)};
            const Vec3d e1 = shape.v1 - shape.v0, e2 = shape.v2 - shape.v0;
            Vec3d n = cross(e1, e2);
            if (dot(n, n) < 1e-6 * dot(e1, e1) * dot(e2, e2)) continue;  // a sliver: its normal is not the point
            n = n * (1 / std::sqrt(dot(n, n)));
            const double diameter =
                std::sqrt(std::max({dot(e1, e1), dot(e2, e2), dot(shape.v2 - shape.v1, shape.v2 - shape.v1)}));
            const Scene scene = test::one_object_scene(shape);
            const PacketScene ps = compile(scene);
            for (int packet = 0; packet < 4; ++packet) {
                RayPacket8 rp;
                reference::Ray refs[8];
                for (int i = 0; i < 8; ++i) {
                    // A point inside the triangle, seen at cos in [2^-10, 1] from about dist away.
                    const double b1 = rng.uniform(0.05, 0.9), b2 = rng.uniform(0.05, 0.95 - b1);
                    const Vec3d target = shape.v0 + e1 * b1 + e2 * b2;
                    const double cosine = std::exp2(rng.uniform(-10, 0));
                    Vec3d side = cross(n, unit_vec());
                    side = side * (1 / std::sqrt(dot(side, side)));
                    const Vec3d dir = n * (rng.uniform(0, 1) < 0.5 ? cosine : -cosine) + side * std::sqrt(1 - cosine * cosine);
                    const Vec3d o = test::fl(target - dir * (dist * rng.uniform(0.5, 2)));
                    const Vec3d d = test::fl(dir * std::exp2(rng.uniform(-4, 4)));
                    refs[i] = {o, d};
                    test::set_ray(rp, i, o, d);
                }
                HitPacket8 hp;
                REQUIRE(k.intersect(ps, rp, hp) == 0);
                for (int i = 0; i < 8; ++i) {
                    ++lanes;
                    const auto t = reference::intersect(Shape{shape}, refs[i], 0, 1e300);
                    if (!t || hp.hit[i] == 0) continue;  // an edge within rounding: the hit tests cover those
                    ++hits;
                    const double len = std::sqrt(dot(refs[i].direction, refs[i].direction));
                    const double cosine = std::fabs(dot(n, refs[i].direction)) / len;
                    const double dt = std::fabs(double(hp.t[i]) - *t) - div_bound(p) * *t;
                    worst = std::max(worst, dt / (u * (*t + diameter / len) / cosine));
                }
            }
        }
        MESSAGE(unit_name(unit, p) << ": " << hits << " hits of " << lanes << " lanes, worst "
                                   << worst << " u (|t| + S/|d|)/cos beyond the division's");
        CHECK(hits > lanes * 9 / 10);
        CHECK(worst <= kBound);
    });
}
