// harness/stability_check.cpp — the measuring side of the stability catalogue
// (stability_check.hpp): running a Tracer on a case's lanes and checking hits,
// radiance and masked lanes against the double reference (the error model is
// in stability_cases.hpp).
#include "stability_check.hpp"

#include "reference/reference_parts.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <random>
#include <string>
#include <type_traits>
#include <variant>

#include <immintrin.h>

namespace octray::stability::detail {

namespace {

bool finite3(const Vec3d& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
double comp(const Vec3d& v, int k) { return k == 0 ? v.x : k == 1 ? v.y : v.z; }

// MXCSR flush-to-zero (bit 15) and denormals-are-zero (bit 6), set or cleared
// around the kernel calls and restored afterwards.
class Mxcsr {
public:
    explicit Mxcsr(bool flush) : saved_(_mm_getcsr()) { _mm_setcsr(flush ? saved_ | 0x8040u : saved_ & ~0x8040u); }
    ~Mxcsr() { _mm_setcsr(saved_); }
    Mxcsr(const Mxcsr&) = delete;
    Mxcsr& operator=(const Mxcsr&) = delete;

private:
    unsigned saved_;
};

double mode_eps(Precision p) { return std::max(div_bound(p), rsqrt_bound(p)); }

// Size and position of a primitive: what its float coordinates are rounded against.
double primitive_scale(const Shape& shape) {
    return std::visit(
        [](const auto& s) -> double {
            using S = std::decay_t<decltype(s)>;
            if constexpr (std::is_same_v<S, Sphere>) return norm(s.center) + s.radius;
            else if constexpr (std::is_same_v<S, Plane>) return norm(s.point);
            else if constexpr (std::is_same_v<S, Disk>) return norm(s.center) + s.radius;
            else if constexpr (std::is_same_v<S, Rectangle>) return norm(s.corner) + norm(s.a) + norm(s.b);
            else if constexpr (std::is_same_v<S, Box>) return std::max(norm(s.min), norm(s.max));
            else return std::max({norm(s.v0), norm(s.v1), norm(s.v2)});
        },
        shape);
}

void fail(Measure& m, const std::string& why) {
    if (m.pass) m.note = why;
    m.pass = false;
    m.error = kInf;
}

void note_lane(Measure& m, std::size_t i, const std::string& why) { fail(m, "lane " + std::to_string(i) + ": " + why); }

// Radiance of every lane where kernel and reference hit the same primitive.
// tau = eps L + sum_k F_k (dn + dl_k): F_k the light's term with n.l = 1, dn
// the error of the normal, dl_k of the light direction (a point light's
// direction and 1/r^2 move by ~3 dp / r when the hit point moves by dp). dp
// is the kernel's own hit-point error: its measured t error (which the t
// check bounds) times |d|, the rounding of o + t d, and with inexact inputs
// u |o|: the shading is judged given the hit the intersector found. +inf is
// right where the interval reaches past FLT_MAX, or where the irradiance
// E = sum ls cl n.l [/r^2] itself overflows float (the kernel forms E before
// multiplying by kd cd / pi). Display colours must be finite and in [0, 1].
Measure check_radiance(const Scene& scene, const std::vector<Lane>& lanes, const Traced& tr, RadianceOptions opt = {}) {
    Measure m;
    const double in = opt.exact_inputs ? 0 : kUnitRoundoff;  // input rounding
    for (std::size_t i = 0; i < lanes.size(); ++i) {
        const Lane& l = lanes[i];
        const Out& k = tr.lanes[i];
        if (!l.active) continue;
        for (int c = 0; c < 3; ++c)
            if (!(comp(k.shown, c) >= 0 && comp(k.shown, c) <= 1)) note_lane(m, i, "display colour outside [0, 1]");
        const reference::Hit h = ref_trace(scene, l);
        if (h.object != k.object) continue;  // check_hits judges these
        const Vec3d L = reference::shade(scene, ref_ray(l), h);
        Vec3d cond, irradiance, diffuse;  // sum F_k (dn + dl_k); sum ls cl n.l [/r^2]; kd cd / pi
        if (h.object >= 0) {
            const Object& obj = scene.objects[std::size_t(h.object)];
            const Material& mat = scene.materials[std::size_t(obj.material)];
            diffuse = reference::lambertian_brdf(mat);
            const Vec3d& p = h.point;
            // The kernel shades its own hit point: off by its t error along d,
            // by the rounding of o + t d, and by the inputs' rounding.
            const double dp = std::fabs(k.t - h.t) * norm(l.d) + kUnitRoundoff * norm(p) + in * norm(l.o);
            double dn = 2 * in;
            if (const Sphere* s = std::get_if<Sphere>(&obj.shape)) dn += 2 * kUnitRoundoff + dp / s->radius;
            auto add = [&](const Vec3d& radiance, double ndl, double falloff, double dl) {
                if (ndl < -1e-3) return;  // clearly behind: exactly 0 on both sides
                cond += hadamard(diffuse, radiance) * (falloff * (dn + dl));
                if (ndl > 0) irradiance += radiance * (falloff * ndl);
            };
            for (const DirectionalLight& d : scene.directional_lights)
                add(d.color * d.ls, dot(h.normal, unit_direction(d.direction)), 1, 2 * in);
            for (const PointLight& pl : scene.point_lights) {
                const Vec3d v = pl.position - p;
                const double r = norm(v);
                if (r == 0) continue;
                const double falloff = pl.attenuation == Attenuation::inverse_square ? 1 / (r * r) : 1;
                add(pl.color * pl.ls, dot(h.normal, v) / r, falloff, 3 * (dp + in * norm(pl.position)) / r + 2 * kUnitRoundoff);
            }
        }
        for (int c = 0; c < 3; ++c) {
            const double ref = comp(L, c), got = comp(k.L, c);
            double tau = tr.eps * std::fabs(ref) + comp(cond, c);
            if (tr.flush) tau += 4 * FLT_MIN;  // results below FLT_MIN may flush to 0
            tau += 4 * std::numeric_limits<float>::denorm_min();  // subnormal results keep fewer bits
            if (got == kInf) {
                const bool e_overflows = comp(irradiance, c) * (1 + 16 * tr.eps) > FLT_MAX && comp(diffuse, c) > 0;
                if (!(ref + 16 * tau > FLT_MAX) && !e_overflows)
                    note_lane(m, i, fmt("channel %g: kernel +inf, reference %.9g (tau %.3g)", c, ref, tau));
                continue;
            }
            if (!std::isfinite(got)) {
                note_lane(m, i, fmt("channel %g: kernel radiance %g, reference %.9g", c, got, ref));
                continue;
            }
            const double err = std::fabs(got - ref);
            if (debug())
                std::fprintf(stderr, "  lane %zu ch %d: L=%.9g ref=%.9g tau=%.3g err=%.3g\n", i, c, got, ref, tau, err / tau);
            m.error = std::max(m.error, err == 0 ? 0.0 : err / tau);
        }
    }
    return m;
}

}  // namespace

double fl(double x) { return round_to_float(x); }
Vec3d fl(const Vec3d& v) { return round_to_float(v); }
double norm(const Vec3d& v) { return std::sqrt(dot(v, v)); }
// A unit vector as the kernels see it: normalized in double, rounded to float.
Vec3d dir(double x, double y, double z) {
    const Vec3d v{x, y, z};
    return fl(v * (1.0 / norm(v)));
}

std::string fmt(const char* f, double a, double b, double c, double d) {
    char buf[200];
    std::snprintf(buf, sizeof buf, f, a, b, c, d);
    return buf;
}

double uniform(std::mt19937& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }

// ---- running a tracer ---------------------------------------------------------

bool debug() {
    static const bool on = std::getenv("OCTRAY_STABILITY_DEBUG") != nullptr;
    return on;
}

Traced run(const Tracer& tr, const Scene& scene, const std::vector<Lane>& lanes, bool flush) {
    const PacketScene ps = compile(scene);
    Kernel k = tr.naive    ? general_kernel(Path::scalar)
               : tr.kernel ? tr.kernel(tr.precision)
                           : select_kernel(ps, tr.path, tr.precision);
    Traced out;
    out.flush = flush;
    out.eps = tr.naive ? kUnitRoundoff : mode_eps(k.precision);
    if (!tr.naive && k.precision != tr.precision) out.note = std::string("ran as ") + precision_name(k.precision);
    for (std::size_t base = 0; base < lanes.size(); base += 8) {
        RayPacket8 rp{};
        for (int i = 0; i < 8; ++i) {
            if (base + std::size_t(i) >= lanes.size()) continue;
            const Lane& l = lanes[base + std::size_t(i)];
            rp.ox[i] = float(l.o.x), rp.oy[i] = float(l.o.y), rp.oz[i] = float(l.o.z);
            rp.dx[i] = float(l.d.x), rp.dy[i] = float(l.d.y), rp.dz[i] = float(l.d.z);
            rp.ox_lo[i] = float(l.o_lo.x), rp.oy_lo[i] = float(l.o_lo.y), rp.oz_lo[i] = float(l.o_lo.z);
            rp.dx_lo[i] = float(l.d_lo.x), rp.dy_lo[i] = float(l.d_lo.y), rp.dz_lo[i] = float(l.d_lo.z);
            rp.tmin[i] = float(l.tmin), rp.tmax[i] = float(l.tmax);
            rp.active[i] = l.active ? -1 : 0;
        }
        HitPacket8 hp;
        ColorPacket8 c, shown;
        {
            const Mxcsr mx(flush);
            out.masked += tr.naive ? naive_intersect(ps, rp, hp) : k.intersect(ps, rp, hp);
            if (tr.naive) naive_shade(ps, rp, hp, c);
            else k.shade(ps, rp, hp, c);
            k.tonemap(ps, c, shown);
        }
        for (int i = 0; i < 8 && base + std::size_t(i) < lanes.size(); ++i) {
            Out o;
            o.hit = hp.hit[i] != 0;
            o.object = hp.primitive[i];
            o.t = hp.t[i];
            o.n = {hp.nx[i], hp.ny[i], hp.nz[i]};
            o.L = {c.r[i], c.g[i], c.b[i]};
            o.shown = {shown.r[i], shown.g[i], shown.b[i]};
            out.lanes.push_back(o);
        }
    }
    return out;
}

// ---- the reference side --------------------------------------------------------

reference::Ray ref_ray(const Lane& l) { return {l.o + l.o_lo, l.d + l.d_lo}; }
double ref_tmax(const Lane& l) { return std::isinf(l.tmax) ? 1e300 : l.tmax; }

reference::Hit ref_trace(const Scene& scene, const Lane& l) {
    return reference::trace(scene, ref_ray(l), l.tmin, ref_tmax(l));
}

// S of the error model for a lane: origin, hit point and the primitives involved.
double lane_scale(const Scene& scene, const Lane& l, const reference::Hit& h, int other_object) {
    double s = norm(l.o);
    if (h.object >= 0) s = std::max({s, norm(h.point), primitive_scale(scene.objects[std::size_t(h.object)].shape)});
    if (other_object >= 0 && other_object < int(scene.objects.size()))
        s = std::max(s, primitive_scale(scene.objects[std::size_t(other_object)].shape));
    return s;
}

bool ambiguous(const Scene& scene, const Lane& l, double scale) {
    const int base = ref_trace(scene, l).object;
    return any_perturbation(scene, l, scale, [base](const reference::Hit& h) { return h.object != base; });
}

// ---- checks --------------------------------------------------------------------

Measure check_hits(const Scene& scene, const std::vector<Lane>& lanes, const Traced& tr, HitOptions opt) {
    Measure m;
    for (std::size_t i = 0; i < lanes.size(); ++i) {
        const Lane& l = lanes[i];
        const Out& k = tr.lanes[i];
        if (!l.active) continue;
        const reference::Hit h = ref_trace(scene, l);
        if (h.object != k.object || (h.object >= 0) != k.hit) {
            const double s = lane_scale(scene, l, h, k.object);
            if (!opt.strict && ambiguous(scene, l, s)) continue;
            note_lane(m, i, "reference " + (h.object < 0 ? std::string("misses") : fmt("hits #%g at t=%.9g", h.object, h.t)) +
                                ", kernel " + (k.hit ? fmt("hits #%g at t=%.9g", k.object, k.t) : std::string("misses")));
            continue;
        }
        if (!k.hit) continue;
        if (!std::isfinite(k.t) || !finite3(k.n) || dot(k.n, l.d) > 0) {
            note_lane(m, i, fmt("non-finite t/normal or normal not facing the ray (t=%g)", k.t));
            continue;
        }
        const double cosine = std::fabs(dot(h.normal, l.d)) / norm(l.d);
        double tau = tr.eps * std::fabs(h.t);
        if (!opt.exact_inputs) tau += kUnitRoundoff * lane_scale(scene, l, h, -1) / std::max(cosine, std::sqrt(kUnitRoundoff));
        const double err = std::fabs(k.t - h.t);
        if (debug())
            std::fprintf(stderr, "  lane %zu: t=%.9g ref=%.9g tau=%.3g err=%.3g\n", i, k.t, h.t, tau, err / tau);
        m.error = std::max(m.error, err == 0 ? 0.0 : err / tau);
    }
    return m;
}

Measure check_masked(const Scene& scene, const std::vector<Lane>& lanes, const Traced& tr, const std::vector<bool>& masked) {
    Measure m;
    int expected = 0, wrong = 0;
    for (std::size_t i = 0; i < lanes.size(); ++i) {
        if (!masked[i]) continue;
        ++expected;
        const Out& k = tr.lanes[i];
        const bool ok = !k.hit && k.L.x == fl(scene.background.x) && k.L.y == fl(scene.background.y) &&
                        k.L.z == fl(scene.background.z) && finite3(k.shown);
        if (!ok) {
            ++wrong;
            if (m.pass) m.note = "lane " + std::to_string(i) + " not masked to the background";
            m.pass = false;
        }
    }
    if (tr.masked != expected) {
        wrong += std::abs(tr.masked - expected);
        m.pass = false;
        m.note = "masked count " + std::to_string(tr.masked) + ", expected " + std::to_string(expected);
    }
    m.error = wrong;
    return m;
}

Measure check_all(const Scene& scene, const std::vector<Lane>& lanes, const Traced& tr, HitOptions ho,
                  RadianceOptions ro) {
    Measure a = check_hits(scene, lanes, tr, ho);
    const Measure b = check_radiance(scene, lanes, tr, ro);
    if (!b.pass && a.pass) a.note = b.note;
    a.pass = a.pass && b.pass;
    a.error = std::max(a.error, b.error);
    return a;
}

// Merges the measure of one more scene of a case into `m`.
void merge(Measure& m, const Measure& more) {
    if (!more.pass && m.pass) m.note = more.note;
    m.pass = m.pass && more.pass;
    m.error = std::max(m.error, more.error);
}

void add_note(Measure& m, const Traced& tr) {
    if (m.pass && !tr.note.empty()) m.note = tr.note;
}

Measure measure_hits(const Tracer& tr, const Scene& s, const std::vector<Lane>& lanes, HitOptions opt) {
    const Traced t = run(tr, s, lanes);
    Measure m = check_hits(s, lanes, t, opt);
    add_note(m, t);
    return m;
}

Measure measure_all(const Tracer& tr, const Scene& s, const std::vector<Lane>& lanes, HitOptions ho,
                    RadianceOptions ro) {
    const Traced t = run(tr, s, lanes);
    Measure m = check_all(s, lanes, t, ho, ro);
    add_note(m, t);
    return m;
}

// ---- scene building ------------------------------------------------------------

Material matte(const char* name, Vec3d cd, double ka, double kd) {
    return Material{name, ka, kd, cd};
}

Scene scene_of(std::vector<Shape> shapes) {
    Scene s;
    s.materials.push_back(matte());
    for (Shape& sh : shapes) s.objects.push_back(Object{std::move(sh), 0});
    return s;
}

// A ray from o toward `target` with the float-rounded unit direction.
Lane toward(const Vec3d& o, const Vec3d& target) {
    const Vec3d v = target - o;
    return {fl(o), dir(v.x, v.y, v.z)};
}

Lane toward_exact(const Vec3d& o, const Vec3d& target) {
    const Vec3d v = target - o, d = v * (1 / norm(v));
    Lane l{fl(o), fl(d)};
    l.o_lo = o - l.o, l.d_lo = d - l.d;
    return l;
}

std::vector<Lane> down_onto(std::initializer_list<std::pair<double, double>> xy, double h) {
    std::vector<Lane> out;
    for (const auto& [x, y] : xy) out.push_back({fl(Vec3d{x, y, h}), {0, 0, -1}});
    return out;
}

}  // namespace octray::stability::detail
