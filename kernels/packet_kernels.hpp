// kernels/packet_kernels.hpp — the packet kernels, written once over a lane type.
//
// T is `float` (the scalar path: one lane at a time), `xsimd::batch<float, A>`
// (the SIMD path) or a double lane type; P is the precision mode; F is the
// set of features (features.hpp) compiled in: code for a feature outside F is
// removed at compile time, not skipped at run time.
//
// Sources: shading is the seed's eq. 7-8 (ambient + sum of Lambertian terms,
// n.l clamped at zero), point lights eq. 6. Sphere: stable quadratic with the
// perpendicular-distance discriminant (pbrt-v4, Pharr et al., sec. 6.8.1), or
// b^2/a - c where that is the better conditioned, c = |f|^2 - r^2 by a
// compensated dot product (Ogita, Rump & Oishi 2005). The stiff and extreme
// cases these choices answer, each with its bound, are the catalogue of
// tools/stability_cases.hpp (`octray stability`).
// Triangle: the watertight test of Woop, Benthin & Wald (JCGT 2013): vertices
// projected per ray onto the plane across the ray, then 2D edge functions
// whose sign is exact or zero, so no ray through a shared edge or vertex
// misses every triangle (see triangle_t). Box: slab test (Kay & Kajiya 1986)
// with the NaN cases resolved explicitly.
//
// Each translation unit that includes this file defines OCTRAY_ISA, a name
// for its instruction set; every template here lives in a namespace of that
// name, so instantiations compiled with different -m flags never merge at
// link time (one ISA per translation unit).
#pragma once

#ifndef OCTRAY_ISA
#error "define OCTRAY_ISA before including packet_kernels.hpp"
#endif

#include <octray/features.hpp>
#include <octray/lane.hpp>
#include <octray/lane_pow.hpp>
#include <octray/packet.hpp>
#include <octray/packet_scene.hpp>
#include <octray/vec3.hpp>

#include <cassert>
#include <cstdint>
#include <limits>
#include <type_traits>

// The hot path of a primitive test must inline into its loop (GCC otherwise
// keeps the sphere test out of line and reloads the ray from memory for every
// sphere); the rare robust paths stay out of line to keep that loop small.
#ifndef OCTRAY_HOT
#define OCTRAY_HOT inline __attribute__((always_inline))
#define OCTRAY_COLD __attribute__((noinline, cold))
// The per-primitive lambdas handed to for_each_candidate: left to the
// inliner, a translation unit may keep one out of line, a call per test.
#define OCTRAY_HOT_LAMBDA __attribute__((always_inline))
#define OCTRAY_WALK __attribute__((noinline))
#endif

namespace octray::kernels::OCTRAY_ISA {

using lane::Mask;

// ---- packet <-> lane I/O ---------------------------------------------------
// A packet of 8 is processed as 8 / width<T> groups; `lane` is the first lane.
template <class T>
inline T load(const float* p, int lane) {
    if constexpr (lane::width<T> == 1) return T(p[lane]);
    else return lane::load_floats<T>(p + lane);
}
template <class T>
inline T load_index(const std::int32_t* p, int lane) {
    if constexpr (lane::width<T> == 1) return T(p[lane]);
    else return lane::load_ints<T>(p + lane);  // converts int32 -> float (or double) lanes
}
template <class T>
inline void store(float* p, int lane, const T& v) {
    if constexpr (lane::width<T> == 1) p[lane] = float(v);
    else lane::store_floats(p + lane, v);
}
// Stores a small integer carried as an exact float.
template <class T>
inline void store_index(std::int32_t* p, int lane, const T& v) {
    if constexpr (lane::width<T> == 1) {
        p[lane] = std::int32_t(v);
#if defined(__AVX__)
    } else if constexpr (std::is_same_v<lane::Scalar<T>, float> && lane::width<T> == 8) {
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(p + lane), _mm256_cvttps_epi32(v));
#endif
    } else {
        alignas(64) lane::Scalar<T> tmp[lane::width<T>];
        v.store_aligned(tmp);
        for (int i = 0; i < lane::width<T>; ++i) p[lane + i] = std::int32_t(tmp[i]);
    }
}
template <class T>
inline void store_mask(std::int32_t* p, int lane, const Mask<T>& m) {
    store_index(p, lane, lane::keep(m, T(-1)));
}
template <class T>
inline Mask<T> load_mask(const std::int32_t* p, int lane) {
    return load_index<T>(p, lane) != T(0);
}
template <class T>
inline T broadcast(const Floats& a, int k) { return T(a[std::size_t(k)]); }
template <class T>
inline Vec3<T> broadcast3(const Floats& x, const Floats& y, const Floats& z, int k) {
    return {T(x[std::size_t(k)]), T(y[std::size_t(k)]), T(z[std::size_t(k)])};
}
template <class T>
inline Vec3<T> gather3(const Floats& x, const Floats& y, const Floats& z, const T& idx) {
    return {lane::gather(x.data(), idx), lane::gather(y.data(), idx), lane::gather(z.data(), idx)};
}

// Per-lane reads of scene arrays at `idx` (exact small integers), where only
// the lanes of `m` matter: one broadcast load when those lanes agree on the
// index, which a packet of coherent rays mostly does, else a gather. Lanes
// outside `m` then read the agreed element instead of their own: callers
// select them away.
template <class T>
struct Lookup {
    T idx;
    int first;
    bool uniform;
    Lookup(const T& index, const Mask<T>& m) : idx(index), uniform(lane::uniform_on(index, m, first)) {}
    // Every lane reads element k.
    static Lookup at_index(int k) { return Lookup(k); }
    T operator()(const Floats& a) const { return uniform ? T(a[std::size_t(first)]) : lane::gather(a.data(), idx); }
    Vec3<T> operator()(const Floats& x, const Floats& y, const Floats& z) const {
        if (uniform) return broadcast3<T>(x, y, z, first);
        return gather3(x, y, z, idx);
    }

  private:
    explicit Lookup(int k) : idx(T(float(k))), first(k), uniform(true) {}
};

template <class T>
inline T fdot(const Vec3<T>& a, const Vec3<T>& b) { return lane::fma(a.x, b.x, lane::fma(a.y, b.y, a.z * b.z)); }

template <class T>
inline T inf() { return T(std::numeric_limits<float>::infinity()); }

// ---- rays ------------------------------------------------------------------
template <class T, Precision P>
struct Ray {
    Vec3<T> o, d;
    T tmin, tmax;
    Mask<T> valid;    // active and numerically usable
    Mask<T> invalid;  // active but masked off for bad input
    // Per-ray quantities shared by every primitive test (hoisted out of the loops).
    T dd;            // d.d
    T inv_dd;        // 1 / (d.d), IEEE in every precision mode (see finish_ray)
    T neg_inv_dd;    // -1 / (d.d)
    T exit_scale;    // -2^-18 d.d: the sphere test's miss-exit margin per unit of |f|^2 + r^2
    T len_d;         // |d| = sqrt(d.d)
    // What only box and triangle tests use, made when a packet's walk of
    // that type gets past its root (make_slabs, make_shear, called by
    // for_each_candidate): culling keeps most packets of most scenes from
    // reaching one, and the setup costs four IEEE divisions per ray.
    mutable Vec3<T> inv_d;   // 1 / d per axis, +-inf for a zero or subnormal component
    // Projection across the ray for triangles: (v.proj_a, v.proj_b) are v's
    // coordinates in the plane sheared along d (Woop et al.'s Sx, Sy, kz).
    mutable Vec3<T> proj_a, proj_b;
};

// Smallest and largest d.d a ray may have: 1/(d.d) and d.d must both be normal
// floats, so |d| in [2^-63, 2^63).
inline constexpr float kMinDirection2 = 0x1p-126f;
inline constexpr float kMaxDirection2 = 0x1p126f;

// Fills the per-ray reciprocals. 1/(d.d) is an IEEE division whatever the
// precision mode: it is paid once per ray, and the sphere's perpendicular
// offset f - d (f.d / d.d) subtracts nearly equal vectors for a far sphere,
// where an estimate's 2^-12 error in 1/(d.d) would move the ray by 2^-12 |f|
// (a miss for r = 1 at distance 1e4).
template <class T, Precision P>
inline void finish_ray(Ray<T, P>& r, const T& dd) {
    r.dd = dd;
    r.inv_dd = T(1) / dd;
    r.neg_inv_dd = T(0) - r.inv_dd;
    r.exit_scale = T(-0x1p-18f) * dd;
    r.len_d = lane::sqrt(dd);
}

// The box test's slab reciprocals (Ray::inv_d). A subnormal component
// counts as zero (signed infinity): the estimate instructions read
// subnormals as zero and their Newton step would make inf * 0 = NaN.
template <class T, Precision P>
inline void make_slabs(const Ray<T, P>& r) {
    auto inv_axis = [](const T& c) {
        return lane::select(lane::abs(c) < T(std::numeric_limits<float>::min()), lane::copysign(inf<T>(), c),
                            lane::rcp<P>(c));
    };
    r.inv_d = {inv_axis(r.d.x), inv_axis(r.d.y), inv_axis(r.d.z)};
}

// The triangle test's shear (Ray::proj_a, proj_b): along the dominant axis
// kz of d (kx, ky the next two, cyclic), proj_a = e_kx - (d_kx / d_kz) e_kz,
// proj_b = e_ky - (d_ky / d_kz) e_kz, both orthogonal to d; |d_kz| >= |d| /
// sqrt(3), so the ratios are <= 1.
template <class T, Precision P>
inline void make_shear(const Ray<T, P>& r) {
    const T ax = lane::abs(r.d.x), ay = lane::abs(r.d.y), az = lane::abs(r.d.z);
    const Mask<T> zx = ax >= ay && ax >= az, zy = lane::not_(zx) && ay >= az;
    const T inv_dz = T(1) / lane::select(zx, r.d.x, lane::select(zy, r.d.y, r.d.z));
    // kz = x: (kx, ky) = (y, z); kz = y: (z, x); kz = z: (x, y).
    const T sx = lane::select(zx, r.d.y, lane::select(zy, r.d.z, r.d.x)) * inv_dz;
    const T sy = lane::select(zx, r.d.z, lane::select(zy, r.d.x, r.d.y)) * inv_dz;
    const T zero(0), one(1), msx = zero - sx, msy = zero - sy;
    r.proj_a = {lane::select(zx, msx, lane::select(zy, zero, one)), lane::select(zx, one, lane::select(zy, msx, zero)),
                lane::select(zx, zero, lane::select(zy, one, msx))};
    r.proj_b = {lane::select(zx, msy, lane::select(zy, one, zero)), lane::select(zx, zero, lane::select(zy, msy, one)),
                lane::select(zx, one, lane::select(zy, zero, msy))};
}

// Loads lanes [lane, lane + width) and masks off what no kernel can trace:
// inactive lanes, non-finite origin or direction, zero direction, an empty or
// NaN interval. Masked lanes get a harmless ray so no NaN is ever computed.
template <class T, Precision P>
inline Ray<T, P> load_ray(const RayPacket8& rp, int lane, int& masked) {
    Ray<T, P> r;
    r.o = {load<T>(rp.ox, lane), load<T>(rp.oy, lane), load<T>(rp.oz, lane)};
    r.d = {load<T>(rp.dx, lane), load<T>(rp.dy, lane), load<T>(rp.dz, lane)};
    r.tmin = load<T>(rp.tmin, lane);
    r.tmax = load<T>(rp.tmax, lane);
    const Mask<T> active = load_mask<T>(rp.active, lane);
    T dd = fdot(r.d, r.d);
    const Mask<T> finite = lane::isfinite(r.o.x) && lane::isfinite(r.o.y) && lane::isfinite(r.o.z) &&
                           lane::isfinite(r.d.x) && lane::isfinite(r.d.y) && lane::isfinite(r.d.z);
    // dd must be a normal float with a normal reciprocal: a zero or subnormal
    // length has no usable reciprocal; a huge one (|d| >= 2^63) none either.
    const Mask<T> usable_d = dd >= T(kMinDirection2) && dd < T(kMaxDirection2);
    const Mask<T> interval = r.tmin < r.tmax && lane::not_(lane::isnan(r.tmin)) && lane::not_(lane::isnan(r.tmax));
    r.valid = active && finite && usable_d && interval;
    r.invalid = active && lane::not_(r.valid);
    masked += lane::count(r.invalid);
    // Replace what was masked off by a ray that hits nothing it could poison
    // (the usual packet has nothing to replace).
    if (!lane::all(r.valid)) {
        r.o = {lane::keep(r.valid, r.o.x), lane::keep(r.valid, r.o.y), lane::keep(r.valid, r.o.z)};
        r.d = {lane::keep(r.valid, r.d.x), lane::keep(r.valid, r.d.y), lane::select(r.valid, r.d.z, T(1))};
        r.tmin = lane::keep(r.valid, r.tmin);
        r.tmax = lane::keep(r.valid, r.tmax);  // empty interval: no hit can be accepted
        dd = lane::select(r.valid, dd, T(1));
    }
    finish_ray(r, dd);
    return r;
}

// ---- primitive tests ---------------------------------------------------------
// Each returns the candidate t (anything, NaN included, where `hit` is false)
// and the hit mask for the open interval (tmin, tbest).

// Rounding error of s = a + b: a + b = s + two_sum_error(a, b, s) exactly
// (Knuth's TwoSum; needs -ffp-contract=off, which this library builds with).
template <class T>
inline T two_sum_error(const T& a, const T& b, const T& s) {
    const T bv = s - a;
    return (a - (s - bv)) + (b - bv);
}

// |f|^2 - r^2 without cancellation ("Dot2", Ogita, Rump & Oishi 2005): each
// square is split exactly, x*x = p + fma(x, x, -p), and the rounding errors of
// the sum of the p's are recovered, so |f|^2 is held as s2 + lo to O(u^2 |f|^2);
// r^2 comes as r2 + r2_lo likewise. Near the surface s2 and r2 agree to many
// digits and s2 - r2 is exact (Sterbenz): c comes out correctly rounded up to
// O(u^2 |f|^2). The textbook fdot(f, f) - r2 (and equally (|f| - r)(|f| + r)
// with |f| = sqrt(fl(f.f))) keeps an absolute error ~u |f|^2: 3% of t for an
// origin 1 unit above a planet of radius 1e6.
template <class T>
inline T norm2_compensated(const Vec3<T>& f, const T& r2, const T& r2_lo) {
    const T px = f.x * f.x, py = f.y * f.y, pz = f.z * f.z;
    const T s1 = px + py, s2 = s1 + pz;
    const T lo = (lane::fma(f.x, f.x, T(0) - px) + lane::fma(f.y, f.y, T(0) - py)) + lane::fma(f.z, f.z, T(0) - pz);
    return (s2 - r2) + ((lo - r2_lo) + (two_sum_error(px, py, s1) + two_sum_error(s1, pz, s2)));
}

template <class T>
struct SphereRoots {
    T t0, t1;   // q/a and c/q (unordered)
    T disc;     // r^2 - |perp|^2: the hit needs disc >= 0
    T size2;    // max(|f|^2, r^2), to detect overflow
};

// r^2 = r2 + r2_lo exactly, r2 = fl(radius^2) and r2_lo = fma(radius, radius, -r2).
template <class T, Precision P>
OCTRAY_HOT SphereRoots<T> sphere_roots(const Ray<T, P>& r, const Vec3<T>& f, const T& r2, const T& radius) {
    const T b = fdot(f, r.d);                       // half of the textbook b
    const T s2 = fdot(f, f);
    T c = s2 - r2;
    // A packet whose every lane misses by far more than the rounding error
    // stops here: most packets miss most spheres, and the rest of the test
    // (two dependent dot products, a sqrt and a division) is the slow part.
    // The exit tests the textbook a disc = b^2 - a c, whose dependency chain
    // is half as long as disc's below (this loop is latency-bound); its
    // rounding error is below ~12u a (|f|^2 + r^2), the margin is 2^-18 a
    // (|f|^2 + r^2) = 64u, so an exiting lane misses by that much and the
    // full test would say so too (disc's error is smaller still). NaN or inf
    // (huge coordinates) never exits; a lane's answer is the same either way.
    const T bb = b * b, ac = r.dd * c;
    if (lane::all(bb - ac < r.exit_scale * (s2 + r2))) return {T(0), T(0), T(-1), T(0)};
    // f minus its projection on d, one rounding per component (FMA).
    const T nb_a = b * r.neg_inv_dd;
    const Vec3<T> perp{lane::fma(r.d.x, nb_a, f.x), lane::fma(r.d.y, nb_a, f.y), lane::fma(r.d.z, nb_a, f.z)};
    // disc = (b^2 - a c) / a^2 = r^2 - |perp|^2: from perp its error is
    // ~u |perp| |f|, small for a ray passing a far sphere, where the
    // textbook b^2 - ac cancels.
    const T perp2 = fdot(perp, perp);
    T disc = r2 - perp2;
    // Near the surface c cancels: the plain difference keeps an error
    // ~2u max(|f|^2, r^2), within 8u of |c| unless |c| < max / 4. Lanes that
    // cancel more (origins within ~15% of the radius of the surface: shadow
    // rays, a camera near a big sphere) take the compensated c, and there
    // disc = b^2/a - c where that is the better conditioned: its error is
    // ~u (b^2/a + |c|), small for a grazing ray (1 above a planet toward the
    // horizon), where |perp| ~ r ~ |f| cancels instead; it is taken when
    // b^2/a + |c| < |f|^2 / 2 (then its bound is below the other's; else the
    // other's is at most twice it). The choice is per lane, so a lane's result
    // never depends on its packet; a packet with no such lane skips the work.
    const T size2 = lane::max(s2, r2);
    const Mask<T> cancels = lane::abs(c) < T(0.25f) * size2;
    if (lane::any(cancels)) {
        const T r2_lo = lane::fma(radius, radius, T(0) - r2);
        c = lane::select(cancels, norm2_compensated(f, r2, r2_lo), c);
        const T b2_a = T(0) - b * nb_a;  // b^2 / a
        disc = lane::select(cancels && b2_a + lane::abs(c) < T(0.5f) * s2, b2_a - c, disc);
    }
    // sqrt(disc) |d| rather than sqrt(disc a): no overflow for long directions.
    // q = -(b + sign(b) sd), written (-b) - sign(b) sd: the same rounding, and
    // -b is ready long before sd.
    const T sd = lane::sqrt(lane::max(disc, T(0))) * r.len_d;
    const T q = (T(0) - b) - lane::with_sign_of(sd, b);
    // Stable pair q/a and c/q: never -b + sqrt(...) with the two nearly equal.
    return {q * r.inv_dd, lane::div<P>(c, q), disc, size2};
}

// The lanes in `huge` recomputed in units of 2^72 (see sphere_hit).
template <class T, Precision P>
OCTRAY_COLD SphereRoots<T> sphere_roots_scaled(const Ray<T, P>& r, const Vec3<T>& center, const T& r2, const T& radius,
                                               const Mask<T>& huge) {
    const T k = lane::select(huge, T(0x1p-72f), T(1)), unscale = lane::select(huge, T(0x1p72f), T(1));
    const SphereRoots<T> h = sphere_roots(r, r.o * k - center * k, r2 * (k * k), radius * k);
    return {h.t0 * unscale, h.t1 * unscale, h.disc, h.size2};
}

// Sphere of the given radius (r^2 = r2 exactly split, see sphere_roots).
// Boundary rule: a tangent ray (discriminant exactly 0) hits. From inside, the
// far root is the hit. Neither the discriminant nor c = |f|^2 - r^2 cancels
// catastrophically (sphere_roots).
// Huge coordinates: where |f|^2 or r^2 exceeds 2^100 (|f| beyond ~1e15; the
// squares overflow float near 1.8e19) the lanes are recomputed in units of
// 2^72 — a power of two, so the scaling is exact and t = 2^72 t'. The branch
// is taken only by packets that need it; a root beyond the float range is +inf
// and misses.
template <class T, Precision P>
OCTRAY_HOT T sphere_hit(const Ray<T, P>& r, const Vec3<T>& center, const T& radius, Mask<T>& hit, const T& tbest) {
    const T r2 = radius * radius;
    SphereRoots<T> s = sphere_roots(r, r.o - center, r2, radius);
    const Mask<T> huge = lane::not_(s.size2 <= T(0x1p100f));
    if (lane::any(huge)) s = sphere_roots_scaled(r, center, r2, radius, huge);
    const T tnear = lane::min(s.t0, s.t1), tfar = lane::max(s.t0, s.t1);
    const T t = lane::select(tnear > r.tmin, tnear, tfar);
    hit = s.disc >= T(0) && t > r.tmin && t < tbest;
    return t;
}

// A sphere's radius as authored (SphereArrays::radius), to tell it from r^2.
template <class T>
struct SphereRadius {
    T r;
};

// The sphere of the compiled scene: r^2 split exactly from the float radius,
// so a radius such as 1e6 (exact in float; its square is not: float(1e12)
// moves the surface by 0.002, 0.2% of t from 1 unit above) loses nothing.
template <class T, Precision P>
OCTRAY_HOT T sphere_t(const Ray<T, P>& r, const Vec3<T>& center, const SphereRadius<T>& radius, Mask<T>& hit,
                  const T& tbest) {
    return sphere_hit(r, center, radius.r, hit, tbest);
}

// Plane. Boundary rule: a ray parallel to the plane (d.n == 0), including one
// lying in it, misses.
template <class T, Precision P>
OCTRAY_HOT T plane_t(const Ray<T, P>& r, const Vec3<T>& point, const Vec3<T>& n, Mask<T>& hit, const T& tbest) {
    const T den = fdot(r.d, n);
    const T num = fdot(point - r.o, n);
    const Mask<T> facing = den != T(0);
    const T t = lane::div<P>(num, lane::select(facing, den, T(1)));
    hit = facing && t > r.tmin && t < tbest;
    return t;
}

// Disk. Boundary rule: the rim |p - c| = r is a hit; parallel rays miss.
template <class T, Precision P>
OCTRAY_HOT T disk_t(const Ray<T, P>& r, const Vec3<T>& center, const Vec3<T>& n, const T& radius2, Mask<T>& hit,
                const T& tbest) {
    const T t = plane_t(r, center, n, hit, tbest);
    const Vec3<T> q = r.o + r.d * t - center;
    hit = hit && fdot(q, q) <= radius2;
    return t;
}

// Rectangle (parallelogram corner + s a + t b). Boundary rule: s, t in the
// closed [0, 1]: edges and corners are hits; parallel rays miss.
template <class T, Precision P>
OCTRAY_HOT T rectangle_t(const Ray<T, P>& r, const Vec3<T>& corner, const Vec3<T>& n, const Vec3<T>& dual_a,
                     const Vec3<T>& dual_b, Mask<T>& hit, const T& tbest) {
    const T t = plane_t(r, corner, n, hit, tbest);
    const Vec3<T> q = r.o + r.d * t - corner;
    const T s = fdot(q, dual_a), u = fdot(q, dual_b);
    hit = hit && s >= T(0) && s <= T(1) && u >= T(0) && u <= T(1);
    return t;
}

// Axis-aligned box. Boundary rule: the box is closed (faces, edges and
// corners hit). A ray with a zero direction component whose origin lies on
// that slab's plane is inside the slab (0 * inf = NaN there becomes the whole
// line). From inside, the exit point is the hit. Needs make_slabs(r) first
// (for_each_candidate makes it).
template <class T, Precision P>
OCTRAY_HOT T box_t(const Ray<T, P>& r, const Vec3<T>& lo, const Vec3<T>& hi, Mask<T>& hit, const T& tbest) {
    auto slab = [&](const T& o, const T& inv, const T& a, const T& b, T& enter, T& leave) {
        const T t1 = (a - o) * inv, t2 = (b - o) * inv;
        const Mask<T> nan = lane::isnan(t1) || lane::isnan(t2);
        enter = lane::max(enter, lane::select(nan, T(0) - inf<T>(), lane::min(t1, t2)));
        leave = lane::min(leave, lane::select(nan, inf<T>(), lane::max(t1, t2)));
    };
    T enter = T(0) - inf<T>(), leave = inf<T>();
    slab(r.o.x, r.inv_d.x, lo.x, hi.x, enter, leave);
    slab(r.o.y, r.inv_d.y, lo.y, hi.y, enter, leave);
    slab(r.o.z, r.inv_d.z, lo.z, hi.z, enter, leave);
    const T t = lane::select(enter > r.tmin, enter, leave);
    hit = enter <= leave && t > r.tmin && t < tbest;
    return t;
}

// Edge functions of the watertight test: the vertices' coordinates across the
// ray (projections shared by every triangle that has the vertex), then 2D
// cross products fl(fl(a b) - fl(c d)). Rounding is monotone, so each sign
// is the exact sign for the projected points or 0; a shared edge gives
// exactly opposite values; and around a shared vertex the signs are those of
// one exact 2D configuration, in which the ray's point lies in some closed
// triangle of the fan. lo/hi: the least and greatest of the three.
template <class T, Precision P>
inline void triangle_edges(const Ray<T, P>& r, const Vec3<T>& v0, const Vec3<T>& v1, const Vec3<T>& v2, T& lo, T& hi) {
    const T x0 = fdot(r.proj_a, v0), y0 = fdot(r.proj_b, v0);
    const T x1 = fdot(r.proj_a, v1), y1 = fdot(r.proj_b, v1);
    const T x2 = fdot(r.proj_a, v2), y2 = fdot(r.proj_b, v2);
    const T e0 = x1 * y2 - y1 * x2, e1 = x2 * y0 - y2 * x0, e2 = x0 * y1 - y0 * x1;
    lo = lane::min(e0, lane::min(e1, e2)), hi = lane::max(e0, lane::max(e1, e2));
}

// Triangle, watertight (see triangle_edges). Boundary rule: edges and
// vertices hit (closed edge tests); a ray in the triangle's plane misses.
// Needs make_shear(r) first (for_each_candidate makes it).
// t comes from the compiled unit normal n (rounded once from double), not
// from cross products of the ray-relative vertices: those lose |v|/edge ulps
// for a triangle far from the origin, and their cube overflows float sooner.
// Huge coordinates: the edge functions are of degree 2 in v = vertex - o;
// where one is not finite (|v| beyond ~1e18) the lane is re-evaluated in units
// of 2^72 — exact, and only signs count, so an edge shared with an unscaled
// neighbour keeps its exactly opposite sign (rare branch).
template <class T, Precision P>
OCTRAY_HOT T triangle_t(const Ray<T, P>& r, const Vec3<T>& a, const Vec3<T>& b, const Vec3<T>& c, const Vec3<T>& n,
                    Mask<T>& hit, const T& tbest) {
    const Vec3<T> v0 = a - r.o;
    T lo, hi;
    triangle_edges(r, v0, b - r.o, c - r.o, lo, hi);
    const Mask<T> huge = lane::not_(lane::isfinite(lo + hi));
    if (lane::any(huge)) {
        const T k = lane::select(huge, T(0x1p-72f), T(1));
        const Vec3<T> ok = r.o * k;
        triangle_edges(r, a * k - ok, b * k - ok, c * k - ok, lo, hi);
    }
    // In the plane (or degenerate): all three are 0, or d.n = 0.
    const Mask<T> inside = (lo >= T(0) || hi <= T(0)) && (lo != T(0) || hi != T(0));
    const T den = fdot(n, r.d);
    const Mask<T> facing = den != T(0);
    const T t = lane::div<P>(fdot(n, v0), lane::select(facing, den, T(1)));
    hit = inside && facing && t > r.tmin && t < tbest;
    return t;
}

// ---- closest hit -----------------------------------------------------------
template <class T>
struct Closest {
    T t;    // tmax until something is hit
    T cid;  // compiled id of the hit primitive (exact float), -1 on a miss

    // Keeps the lanes of `hit` (a test accepted them for t' < t) at t' and id.
    OCTRAY_HOT void take(const Mask<T>& hit, const T& t_hit, int id) {
        if (!lane::any(hit)) return;  // most tests miss on every lane
        t = lane::select(hit, t_hit, t);
        cid = lane::select(hit, T(float(id)), cid);
    }
};

template <PrimitiveType Type>
using TypeTag = std::integral_constant<PrimitiveType, Type>;

// Calls body(TypeTag<type>, count) for each primitive type in F. Absent types
// are removed at compile time; present ones loop over s.count.
template <unsigned F, class Body>
inline void for_each_primitive_type(const PacketScene& s, Body&& body) {
    if constexpr ((F & kSphere) != 0) body(TypeTag<PrimitiveType::sphere>{}, s.count[0]);
    if constexpr ((F & kPlane) != 0) body(TypeTag<PrimitiveType::plane>{}, s.count[1]);
    if constexpr ((F & kDisk) != 0) body(TypeTag<PrimitiveType::disk>{}, s.count[2]);
    if constexpr ((F & kRectangle) != 0) body(TypeTag<PrimitiveType::rectangle>{}, s.count[3]);
    if constexpr ((F & kBox) != 0) body(TypeTag<PrimitiveType::box>{}, s.count[4]);
    if constexpr ((F & kTriangle) != 0) body(TypeTag<PrimitiveType::triangle>{}, s.count[5]);
}

// Tests primitive k of type `Type` (parameters broadcast from the scene arrays).
template <PrimitiveType Type, class T, Precision P>
OCTRAY_HOT T test_primitive(const PacketScene& s, int k, const Ray<T, P>& r, Mask<T>& hit, const T& tbest) {
    if constexpr (Type == PrimitiveType::sphere) {
        const SphereArrays& a = s.spheres;
        return sphere_t(r, broadcast3<T>(a.cx, a.cy, a.cz, k), SphereRadius<T>{broadcast<T>(a.radius, k)}, hit, tbest);
    } else if constexpr (Type == PrimitiveType::plane) {
        const PlaneArrays& a = s.planes;
        return plane_t(r, broadcast3<T>(a.px, a.py, a.pz, k), broadcast3<T>(a.nx, a.ny, a.nz, k), hit, tbest);
    } else if constexpr (Type == PrimitiveType::disk) {
        const DiskArrays& a = s.disks;
        return disk_t(r, broadcast3<T>(a.cx, a.cy, a.cz, k), broadcast3<T>(a.nx, a.ny, a.nz, k),
                      broadcast<T>(a.radius2, k), hit, tbest);
    } else if constexpr (Type == PrimitiveType::rectangle) {
        const RectangleArrays& a = s.rectangles;
        return rectangle_t(r, broadcast3<T>(a.cx, a.cy, a.cz, k), broadcast3<T>(a.nx, a.ny, a.nz, k),
                           broadcast3<T>(a.dual_ax, a.dual_ay, a.dual_az, k),
                           broadcast3<T>(a.dual_bx, a.dual_by, a.dual_bz, k), hit, tbest);
    } else if constexpr (Type == PrimitiveType::box) {
        const BoxArrays& a = s.boxes;
        return box_t(r, broadcast3<T>(a.minx, a.miny, a.minz, k), broadcast3<T>(a.maxx, a.maxy, a.maxz, k), hit,
                     tbest);
    } else {
        const TriangleArrays& a = s.triangles;
        return triangle_t(r, broadcast3<T>(a.x0, a.y0, a.z0, k), broadcast3<T>(a.x1, a.y1, a.z1, k),
                          broadcast3<T>(a.x2, a.y2, a.z2, k), broadcast3<T>(a.nx, a.ny, a.nz, k), hit, tbest);
    }
}

// May a valid lane of the packet hit anything inside the bounding sphere j of
// `c` before `tbest`? It answers no only when, on every valid lane, the ray's
// line passes outside the sphere, or the sphere lies behind the origin, or
// it begins beyond tbest — each by a margin of 2^-18 of the squared scale
// (t: 2^-10 relative), far above the rounding error of these few operations
// (~12u). NaN or inf (huge coordinates) answers maybe. Skipping changes no
// lane's result, so the scalar and SIMD paths still agree bit for bit.
template <class T, Precision P>
OCTRAY_HOT bool cluster_may_hit(const Ray<T, P>& r, const ClusterTree& c, int j, const T& tbest) {
    const Vec3<T> f = r.o - broadcast3<T>(c.cx, c.cy, c.cz, j);
    const T rb = broadcast<T>(c.radius, j);
    const T rb2 = rb * rb, s2 = fdot(f, f);
    const T b = fdot(f, r.d);
    // The line misses: a (rb^2 - |perp|^2) = b^2 - a (s2 - rb2) < 0, in the
    // textbook form for its short dependency chain (as sphere_roots' exit;
    // its error is below ~12u a (s2 + rb2), a sixth of the margin).
    const T outside = s2 - rb2, margin = T(0x1p-18f) * (s2 + rb2);
    const Mask<T> line_misses = b * b - r.dd * outside < T(0) - r.dd * margin;
    // Most packets pass a small type's root far off: stop before the other
    // two tests, as a single ray's short-circuit would.
    if (lane::all(line_misses || lane::not_(r.valid))) return false;
    const Mask<T> behind = b > T(0) && outside > margin;
    const T t_enter = (T(0) - b - rb * r.len_d) * r.inv_dd;  // no point of the sphere is nearer
    const Mask<T> beyond = t_enter - lane::abs(t_enter) * T(0x1p-10f) > tbest;
    return lane::any(r.valid && lane::not_(line_misses || behind || beyond));
}

// A node's children are tested against a packet's beam a vector of them at a
// time, on every path (the scalar path too, as single-ray tracers test wide
// nodes): 8 floats where the unit has AVX, else 4.
#if defined(__AVX__)
using NodeLanes = xsimd::batch<float, xsimd::avx>;
#else
using NodeLanes = xsimd::batch<float, xsimd::sse2>;
#endif
static_assert(kTreeWidth % NodeLanes::size == 0, "a node's children fill whole vectors");

// The valid rays of a packet as one beam: every ray's line passes within
// `spread` of `origin` and runs at an angle theta or less to the unit `axis`
// (cos_theta <= cos of each ray's angle, sin_theta >= its sine). Axis and
// origin are lane 0's: any ray would do, the bound holds for every choice (a
// masked-off lane 0, rare, makes it loose). sin theta is taken as
// |d x axis|, not sqrt(1 - cos^2), which cancels for the small angles of
// coherent rays. Broadcast to the node lanes; computed in float (double
// lanes round to it).
struct Beam {
    Vec3<NodeLanes> origin, axis;
    NodeLanes cos2_theta, sin_theta, spread;
};

template <class T, Precision P>
inline Beam make_beam(const Ray<T, P>& r) {
    const T inv_len = r.len_d * r.inv_dd;  // 1 / |d|
    const Vec3<T> dir = r.d * inv_len;
    // The origin in float, and the spread measured from it: double lanes'
    // rounding of it is part of the spread.
    const float ox = float(lane::lane0(r.o.x)), oy = float(lane::lane0(r.o.y)), oz = float(lane::lane0(r.o.z));
    const float ax = float(lane::lane0(dir.x)), ay = float(lane::lane0(dir.y)), az = float(lane::lane0(dir.z));
    const Vec3<T> axis{T(ax), T(ay), T(az)};
    const Vec3<T> across = cross(dir, axis);
    const Vec3<T> off = r.o - Vec3<T>{T(ox), T(oy), T(oz)};  // each component rounded once: relative error u
    const float cos_theta = float(lane::lane0(lane::hmin(lane::select(r.valid, fdot(dir, axis), T(1)))));
    const float sin2_theta = float(lane::lane0(lane::hmax(lane::keep(r.valid, fdot(across, across)))));
    const float spread2 = float(lane::lane0(lane::hmax(lane::keep(r.valid, fdot(off, off)))));
    // At 90 degrees or more (cos <= 0, or NaN) the bound says nothing: cos 0, sin 1.
    const bool narrow = cos_theta > 0.0f;
    return {{NodeLanes(ox), NodeLanes(oy), NodeLanes(oz)},
            {NodeLanes(ax), NodeLanes(ay), NodeLanes(az)},
            NodeLanes(narrow ? cos_theta * cos_theta : 0.0f),
            NodeLanes(narrow ? std::sqrt(sin2_theta) : 1.0f),
            NodeLanes(std::sqrt(spread2) * (1 + 0x1p-16f))};
}

// A packet's beam, made when a walk first needs it and shared by the types'
// walks (any_hit's later walks have fewer valid lanes: the beam still covers
// them).
template <class T, Precision P>
struct LazyBeam {
    const Ray<T, P>& r;
    bool made = false;
    Beam beam;
    explicit LazyBeam(const Ray<T, P>& ray) : r(ray) {}
    const Beam& get() {
        if (!made) beam = make_beam(r), made = true;
        return beam;
    }
};

// Which of the `count` spheres at cx[first..] (a node's children, or a
// leaf's primitives) may a ray of the beam come near? Bit i clear means every
// ray's line passes outside sphere i. With q = centre - origin, the distance
// from the centre to a ray's line is at least |q x axis| cos theta -
// |q.axis| sin theta - spread (the angle between the lines of q and of the
// ray is at least that between q's and the axis' less theta); the test
// compares squares (no sqrt on the way to the branch). The rounding error is
// a few u |q| (a few float u more for double lanes' beam); the test keeps a
// margin of 2^-14 max|q_i| (>= 2^-15 |q|). Infinite or NaN terms (huge
// coordinates, infinite radii) keep the sphere.
OCTRAY_HOT unsigned beam_near(const Beam& b, const Floats& cx, const Floats& cy, const Floats& cz, const Floats& radius,
                              int first, int count) {
    using N = NodeLanes;
    constexpr int w = int(N::size);
    unsigned near = 0;
    for (int i = 0; i < count; i += w) {
        const std::size_t at = std::size_t(first + i);
        const Vec3<N> q = Vec3<N>{N::load_unaligned(cx.data() + at), N::load_unaligned(cy.data() + at),
                                  N::load_unaligned(cz.data() + at)} - b.origin;
        const Vec3<N> x = cross(q, b.axis);
        const N q_max = lane::max(lane::abs(q.x), lane::max(lane::abs(q.y), lane::abs(q.z)));
        const N reach = N::load_unaligned(radius.data() + at) + b.spread + lane::abs(fdot(q, b.axis)) * b.sin_theta +
                        q_max * N(0x1p-14f);
        const N across2 = fdot(x, x);
        const auto outside = across2 * b.cos2_theta > reach * reach && across2 < N(INFINITY);
        near |= (lane::bits(outside) ^ ((1u << w) - 1u)) << i;
    }
    return near & ((1u << count) - 1u);
}

// for_each_candidate's walk below the root.
template <PrimitiveType Type, class T, Precision P, class Test>
OCTRAY_HOT void walk_tree(const ClusterTree& tree, int n, const Ray<T, P>& r, LazyBeam<T, P>& lazy, Test& test) {
    const Beam& beam = lazy.get();
    int stack[64];  // a pop pushes <= kTreeWidth - 1 more per level: 8 levels for 2^24 primitives
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const int j = stack[--top];
        const int first = tree.first_child[std::size_t(j)];
        if (first < 0) {
            const int k0 = tree.cluster[std::size_t(j)] * kClusterSize;
            const int k1 = k0 + kClusterSize < n ? k0 + kClusterSize : n;
            for (unsigned near = beam_near(beam, tree.px, tree.py, tree.pz, tree.pradius, k0, k1 - k0); near != 0;
                 near &= near - 1)
                test(k0 + __builtin_ctz(near));
            if (!lane::any(r.valid)) return;  // any_hit: every lane blocked
            continue;
        }
        // Pushed last to first, so they pop in order.
        for (unsigned near = beam_near(beam, tree.cx, tree.cy, tree.cz, tree.radius, first,
                                       tree.child_count[std::size_t(j)]);
             near != 0;) {
            const int i = 31 - __builtin_clz(near);
            near &= ~(1u << i);
            assert(top < 64 && "deeper than a tree of 2^24 primitives");
            stack[top++] = first + i;
        }
    }
}

// Out of line, for kernels with several bounded primitive types: inline, six
// walks crowd the small scenes' path (one node per type), where they never
// run (callgrind, scenes/default.json: +12% instructions in intersect); with
// one type the walk stays inline (the Embree peer's spheres:64: 10% fewer).
template <PrimitiveType Type, class T, Precision P, class Test>
OCTRAY_WALK void walk_tree_out_of_line(const ClusterTree& tree, int n, const Ray<T, P>& r, LazyBeam<T, P>& lazy,
                                       Test& test) {
    walk_tree<Type>(tree, n, r, lazy, test);
}

// Primitive types other than planes (those with a tree) in a feature set.
inline constexpr int bounded_types(unsigned f) {
    return __builtin_popcount(f & kAllPrimitives & ~unsigned(kPlane));
}

// Calls test(k) for every primitive k of the type that may hit before `tbest`,
// walking the type's bounding-sphere tree (planes: all of them). The root is
// tested ray by ray (cluster_may_hit, which knows tbest); below it a node's
// children, and a leaf's primitives, are tested against the packet's beam a
// vector at a time, and only those it comes near are visited. Ray by ray
// every node cost about a sphere test; the beam tests 8 for about one
// (callgrind, the Embree peer's spheres:64 scene: 1048 instructions per
// packet with the binary tree of per-ray tests, 722 so). `test` may lower
// tbest and narrow r.valid as it goes (any_hit drops blocked lanes; the walk
// ends when none is left). Children are visited in order whatever the rays'
// direction, so primitives are tested in compiled order, as without the
// tree: exact-t ties resolve the same way on every path. F, the kernel's
// features, decides where the walk is compiled (walk_tree_out_of_line).
template <PrimitiveType Type, unsigned F = (1u << unsigned(Type)), class T, Precision P, class Test>
OCTRAY_HOT void for_each_candidate(const PacketScene& s, int n, const Ray<T, P>& r, const T& tbest, LazyBeam<T, P>& lazy,
                                   Test&& test) {
    if constexpr (Type == PrimitiveType::plane) {
        for (int k = 0; k < n; ++k) test(k);
    } else {
        const ClusterTree& tree = s.clusters[std::size_t(Type)];
        if (tree.size() == 0 || !cluster_may_hit(r, tree, 0, tbest)) return;
        if constexpr (Type == PrimitiveType::box) make_slabs(r);
        if constexpr (Type == PrimitiveType::triangle) make_shear(r);
        if (tree.size() == 1) {  // one cluster (a scene with few of the type): no walk
            for (int k = 0; k < n; ++k) test(k);
            return;
        }
        if constexpr (bounded_types(F) > 1) walk_tree_out_of_line<Type>(tree, n, r, lazy, test);
        else walk_tree<Type>(tree, n, r, lazy, test);
    }
}

// The same for a walk of one type alone.
template <PrimitiveType Type, class T, Precision P, class Test>
OCTRAY_HOT void for_each_candidate(const PacketScene& s, int n, const Ray<T, P>& r, const T& tbest, Test&& test) {
    LazyBeam<T, P> lazy(r);
    for_each_candidate<Type>(s, n, r, tbest, lazy, test);
}

template <class T, Precision P, unsigned F>
inline Closest<T> closest_hit(const PacketScene& s, const Ray<T, P>& r) {
    Closest<T> best{r.tmax, T(-1)};
    LazyBeam<T, P> beam(r);
    for_each_primitive_type<F>(s, [&](auto tag, int n) {
        constexpr PrimitiveType type = decltype(tag)::value;
        const int base = s.offset[int(type)];
        for_each_candidate<type, F>(s, n, r, best.t, beam, [&](int k) OCTRAY_HOT_LAMBDA {
            Mask<T> hit;
            const T t = test_primitive<type, T, P>(s, k, r, hit, best.t);
            best.take(hit, t, base + k);
        });
    });
    return best;
}

// Unit geometric normal of a primitive of type `Type` at p, its data read
// through `at` (the lanes' indices within the type). `d` (the ray direction)
// breaks ties on box edges.
template <PrimitiveType Type, class T>
inline Vec3<T> type_normal(const PacketScene& s, const Lookup<T>& at, const Vec3<T>& p, const Vec3<T>& d) {
    if constexpr (Type == PrimitiveType::sphere) {
        const SphereArrays& a = s.spheres;
        return (p - at(a.cx, a.cy, a.cz)) * at(a.inv_radius);
    } else if constexpr (Type == PrimitiveType::plane) {
        return at(s.planes.nx, s.planes.ny, s.planes.nz);
    } else if constexpr (Type == PrimitiveType::disk) {
        return at(s.disks.nx, s.disks.ny, s.disks.nz);
    } else if constexpr (Type == PrimitiveType::rectangle) {
        return at(s.rectangles.nx, s.rectangles.ny, s.rectangles.nz);
    } else if constexpr (Type == PrimitiveType::box) {
        // The face is the axis where p sits farthest out relative to the
        // half extent. On an edge or corner (a tie) it is the face the ray
        // crosses most steeply (largest |d| component; then x, then y): a
        // ray gliding along one face into an edge enters through the other,
        // as the reference's deciding slab says.
        const BoxArrays& a = s.boxes;
        const Vec3<T> lo = at(a.minx, a.miny, a.minz), hi = at(a.maxx, a.maxy, a.maxz);
        const Vec3<T> c = (lo + hi) * T(0.5f), h = (hi - lo) * T(0.5f);
        const Vec3<T> q = p - c;
        const T rx = lane::abs(q.x) / h.x, ry = lane::abs(q.y) / h.y, rz = lane::abs(q.z) / h.z;
        const T dx = lane::abs(d.x), dy = lane::abs(d.y), dz = lane::abs(d.z);
        const Mask<T> ax = (rx > ry || (rx == ry && dx >= dy)) && (rx > rz || (rx == rz && dx >= dz));
        const Mask<T> ay = lane::not_(ax) && (ry > rz || (ry == rz && dy >= dz)), az = lane::not_(ax || ay);
        return {lane::keep(ax, lane::copysign(T(1), q.x)), lane::keep(ay, lane::copysign(T(1), q.y)),
                lane::keep(az, lane::copysign(T(1), q.z))};
    } else {
        return at(s.triangles.nx, s.triangles.ny, s.triangles.nz);
    }
}

// Unit geometric normal at p for the lanes of `hit`, whose hits' compiled ids
// `at` looks up (at.idx; the caller's id stores share the lookup); other
// lanes get an unspecified normal (the caller drops them).
// A coherent packet's hit lanes mostly share one primitive: then only that
// type's normal is computed, from its broadcast data; else each type present
// computes its lanes' normals from gathered data.
template <class T, unsigned F>
inline Vec3<T> hit_normal(const PacketScene& s, const Lookup<T>& at, const Vec3<T>& p, const Mask<T>& hit,
                          const Vec3<T>& d) {
    Vec3<T> n{T(0), T(0), T(1)};
    if (!lane::any(hit)) return n;
    if (at.uniform) {
        const int shared = at.first;
        for_each_primitive_type<F>(s, [&](auto tag, int count) {
            constexpr PrimitiveType type = decltype(tag)::value;
            const int base = s.offset[int(type)];
            if (shared >= base && shared < base + count)
                n = type_normal<type>(s, Lookup<T>::at_index(shared - base), p, d);
        });
        return n;
    }
    const T& cid = at.idx;
    for_each_primitive_type<F>(s, [&](auto tag, int count) {
        constexpr PrimitiveType type = decltype(tag)::value;
        const int base = s.offset[int(type)];
        const Mask<T> mine = hit && cid >= T(float(base)) && cid < T(float(base + count));
        if (count == 0 || !lane::any(mine)) return;
        const Vec3<T> m = type_normal<type>(s, Lookup<T>(lane::keep(mine, cid - T(float(base))), mine), p, d);
        n = {lane::select(mine, m.x, n.x), lane::select(mine, m.y, n.y), lane::select(mine, m.z, n.z)};
    });
    return n;
}

template <class T, Precision P, unsigned F>
inline int intersect_lanes(const PacketScene& s, const RayPacket8& rp, HitPacket8& hp, int lane) {
    int masked = 0;
    const Ray<T, P> r = load_ray<T, P>(rp, lane, masked);
    const Closest<T> best = closest_hit<T, P, F>(s, r);
    const Mask<T> hit = r.valid && best.cid >= T(0);
    const T cid = lane::keep(hit, best.cid);
    const Vec3<T> p = r.o + r.d * best.t;
    const Lookup<T> at(cid, hit);
    Vec3<T> n = hit_normal<T, F>(s, at, p, hit, r.d);
    // Face-forward (two-sided shading): the normal opposes the ray.
    const Mask<T> away = fdot(n, r.d) > T(0);
    n = {lane::select(away, T(0) - n.x, n.x), lane::select(away, T(0) - n.y, n.y), lane::select(away, T(0) - n.z, n.z)};
    store(hp.t, lane, lane::select(hit, best.t, inf<T>()));
    store_index(hp.primitive, lane, lane::select(hit, at(s.object_of), T(-1)));
    store_index(hp.material, lane, lane::select(hit, at(s.material_of), T(-1)));
    store(hp.nx, lane, lane::keep(hit, n.x));
    store(hp.ny, lane, lane::keep(hit, n.y));
    store(hp.nz, lane, lane::keep(hit, n.z));
    store_mask<T>(hp.hit, lane, hit);
    store_mask<T>(hp.invalid, lane, r.invalid);
    return masked;
}

template <class T, Precision P, unsigned F>
int intersect_packet(const PacketScene& s, const RayPacket8& rp, HitPacket8& hp) noexcept {
    int masked = 0;
    for (int lane = 0; lane < kPacketWidth; lane += lane::width<T>) masked += intersect_lanes<T, P, F>(s, rp, hp, lane);
    return masked;
}

// ---- any hit (shadow rays) -------------------------------------------------
// The valid lanes of `live` blocked in (tmin, tmax). live.valid narrows as
// lanes are blocked (the walk culls what none of the others can reach and
// stops when none is left); the ray is the caller's, not copied: a copy of
// the whole Ray costs more than a shadow ray's culling.
template <class T, Precision P, unsigned F>
inline Mask<T> any_hit(const PacketScene& s, Ray<T, P>& live) {
    const Mask<T> valid = live.valid;
    LazyBeam<T, P> beam(live);
    for_each_primitive_type<F>(s, [&](auto tag, int n) {
        constexpr PrimitiveType type = decltype(tag)::value;
        if (!lane::any(live.valid)) return;
        for_each_candidate<type, F>(s, n, live, live.tmax, beam, [&](int k) OCTRAY_HOT_LAMBDA {
            Mask<T> hit;
            test_primitive<type, T, P>(s, k, live, hit, live.tmax);
            live.valid = live.valid && lane::not_(hit);
        });
    });
    return valid && lane::not_(live.valid);
}

template <class T, Precision P, unsigned F>
void occluded_packet(const PacketScene& s, const RayPacket8& rp, std::int32_t* occluded) noexcept {
    for (int lane = 0; lane < kPacketWidth; lane += lane::width<T>) {
        int masked = 0;
        Ray<T, P> r = load_ray<T, P>(rp, lane, masked);
        store_mask<T>(occluded, lane, any_hit<T, P, F & kAllPrimitives>(s, r));
    }
}

// ---- shading (seed eq. 7-8) ------------------------------------------------
// Fills r with the shadow ray from p toward a light at distance `dist` along
// unit `l`. The origin moves off the surface along the facing normal so the
// surface does not shadow itself: by 1e-4 |p|, or by more than the hit point's error where the
// precision mode's error over the camera ray's length `reach` (|p - o|, max
// norm) is larger (precision.hpp, shadow_offset).
template <class T, Precision P>
inline void shadow_ray(Ray<T, P>& r, const Vec3<T>& p, const Vec3<T>& n, const Vec3<T>& l, const T& dist,
                       const Mask<T>& valid, const T& reach) {
    const T scale = lane::max(lane::max(lane::abs(p.x), lane::abs(p.y)), lane::max(lane::abs(p.z), T(1)));
    const T eps = lane::max(scale * T(1e-4f), (scale + reach) * T(float(shadow_offset(P))));
    r.o = p + n * eps;
    r.d = l;
    r.tmin = T(0);
    r.tmax = dist;
    r.valid = valid;
    r.invalid = Mask<T>(false);
    finish_ray(r, fdot(l, l));
}

// The lanes of `lit` whose shadow ray (shadow_ray's arguments) something
// blocks; the ray is built in place for any_hit, which narrows it.
template <class T, Precision P>
inline Mask<T> shadowed(const PacketScene& s, const Vec3<T>& p, const Vec3<T>& n, const Vec3<T>& l, const T& dist,
                        const Mask<T>& lit, const T& reach) {
    Ray<T, P> shadow;
    shadow_ray(shadow, p, n, l, dist, lit, reach);
    return any_hit<T, P, kAllPrimitives>(s, shadow);
}

// Adds one light's ls*cl * max(0, n.l) [* 1/r^2] to E where `lit`.
// Summation: plain recursive, one FMA per term. Every term is >= 0, so the
// relative error of the sum is <= (n-1) u for n lights whatever their dynamic
// range (Higham, "Accuracy and Stability of Numerical Algorithms", 2nd ed.,
// sec. 4.2): a term below u of the total is rounded away, which is its correct
// rounding. Compensated summation would only remove that (n-1) u, which the
// per-term errors (n.l, 1/r^2, a few u each) match anyway; `octray stability`
// measures it (case lights_64_over_12_decades). Overflow: a term whose weight
// or ls*cl is +inf gives +inf, never NaN: 0 * inf (an unlit lane's zero weight
// times an infinite ls*cl, or a zero colour channel times an infinite weight)
// is NaN, and max(x, e) keeps e there (lane::max returns its second operand on
// NaN); elsewhere x = e + radiance * w >= e, so the max changes nothing.
template <class T>
inline void accumulate(Vec3<T>& e, const Mask<T>& lit, const T& weight, const Vec3<T>& radiance) {
    const T w = lane::keep(lit, weight);
    e = {lane::max(lane::fma(radiance.x, w, e.x), e.x), lane::max(lane::fma(radiance.y, w, e.y), e.y),
         lane::max(lane::fma(radiance.z, w, e.z), e.z)};
}

template <class T, Precision P, unsigned F>
inline void shade_lanes(const PacketScene& s, const RayPacket8& rp, const HitPacket8& hp, ColorPacket8& out, int lane) {
    const Mask<T> hit = load_mask<T>(hp.hit, lane) && load_mask<T>(rp.active, lane);
    const Vec3<T> o{load<T>(rp.ox, lane), load<T>(rp.oy, lane), load<T>(rp.oz, lane)};
    const Vec3<T> d{load<T>(rp.dx, lane), load<T>(rp.dy, lane), load<T>(rp.dz, lane)};
    const T t = lane::keep(hit, load<T>(hp.t, lane));
    const Vec3<T> p{lane::keep(hit, lane::fma(d.x, t, o.x)), lane::keep(hit, lane::fma(d.y, t, o.y)),
                    lane::keep(hit, lane::fma(d.z, t, o.z))};
    const Vec3<T> n{load<T>(hp.nx, lane), load<T>(hp.ny, lane), load<T>(hp.nz, lane)};
    const T m = lane::keep(hit, load_index<T>(hp.material, lane));
    [[maybe_unused]] const T reach = t * lane::max(lane::max(lane::abs(d.x), lane::abs(d.y)), lane::abs(d.z));

    Vec3<T> e{T(0), T(0), T(0)};  // sum over lights of ls*cl * n.l [/ r^2]
    if constexpr ((F & kDirectional) != 0) {
        const DirectionalArrays& a = s.directional;
        for (int k = 0; k < s.directional_count; ++k) {
            const Vec3<T> l = broadcast3<T>(a.lx, a.ly, a.lz, k);
            const T ndl = fdot(n, l);
            Mask<T> lit = hit && ndl > T(0);
            if constexpr ((F & kShadows) != 0) {
                if (a.shadows[std::size_t(k)] != 0.0f && lane::any(lit))
                    lit = lit && lane::not_(shadowed<T, P>(s, p, n, l, inf<T>(), lit, reach));
            }
            accumulate(e, lit, ndl, broadcast3<T>(a.r, a.g, a.b, k));
        }
    }
    auto point_lights = [&](const PointArrays& a, int count, auto attenuated) {
        for (int k = 0; k < count; ++k) {
            const Vec3<T> pos = broadcast3<T>(a.px, a.py, a.pz, k);
            Vec3<T> v = pos - p;
            T r2 = fdot(v, v), scale = T(1), unscale = T(1);
            // r^2 outside [2^-100, 2^100] (a light nearer than ~1e-15 or farther
            // than ~1e15: r^2 subnormal, zero or overflowing, where rsqrt loses
            // bits or the estimate modes read 0): measure v in units of 2^-80
            // or 2^80 instead. Powers of two, so exact; a rare branch.
            const Mask<T> odd = hit && lane::not_(r2 >= T(0x1p-100f) && r2 <= T(0x1p100f));
            if (lane::any(odd)) {
                const Mask<T> far = r2 > T(1);
                scale = lane::select(odd, lane::select(far, T(0x1p-80f), T(0x1p80f)), T(1));
                unscale = lane::select(odd, lane::select(far, T(0x1p80f), T(0x1p-80f)), T(1));
                v = pos * scale - p * scale;
                r2 = fdot(v, v);
            }
            const Mask<T> apart = r2 > T(0);  // a light exactly on the surface point lights nothing
            const T inv_r = lane::rsqrt<P>(lane::select(apart, r2, T(1)));  // 1/|v|, v in its units
            const T ndl = fdot(n, v) * inv_r;
            Mask<T> lit = hit && apart && ndl > T(0);
            if constexpr ((F & kShadows) != 0) {
                if (a.shadows[std::size_t(k)] != 0.0f && lane::any(lit))
                    lit = lit && lane::not_(shadowed<T, P>(s, p, n, v * inv_r, (r2 * inv_r) * unscale, lit, reach));
            }
            T weight = ndl;
            if constexpr (decltype(attenuated)::value) {
                // eq. 6: 1/r^2. Below r ~ 1e-19 it overflows to +inf: the lit
                // channels become +inf, never NaN (see accumulate).
                const T inv_dist = inv_r * scale;
                weight = weight * (inv_dist * inv_dist);
            }
            accumulate(e, lit, weight, broadcast3<T>(a.r, a.g, a.b, k));
        }
    };
    if constexpr ((F & kPoint) != 0) point_lights(s.point, s.point_count, std::false_type{});
    if constexpr ((F & kPointAttenuated) != 0) point_lights(s.point_attenuated, s.point_attenuated_count, std::true_type{});

    // L = ka cd * ls cl  +  kd cd / pi * E   (eq. 8, the diffuse factor taken out of the sum)
    const Lookup<T> material(m, hit);
    Vec3<T> c = hadamard(material(s.diffuse_r, s.diffuse_g, s.diffuse_b), e);
    // kd cd = 0 times an overflowed E = +inf is NaN; the radiance is 0 there
    // (max(x, 0) flushes NaN to 0; every other x is >= 0 and passes).
    c = {lane::max(c.x, T(0)), lane::max(c.y, T(0)), lane::max(c.z, T(0))};
    if constexpr ((F & kAmbient) != 0) c += material(s.ambient_r, s.ambient_g, s.ambient_b);
    store(out.r, lane, lane::select(hit, c.x, T(s.background[0])));
    store(out.g, lane, lane::select(hit, c.y, T(s.background[1])));
    store(out.b, lane, lane::select(hit, c.z, T(s.background[2])));
}

template <class T, Precision P, unsigned F>
void shade_packet(const PacketScene& s, const RayPacket8& rp, const HitPacket8& hp, ColorPacket8& out) noexcept {
    for (int lane = 0; lane < kPacketWidth; lane += lane::width<T>) shade_lanes<T, P, F>(s, rp, hp, out, lane);
}

// ---- tone mapping (DESIGN.md) ---------------------------------------------
// c^y for c > 0: on float lanes lane_pow.hpp's, the same code on both paths
// (libm's powf and xsimd's pow differ, and xsimd's is ~100 cycles per batch);
// double lanes (the f64 mode) keep libm's / xsimd's double pow.
template <class T>
inline T gamma_pow(const T& c, const T& y) {
    if constexpr (std::is_same_v<lane::Scalar<T>, float>) return lane::pow_positive(c, y);
    else return lane::pow(c, y);
}

// NaN radiance becomes 0. Under max_to_one an infinite component becomes 1
// and the finite ones 0 (the limit of c / max as max -> inf); clamp_to_color
// treats inf as out of gamut; saturate clamps it to 1.
template <class T, Precision P, ToneMap M>
inline void tonemap_lanes(const PacketScene& s, const ColorPacket8& in, ColorPacket8& out, int lane) {
    // max(x, 0) flushes NaN to 0 (lane::max returns its second operand on NaN).
    T r = lane::max(load<T>(in.r, lane), T(0));
    T g = lane::max(load<T>(in.g, lane), T(0));
    T b = lane::max(load<T>(in.b, lane), T(0));
    if constexpr (M == ToneMap::max_to_one) {
        const T mx = lane::max(r, lane::max(g, b));
        const Mask<T> over = mx > T(1);
        const Mask<T> infinite = mx == inf<T>();
        const T scale = lane::rcp<P>(lane::select(over && lane::not_(infinite), mx, T(1)));
        auto fix = [&](const T& c) {
            return lane::select(infinite, lane::keep(c == inf<T>(), T(1)), lane::select(over, lane::min(c * scale, T(1)), c));
        };
        r = fix(r), g = fix(g), b = fix(b);
    } else if constexpr (M == ToneMap::clamp_to_color) {
        const Mask<T> over = r > T(1) || g > T(1) || b > T(1);
        r = lane::select(over, T(s.clamp_color[0]), r);
        g = lane::select(over, T(s.clamp_color[1]), g);
        b = lane::select(over, T(s.clamp_color[2]), b);
    } else {
        r = lane::min(r, T(1)), g = lane::min(g, T(1)), b = lane::min(b, T(1));
    }
    if (s.inv_gamma != 1.0f) {
        const T ig(s.inv_gamma);
        // c = 0 computes a finite value that the select drops.
        auto gam = [&](const T& c) { return lane::keep(c > T(0), gamma_pow(c, ig)); };
        r = gam(r), g = gam(g), b = gam(b);
    }
    store(out.r, lane, r);
    store(out.g, lane, g);
    store(out.b, lane, b);
}

template <class T, Precision P>
void tonemap_packet(const PacketScene& s, const ColorPacket8& in, ColorPacket8& out) noexcept {
    for (int lane = 0; lane < kPacketWidth; lane += lane::width<T>) {
        switch (s.tonemap) {
        case ToneMap::max_to_one: tonemap_lanes<T, P, ToneMap::max_to_one>(s, in, out, lane); break;
        case ToneMap::clamp_to_color: tonemap_lanes<T, P, ToneMap::clamp_to_color>(s, in, out, lane); break;
        case ToneMap::saturate: tonemap_lanes<T, P, ToneMap::saturate>(s, in, out, lane); break;
        }
    }
}

// ---- camera rays (DESIGN.md convention) ------------------------------------
template <class T, Precision P>
inline void camera_lanes(const PacketScene& s, int x0, int y, RayPacket8& rp, int lane) {
    const PacketCamera& c = s.camera;
    T col;
    if constexpr (lane::width<T> == 1) {
        col = T(float(x0 + lane));
    } else {
        alignas(64) lane::Scalar<T> idx[lane::width<T>];
        for (int i = 0; i < lane::width<T>; ++i) idx[i] = lane::Scalar<T>(x0 + lane + i);
        col = T::load_aligned(idx);
    }
    const T sx = (T(2) * (col + T(0.5f)) / T(float(c.width)) - T(1)) * T(c.scale_x);
    const T sy = T((1.0f - 2.0f * (float(y) + 0.5f) / float(c.height)) * c.scale_y);
    const Vec3<T> u{T(c.u[0]), T(c.u[1]), T(c.u[2])}, v{T(c.v[0]), T(c.v[1]), T(c.v[2])};
    const Vec3<T> w{T(c.w[0]), T(c.w[1]), T(c.w[2])}, eye{T(c.eye[0]), T(c.eye[1]), T(c.eye[2])};
    Vec3<T> o, d;
    if (c.orthographic) {
        o = eye + u * sx + v * sy;
        d = {T(0) - w.x, T(0) - w.y, T(0) - w.z};
    } else {
        o = eye;
        d = u * sx + v * sy - w;
        d = d * lane::rsqrt<P>(fdot(d, d));
    }
    store(rp.ox, lane, o.x), store(rp.oy, lane, o.y), store(rp.oz, lane, o.z);
    store(rp.dx, lane, d.x), store(rp.dy, lane, d.y), store(rp.dz, lane, d.z);
    store(rp.tmin, lane, T(0));
    store(rp.tmax, lane, inf<T>());
    store_mask<T>(rp.active, lane, col < T(float(c.width)));
}

template <class T, Precision P>
void camera_packet(const PacketScene& s, int x0, int y, RayPacket8& rp) noexcept {
    for (int lane = 0; lane < kPacketWidth; lane += lane::width<T>) camera_lanes<T, P>(s, x0, y, rp, lane);
}

}  // namespace octray::kernels::OCTRAY_ISA
