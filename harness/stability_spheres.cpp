// harness/stability_spheres.cpp — the sphere cases of the stability catalogue: a
// planet seen from just above it, tiny and far spheres, normals in the sphere's
// frame at large t/r, tangent rays, the camera inside, the origin on the surface.
#include "stability_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <utility>
#include <variant>
#include <vector>

namespace octray::stability::detail {

namespace {

// Planet of radius 1e6 centred at the origin; origin 1 above its surface.
Scene planet_scene() { return scene_of({Sphere{{0, 0, 0}, fl(1e6)}}); }
Vec3d planet_origin() { return {0, fl(1e6 + 1), 0}; }
Lane planet_ray(double theta_deg, double phi_deg) {
    const double th = theta_deg * kPi / 180, ph = phi_deg * kPi / 180;
    return {planet_origin(), dir(std::sin(th) * std::cos(ph), -std::cos(th), std::sin(th) * std::sin(ph))};
}

}  // namespace

// A small or far sphere hit through its centre and at fractions of its radius;
// `miss` fractions beyond it.
std::vector<Lane> sphere_probe(const Vec3d& o, const Vec3d& c, double r, std::initializer_list<double> fractions,
                               Lane (*ray)(const Vec3d&, const Vec3d&)) {
    const Vec3d axis = c - o;
    // Two directions perpendicular to the axis.
    Vec3d e1 = std::fabs(axis.x) < std::fabs(axis.z) ? cross(axis, Vec3d{1, 0, 0}) : cross(axis, Vec3d{0, 0, 1});
    e1 = e1 * (1 / norm(e1));
    Vec3d e2 = cross(axis, e1);
    e2 = e2 * (1 / norm(e2));
    std::vector<Lane> out;
    for (double f : fractions)
        for (int k = 0; k < 3; ++k) {
            const double a = 2 * kPi * k / 3 + f;
            out.push_back(ray(o, c + (e1 * std::cos(a) + e2 * std::sin(a)) * (f * r)));
        }
    return out;
}

namespace {

// ---- sphere hits in the sphere's frame ---------------------------------------
// The normal of every lane where kernel and reference hit the same sphere,
// against the reference's normal on the same float inputs: |n - n_ref| in
// units of u (1 + 1/cos), cos = |n_ref.d| / |d|. The kernels form it from
// the sphere's own frame (kernels/geometry/sphere.hpp, sphere_offset): a few u, and
// near the outline the one 1/cos of h (precision.hpp), whatever t/r.
Measure check_normals(const Scene& scene, const std::vector<Lane>& lanes, const Traced& tr) {
    Measure m;
    for (std::size_t i = 0; i < lanes.size(); ++i) {
        const Lane& l = lanes[i];
        const Out& k = tr.lanes[i];
        if (!l.active || !k.hit) continue;
        const reference::Hit h = ref_trace(scene, l);
        if (h.object != k.object || !std::holds_alternative<Sphere>(scene.objects[std::size_t(h.object)].shape)) continue;
        const double cosine = std::fabs(dot(h.normal, l.d)) / norm(l.d);
        const double err = norm(k.n - h.normal) / (kUnitRoundoff * (1 + 1 / std::max(cosine, std::sqrt(kUnitRoundoff))));
        if (debug()) std::fprintf(stderr, "  lane %zu: cos=%.3g |dn|=%.3g -> %.3g\n", i, cosine, norm(k.n - h.normal), err);
        m.error = std::max(m.error, err);
    }
    return m;
}

// The kernels' normals before they moved to the sphere's frame, for these
// cases' naive column: from their own hit point, n = (o + t d - c) / r, in
// float as they formed it (o + d t rounded per operation, then face-forwarded).
// Its error grows as t/r.
void point_normals(const Scene& scene, const std::vector<Lane>& lanes, Traced& tr) {
    for (std::size_t i = 0; i < lanes.size(); ++i) {
        Out& k = tr.lanes[i];
        if (!k.hit) continue;
        const Sphere* s = std::get_if<Sphere>(&scene.objects[std::size_t(k.object)].shape);
        if (s == nullptr) continue;
        const float t = float(k.t), inv_r = float(1.0 / s->radius);
        auto axis = [&](double o, double d, double c) {
            volatile float step = float(d) * t;  // the kernel built without contraction: no FMA here
            volatile float p = float(o) + step;
            return (p - float(c)) * inv_r;
        };
        Vec3d n{axis(lanes[i].o.x, lanes[i].d.x, s->center.x), axis(lanes[i].o.y, lanes[i].d.y, s->center.y),
                axis(lanes[i].o.z, lanes[i].d.z, s->center.z)};
        if (dot(n, lanes[i].d) > 0) n = n * -1.0;
        k.n = n;
    }
}

}  // namespace

// Hits (t, hit/miss) and sphere normals. The naive tracer runs the SIMD exact
// kernel with point_normals: the formulation these cases replaced.
Measure measure_frame(const Tracer& tr, const Scene& s, const std::vector<Lane>& lanes) {
    Traced t = run(tr.naive ? Tracer{Path::simd, Precision::exact, false} : tr, s, lanes);
    if (tr.naive) point_normals(s, lanes, t);
    Measure m = check_hits(s, lanes, t);
    merge(m, check_normals(s, lanes, t));
    if (tr.naive) m.note = "naive here: the kernels' earlier normals, n = (o + t d - c) / r";
    else add_note(m, t);
    return m;
}

Measure planet(const Tracer& tr) {
    const Scene s = planet_scene();
    std::vector<Lane> lanes;
    // From straight down to past the horizon (at 89.92 degrees from the vertical).
    for (double th : {0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 85.0, 88.0, 89.5, 89.85, 89.95, 90.0, 95.0})
        for (double ph : {0.0, 37.0}) lanes.push_back(planet_ray(th, ph));
    return measure_hits(tr, s, lanes);
}

Measure planet_exact(const Tracer& tr) {
    const Scene s = planet_scene();
    std::vector<Lane> lanes;
    for (double th : {0.0, 5.0, 10.0, 20.0, 30.0})
        for (double ph : {0.0, 45.0, 120.0}) lanes.push_back(planet_ray(th, ph));
    return measure_hits(tr, s, lanes, {true, false});
}

Measure tiny_sphere(const Tracer& tr) {
    const Vec3d c{0, 0, 1};
    const double r = fl(1e-4);
    const Scene s = scene_of({Sphere{c, r}});
    const auto lanes = sphere_probe({0, 0, 0}, c, r, {0.0, 0.5, 0.9, 0.99, 1.2, 3.0});
    return measure_hits(tr, s, lanes);
}

Measure far_sphere(const Tracer& tr, double distance) {
    Measure m;
    for (const Vec3d& axis : {Vec3d{0, 0, 1}, Vec3d{0.6, -0.48, 0.64}}) {
        const Vec3d c = fl(axis * distance);
        const Scene s = scene_of({Sphere{c, 1}});
        const auto lanes = sphere_probe({0, 0, 0}, c, 1, {0.0, 0.3, 0.5, 0.9, 1.5, 3.0});
        merge(m, measure_hits(tr, s, lanes));
    }
    return m;
}

// A sphere of radius 1e-2 at distance 1e3 (t/r = 1e5), through its centre
// and at fractions of its radius out to 0.9999 (cos = 0.014), along two axes.
Measure small_far_outline(const Tracer& tr) {
    Measure m;
    for (const Vec3d& axis : {Vec3d{0, 0, 1}, Vec3d{0.6, -0.48, 0.64}}) {
        const Vec3d c = fl(axis * 1e3);
        const double r = fl(1e-2);
        merge(m, measure_frame(tr, scene_of({Sphere{c, r}}), sphere_probe({0, 0, 0}, c, r, {0.0, 0.5, 0.9, 0.99, 0.999, 0.9999})));
    }
    return m;
}

// 400 spheres of radius 0.01 to 0.05 scattered 10 to 40 units away (t/r up
// to ~4000); rays from the origin at 64 of them, across their disks and near
// their outlines (others may be hit first: whatever is hit is checked).
Measure small_sphere_field(const Tracer& tr) {
    std::mt19937 rng(16);
    std::vector<Shape> shapes;
    std::vector<Sphere> aimed;
    for (int k = 0; k < 400; ++k) {
        const Sphere sp{fl(Vec3d{uniform(rng, -5, 5), uniform(rng, -2, 2), uniform(rng, -40, -10)}), fl(uniform(rng, 0.01, 0.05))};
        shapes.push_back(sp);
        if (k < 64) aimed.push_back(sp);
    }
    std::vector<Lane> lanes;
    for (const Sphere& sp : aimed)
        for (const Lane& l : sphere_probe({0, 0, 0}, sp.center, sp.radius, {0.3, 0.9, 0.99})) lanes.push_back(l);
    return measure_frame(tr, scene_of(std::move(shapes)), lanes);
}

// A sphere of radius 1e3 at distance 1e6 (t/r = 1e3), as small_far_outline.
Measure large_far_sphere(const Tracer& tr) {
    Measure m;
    for (const Vec3d& axis : {Vec3d{0, 0, 1}, Vec3d{0.6, -0.48, 0.64}}) {
        const Vec3d c = fl(axis * 1e6);
        merge(m, measure_frame(tr, scene_of({Sphere{c, 1e3}}), sphere_probe({0, 0, 0}, c, 1e3, {0.0, 0.5, 0.9, 0.99, 0.999})));
    }
    return m;
}

Measure tangent_rays(const Tracer& tr) {
    Measure m;
    {
        const Scene s = scene_of({Sphere{{0, 0, 0}, 1}});
        const double above = fl(1 + 0x1p-23);
        std::vector<Lane> lanes = {
            {{-5, 1, 0}, {1, 0, 0}},        // tangent at (0, 1, 0), t = 5 exactly
            {{0, -3, -1}, {0, 1, 0}},       // tangent at (0, 0, -1)
            {{1, 0, 5}, {0, 0, -1}},        // tangent at (1, 0, 0)
            {{-5, 0, 1}, {2, 0, 0}},        // non-unit direction, t = 2.5
            {{-5, above, 0}, {1, 0, 0}},    // one ulp outside: misses
            {{-5, 0.5, 0}, {1, 0, 0}},      // a clear chord
        };
        // Diagonal tangents: within rounding of tangent, either answer is right.
        for (int k = 0; k < 6; ++k) {
            const double a = 0.7 * k + 0.3;
            const Vec3d touch{std::cos(a) * std::sqrt(0.5), std::sin(a) * std::sqrt(0.5), std::sqrt(0.5)};
            const Vec3d along = dir(-std::sin(a), std::cos(a), 0.3 * k - 0.4);
            Vec3d d = along - touch * dot(along, touch);  // perpendicular to the radius
            d = d * (1 / norm(d));
            lanes.push_back({fl(touch - d * 4), fl(d)});
        }
        merge(m, measure_hits(tr, s, lanes));
    }
    {
        const Scene s = scene_of({Sphere{{0, 0, 0}, 1024}});
        const std::vector<Lane> lanes = {{{-4096, 1024, 0}, {1, 0, 0}}, {{0, -1024, 5000}, {0, 0, -1}}};
        merge(m, measure_hits(tr, s, lanes));
    }
    return m;
}

Measure camera_inside(const Tracer& tr) {
    Measure m;
    {
        const Scene s = scene_of({Sphere{{0, 0, 0}, 1}});
        std::vector<Lane> lanes;
        for (const Vec3d& o : {Vec3d{0, 0, 0}, Vec3d{0.5, 0.25, -0.125}, Vec3d{0, 0, fl(1 - 0x1p-20)}})
            for (const Vec3d& d : {Vec3d{0, 0, 1}, Vec3d{0, 0, -1}, dir(1, 2, 3), dir(-3, 1, -0.5)}) lanes.push_back({o, d});
        merge(m, measure_hits(tr, s, lanes));
    }
    {
        const Scene s = planet_scene();
        const Vec3d o{0, 999999, 0};  // 1 below the surface, inside
        std::vector<Lane> lanes;
        for (const Vec3d& d : {Vec3d{0, 1, 0}, dir(0.1, 1, 0), dir(1, 0.001, 0), Vec3d{1, 0, 0}, Vec3d{0, -1, 0}, dir(1, -1, 1)})
            lanes.push_back({o, d});
        merge(m, measure_hits(tr, s, lanes));
    }
    return m;
}

Measure origin_on_surface(const Tracer& tr) {
    const Scene s = scene_of({Sphere{{0, 0, 0}, 1}});
    std::vector<Lane> lanes;
    for (const Vec3d& o : {Vec3d{1, 0, 0}, Vec3d{0, -1, 0}, Vec3d{0, 0, 1}})
        for (const Vec3d& d : {o * 1.0, o * -1.0, cross(o, Vec3d{0.5, 0.25, 0.75}), dir(-o.x + 0.3, -o.y + 0.4, -o.z - 0.2),
                               dir(-o.x - 0.5, -o.y + 0.1, -o.z + 0.7)})
            lanes.push_back({o, fl(d)});
    return measure_hits(tr, s, lanes, {false, false});
}

}  // namespace octray::stability::detail
