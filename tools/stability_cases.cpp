// tools/stability_cases.cpp — the catalogue of stiff and extreme cases and the
// machinery that measures a Tracer on them (see stability_cases.hpp for the
// error model).
#include "stability_cases.hpp"

#include <octray/reference.hpp>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <random>
#include <sstream>

#include <immintrin.h>

namespace octray::stability {

std::string Tracer::name() const {
    return naive ? std::string("naive") : std::string(path_name(path)) + "/" + precision_name(precision);
}

std::vector<Tracer> kernel_tracers() {
    std::vector<Tracer> out;
    for (Path path : {Path::scalar, Path::simd})
        for (Precision p : kPrecisions) out.push_back(Tracer{path, p, false});
    return out;
}

Tracer naive_tracer() { return Tracer{Path::scalar, Precision::exact, true}; }

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Rounds to float, through a volatile: GCC 12.2 at -O3 (SLP vectorizer) drops
// the (double)(float)x round trip of paired x, y components (wrong code,
// reproduced with this file's rays_at; -O2 and -fno-tree-slp-vectorize are right).
double fl(double x) {
    volatile float f = float(x);
    return f;
}
Vec3d fl(const Vec3d& v) { return {fl(v.x), fl(v.y), fl(v.z)}; }
double norm(const Vec3d& v) { return std::sqrt(dot(v, v)); }
// A unit vector as the kernels see it: normalized in double, rounded to float.
Vec3d dir(double x, double y, double z) {
    const Vec3d v{x, y, z};
    return fl(v * (1.0 / norm(v)));
}
bool finite3(const Vec3d& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
double comp(const Vec3d& v, int k) { return k == 0 ? v.x : k == 1 ? v.y : v.z; }

std::string fmt(const char* f, double a, double b = 0, double c = 0, double d = 0) {
    char buf[200];
    std::snprintf(buf, sizeof buf, f, a, b, c, d);
    return buf;
}

// ---- running a tracer ---------------------------------------------------------

// One ray as authored: every number already a float (as a double).
struct Lane {
    Vec3d o, d;
    double tmin = 0, tmax = kInf;
    bool active = true;
};

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

struct Out {
    bool hit = false;
    int object = -1;
    double t = 0;
    Vec3d n, L, shown;
};

struct Traced {
    std::vector<Out> lanes;
    int masked = 0;
    double eps = kUnitRoundoff;  // the mode's bound for 1/x and 1/sqrt(x)
    bool flush = false;
    std::string note;  // e.g. "ran as fast" when the CPU lacks a mode
};

// OCTRAY_STABILITY_DEBUG=1 in the environment: every lane's error on stderr.
bool debug() {
    static const bool on = std::getenv("OCTRAY_STABILITY_DEBUG") != nullptr;
    return on;
}

double mode_eps(Precision p) { return std::max(div_bound(p), rsqrt_bound(p)); }

Traced run(const Tracer& tr, const Scene& scene, const std::vector<Lane>& lanes, bool flush = false) {
    const PacketScene ps = compile(scene);
    Kernel k = tr.naive ? general_kernel(Path::scalar) : select_kernel(ps, tr.path, tr.precision);
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

reference::Ray ref_ray(const Lane& l) { return {l.o, l.d}; }
double ref_tmax(const Lane& l) { return std::isinf(l.tmax) ? 1e300 : l.tmax; }

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

// True when `pred` holds for the reference's hit of the ray with the origin
// moved by 4 u S or the direction by 4 u |d| along some axis (12 rays).
template <class Pred>
bool any_perturbation(const Scene& scene, const Lane& l, double scale, Pred pred) {
    for (int axis = 0; axis < 3; ++axis)
        for (double sign : {-1.0, 1.0}) {
            Vec3d e;
            (axis == 0 ? e.x : axis == 1 ? e.y : e.z) = sign * 4 * kUnitRoundoff;
            Lane moved = l, turned = l;
            moved.o = l.o + e * scale;
            turned.d = l.d + e * norm(l.d);
            if (pred(ref_trace(scene, moved)) || pred(ref_trace(scene, turned))) return true;
        }
    return false;
}

// True when the reference's answer (which object) changes under such a
// perturbation: the ray is within its own rounding of a boundary, where
// either answer is right.
bool ambiguous(const Scene& scene, const Lane& l, double scale) {
    const int base = ref_trace(scene, l).object;
    return any_perturbation(scene, l, scale, [base](const reference::Hit& h) { return h.object != base; });
}

void fail(Measure& m, const std::string& why) {
    if (m.pass) m.note = why;
    m.pass = false;
    m.error = kInf;
}

void note_lane(Measure& m, std::size_t i, const std::string& why) { fail(m, "lane " + std::to_string(i) + ": " + why); }

// ---- checks --------------------------------------------------------------------

struct HitOptions {
    bool exact_inputs = false;  // |dt| <= K eps |t| only (no u S term)
    bool strict = false;        // a boundary rule decides: no ambiguity allowed
};

// Hit/miss, primitive and t of every active lane against the reference.
Measure check_hits(const Scene& scene, const std::vector<Lane>& lanes, const Traced& tr, HitOptions opt = {}) {
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

// Lanes that must come out masked (counted, missed, background, finite).
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

struct RadianceOptions {
    bool exact_inputs = false;  // the scene's floats are exact: only the modes' errors count
};

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

// Both checks; the worse error.
Measure check_all(const Scene& scene, const std::vector<Lane>& lanes, const Traced& tr, HitOptions ho = {},
                  RadianceOptions ro = {}) {
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

// Runs `lanes` through the tracer and checks the hits (measure_hits) or hits
// and radiance (measure_all) against the reference.
Measure measure_hits(const Tracer& tr, const Scene& s, const std::vector<Lane>& lanes, HitOptions opt = {}) {
    const Traced t = run(tr, s, lanes);
    Measure m = check_hits(s, lanes, t, opt);
    add_note(m, t);
    return m;
}

Measure measure_all(const Tracer& tr, const Scene& s, const std::vector<Lane>& lanes, HitOptions ho = {},
                    RadianceOptions ro = {}) {
    const Traced t = run(tr, s, lanes);
    Measure m = check_all(s, lanes, t, ho, ro);
    add_note(m, t);
    return m;
}

// ---- scene building ------------------------------------------------------------

Material matte(const char* name = "m", Vec3d cd = {1, 1, 1}, double ka = 0.0, double kd = 0.65) {
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

// Rays straight down (-z) from height h onto points (x, y, 0): t = h exactly.
std::vector<Lane> down_onto(std::initializer_list<std::pair<double, double>> xy, double h = 1) {
    std::vector<Lane> out;
    for (const auto& [x, y] : xy) out.push_back({fl(Vec3d{x, y, h}), {0, 0, -1}});
    return out;
}

// ---- the cases -------------------------------------------------------------------

const char* kTBound = "dt/(eps t + u S/cos)";
const char* kTExact = "dt/(eps t)";
const char* kLBound = "dL/(eps L + u sum F g)";
const char* kLExact = "dL/(eps L)";

// Planet of radius 1e6 centred at the origin; origin 1 above its surface.
Scene planet_scene() { return scene_of({Sphere{{0, 0, 0}, fl(1e6)}}); }
Vec3d planet_origin() { return {0, fl(1e6 + 1), 0}; }
Lane planet_ray(double theta_deg, double phi_deg) {
    const double th = theta_deg * kPi / 180, ph = phi_deg * kPi / 180;
    return {planet_origin(), dir(std::sin(th) * std::cos(ph), -std::cos(th), std::sin(th) * std::sin(ph))};
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

// A small or far sphere hit through its centre and at fractions of its radius;
// `miss` fractions beyond it.
std::vector<Lane> sphere_probe(const Vec3d& o, const Vec3d& c, double r, std::initializer_list<double> fractions) {
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
            out.push_back(toward(o, c + (e1 * std::cos(a) + e2 * std::sin(a)) * (f * r)));
        }
    return out;
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

double uniform(std::mt19937& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }

// ---- sphere hits in the sphere's frame (issue 16) ---------------------------------
// The normal of every lane where kernel and reference hit the same sphere,
// against the reference's normal on the same float inputs: |n - n_ref| in
// units of u (1 + 1/cos), cos = |n_ref.d| / |d|. The kernels form it from
// the sphere's own frame (kernels/sphere.hpp, sphere_offset): a few u, and
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

// The kernels' normals before issue 16, for these cases' naive column: from
// their own hit point, n = (o + t d - c) / r, in float as they formed it
// (o + d t rounded per operation, then face-forwarded). Its error grows as t/r.
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

// Hits (t, hit/miss) and sphere normals. The naive tracer runs the SIMD exact
// kernel with point_normals: the formulation these cases replaced.
Measure measure_frame(const Tracer& tr, const Scene& s, const std::vector<Lane>& lanes) {
    Traced t = run(tr.naive ? Tracer{Path::simd, Precision::exact, false} : tr, s, lanes);
    if (tr.naive) point_normals(s, lanes, t);
    Measure m = check_hits(s, lanes, t);
    merge(m, check_normals(s, lanes, t));
    if (tr.naive) m.note = "naive here: the kernel before issue 16, n = (o + t d - c) / r";
    else add_note(m, t);
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

Vec3d tilted_normal() { return dir(1, 1, 0); }  // (0.70710677, 0.70710677, 0): d = (1, -1, 0) is exactly parallel

Measure plane_parallel(const Tracer& tr) {
    Measure m;
    const Scene a = scene_of({Plane{{0, 0, 0}, {0, 1, 0}}});
    const std::vector<Lane> la = {{{0, 1, 0}, {1, 0, 0}}, {{3, -2, 1}, {0, 0, -1}}, {{1, 5, 1}, dir(0.6, 0, 0.8)},
                                  {{0, 1e-30, 0}, {1, 0, 0}}};
    merge(m, measure_hits(tr, a, la, {false, true}));
    const Scene b = scene_of({Plane{{0, 0, 0}, tilted_normal()}});
    const std::vector<Lane> lb = {{{1, 2, 0}, {1, -1, 0}}, {{-3, 0, 2}, {-2, 2, 0}}};
    merge(m, measure_hits(tr, b, lb, {false, true}));
    return m;
}

Measure plane_in_plane(const Tracer& tr) {
    Measure m;
    const Scene a = scene_of({Plane{{0, 0, 0}, {0, 1, 0}}});
    const std::vector<Lane> la = {{{1, 0, 2}, {1, 0, 0}}, {{0, 0, 0}, dir(0.6, 0, -0.8)}, {{-7, 0, 3}, {0, 0, -1}}};
    merge(m, measure_hits(tr, a, la, {false, true}));
    const Scene b = scene_of({Plane{{0, 0, 0}, tilted_normal()}});
    const std::vector<Lane> lb = {{{1, -1, 0}, {1, -1, 0}}, {{-2, 2, 5}, {-1, 1, 0}}};
    merge(m, measure_hits(tr, b, lb, {false, true}));
    return m;
}

Measure plane_grazing(const Tracer& tr) {
    const Scene s = scene_of({Plane{{0, 0, 0}, {0, 1, 0}}});
    std::vector<Lane> lanes;
    for (double slope : {1e-7, 3e-7, 1e-6, 1e-5})
        for (const Vec3d& along : {Vec3d{1, 0, 0}, Vec3d{-0.5, 0, 0.75}})
            lanes.push_back({{0, 1, 0}, fl(Vec3d{along.x, -slope, along.z})});
    return measure_hits(tr, s, lanes, {true, false});
}

Measure disk_rim(const Tracer& tr) {
    const Scene s = scene_of({Disk{{0, 0, 0}, {0, 0, 1}, 1}});
    const double out = fl(1 + 0x1p-23), in = fl(1 - 0x1p-24);
    std::vector<Lane> lanes = down_onto({{1, 0}, {0, -1}, {-1, 0}, {0, 1}, {out, 0}, {0, -out}, {in, 0}, {0.6, 0.8}});
    lanes.push_back({{0, 0, 1}, {1, 0, -1}});   // oblique onto the rim point (1, 0, 0)
    lanes.push_back({{-1, 0, 2}, {1, 0, -1}});  // the same point, t = 2
    lanes.push_back({{0, 3, 1}, {0, -2, -1}});  // onto (0, 1, 0)
    return measure_hits(tr, s, lanes);
}

Measure rectangle_edges(const Tracer& tr) {
    Measure m;
    const Scene a = scene_of({Rectangle{{-1, -1, 0}, {2, 0, 0}, {0, 2, 0}}});
    const double out = fl(1 + 0x1p-23);
    std::vector<Lane> la = down_onto({{-1, 0}, {1, 0.5}, {0, -1}, {0.25, 1}, {-1, -1}, {1, 1}, {1, -1}, {-1, 1}, {out, 0},
                                      {0, -out}, {-out, -out}});
    la.push_back({{-2, 0.5, 1}, {1, 0, -1}});  // oblique onto the edge x = -1
    la.push_back({{3, 3, 2}, {-1, -1, -1}});   // oblique onto the corner (1, 1)
    merge(m, measure_hits(tr, a, la));
    const Scene b = scene_of({Rectangle{{0, 0, 0}, {2, 0, 0}, {1, 2, 0}}});  // a parallelogram
    const std::vector<Lane> lb = down_onto({{0, 0}, {2, 0}, {3, 2}, {1, 2}, {0.5, 1}, {2.5, 1}, {1, 0}, {2, 2}});
    merge(m, measure_hits(tr, b, lb));
    return m;
}

Scene unit_box() { return scene_of({Box{{-1, -1, -1}, {1, 1, 1}}}); }

Measure box_origin_on_face(const Tracer& tr) {
    const Scene s = unit_box();
    std::vector<Lane> lanes;
    for (const Vec3d& o : {Vec3d{1, 0.25, 0.5}, Vec3d{1, 1, 0.5}, Vec3d{1, 1, 1}, Vec3d{-0.5, -1, 0.75}})
        for (const Vec3d& d : {Vec3d{-1, 0, 0}, Vec3d{1, 0, 0}, Vec3d{0, 1, 0}, Vec3d{0, -1, 0}, Vec3d{0, 0, -1},
                               dir(-1, -0.5, 0.25), dir(1, 1, 1)})
            lanes.push_back({o, d});
    return measure_hits(tr, s, lanes, {false, true});
}

Measure box_zero_components(const Tracer& tr) {
    const Scene s = unit_box();
    std::vector<Lane> lanes;
    const double nz = -0.0;
    for (const Vec3d& o : {Vec3d{-3, 0, 0}, Vec3d{-3, 1, 0}, Vec3d{-3, 1, -1}, Vec3d{-3, fl(1 + 0x1p-23), 0}, Vec3d{-3, -1, 1}})
        for (const Vec3d& d : {Vec3d{1, 0, 0}, Vec3d{1, nz, nz}, Vec3d{2, 0, nz}}) lanes.push_back({o, d});
    lanes.push_back({{0.5, 0.5, 5}, {nz, 0, -1}});
    lanes.push_back({{0.5, -4, 1}, {0, 1, nz}});
    return measure_hits(tr, s, lanes, {false, true});
}

Measure box_edges_corners(const Tracer& tr) {
    const Scene s = unit_box();
    const std::vector<Lane> lanes = {
        {{-3, 1, 0}, {1, 0, 0}},     // along the face y = 1: hits at t = 2
        {{-3, 1, 1}, {1, 0, 0}},     // along the edge y = z = 1
        {{-3, -3, 0}, {1, 1, 0}},    // enters through the edge x = y = -1
        {{-3, -3, -3}, {1, 1, 1}},   // enters through the corner (-1, -1, -1)
        {{-3, 1, 0}, {1, -1, 0}},    // touches only the edge x = y = -1 (enter t = exit t = 2)
        {{2, 2, 0}, {-1, -1, 1}},    // touches only the corner (1, 1, 1) at t = 1
        {{0, 3, 0}, {1, -1, 0}},     // passes the edge x = 1 at y = 2: misses
        {{3, 1, -3}, {-1, 0, 1}},    // enters at the corner (1, 1, -1), runs along the face y = 1
    };
    return measure_hits(tr, s, lanes, {false, true});
}

// A jittered height field over ~[0, n]^2 with random float heights, quads
// split along alternating diagonals: shared edges and vertices in general
// position (no dyadic coincidences that would make a formulation exact).
std::vector<std::array<Vec3d, 3>> height_field(int n, unsigned seed, std::vector<Vec3d>& interior_vertices,
                                               std::vector<std::array<Vec3d, 2>>& interior_edges) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> jitter(-0.3, 0.3), height(-0.7, 0.7);
    std::vector<Vec3d> v;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) v.push_back(fl(Vec3d{i + jitter(rng), j + jitter(rng), height(rng)}));
    auto at = [&](int i, int j) { return v[std::size_t(j * (n + 1) + i)]; };
    std::vector<std::array<Vec3d, 3>> tris;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const Vec3d a = at(i, j), b = at(i + 1, j), c = at(i, j + 1), d = at(i + 1, j + 1);
            if ((i + j) % 2 == 0) tris.push_back({a, b, d}), tris.push_back({a, d, c}), interior_edges.push_back({a, d});
            else tris.push_back({a, b, c}), tris.push_back({b, d, c}), interior_edges.push_back({b, c});
            if (j > 0) interior_edges.push_back({a, b});
            if (i > 0) interior_edges.push_back({a, c});
        }
    for (int j = 1; j < n; ++j)
        for (int i = 1; i < n; ++i) interior_vertices.push_back(at(i, j));
    return tris;
}

Scene triangles_scene(const std::vector<std::array<Vec3d, 3>>& tris) {
    Scene s;
    s.materials.push_back(matte());
    for (const auto& t : tris) s.objects.push_back(Object{Triangle{t[0], t[1], t[2]}, 0});
    return s;
}


// Rays from random origins (from `origin`) at each target: half with the
// direction target - o rounded to float, half normalized: the float ray
// passes within a rounding of the edge or vertex.
template <class Origin>
std::vector<Lane> rays_at(const std::vector<Vec3d>& targets, int rounds, unsigned seed, Origin origin) {
    std::mt19937 rng(seed);
    std::vector<Lane> lanes;
    for (int round = 0; round < rounds; ++round)
        for (const Vec3d& p : targets) {
            const Vec3d o = fl(origin(rng, round));
            const Vec3d v = p - o;
            lanes.push_back({o, round % 4 < 2 ? fl(v) : dir(v.x, v.y, v.z)});
        }
    return lanes;
}

// True when the reference hits something, and still does with the origin
// moved by 4 u S or the direction by 4 u |d| along any axis: the ray crosses
// the mesh well inside its coverage (not at its border, not at a silhouette).
bool surely_hits(const Scene& scene, const Lane& l) {
    const reference::Hit h = ref_trace(scene, l);
    return h.object >= 0 && !any_perturbation(scene, l, lane_scale(scene, l, h, -1),
                                              [](const reference::Hit& p) { return p.object < 0; });
}

// A leak is a kernel miss where the reference surely hits. The t of a hit is
// checked against the reference's (the primitive may differ on an edge).
Measure must_hit(const Tracer& tr, const Scene& s, const std::vector<Lane>& lanes) {
    const Traced t = run(tr, s, lanes);
    Measure m;
    int leaks = 0;
    double terr = 0;
    for (std::size_t i = 0; i < lanes.size(); ++i) {
        if (!t.lanes[i].hit) {
            if (debug() && surely_hits(s, lanes[i]))
                std::fprintf(stderr, "  leak lane %zu of %zu, %zu triangles: o=(%a, %a, %a) d=(%a, %a, %a)\n", i, lanes.size(),
                             s.objects.size(), lanes[i].o.x, lanes[i].o.y, lanes[i].o.z, lanes[i].d.x, lanes[i].d.y, lanes[i].d.z);
            if (surely_hits(s, lanes[i]) && leaks++ == 0)
                m.note = "leak: o=" + fmt("(%.9g, %.9g, %.9g)", lanes[i].o.x, lanes[i].o.y, lanes[i].o.z) +
                         fmt(" d=(%.9g, %.9g, %.9g)", lanes[i].d.x, lanes[i].d.y, lanes[i].d.z);
            continue;
        }
        // t against the reference's t for the triangle the kernel hit (on an
        // edge either neighbour is right; one the reference misses must be
        // within rounding of its border).
        const Lane& l = lanes[i];
        const reference::Hit h = ref_trace(s, l);
        const int obj = t.lanes[i].object;
        if (obj < 0 || obj >= int(s.objects.size())) continue;
        const auto tk = reference::intersect(s.objects[std::size_t(obj)].shape, ref_ray(l), l.tmin, ref_tmax(l));
        if (!tk) {
            if (!ambiguous(s, l, lane_scale(s, l, h, obj)) && m.pass) m.note = "a hit on a triangle the reference misses";
            if (!ambiguous(s, l, lane_scale(s, l, h, obj))) m.pass = false;
            continue;
        }
        const Vec3d nr = reference::geometric_normal(s.objects[std::size_t(obj)].shape, l.o + l.d * *tk);
        const double cosine = std::fabs(dot(nr, l.d)) / norm(l.d);
        const double tau = t.eps * *tk + kUnitRoundoff * lane_scale(s, l, h, obj) / std::max(cosine, std::sqrt(kUnitRoundoff));
        terr = std::max(terr, std::fabs(t.lanes[i].t - *tk) / tau);
    }
    m.error = leaks;
    m.pass = leaks == 0;
    if (terr > 8) {
        if (m.pass) m.note = fmt("t error %.3g > 8", terr);
        m.pass = false;
    }
    add_note(m, t);
    return m;
}

// Sums the leaks of several meshes.
void add_leaks(Measure& m, const Measure& more) {
    const double leaks = m.error + more.error;
    merge(m, more);
    m.error = leaks;
}

Vec3d above_or_below(std::mt19937& rng, int round) {
    return {uniform(rng, -3, 7), uniform(rng, -3, 7), (round % 2 == 0 ? 1 : -1) * uniform(rng, 2, 9)};
}

// A random terrain, rays at dyadic fractions along its interior edges or at
// its interior vertices.
Measure terrain_leaks(const Tracer& tr, unsigned seed, bool at_vertices) {
    std::vector<Vec3d> vertices;
    std::vector<std::array<Vec3d, 2>> edges;
    const Scene s = triangles_scene(height_field(4, seed, vertices, edges));
    if (at_vertices) return must_hit(tr, s, rays_at(vertices, 32, seed, above_or_below));
    std::vector<Vec3d> targets;
    for (const auto& e : edges)
        for (double f : {0.5, 0.25, 0.8125, 0.0625}) targets.push_back(e[0] + (e[1] - e[0]) * f);
    return must_hit(tr, s, rays_at(targets, 8, seed, above_or_below));
}

Measure mesh_edges(const Tracer& tr) {
    Measure m;
    for (unsigned seed : {21u, 22u}) add_leaks(m, terrain_leaks(tr, seed, false));
    return m;
}

Measure mesh_vertices(const Tracer& tr) {
    Measure m;
    for (unsigned seed : {31u, 32u}) add_leaks(m, terrain_leaks(tr, seed, true));
    {
        // A fan of 9 uneven triangles around a vertex, from above and below.
        const Vec3d c = fl(Vec3d{1.3, 1.7, 0.45});
        std::vector<std::array<Vec3d, 3>> fan;
        const int k = 9;
        for (int i = 0; i < k; ++i) {
            const double a0 = 2 * kPi * (i + 0.3 * (i % 3)) / k, a1 = 2 * kPi * (i + 1 + 0.3 * ((i + 1) % 3)) / k;
            fan.push_back({c, fl(c + Vec3d{std::cos(a0), std::sin(a0), 0.1 * (i % 4) - 0.15}),
                           fl(c + Vec3d{std::cos(a1), std::sin(a1), 0.1 * ((i + 1) % 4) - 0.15})});
        }
        add_leaks(m, must_hit(tr, triangles_scene(fan), rays_at({c}, 256, 33, above_or_below)));
    }
    {
        // A closed octahedron with rotated float vertices, from inside through
        // its vertices and edge midpoints.
        const Vec3d ax = dir(0.9, 0.3, 0.1), ay0 = dir(-0.3, 0.9, 0.2);
        const Vec3d az = dir(cross(ax, ay0).x, cross(ax, ay0).y, cross(ax, ay0).z), ay = cross(az, ax);
        const Vec3d v[6] = {fl(ax * 2.0), fl(ax * -2.0), fl(ay * 2.0), fl(ay * -2.0), fl(az * 2.0), fl(az * -2.0)};
        std::vector<std::array<Vec3d, 3>> tris;
        for (int a : {0, 1})
            for (int b : {2, 3})
                for (int c : {4, 5}) tris.push_back({v[a], v[b], v[c]});
        std::vector<Vec3d> targets(std::begin(v), std::end(v));
        for (int a = 0; a < 6; ++a)
            for (int b = a + 1; b < 6; ++b)
                if (a / 2 != b / 2) targets.push_back((v[a] + v[b]) * 0.5);
        auto inside = [](std::mt19937& rng, int) { return Vec3d{uniform(rng, -0.5, 0.5), uniform(rng, -0.5, 0.5), uniform(rng, -0.5, 0.5)}; };
        add_leaks(m, must_hit(tr, triangles_scene(tris), rays_at(targets, 16, 34, inside)));
    }
    return m;
}

Measure triangle_in_plane(const Tracer& tr) {
    Measure m;
    const Scene a = scene_of({Triangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}});
    const std::vector<Lane> la = {{{-1, 0.25, 0}, {1, 0, 0}}, {{0.25, 0.25, 0}, {1, 1, 0}}, {{2, 2, 0}, {-1, -1, 0}}};
    merge(m, measure_hits(tr, a, la, {false, true}));
    // In the tilted plane x + y = 0 (collinear triangles never get here: validate() rejects them).
    const Scene b = scene_of({Triangle{{1, -1, 0}, {-1, 1, 0}, {0, 0, 1}}});
    const std::vector<Lane> lb = {{{2, -2, 0.25}, {-1, 1, 0}}, {{-3, 3, 0.5}, {1, -1, 0}}, {{0, 0, -2}, {0, 0, 1}}};
    merge(m, measure_hits(tr, b, lb, {false, true}));
    return m;
}

// ---- lighting cases --------------------------------------------------------------

Scene lit_plane() {
    Scene s = scene_of({Plane{{0, 0, 0}, {0, 0, 1}}});
    s.materials[0] = matte("m", {1, 0.5, 0.25}, 0.0, 0.65);
    return s;
}

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

// ---- input validity, subnormals, huge coordinates ------------------------------

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

// Denormals-are-zero reads a subnormal input as 0: the right answer is the
// reference's on the inputs as given or on the inputs with subnormals zeroed.
Vec3d flush(const Vec3d& v) {
    auto f = [](double x) { return std::fabs(x) < FLT_MIN ? std::copysign(0.0, x) : x; };
    return {f(v.x), f(v.y), f(v.z)};
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

// ---- the list ----------------------------------------------------------------------

Case make(std::string name, std::string expectation, std::string bound_text, double bound, Measure (*fn)(const Tracer&)) {
    return Case{std::move(name), std::move(expectation), std::move(bound_text), bound, [fn, bound](const Tracer& tr) {
                    Measure m = fn(tr);
                    if (!(m.error <= bound)) {
                        if (m.pass) m.note = "error over the bound";
                        m.pass = false;
                    }
                    return m;
                }};
}

}  // namespace

const std::vector<Case>& catalogue() {
    static const std::vector<Case> cases = [] {
        std::vector<Case> c;
        const std::string t8 = std::string(kTBound) + " <= 8", te = std::string(kTExact) + " <= 16";
        const std::string l16 = std::string(kLBound) + " <= 16", le = std::string(kLExact) + " <= 16";
        const std::string zero = "wrong lanes = 0", leaks = "leaks = 0, t err <= 8";
        c.push_back(make("planet_1e6_from_1_above", "hits down to the horizon; t to input precision", t8, 8, planet));
        c.push_back(make("planet_exact_inputs", "exact o, c: t ~1 to a few eps (cancel-free c)", te, 16, planet_exact));
        c.push_back(make("sphere_r1e-4_at_1", "hit/miss and t of a tiny sphere", t8, 8, tiny_sphere));
        c.push_back(make("sphere_r1_at_1e4", "far sphere: no lost discriminant", t8, 8,
                         [](const Tracer& tr) { return far_sphere(tr, 1e4); }));
        c.push_back(make("sphere_r1_at_t1e7", "t ~ 1e7 to input precision", t8, 8,
                         [](const Tracer& tr) { return far_sphere(tr, 1e7); }));
        const std::string nb = "dn/(u(1+1/cos)) <= 8, t8";
        c.push_back(make("sphere_r1e-2_at_1e3_outline", "normal to a few u near the outline, t/r = 1e5", nb, 8,
                         small_far_outline));
        c.push_back(make("small_sphere_field", "400 spheres r <= 0.05 at 10-40: normals few u", nb, 8, small_sphere_field));
        c.push_back(make("sphere_r1e3_at_1e6", "large sphere seen from far: normals few u", nb, 8, large_far_sphere));
        c.push_back(make("sphere_tangent_rays", "exact tangent hits (disc = 0); 1 ulp out misses", t8, 8, tangent_rays));
        c.push_back(make("camera_inside_sphere", "the far root (exit) is the hit", t8, 8, camera_inside));
        c.push_back(make("origin_on_sphere", "no self-hit at t = 0; chords hit", t8, 8, origin_on_surface));
        c.push_back(make("plane_ray_parallel", "d.n = 0 exactly: miss, no NaN", zero + " (t8)", 8, plane_parallel));
        c.push_back(make("plane_ray_in_plane", "ray lying in the plane: miss", zero + " (t8)", 8, plane_in_plane));
        c.push_back(make("plane_grazing_1e-7", "d.n = 1e-7: hit at t = 1e7", te, 16, plane_grazing));
        c.push_back(make("disk_rim_hits", "points on the rim hit; 1 ulp outside misses", t8, 8, disk_rim));
        c.push_back(make("rectangle_edge_hits", "edges and corners hit (closed)", t8, 8, rectangle_edges));
        c.push_back(make("box_origin_on_face", "closed box: exit face from the face", t8, 8, box_origin_on_face));
        c.push_back(make("box_zero_dir_components", "0 * inf slabs: inside iff origin in slab", t8, 8, box_zero_components));
        c.push_back(make("box_edges_corners", "edge/corner grazes hit (enter = exit)", t8, 8, box_edges_corners));
        c.push_back(make("mesh_shared_edges", "watertight: rays through edges hit", leaks, 0, mesh_edges));
        c.push_back(make("mesh_shared_vertices", "watertight: rays through vertices hit", leaks, 0, mesh_vertices));
        c.push_back(make("triangle_ray_in_plane", "ray in the triangle's plane: miss", zero + " (t8)", 8, triangle_in_plane));
        c.push_back(make("grazing_light_1e-7", "n.l = 1e-7 lights to eps relative", le, 16, grazing_light));
        c.push_back(make("lights_1e30_and_1e-30", "tiny term absorbed; alone it is exact", l16, 16, lights_dynamic_range));
        c.push_back(make("lights_64_over_12_decades", "sum of >= 0 terms: (n-1)u + terms", std::string(kLBound) + " <= 80", 80,
                         lights_64_decades));
        c.push_back(make("point_light_1e-6_inv_square", "1/r^2 = 1e12 to a few eps", le, 16, point_light_near));
        c.push_back(make("point_light_at_distance_0", "r=0: nothing; r->0: +inf, never NaN", l16, 16, point_light_zero));
        c.push_back(make("radiance_overflow_to_inf", "E > FLT_MAX: +inf; 0*inf = 0; no NaN", l16, 16, radiance_overflow));
        c.push_back(make("zero_direction", "masked, counted, background", zero, 0, zero_direction));
        c.push_back(make("nan_direction", "masked, counted, background", zero, 0, nan_direction));
        c.push_back(make("inf_direction", "masked, counted, background", zero, 0, inf_direction));
        c.push_back(make("subnormals_ftz_daz_off", "subnormal inputs as given", "dL/(eps L+u sum F g), dt <= 16", 16,
                         [](const Tracer& tr) { return subnormals(tr, false); }));
        c.push_back(make("subnormals_ftz_daz_on", "as given or as zero, never NaN", "dL/(eps L+u sum F g), dt <= 16", 16,
                         [](const Tracer& tr) { return subnormals(tr, true); }));
        c.push_back(make("coordinates_near_1e19", "squares overflow: correct hits (scaled)", "dL/(eps L+u sum F g), dt <= 16", 16, huge_coordinates));
        return c;
    }();
    return cases;
}

}  // namespace octray::stability
