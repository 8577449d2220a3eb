// kernels/camera.hpp — a row's camera rays, 8 pixels a packet, pinhole or
// orthographic (docs/scene-format.md, camera convention).
//
// The rays are formed in double from the double camera frame, as the
// reference forms them, then rounded to float once per component; the
// rounding's residuals go into RayPacket::ox_lo... (a double-float ray, the
// "double-double" of Dekker, "A floating-point technique for extending the
// available precision", Numer. Math. 1971). Rounded alone, a pinhole ray's
// direction is off by ~u per component, which moves its hit by ~u t: the
// normal of a sphere of radius r by ~u t / r (precision.hpp, dn_in).
#pragma once

#include "packet_io.hpp"

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

// x rounded to float into hi, x - hi (exact in double, rounded once more to
// float) into lo: hi + lo is x to ~u^2 |x|. In registers where the unit has
// the conversions (the store and reload of hi were a third of the camera).
template <class D>
inline void store_split(float* hi, float* lo, int lane, const D& x) {
#if defined(__AVX512F__)
    if constexpr (sizeof(D) == 64) {
        const __m256 h = _mm512_cvtpd_ps(x);
        _mm256_storeu_ps(hi + lane, h);
        _mm256_storeu_ps(lo + lane, _mm512_cvtpd_ps(_mm512_sub_pd(x, _mm512_cvtps_pd(h))));
        return;
    }
#endif
#if defined(__AVX__)
    if constexpr (sizeof(D) == 32) {
        const __m128 h = _mm256_cvtpd_ps(x);
        _mm_storeu_ps(hi + lane, h);
        _mm_storeu_ps(lo + lane, _mm256_cvtpd_ps(_mm256_sub_pd(x, _mm256_cvtps_pd(h))));
        return;
    }
#endif
    store(hi, lane, x);
    store(lo, lane, x - load<D>(hi, lane));
}

// 1/sqrt(n2) in float, from float's correctly rounded square root and
// quotient, so every unit rounds it alike. Only the ray's length carries its
// rounding (|d| = 1 to ~u): the direction the lanes store (float + residual)
// is the double one to ~u^2, and no kernel takes |d| = 1 (Ray::inv_dd). The
// double divider's square root and quotient took more time than the rest of
// the camera.
template <class D>
inline D inverse_length(const D& n2) {
    if constexpr (lane::width<D> == 1) {
        return double(1.0f / std::sqrt(float(n2)));
    }
#if defined(__AVX512F__)
    else if constexpr (sizeof(D) == 64) {
        return D(_mm512_cvtps_pd(_mm256_div_ps(_mm256_set1_ps(1.0f), _mm256_sqrt_ps(_mm512_cvtpd_ps(n2)))));
    }
#endif
#if defined(__AVX__)
    else if constexpr (sizeof(D) == 32) {
        return D(_mm256_cvtps_pd(_mm_div_ps(_mm_set1_ps(1.0f), _mm_sqrt_ps(_mm256_cvtpd_ps(n2)))));
    }
#endif
    else {
        static_assert(sizeof(D) == 0, "inverse_length: no float conversion for this double batch");
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
// The lanes' ray directions (pinhole) or origins (orthographic), the part
// that differs per lane, in double lanes D. The image-plane coordinates come
// from PacketCamera's affine steps: within ~1e-16 of the reference's
// divisions, far below float's u.
template <class D>
inline void camera_varying(const PacketCamera& c, int x0, double sy, RayPacket8& rp, int lane) {
    const D sx = lane::fma(columns<D>(x0, lane), D(c.sx_step), D(c.sx_first));
    if (c.orthographic) {
        // The row's point, eye + v sy, is the same for every lane.
        const D ox = lane::fma(D(c.u[0]), sx, D(lane::fma(c.v[0], sy, c.eye[0])));
        const D oy = lane::fma(D(c.u[1]), sx, D(lane::fma(c.v[1], sy, c.eye[1])));
        const D oz = lane::fma(D(c.u[2]), sx, D(lane::fma(c.v[2], sy, c.eye[2])));
        store_split(rp.ox, rp.ox_lo, lane, ox), store_split(rp.oy, rp.oy_lo, lane, oy);
        store_split(rp.oz, rp.oz_lo, lane, oz);
    } else {
        // v sy - w is the row's.
        Vec3<D> d{lane::fma(D(c.u[0]), sx, D(lane::fma(c.v[0], sy, -c.w[0]))),
                  lane::fma(D(c.u[1]), sx, D(lane::fma(c.v[1], sy, -c.w[1]))),
                  lane::fma(D(c.u[2]), sx, D(lane::fma(c.v[2], sy, -c.w[2])))};
        d = d * inverse_length(fdot(d, d));
        store_split(rp.dx, rp.dx_lo, lane, d.x), store_split(rp.dy, rp.dy_lo, lane, d.y);
        store_split(rp.dz, rp.dz_lo, lane, d.z);
    }
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

// Precision P does not enter: the camera is exact in every mode (its rounding
// would be every mode's error).
template <class T, Precision P>
void camera_packet(const PacketScene& scene, int x0, int y, RayPacket8& rp) noexcept {
    using D = typename CameraLanes<T>::type;
    const PacketCamera& c = scene.data().camera;
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
    for (int lane = 0; lane < kPacketWidth; lane += lane::width<D>) camera_varying<D>(c, x0, sy, rp, lane);
    camera_flags<T>(c, x0, y, rp);
}

}  // namespace octray::kernels::OCTRAY_ISA
