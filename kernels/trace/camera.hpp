// kernels/trace/camera.hpp — a row's camera rays, 8 pixels a packet, pinhole or
// orthographic (docs/scene-format.md, camera convention).
//
// The rays are formed in double from the double camera frame, as the
// reference forms them, then rounded to float once per component; the
// rounding's residuals go into RayPacket::ox_lo... A pinhole's direction is
// then scaled to unit length in float, its residual carried along by an FMA
// (normalize_split). A double-float ray, the
// "double-double" of Dekker, "A floating-point technique for extending the
// available precision", Numer. Math. 1971). Rounded alone, a pinhole ray's
// direction is off by ~u per component, which moves its hit by ~u t: the
// normal of a sphere of radius r by ~u t / r (precision.hpp, dn_in).
#pragma once

#include "kernels/trace/packet_io.hpp"

namespace octray::kernels::OCTRAY_ISA {

// The double lanes a packet's camera rays are formed in: one double for the
// scalar path; for the SIMD paths a double batch of the unit's instruction
// set, the whole packet in one zmm register where the unit has AVX-512.
template <class T>
struct CameraLanes {
    using type = double;
};
template <class S, class A>
struct CameraLanes<xsimd::batch<S, A>> {
#if defined(__AVX512F__)
    using type = xsimd::batch<double, xsimd::avx512f>;
#else
    using type = xsimd::batch<double, A>;
#endif
};

// The lanes of x (double lanes D, `parts` batches of them side by side)
// rounded to the float lanes T in hi, and x - hi (exact in double, rounded
// once more to float) in lo: hi + lo is x to ~u^2 |x|.
template <class T, class D, int parts>
inline void split(const D (&x)[parts], T& hi, T& lo) {
    static_assert(parts * lane::width<D> == lane::width<T>, "split: the double lanes must fill the float lanes");
    if constexpr (lane::width<T> == 1) {
        hi = float(x[0]);
        lo = float(x[0] - round_to_float(x[0]));  // (GCC 12 folds x - double(float(x)) to 0)
    }
#if defined(__AVX512F__)
    else if constexpr (sizeof(D) == 64) {
        const __m256 h = _mm512_cvtpd_ps(x[0]);
        hi = T(h), lo = T(_mm512_cvtpd_ps(_mm512_sub_pd(x[0], _mm512_cvtps_pd(h))));
    }
#endif
#if defined(__AVX__)
    else if constexpr (sizeof(D) == 32 && parts == 2) {
        const __m128 h0 = _mm256_cvtpd_ps(x[0]), h1 = _mm256_cvtpd_ps(x[1]);
        const __m128 l0 = _mm256_cvtpd_ps(_mm256_sub_pd(x[0], _mm256_cvtps_pd(h0)));
        const __m128 l1 = _mm256_cvtpd_ps(_mm256_sub_pd(x[1], _mm256_cvtps_pd(h1)));
        hi = T(_mm256_set_m128(h1, h0)), lo = T(_mm256_set_m128(l1, l0));
    }
#endif
    else {
        static_assert(sizeof(D) == 0, "split: no conversion for these lanes");
    }
}

// Lanes x0 + lane, x0 + lane + 1, ... as lane type L.
template <class L>
inline L columns(int x0, int lane) {
    if constexpr (lane::width<L> == 1) {
        return L(lane::Scalar<L>(x0 + lane));
    } else {
        alignas(64) static constexpr lane::Scalar<L> kIota[kPacketWidth] = {0, 1, 2, 3, 4, 5, 6, 7};
        return L(lane::Scalar<L>(x0)) + L::load_aligned(kIota + lane);
    }
}

// ---- camera rays (docs/scene-format.md convention) --------------------------
// The part of the lanes' rays that differs per lane, in double lanes D: a
// pinhole's direction before normalization, an orthographic camera's
// origin. The image-plane coordinates come from PacketCamera's affine
// steps: within ~1e-16 of the reference's divisions, far below float's u.
template <class D>
inline Vec3<D> camera_varying(const PacketCamera& c, int x0, double sy, int lane) {
    const D sx = lane::fma(columns<D>(x0, lane), D(c.sx_step), D(c.sx_first));
    // The row's part, eye + v sy or v sy - w, is the same for every lane.
    const double* base = c.orthographic ? c.eye : c.w;
    const double sign = c.orthographic ? 1.0 : -1.0;
    return {lane::fma(D(c.u[0]), sx, D(lane::fma(c.v[0], sy, sign * base[0]))),
            lane::fma(D(c.u[1]), sx, D(lane::fma(c.v[1], sy, sign * base[1]))),
            lane::fma(D(c.u[2]), sx, D(lane::fma(c.v[2], sy, sign * base[2])))};
}

// A pinhole direction, hi + lo, scaled to unit length in float: k = 1/|hi|
// from float's correctly rounded square root and quotient (every unit rounds
// them alike), then hi k split exactly by an FMA and lo k added to its error.
// Only the ray's length carries k's rounding (|d| = 1 to ~u, and no kernel
// takes |d| = 1: Ray::inv_dd); its line stays the double one to ~u^2.
template <class T>
inline void normalize_split(Vec3<T>& hi, Vec3<T>& lo) {
    const T k = T(1) / lane::sqrt(fdot(hi, hi));
    const Vec3<T> scaled = hi * k;
    lo = {lane::fma(lo.x, k, lane::fma(hi.x, k, T(0) - scaled.x)), lane::fma(lo.y, k, lane::fma(hi.y, k, T(0) - scaled.y)),
          lane::fma(lo.z, k, lane::fma(hi.z, k, T(0) - scaled.z))};
    hi = scaled;
}

// The shared part (PacketCamera::shared_hi, shared_lo) into every lane of
// hi[0..2] and lo[0..2], whole-width stores of the float lanes T.
template <class T>
inline void fill_shared(const PacketCamera& c, float* const hi[3], float* const lo[3]) {
    for (int i = 0; i < 3; ++i) {
        const T h(c.shared_hi[i]), l(c.shared_lo[i]);
        for (int lane = 0; lane < kPacketWidth; lane += lane::width<T>) store(hi[i], lane, h), store(lo[i], lane, l);
    }
}

// The interval, activity and pixel keys, in the float lanes T (8 int32
// lanes in one register where the unit has AVX2).
template <class T>
inline void camera_flags(const PacketCamera& c, int x0, int y, RayPacket8& rp) {
    for (int lane = 0; lane < kPacketWidth; lane += lane::width<T>) store(rp.tmin, lane, T(0)), store(rp.tmax, lane, inf<T>());
#if defined(__AVX2__)
    if constexpr (lane::width<T> == kPacketWidth) {
        const __m256i column = _mm256_add_epi32(_mm256_set1_epi32(x0), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(rp.active), _mm256_cmpgt_epi32(_mm256_set1_epi32(c.width), column));
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(rp.pixel), _mm256_add_epi32(column, _mm256_set1_epi32(y * c.width)));
        return;
    }
#endif
    for (int lane = 0; lane < kPacketWidth; ++lane) {
        rp.active[lane] = x0 + lane < c.width ? -1 : 0;
        rp.pixel[lane] = y * c.width + x0 + lane;
    }
}

// A packet's rays in the float lanes T.
template <class T>
void camera_rays(const PacketCamera& c, int x0, int y, RayPacket8& rp) {
    using D = typename CameraLanes<T>::type;
    if (c.orthographic) {
        float* const hi[3] = {rp.dx, rp.dy, rp.dz};
        float* const lo[3] = {rp.dx_lo, rp.dy_lo, rp.dz_lo};
        fill_shared<T>(c, hi, lo);
    } else {
        float* const hi[3] = {rp.ox, rp.oy, rp.oz};
        float* const lo[3] = {rp.ox_lo, rp.oy_lo, rp.oz_lo};
        fill_shared<T>(c, hi, lo);
    }
    const double sy = lane::fma(double(y), c.sy_step, c.sy_first);
    constexpr int parts = lane::width<T> / lane::width<D>;
    for (int lane = 0; lane < kPacketWidth; lane += lane::width<T>) {
        D x[parts], y_[parts], z[parts];
        for (int p = 0; p < parts; ++p) {
            const Vec3<D> v = camera_varying<D>(c, x0, sy, lane + p * lane::width<D>);
            x[p] = v.x, y_[p] = v.y, z[p] = v.z;
        }
        Vec3<T> hi, lo;
        split(x, hi.x, lo.x), split(y_, hi.y, lo.y), split(z, hi.z, lo.z);
        if (c.orthographic) {
            store(rp.ox, lane, hi.x), store(rp.oy, lane, hi.y), store(rp.oz, lane, hi.z);
            store(rp.ox_lo, lane, lo.x), store(rp.oy_lo, lane, lo.y), store(rp.oz_lo, lane, lo.z);
        } else {
            normalize_split(hi, lo);
            store(rp.dx, lane, hi.x), store(rp.dy, lane, hi.y), store(rp.dz, lane, hi.z);
            store(rp.dx_lo, lane, lo.x), store(rp.dy_lo, lane, lo.y), store(rp.dz_lo, lane, lo.z);
        }
    }
    camera_flags<T>(c, x0, y, rp);
}

// Precision P does not enter: the camera is exact in every mode (its rounding
// would be every mode's error). The f64 mode's double lanes form the same
// rays as the unit's float lanes.
template <class T, Precision P>
void camera_packet(const PacketScene& scene, int x0, int y, RayPacket8& rp) noexcept {
    if constexpr (std::is_same_v<lane::Scalar<T>, double>) {
        using Floats = std::conditional_t<lane::width<T> == 1, float, xsimd::batch<float, xsimd::fma3<xsimd::avx2>>>;
        camera_rays<Floats>(scene_data(scene).camera, x0, y, rp);
    } else {
        camera_rays<T>(scene_data(scene).camera, x0, y, rp);
    }
}

}  // namespace octray::kernels::OCTRAY_ISA
