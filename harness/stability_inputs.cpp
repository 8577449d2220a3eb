// harness/stability_inputs.cpp — the input cases of the stability catalogue: zero,
// NaN and infinite directions (masked, counted, background), subnormal inputs
// with flush-to-zero and denormals-are-zero off and on, coordinates near 1e19.
#include "stability_check.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>
#include <type_traits>
#include <variant>
#include <vector>

namespace octray::stability::detail {

namespace {

Scene validity_scene() { return scene_of({Sphere{{0, 0, 5}, 2}, Plane{{0, 0, 10}, {0, 0, 1}}}); }

Measure degenerate(const Tracer& tr, const std::vector<Lane>& bad) {
    const Scene s = validity_scene();
    std::vector<Lane> lanes = bad;
    std::vector<bool> masked(bad.size(), true);
    for (const Lane& l : down_onto({{0, 0}, {1, 1}, {5, 5}}, -1)) lanes.push_back({l.o, {0, 0, 1}}), masked.push_back(false);
    const Traced t = run(tr, s, lanes);
    Measure m = check_masked(s, lanes, t, masked);
    std::vector<Lane> good = lanes;
    for (std::size_t i = 0; i < good.size(); ++i) good[i].active = !masked[i];
    const Measure h = check_all(s, good, t);
    if (!h.pass) {
        if (m.pass) m.note = h.note;
        m.pass = false;
        m.error = std::max(m.error, 1.0);
    }
    add_note(m, t);
    return m;
}

// Denormals-are-zero reads a subnormal input as 0: the right answer is the
// reference's on the inputs as given or on the inputs with subnormals zeroed.
Vec3d flush(const Vec3d& v) {
    auto f = [](double x) { return std::fabs(x) < FLT_MIN ? std::copysign(0.0, x) : x; };
    return {f(v.x), f(v.y), f(v.z)};
}

}  // namespace

Measure zero_direction(const Tracer& tr) {
    return degenerate(tr, {{{0, 0, 0}, {0, 0, 0}},
                           {{0, 0, 0}, {-0.0, 0, -0.0}},
                           {{1, 2, 3}, {fl(1e-30), 0, 0}},         // |d|^2 underflows
                           {{0, 0, 0}, {fl(1e-20), fl(1e-20), 0}}}); // |d|^2 subnormal
}

Measure nan_direction(const Tracer& tr) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::vector<Lane> lanes = {{{0, 0, 0}, {nan, 0, 1}}, {{0, 0, 0}, {0, nan, 1}}, {{0, 0, 0}, {0, 0, nan}},
                               {{nan, 0, 0}, {0, 0, 1}}, {{0, 0, 0}, {0, 0, 1}, nan, kInf}, {{0, 0, 0}, {0, 0, 1}, 0, nan}};
    return degenerate(tr, lanes);
}

Measure inf_direction(const Tracer& tr) {
    return degenerate(tr, {{{0, 0, 0}, {kInf, 0, 0}},
                           {{0, 0, 0}, {-kInf, 1, 1}},
                           {{0, 0, 0}, {0, 0, kInf}},
                           {{0, kInf, 0}, {0, 0, 1}},
                           {{0, 0, 0}, {fl(1e20), 0, 1}}});  // |d| >= 2^63: no normal 1/|d|^2
}

Measure subnormals(const Tracer& tr, bool ftz_daz) {
    const double s1 = fl(1e-40), s2 = fl(3e-39), s3 = fl(-7e-41);
    auto build = [&](bool zeroed) {
        auto z = [&](const Vec3d& v) { return zeroed ? flush(v) : v; };
        Scene s = scene_of({Sphere{z({s1, 0, 3}), 1}, Box{{0, -2, 6}, {1, -1, 7}}, Plane{z({0, 0, 12 + 0.0}), {0, 0, 1}},
                            Triangle{z({s2, 1, 8}), {1, 1, 8}, {0, 2, 8}}});
        s.materials[0] = matte("m", {1, 1, 1}, 0.0, 0.65);
        s.directional_lights.push_back({{0, 0, 1}, {1, 1, 1}, 1.0, false});  // lights what is hit from above
        // Lights what is hit from below, with a subnormal radiance (2e-38 kd / pi).
        s.point_lights.push_back({z({s2, s1, 0}), {1, 1, 1}, fl(2e-38), Attenuation::none, false});
        return s;
    };
    // Lane 2 starts a subnormal outside the box's x = 0 face, parallel to it:
    // a miss as given, a hit (on the face) with denormals-are-zero.
    std::vector<Lane> lanes = {{{s1, s3, 0}, {0, 0, 1}}, {{0, 0, 0}, {s2, 0, 1}}, {{s3, -1.5, 0}, {0, 0, 1}},
                               {{0, -1.5, 0}, {s1, 0, 1}}, {{s2, 1.25, 0}, {0, 0, 1}}, {{0.25, 1.25, 0}, {s3, s1, 1}},
                               {{0, 0, 0}, {0, 0, 1}, s1, kInf}, {{s3, 0.5, 20}, {0, 0, -1}}};
    const Scene as_given = build(false);
    const Traced t = run(tr, as_given, lanes, ftz_daz);
    Measure m = check_all(as_given, lanes, t);
    if (ftz_daz && !m.pass) {
        std::vector<Lane> zl = lanes;
        for (Lane& l : zl) l.o = flush(l.o), l.d = flush(l.d), l.tmin = std::fabs(l.tmin) < FLT_MIN ? 0 : l.tmin;
        const Scene zeroed = build(true);
        const Measure z = check_all(zeroed, zl, t);
        if (z.pass) m = z;
    }
    add_note(m, t);
    return m;
}

Measure huge_coordinates(const Tracer& tr) {
    const double e = 1e19;
    Scene s = scene_of({Sphere{{e, 0, 0}, 2e18}, Box{{0.9 * e, 0.4 * e, -0.1 * e}, {1.1 * e, 0.6 * e, 0.1 * e}},
                        Triangle{{e, -0.6 * e, -0.1 * e}, {e, -0.4 * e, -0.1 * e}, {e, -0.5 * e, 0.1 * e}},
                        Disk{{e, 0, 0.5 * e}, {-1, 0, 0}, 0.05 * e}, Plane{{2 * e, 0, 0}, {-1, 0, 0}}});
    for (Object& o : s.objects)
        std::visit([](auto& p) {
            using P = std::decay_t<decltype(p)>;
            if constexpr (std::is_same_v<P, Sphere>) p.center = fl(p.center), p.radius = fl(p.radius);
            else if constexpr (std::is_same_v<P, Box>) p.min = fl(p.min), p.max = fl(p.max);
            else if constexpr (std::is_same_v<P, Triangle>) p.v0 = fl(p.v0), p.v1 = fl(p.v1), p.v2 = fl(p.v2);
            else if constexpr (std::is_same_v<P, Disk>) p.center = fl(p.center);
            else if constexpr (std::is_same_v<P, Plane>) p.point = fl(p.point);
        }, o.shape);
    s.materials[0] = matte("m", {1, 1, 1}, 0.1, 0.65);
    s.ambient = AmbientLight{{1, 1, 1}, 0.5};
    s.directional_lights.push_back({dir(-1, 0.5, 0.25), {1, 1, 1}, 1.0, false});
    s.point_lights.push_back({fl(Vec3d{-e, 2 * e, e}), {1, 1, 1}, 1.0, Attenuation::none, false});
    const Vec3d o = fl(Vec3d{-e, 0, 0});
    std::vector<Lane> lanes;
    for (const Vec3d& target : {Vec3d{e, 0, 0}, Vec3d{e, 0.1 * e, 0.05 * e}, Vec3d{0.9 * e, 0.5 * e, 0}, Vec3d{0.95 * e, 0.45 * e, 0.05 * e},
                                Vec3d{e, -0.5 * e, -0.05 * e}, Vec3d{e, -0.45 * e, -0.08 * e}, Vec3d{e, 0.01 * e, 0.5 * e},
                                Vec3d{2 * e, 0.3 * e, -0.3 * e}, Vec3d{2 * e, -0.9 * e, 0.9 * e}})
        lanes.push_back(toward(o, target));
    lanes.push_back({fl(Vec3d{0.5 * e, 0, 0}), {1, 0, 0}});  // origin at 5e18: f = -5e18, t = 3e18
    lanes.push_back({fl(Vec3d{e, 0, -3 * e}), {0, 0, 1}});   // from below the sphere, |f| = 3e19
    return measure_all(tr, s, lanes);
}

}  // namespace octray::stability::detail
