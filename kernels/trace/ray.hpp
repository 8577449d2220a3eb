// kernels/trace/ray.hpp — a packet's rays as lanes: loading and masking off what no
// kernel can trace (docs/shading-model.md, invalid input), the per-ray quantities the
// primitive tests share, and the box and triangle tests' lazy setup.
#pragma once

#include "kernels/trace/packet_io.hpp"

namespace octray::kernels::OCTRAY_ISA {

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

// The box test's slab reciprocals (Ray::inv_d): IEEE in every precision
// mode. Each axis' slab t carries its reciprocal's error: with an estimate
// (2^-12, a different error per axis) the largest entry, which decides hit
// or miss near an edge and the face hit, would be the estimate's choice, and
// the box's t could lose to or beat a plane it stands on. Three divisions a
// ray, made once. A subnormal component counts as zero (signed
// infinity), as the BVH walks' inverse_direction does.
template <class T, Precision P>
inline void make_slabs(const Ray<T, P>& r) {
    auto inv_axis = [](const T& c) {
        return lane::select(lane::abs(c) < T(std::numeric_limits<float>::min()), lane::copysign(inf<T>(), c),
                            T(1) / c);
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
    // Double lanes (Precision::f64) answer in float: a hit at |t| beyond the
    // largest float would come out as t = +-inf, so it is a miss, as in the
    // float modes, where such a t overflows to +-inf and fails tmin < t < tmax.
    if constexpr (std::is_same_v<lane::Scalar<T>, double>) {
        const T largest(std::numeric_limits<float>::max());
        r.tmin = lane::max(r.tmin, T(0) - largest);
        r.tmax = lane::min(r.tmax, largest);
    }
    finish_ray(r, dd);
    return r;
}

// A ray's rounding residuals (RayPacket::ox_lo...), as given: the one use,
// sphere_offset, drops a shift they make that is not finite or passes the
// sphere's radius, so garbage cannot leave a normal unbounded.
template <class T>
struct RayResidual {
    Vec3<T> o, d;
};
template <class T>
inline RayResidual<T> load_residual(const RayPacket8& rp, int lane) {
    return {{load<T>(rp.ox_lo, lane), load<T>(rp.oy_lo, lane), load<T>(rp.oz_lo, lane)},
            {load<T>(rp.dx_lo, lane), load<T>(rp.dy_lo, lane), load<T>(rp.dz_lo, lane)}};
}

}  // namespace octray::kernels::OCTRAY_ISA
