// kernels/geometry/sphere.hpp — the ray-sphere test.
//
// Stable quadratic with the perpendicular-distance discriminant (Pharr, Jakob
// & Humphreys, pbrt-v4, sec. 6.8.1), or b^2/a - c where that is the better
// conditioned, c = |f|^2 - r^2 by a compensated dot product (Ogita, Rump &
// Oishi, "Accurate sum and dot product", SIAM J. Sci. Comput. 2005). The
// stiff and extreme cases these choices answer, each with its bound, are the
// catalogue of harness/stability_cases.hpp (`octray stability`).
#pragma once

#include "kernels/trace/ray.hpp"

#include <limits>

namespace octray::kernels::OCTRAY_ISA {

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
    // c/q is an IEEE division in every mode: from outside it is the near
    // root, which decides the nearest primitive (a sphere on a plane).
    return {q * r.inv_dd, c / q, disc, size2};
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
// `near` says which root is the hit: the near one (the ray enters the sphere
// there), else the far one (it leaves: an origin inside, or tmin past the
// entry); sphere_normal needs it, and only this choice knows it for sure.
template <class T, Precision P>
OCTRAY_HOT T sphere_hit(const Ray<T, P>& r, const Vec3<T>& center, const T& radius, Mask<T>& hit, const T& tbest,
                        Mask<T>& near) {
    const T r2 = radius * radius;
    SphereRoots<T> s = sphere_roots(r, r.o - center, r2, radius);
    const Mask<T> huge = lane::not_(s.size2 <= T(0x1p100f));
    if (lane::any(huge)) s = sphere_roots_scaled(r, center, r2, radius, huge);
    const T tnear = lane::min(s.t0, s.t1), tfar = lane::max(s.t0, s.t1);
    near = tnear > r.tmin;
    const T t = lane::select(near, tnear, tfar);
    hit = s.disc >= T(0) && t > r.tmin && t < tbest;
    return t;
}
template <class T, Precision P>
OCTRAY_HOT T sphere_hit(const Ray<T, P>& r, const Vec3<T>& center, const T& radius, Mask<T>& hit, const T& tbest) {
    Mask<T> near;
    return sphere_hit(r, center, radius, hit, tbest, near);
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
OCTRAY_HOT T intersect_sphere(const Ray<T, P>& r, const Vec3<T>& center, const SphereRadius<T>& radius, Mask<T>& hit,
                  const T& tbest, Mask<T>& near) {
    return sphere_hit(r, center, radius.r, hit, tbest, near);
}
template <class T, Precision P>
OCTRAY_HOT T intersect_sphere(const Ray<T, P>& r, const Vec3<T>& center, const SphereRadius<T>& radius, Mask<T>& hit,
                  const T& tbest) {
    return sphere_hit(r, center, radius.r, hit, tbest);
}

// ---- the hit in the sphere's frame -------------------------------------------
// The rounding residuals of a ray and a centre (RayPacket::ox_lo..., a
// double-float camera's): f = o - c is exactly (o - c in float, with its
// TwoSum error) + f, the direction d + this d.
template <class T>
struct SphereResidual {
    Vec3<T> f, d;
};

// p - c at the hit, from the ray's closest approach to the centre rather than
// from p = o + t d: f = o - c exactly (fh + fl, TwoSum), the foot of the
// perpendicular q = f - d (f.d)/(d.d), projected out along d a second time
// ("twice is enough", Parlett & Kahan), then p - c = q -+ h d/|d| with
// h = sqrt(r^2 - |q|^2) (minus at the near root). t carries an error of a
// few u t (its float alone is u t / 2); q and h carry a few u r, whatever the
// distance: the first projection leaves ~7u |f| along d, the second removes
// it to ~5u |q|, and the components across d are each rounded once or twice
// from their own size. h is as exact as |q|^2 is (~4.5u r^2), so h is off by
// ~2.25u r^2 / h = 2.25u r / |n.d| along d: the one 1/|n.d| of the normal's
// error, a perturbation of the ray by ~u r (precision.hpp derives the bound);
// from an origin near the surface, h comes from b^2/a - c instead (below).
// `o`, `c`, `radius`: the same scaling as sphere_roots_scaled, where used.
// `res`: what the float ray and centre leave out (SphereResidual). The exact
// f is fh + fl + res.f and the direction d + res.d; to first order the foot
// of the exact ray is q + res.f + t_foot res.d, less its part along d, which
// the second projection removes (what is left along the exact direction is
// ~u r). Without it a pinhole ray's rounding, ~u t at the hit, would turn the
// normal by ~u t / r. A shift past the radius is no rounding's (a hit that
// far off is noise) and is dropped: q, so the normal, stays within ~r.
template <class T, Precision P>
inline Vec3<T> sphere_offset(const Ray<T, P>& r, const Vec3<T>& o, const Vec3<T>& c, const T& radius,
                             const Mask<T>& near, const SphereResidual<T>& res) {
    const Vec3<T> fh = o - c;
    const Vec3<T> fl{two_sum_error(o.x, T(0) - c.x, fh.x), two_sum_error(o.y, T(0) - c.y, fh.y),
                     two_sum_error(o.z, T(0) - c.z, fh.z)};
    const T b = fdot(fh, r.d);
    const T nb_a = b * r.neg_inv_dd;  // t of the foot; its error moves q along d only
    Vec3<T> shift{lane::fma(res.d.x, nb_a, res.f.x), lane::fma(res.d.y, nb_a, res.f.y),
                  lane::fma(res.d.z, nb_a, res.f.z)};
    const Mask<T> residual = lane::abs(shift.x) + lane::abs(shift.y) + lane::abs(shift.z) <= radius;  // false for NaN
    shift = {lane::keep(residual, shift.x), lane::keep(residual, shift.y), lane::keep(residual, shift.z)};
    Vec3<T> q{lane::fma(r.d.x, nb_a, fh.x) + (fl.x + shift.x), lane::fma(r.d.y, nb_a, fh.y) + (fl.y + shift.y),
              lane::fma(r.d.z, nb_a, fh.z) + (fl.z + shift.z)};
    const T back = fdot(q, r.d) * r.neg_inv_dd;
    q = {lane::fma(r.d.x, back, q.x), lane::fma(r.d.y, back, q.y), lane::fma(r.d.z, back, q.z)};
    const T r2 = radius * radius, r2_lo = lane::fma(radius, radius, T(0) - r2);
    T h2 = (r2 - fdot(q, q)) + r2_lo;
    // An origin near the surface (sphere_roots' `cancels`: a planet seen
    // from above, a shadow ray) has h^2 = b^2/a - c better conditioned toward
    // the horizon, as sphere_roots' disc: r^2 - |q|^2 cancels there (|q| ~ r)
    // and would leave 2.25u r^2 / h; b^2/a - c, with c = |f|^2 - r^2 from the
    // exact f (compensated, plus 2 fh.fl), leaves ~5u (h^2 + |c|) instead.
    const T s2 = fdot(fh, fh);
    const Mask<T> cancels = lane::abs(s2 - r2) < T(0.25f) * lane::max(s2, r2);
    if (lane::any(cancels)) {
        const T c2 = norm2_compensated(fh, r2, r2_lo) + T(2) * fdot(fh, fl);
        const T bf = b + fdot(fl, r.d);
        const T b2_a = bf * bf * r.inv_dd;
        h2 = lane::select(cancels && b2_a + lane::abs(c2) < T(0.5f) * s2, b2_a - c2, h2);
    }
    const T h2_pos = lane::max(h2, T(0));
    T h_t = lane::sqrt(h2_pos * r.inv_dd);  // h / |d|: from the foot to p, in units of t
    // A direction near the shortest load_ray accepts (d.d down to 2^-126) can
    // take h^2/(d.d) past the float range though h/|d| fits (a t near 2^65):
    // those lanes take the two roots apart.
    const Mask<T> overflow = h_t == T(std::numeric_limits<float>::infinity());
    if (lane::any(overflow)) h_t = lane::select(overflow, lane::sqrt(h2_pos) * lane::sqrt(r.inv_dd), h_t);
    const T along = lane::select(near, T(0) - h_t, h_t);
    return {lane::fma(r.d.x, along, q.x), lane::fma(r.d.y, along, q.y), lane::fma(r.d.z, along, q.z)};
}

// The lanes in `huge` in units of 2^72, as sphere_roots_scaled; p - c back in
// scene units (|p - c| = r, a float, so no overflow).
template <class T, Precision P>
OCTRAY_COLD Vec3<T> sphere_offset_scaled(const Ray<T, P>& r, const Vec3<T>& center, const T& radius,
                                         const Mask<T>& near, const Mask<T>& huge, const SphereResidual<T>& res) {
    const T k = lane::select(huge, T(0x1p-72f), T(1)), unscale = lane::select(huge, T(0x1p72f), T(1));
    return sphere_offset(r, r.o * k, center * k, radius * k, near, SphereResidual<T>{res.f * k, res.d}) * unscale;
}

// Unit geometric normal (outward) at the hit of sphere (center, radius) by r,
// at the root `near` says (sphere_hit): (p - c) / r from sphere_offset.
// Every operation is IEEE (sqrt; 1/(d.d) and 1/r are IEEE in every mode), so
// the normal is the same in every precision mode.
template <class T, Precision P>
inline Vec3<T> sphere_normal(const Ray<T, P>& r, const Vec3<T>& center, const T& radius, const Mask<T>& near,
                             const SphereResidual<T>& res) {
    const T inv_radius = T(1) / radius;
    const Vec3<T> f = r.o - center;
    const Mask<T> huge = lane::not_(lane::max(fdot(f, f), radius * radius) <= T(0x1p100f));
    if (lane::any(huge)) return sphere_offset_scaled(r, center, radius, near, huge, res) * inv_radius;
    return sphere_offset(r, r.o, center, radius, near, res) * inv_radius;
}
// The same for a ray and centre taken as exact.
template <class T, Precision P>
inline Vec3<T> sphere_normal(const Ray<T, P>& r, const Vec3<T>& center, const T& radius, const Mask<T>& near) {
    const Vec3<T> zero{T(0), T(0), T(0)};
    return sphere_normal(r, center, radius, near, SphereResidual<T>{zero, zero});
}

}  // namespace octray::kernels::OCTRAY_ISA
