// harness/stability_lighting.cpp — the lighting cases of the stability catalogue:
// light at grazing incidence, terms 60 decades apart, 64 lights summed, point
// lights near and at the hit point, radiance past FLT_MAX.
#include "stability_check.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace octray::stability::detail {

namespace {

Scene lit_plane() {
    Scene s = scene_of({Plane{{0, 0, 0}, {0, 0, 1}}});
    s.materials[0] = matte("m", {1, 0.5, 0.25}, 0.0, 0.65);
    return s;
}

// The summation alone, on the terms the kernel adds (ls cl n.l [/r^2], red
// channel, in the kernel's order: directional, point, attenuated point), each
// rounded to float: the float recursive sum and Kahan's compensated sum
// against the exact sum, in units of u, worst lane.
std::string summation_study(const Scene& s, const std::vector<Lane>& lanes) {
    double naive_err = 0, kahan_err = 0;
    for (const Lane& l : lanes) {
        const reference::Hit h = ref_trace(s, l);
        if (h.object < 0) continue;
        std::vector<double> terms;
        for (const DirectionalLight& d : s.directional_lights)
            if (const double ndl = dot(h.normal, unit_direction(d.direction)); ndl > 0)
                terms.push_back(fl(d.color.x * d.ls) * fl(ndl));
        for (Attenuation att : {Attenuation::none, Attenuation::inverse_square})
            for (const PointLight& p : s.point_lights) {
                if (p.attenuation != att) continue;
                const Vec3d v = p.position - h.point;
                const double r2 = dot(v, v), ndl = dot(h.normal, v) / std::sqrt(r2);
                if (ndl > 0) terms.push_back(fl(p.color.x * p.ls) * fl(att == Attenuation::none ? ndl : ndl / r2));
            }
        long double exact = 0;
        float naive = 0, kahan = 0, carry = 0;
        for (double x : terms) {
            exact += x;
            naive = float(double(naive) + x);  // one FMA: the product exact, one rounding
            const float y = float(x) - carry, sum = kahan + y;
            carry = (sum - kahan) - y;
            kahan = sum;
        }
        if (exact <= 0) continue;
        naive_err = std::max(naive_err, double(std::fabs(naive - exact) / exact) / kUnitRoundoff);
        kahan_err = std::max(kahan_err, double(std::fabs(kahan - exact) / exact) / kUnitRoundoff);
    }
    return fmt("sum alone: recursive %.2f u, Kahan %.2f u (worst case 63 u)", naive_err, kahan_err);
}

}  // namespace

Measure grazing_light(const Tracer& tr) {
    Measure m;
    const std::vector<Lane> lanes = down_onto({{0, 0}, {0.5, 0.25}, {-2, 3}, {100, -50}});
    {
        Scene s = lit_plane();
        s.directional_lights.push_back({dir(1, 0, 1e-7), {1, 1, 1}, 2.0, false});
        merge(m, measure_all(tr, s, lanes, {true, true}, {true}));
    }
    {
        Scene s = lit_plane();
        s.directional_lights.push_back({dir(1, 0, -1e-7), {1, 1, 1}, 2.0, false});  // n.l < 0: nothing
        s.directional_lights.push_back({{0, 1, 0}, {1, 1, 1}, 2.0, false});          // n.l = 0: nothing
        s.point_lights.push_back({fl(Vec3d{1e4, 0, 1e-3}), {1, 1, 1}, 3.0, Attenuation::none, false});
        const Traced t = run(tr, s, lanes);
        merge(m, check_all(s, lanes, t, {true, true}, {true}));
    }
    return m;
}

Measure lights_dynamic_range(const Tracer& tr) {
    Scene s = scene_of({Plane{{0, 0, 0}, {0, 0, 1}}, Sphere{{0, 0, 2}, 0.5}});
    s.materials[0] = matte("m", {1, 0.5, 0.25}, 0.2, 0.65);
    s.ambient = AmbientLight{{1, 1, 1}, 1e-30};
    s.directional_lights.push_back({{0, 0, 1}, {1, 1, 1}, 1e30, false});          // lights the top
    s.directional_lights.push_back({dir(0.6, 0, 0.8), {1, 0.5, 1}, 1e-30, false});  // top, absorbed
    s.directional_lights.push_back({dir(0.6, 0, -0.8), {1, 1, 0.5}, 1e-30, false});  // the underside only
    s.point_lights.push_back({{0.5, 0.25, -2}, {1, 1, 1}, 1e-30, Attenuation::inverse_square, false});
    std::vector<Lane> lanes = down_onto({{0, 0}, {0.25, 0.125}, {2, 1}, {-3, 0.5}}, 5);
    for (const Lane& l : down_onto({{0, 0}, {2, 1}, {-3, 0.5}, {0.5, 0.25}}, -5)) lanes.push_back({l.o, {0, 0, 1}});
    return measure_all(tr, s, lanes);
}

Measure lights_64_decades(const Tracer& tr) {
    Scene s = scene_of({Plane{{0, 0, 0}, {0, 0, 1}}, Sphere{{0, 0, 1.5}, 1}});
    s.materials[0] = matte("m", {0.9, 0.6, 0.3}, 0.0, 0.65);
    std::mt19937 rng(64);
    std::uniform_real_distribution<double> u01(0, 1);
    for (int k = 0; k < 64; ++k) {
        const double ls = std::pow(10.0, -6 + 12.0 * k / 63);
        const Vec3d color{0.2 + 0.8 * u01(rng), 0.2 + 0.8 * u01(rng), 0.2 + 0.8 * u01(rng)};
        if (k % 2 == 0) {
            s.directional_lights.push_back({dir(u01(rng) - 0.5, u01(rng) - 0.5, u01(rng)), color, ls, false});
        } else {
            const Vec3d pos = fl(Vec3d{8 * u01(rng) - 4, 8 * u01(rng) - 4, 1 + 9 * u01(rng)});
            s.point_lights.push_back({pos, color, ls, k % 4 == 1 ? Attenuation::inverse_square : Attenuation::none, false});
        }
    }
    std::vector<Lane> lanes = down_onto({{0, 0}, {0.5, 0.25}, {-0.75, 0.5}, {3, 2}, {-2.5, -3}, {1.5, 0}, {0, -1.25}, {4, 4}}, 6);
    for (int k = 0; k < 8; ++k) lanes.push_back(toward({3.0 - k, 5, 4}, {0.125 * k - 0.5, 0.25, 1.5}));
    const Traced t = run(tr, s, lanes);
    Measure m = check_all(s, lanes, t);
    add_note(m, t);
    if (m.pass && m.note.empty()) m.note = summation_study(s, lanes);
    return m;
}

Measure point_light_near(const Tracer& tr) {
    Scene s = lit_plane();
    const double d = fl(1e-6);
    s.point_lights.push_back({{0, 0, d}, {1, 1, 1}, 1.0, Attenuation::inverse_square, false});
    s.point_lights.push_back({{0, 0, fl(2e-6)}, {1, 0.5, 0.25}, 0.5, Attenuation::none, false});
    const std::vector<Lane> lanes = down_onto({{0, 0}, {d, 0}, {-2 * d, d}, {0, 3 * d}, {fl(0.5e-6), fl(-0.25e-6)}, {10 * d, 0}});
    return measure_all(tr, s, lanes, {true, true}, {true});
}

Measure point_light_zero(const Tracer& tr) {
    // Every lane hits (0, 0, 0) exactly: o = (a, b, 1), d = (-a, -b, -1), t = 1.
    std::vector<Lane> lanes;
    for (const auto& [a, b] : {std::pair{0.0, 0.0}, {0.5, 0.25}, {-1.0, 2.0}, {3.0, -0.75}}) lanes.push_back({{a, b, 1}, {-a, -b, -1}});
    Measure m;
    for (double r : {0.0, 1e-20, 1e-30, 1e-16}) {
        Scene s = lit_plane();
        s.materials[0].ka = 0.25;
        s.ambient = AmbientLight{{1, 1, 1}, 0.5};
        s.point_lights.push_back({{0, 0, fl(r)}, {1, 0, 0.5}, 1.0, Attenuation::inverse_square, false});
        s.point_lights.push_back({fl(Vec3d{r, 0, r}), {0.5, 1, 1}, 2.0, Attenuation::none, false});
        merge(m, measure_all(tr, s, lanes, {true, true}, {true}));
    }
    return m;
}

Measure radiance_overflow(const Tracer& tr) {
    Scene s = scene_of({Plane{{0, 0, 0}, {0, 0, 1}}, Rectangle{{-1, -1, 1}, {2, 0, 0}, {0, 2, 0}}});
    s.materials[0] = matte("red", {1, 0, 0.5}, 0.25, 0.65);
    s.materials.push_back(matte("black", {1, 1, 1}, 0.25, 0.0));  // kd = 0
    s.objects[1].material = 1;
    s.ambient = AmbientLight{{1, 1, 1}, 1.0};
    for (int k = 0; k < 3; ++k) s.directional_lights.push_back({{0, 0, 1}, {1, 1, 1}, 2e38, false});
    s.directional_lights.push_back({{0, 0, -1}, {1, 1, 1}, 1e39, false});  // beyond float: +inf once compiled
    s.directional_lights.push_back({dir(1, 0, 1), {1, 1, 1}, 1e37, false});
    std::vector<Lane> lanes = down_onto({{3, 0}, {-4, 2}, {0, 0}, {0.5, 0.5}}, 5);  // plane (top), rectangle (top)
    for (const auto& [x, y] : {std::pair{3.0, 0.0}, {0.25, 0.5}}) lanes.push_back({{x, y, -5}, {0, 0, 1}});  // undersides
    return measure_all(tr, s, lanes);
}

}  // namespace octray::stability::detail
