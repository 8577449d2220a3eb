// kernels/shading/shade.hpp — Lambertian shading (docs/shading-model.md: ambient plus
// the sum of each light's kd cd / pi * ls cl * max(0, n.l), point lights with
// 1/r^2 where attenuated), with shadow rays where a light casts them.
#pragma once

#include "kernels/trace/any_hit.hpp"
#include "kernels/trace/hit_record.hpp"
#include "kernels/shading/occlusion.hpp"
#include "kernels/shading/shadow_ray.hpp"

namespace octray::kernels::OCTRAY_ISA {

// ---- shading (docs/shading-model.md) ---------------------------------------
// The point a hit is shaded at: p = o + t d carries t's error, a few u t
// along d (`reach` = t max|d_i|). A sphere's hit is c + r n_geo instead
// where the sphere is smaller than that distance (r < reach): its normal came
// from the sphere's frame (sphere_normal), so that point is off by a few u r
// plus the rounding of c + r n, whatever the distance. (A sphere seen from
// closer than its radius, a planet from above, keeps o + t d: there r n
// would scale the normal's few u by r.) n faces the ray, n_geo = +-n: the
// sign is that of (p - c).n with the approximate p, whose error (~u t) is far
// below r unless t/r passes ~1e6; where |(p - c).n| < r/2 the lane keeps
// o + t d. Returns the lanes whose point came from the sphere.
template <class T>
inline Mask<T> sphere_surface_point(const SceneData& s, const T& object, const Mask<T>& hit, const Vec3<T>& o,
                                    const Vec3<T>& d, const T& t, const T& reach, const Vec3<T>& n, Vec3<T>& p) {
    const T cid = Lookup<T>(lane::keep(hit, object), hit)(s.compiled_of);
    const Mask<T> sphere = hit && cid < T(float(s.count[0]));  // spheres are compiled first
    if (!lane::any(sphere)) return sphere;
    const Lookup<T> at(lane::keep(sphere, cid), sphere);
    const Vec3<T> c = at(s.spheres.cx, s.spheres.cy, s.spheres.cz);
    const T radius = at(s.spheres.radius);
    const Vec3<T> f = o - c;
    const T side = fdot(Vec3<T>{lane::fma(d.x, t, f.x), lane::fma(d.y, t, f.y), lane::fma(d.z, t, f.z)}, n);
    const Mask<T> sure = sphere && radius < reach && lane::abs(side) > T(0.5f) * radius;
    const Vec3<T> q = c + n * lane::with_sign_of(radius, side);
    p = {lane::select(sure, q.x, p.x), lane::select(sure, q.y, p.y), lane::select(sure, q.z, p.z)};
    return sure;
}

// The lanes of `lit` whose shadow ray (shadow_ray's arguments) something
// blocks; the ray is built in place for any_hit, which narrows it.
template <class T, Precision P>
inline Mask<T> shadowed(const SceneData& s, const Vec3<T>& p, const Vec3<T>& n, const Vec3<T>& l, const T& dist,
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

template <class T, Precision P, unsigned F, OcclusionLayout L = kOcclusionLayout>
inline void shade_lanes(const SceneData& s, const RayPacket8& rp, const HitPacket8& hp, ColorPacket8& out, int lane) {
    const Mask<T> hit = load_mask<T>(hp.hit, lane) && load_mask<T>(rp.active, lane);
    const Vec3<T> o{load<T>(rp.ox, lane), load<T>(rp.oy, lane), load<T>(rp.oz, lane)};
    const Vec3<T> d{load<T>(rp.dx, lane), load<T>(rp.dy, lane), load<T>(rp.dz, lane)};
    const T t = lane::keep(hit, load<T>(hp.t, lane));
    Vec3<T> p{lane::keep(hit, lane::fma(d.x, t, o.x)), lane::keep(hit, lane::fma(d.y, t, o.y)),
              lane::keep(hit, lane::fma(d.z, t, o.z))};
    const Vec3<T> n{load<T>(hp.nx, lane), load<T>(hp.ny, lane), load<T>(hp.nz, lane)};
    const T m = lane::keep(hit, load_index<T>(hp.material, lane));
    // |t|: with tmin < 0 a hit may lie behind the origin (t < 0).
    [[maybe_unused]] T reach = lane::abs(t) * lane::max(lane::max(lane::abs(d.x), lane::abs(d.y)), lane::abs(d.z));
    // Point lights, shadow rays and occlusion rays use p: a small sphere's from its frame.
    Mask<T> framed(false);
    if constexpr ((F & kSphere) != 0 && (F & (kPoint | kPointAttenuated | kShadows | kOcclusion)) != 0) {
        if (lane::any(hit)) {
            framed = sphere_surface_point(s, load_index<T>(hp.primitive, lane), hit, o, d, t, reach, n, p);
            reach = lane::keep(lane::not_(framed), reach);
        }
    }
    // Shadow and occlusion rays start from p. Its t is IEEE in every mode
    // (the primitive tests divide exactly), so p is exact's in the estimate
    // modes too, and so is the shadow ray's offset (precision.hpp, shadow_offset).

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
                if (a.shadows[std::size_t(k)] != 0.0f && lane::any(lit)) {
                    // The light is at t = 1 / inv_r along v * inv_r. With an
                    // estimate's inv_r, r2 * inv_r ends the segment (1 + e)^2
                    // from it, up to 2^-11 r past it: a surface just behind
                    // the light would shadow it. IEEE modes keep r2 * inv_r.
                    T to_light = r2 * inv_r;
                    if constexpr (!is_ieee(P)) to_light = T(1) / inv_r;
                    lit = lit && lane::not_(shadowed<T, P>(s, p, n, v * inv_r, to_light * unscale, lit, reach));
                }
            }
            T weight = ndl;
            if constexpr (decltype(attenuated)::value) {
                // inverse square: 1/r^2. Below r ~ 1e-19 it overflows to +inf: the lit
                // channels become +inf, never NaN (see accumulate).
                const T inv_dist = inv_r * scale;
                weight = weight * (inv_dist * inv_dist);
            }
            accumulate(e, lit, weight, broadcast3<T>(a.r, a.g, a.b, k));
        }
    };
    if constexpr ((F & kPoint) != 0) point_lights(s.point, s.point_count, std::false_type{});
    if constexpr ((F & kPointAttenuated) != 0) point_lights(s.point_attenuated, s.point_attenuated_count, std::true_type{});

    // L = ka cd * ls cl  +  kd cd / pi * E   (the diffuse factor taken out of the sum)
    const Lookup<T> material(m, hit);
    Vec3<T> c = hadamard(material(s.diffuse_r, s.diffuse_g, s.diffuse_b), e);
    // kd cd = 0 times an overflowed E = +inf is NaN; the radiance is 0 there
    // (max(x, 0) flushes NaN to 0; every other x is >= 0 and passes).
    c = {lane::max(c.x, T(0)), lane::max(c.y, T(0)), lane::max(c.z, T(0))};
    if constexpr ((F & kAmbient) != 0) {
        Vec3<T> ambient = material(s.ambient_r, s.ambient_g, s.ambient_b);
        // The general kernel (F = kAllFeatures) runs a scene without occlusion too: samples 0, no factor.
        if constexpr ((F & kOcclusion) != 0)
            if (s.occlusion.samples > 0) ambient = ambient * occlusion_factor<T, P, F, L>(s, rp, lane, hit, p, n, reach);
        c += ambient;
    }
    store(out.r, lane, lane::select(hit, c.x, T(s.background[0])));
    store(out.g, lane, lane::select(hit, c.y, T(s.background[1])));
    store(out.b, lane, lane::select(hit, c.z, T(s.background[2])));
}

template <class T, Precision P, unsigned F, OcclusionLayout L = kOcclusionLayout>
void shade_packet(const PacketScene& scene, const RayPacket8& rp, const HitPacket8& hp, ColorPacket8& out) noexcept {
    const SceneData& s = scene_data(scene);
    for (int lane = 0; lane < kPacketWidth; lane += lane::width<T>) shade_lanes<T, P, F, L>(s, rp, hp, out, lane);
}

}  // namespace octray::kernels::OCTRAY_ISA
