// kernels/shading/occlusion.hpp — ambient occlusion (docs/shading-model.md, "Ambient occlusion";
// Suffern, "Ray Tracing from the Ground Up", ch. 17, the ambient occluder):
// the ambient term of kernels/shading/shade.hpp times max(min_amount, the fraction of
// `samples` rays over the hemisphere about the facing normal that nothing
// blocks before `distance`).
//
// Sampling: cosine-weighted, by Malley's method (a uniform point on the unit
// disk, polar: r = sqrt(u1), phi = 2 pi u2, lifted to the hemisphere, z =
// sqrt(1 - u1)), as aobench does. For a Lambertian surface under a uniform
// sky the reflected ambient radiance is the cosine-weighted integral of the
// visibility over the hemisphere divided by pi; cosine-distributed rays
// make the plain count k/N its unbiased estimate (uniform rays would need
// each weighted by 2 cos theta, and would spend rays near the horizon, where
// they weigh least). The uniforms u1, u2 come from kernels/shading/sampling.hpp, keyed by
// (pixel, sample): RayPacket8::pixel carries the pixel to the kernel.
//
// The frame about n is Duff et al., "Building an orthonormal basis,
// revisited", JCGT 6(1), 2017, with the sign of n.z taken as + for -0 too
// (the reference's face-forward negation makes -0 where the kernels' 0 - x
// makes +0). cos and sin of 2 pi u2 are polynomials on an octant, in lane
// operations only, so the scalar and SIMD paths compute the same bits; the
// reference takes std::cos and std::sin of the same u2 in double.
#pragma once

#include "kernels/shading/sampling.hpp"
#include "kernels/shading/shadow_ray.hpp"
#include "kernels/trace/any_hit.hpp"

#include <array>
#include <cmath>

namespace octray::kernels::OCTRAY_ISA {

// How a SIMD kernel groups a hit packet's sample rays into ray packets.
enum class OcclusionLayout {
    pixels,   // sample k of the packet's 8 pixels, k = 0 .. N-1: N packets per 8 pixels
    samples,  // samples k .. k+7 of one pixel: ceil(N / 8) packets per pixel hit
};
// The kernels' choice: `pixels`, the faster of the two on scenes/aobench.json
// (bench/bench_aobench.cpp, ao/shade/*; docs/performance.md gives the figures).
inline constexpr OcclusionLayout kOcclusionLayout = OcclusionLayout::pixels;

// The primitive types sample rays test: the variant's own when F names some
// (the ambient-only variant for spheres and planes, dispatch/isa_instantiate.hpp: its
// BVH leaves compile those two types' tests only), else all (the general
// shade). Either way the rays go through any_hit, the shadow rays' BVH walk.
inline constexpr unsigned occluders(unsigned features) {
    return (features & kAllPrimitives) != 0 ? features & kAllPrimitives : kAllPrimitives;
}

// ---- keys: unsigned 32-bit lanes beside T ------------------------------------
template <class T>
struct KeyLanes { using type = std::uint32_t; };  // one lane
template <class A>
struct KeyLanes<xsimd::batch<float, A>> { using type = xsimd::batch<std::uint32_t, A>; };
template <class A>
struct KeyLanes<xsimd::batch<double, A>> { using type = std::array<std::uint32_t, xsimd::batch<double, A>::size>; };
template <class T>
using Keys = typename KeyLanes<T>::type;

template <class T>
inline Keys<T> splat_keys(std::uint32_t v) {
    if constexpr (std::is_same_v<Keys<T>, std::uint32_t>) return v;
    else if constexpr (lane::width<T> > 1 && std::is_same_v<lane::Scalar<T>, float>) return Keys<T>(v);
    else {
        Keys<T> k;
        k.fill(v);
        return k;
    }
}

// lane i: p[lane + i] (pixel ids) or first + i (sample indices) when p is null.
template <class T>
inline Keys<T> load_keys(const std::int32_t* p, int lane, std::uint32_t first = 0) {
    alignas(64) std::uint32_t k[lane::width<T>];
    for (int i = 0; i < lane::width<T>; ++i) k[i] = p ? std::uint32_t(p[lane + i]) : first + std::uint32_t(i);
    if constexpr (std::is_same_v<Keys<T>, std::uint32_t>) return k[0];
    else if constexpr (lane::width<T> > 1 && std::is_same_v<lane::Scalar<T>, float>) return Keys<T>::load_aligned(k);
    else {
        Keys<T> out;
        for (int i = 0; i < lane::width<T>; ++i) out[std::size_t(i)] = k[i];
        return out;
    }
}

// u1, u2 of the lanes' keys (sampling::occlusion_bits), as exact lane values.
template <class T>
inline void uniforms(const Keys<T>& pixel, const Keys<T>& sample, T& u1, T& u2) {
    const T unit(sampling::kUnit24);
    if constexpr (lane::width<T> == 1) {
        std::uint32_t a, b;
        sampling::occlusion_bits(pixel, sample, a, b);
        u1 = T(float(a)) * unit;
        u2 = T(float(b)) * unit;
    } else if constexpr (std::is_same_v<lane::Scalar<T>, float>) {
        using I = xsimd::batch<std::int32_t, typename T::arch_type>;
        Keys<T> a, b;
        sampling::occlusion_bits(pixel, sample, a, b);
        // 24-bit values: the signed conversion is exact.
        u1 = xsimd::batch_cast<float>(xsimd::bitwise_cast<I>(a)) * unit;
        u2 = xsimd::batch_cast<float>(xsimd::bitwise_cast<I>(b)) * unit;
    } else {  // double lanes (the f64 mode): lane by lane
        alignas(64) lane::Scalar<T> x1[lane::width<T>], x2[lane::width<T>];
        for (std::size_t i = 0; i < std::size_t(lane::width<T>); ++i) {
            std::uint32_t a, b;
            sampling::occlusion_bits(pixel[i], sample[i], a, b);
            x1[i] = lane::Scalar<T>(a) * lane::Scalar<T>(sampling::kUnit24);
            x2[i] = lane::Scalar<T>(b) * lane::Scalar<T>(sampling::kUnit24);
        }
        u1 = T::load_aligned(x1);
        u2 = T::load_aligned(x2);
    }
}

// ---- directions ----------------------------------------------------------------
template <class T>
inline T floor_lanes(const T& x) {
    if constexpr (lane::width<T> == 1) return std::floor(x);
    else return xsimd::floor(x);
}

// cos and sin of 2 pi u, u in [0, 1) a multiple of 2^-24. The octant o =
// floor(8u) and the fraction f = 8u - o are exact; on it y = f pi/4 (odd
// octants (1 - f) pi/4) is in [0, pi/4], where the Taylor polynomials to
// y^9 and y^10 are within 2e-9 of sin and cos; the quadrant's rotation by
// multiples of pi/2 is exact (swaps and negations).
template <class T>
inline void cos_sin_turns(const T& u, T& c, T& s) {
    const T v = u * T(8);
    const T o = floor_lanes(v);
    const T f = v - o;
    const T q = floor_lanes(o * T(0.5f));  // quadrant
    const Mask<T> odd = o - q * T(2) > T(0.5f);
    const T y = lane::select(odd, T(1) - f, f) * T(0.785398163397448309616f);
    const T y2 = y * y;
    const T sy = lane::fma(y * y2,
                           lane::fma(y2, lane::fma(y2, lane::fma(y2, T(1.0f / 362880), T(-1.0f / 5040)), T(1.0f / 120)),
                                     T(-1.0f / 6)),
                           y);
    const T cy = lane::fma(
        y2,
        lane::fma(y2, lane::fma(y2, lane::fma(y2, lane::fma(y2, T(-1.0f / 3628800), T(1.0f / 40320)), T(-1.0f / 720)),
                                T(1.0f / 24)),
                  T(-0.5f)),
        T(1));
    // (a, b) = (cos, sin) of the angle less q pi/2; then rotated by q pi/2.
    const T a = lane::select(odd, sy, cy), b = lane::select(odd, cy, sy);
    const Mask<T> q_odd = q == T(1) || q == T(3);
    const T c0 = lane::select(q_odd, b, a), s0 = lane::select(q_odd, a, b);
    c = lane::select(q == T(1) || q == T(2), T(0) - c0, c0);
    s = lane::select(q >= T(2), T(0) - s0, s0);
}

// An orthonormal frame (b1, b2, n) about a unit n.
template <class T>
struct Frame {
    Vec3<T> b1, b2, n;
};
template <class T>
inline Frame<T> frame_about(const Vec3<T>& n) {
    const T sign = lane::select(n.z >= T(0), T(1), T(-1));
    const T a = T(-1) / (sign + n.z);
    const T b = n.x * n.y * a;
    return {{T(1) + sign * n.x * n.x * a, sign * b, T(0) - sign * n.x}, {b, sign + n.y * n.y * a, T(0) - n.y}, n};
}

// The cosine-weighted direction of uniforms (u1, u2) in `frame`.
template <class T>
inline Vec3<T> cosine_direction(const Frame<T>& frame, const T& u1, const T& u2) {
    T c, s;
    cos_sin_turns(u2, c, s);
    const T r = lane::sqrt(u1), z = lane::sqrt(T(1) - u1);
    const T x = r * c, y = r * s;
    const Frame<T>& f = frame;
    return {lane::fma(x, f.b1.x, lane::fma(y, f.b2.x, z * f.n.x)), lane::fma(x, f.b1.y, lane::fma(y, f.b2.y, z * f.n.y)),
            lane::fma(x, f.b1.z, lane::fma(y, f.b2.z, z * f.n.z))};
}

// Points r (whose origin shadow_ray set) along d over (0, dist) for the lanes of `valid`.
template <class T, Precision P>
inline void aim(Ray<T, P>& r, const Vec3<T>& d, const T& dist, const Mask<T>& valid) {
    r.d = d;
    r.tmin = T(0);
    r.tmax = dist;
    r.valid = valid;
    finish_ray(r, fdot(d, d));
}

// ---- the visible fraction -------------------------------------------------------
// The sample rays of a group of lanes: their origin (shadow_ray's, off the
// surface), the frame about each lane's facing normal, the pixel keys.
template <class T, Precision P>
struct OcclusionSamples {
    Ray<T, P> ray;
    Frame<T> frame;
    Keys<T> pixel;
    T dist;
    Mask<T> hit;
    // p, n: the hits' points and facing normals; reach: the camera rays' extent (shadow_ray).
    OcclusionSamples(const SceneData& s, const Keys<T>& pixels, const Mask<T>& hits, const Vec3<T>& p, const Vec3<T>& n,
                     const T& reach)
        : frame(frame_about(n)), pixel(pixels), dist(s.occlusion.distance), hit(hits) {
        shadow_ray(ray, p, n, n, dist, hit, reach);
    }
    // Sample k of every lane of `hit`, aimed (any_hit narrows ray.valid; the next call resets it).
    Ray<T, P>& at(int k) {
        T u1, u2;
        uniforms<T>(pixel, splat_keys<T>(std::uint32_t(k)), u1, u2);
        aim(ray, cosine_direction(frame, u1, u2), dist, hit);
        return ray;
    }
};

// Blocked sample count per lane, layout `samples`: each hit lane's rays as
// packets of 8 of its samples from one origin.
template <class T, Precision P, unsigned Occluders>
inline T blocked_per_pixel(const SceneData& s, const OcclusionSamples<T, P>& from) {
    using S = lane::Scalar<T>;
    constexpr int W = lane::width<T>;
    const int n = s.occlusion.samples;
    alignas(64) S v[12][W], blocked[W] = {}, iota[W];
    alignas(64) std::uint32_t pixel[W];
    const T* parts[12] = {&from.ray.o.x,   &from.ray.o.y,   &from.ray.o.z,   &from.frame.b1.x,
                          &from.frame.b1.y, &from.frame.b1.z, &from.frame.b2.x, &from.frame.b2.y,
                          &from.frame.b2.z, &from.frame.n.x,  &from.frame.n.y,  &from.frame.n.z};
    for (int j = 0; j < 12; ++j) parts[j]->store_aligned(v[j]);
    from.pixel.store_aligned(pixel);
    for (int i = 0; i < W; ++i) iota[i] = S(i);
    const T lane_index = T::load_aligned(iota);
    Ray<T, P> r = from.ray;
    for (unsigned on = lane::bits(from.hit); on != 0; on &= on - 1) {
        const int i = __builtin_ctz(on);
        r.o = {T(v[0][i]), T(v[1][i]), T(v[2][i])};
        const Frame<T> f{{T(v[3][i]), T(v[4][i]), T(v[5][i])}, {T(v[6][i]), T(v[7][i]), T(v[8][i])},
                         {T(v[9][i]), T(v[10][i]), T(v[11][i])}};
        const Keys<T> key = splat_keys<T>(pixel[i]);
        int count = 0;
        for (int k0 = 0; k0 < n; k0 += W) {
            T u1, u2;
            uniforms<T>(key, load_keys<T>(nullptr, 0, std::uint32_t(k0)), u1, u2);
            aim(r, cosine_direction(f, u1, u2), from.dist, lane_index < T(S(n - k0)));
            count += lane::count(any_hit<T, P, Occluders>(s, r));
        }
        blocked[i] = S(count);
    }
    return T::load_aligned(blocked);
}

// Blocked samples per lane: every sample of the lanes of `samples.hit`, in layout L.
template <class T, Precision P, unsigned Occluders, OcclusionLayout L>
inline T blocked_count(const SceneData& s, OcclusionSamples<T, P>& samples) {
    if constexpr (L == OcclusionLayout::samples && lane::width<T> > 1 && std::is_same_v<lane::Scalar<T>, float>) {
        return blocked_per_pixel<T, P, Occluders>(s, samples);
    } else {
        T blocked(0);
        for (int k = 0; k < s.occlusion.samples; ++k)
            blocked = blocked + lane::keep(any_hit<T, P, Occluders>(s, samples.at(k)), T(1));
        return blocked;
    }
}

// max(min_amount, visible fraction) on the lanes of `hit` (1 elsewhere, and
// on every lane of a scene without occlusion); p and n are the hits' points
// and facing normals, reach the camera rays' extent (shadow_ray). L: the
// sample rays' layout (the library's kernels use kOcclusionLayout).
template <class T, Precision P, unsigned F, OcclusionLayout L = kOcclusionLayout>
T occlusion_factor(const SceneData& s, const RayPacket8& rp, int lane, const Mask<T>& hit, const Vec3<T>& p,
                   const Vec3<T>& n, const T& reach) {
    const OcclusionData& ao = s.occlusion;
    if (ao.samples == 0 || !lane::any(hit)) return T(1);
    constexpr unsigned Occluders = occluders(F);
    OcclusionSamples<T, P> samples(s, load_keys<T>(rp.pixel, lane), hit, p, n, reach);
    const T blocked = blocked_count<T, P, Occluders, L>(s, samples);
    // (N - k) / N correctly rounded, as float(the reference's double).
    const T count(float(ao.samples));
    const T visible = (count - blocked) / count;
    return lane::select(hit, lane::max(visible, T(ao.min_amount)), T(1));
}

}  // namespace octray::kernels::OCTRAY_ISA
