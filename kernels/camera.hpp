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
// float) into lo: hi + lo is x to ~u^2 |x|.
template <class D>
inline void store_split(float* hi, float* lo, int lane, const D& x) {
    store(hi, lane, x);
    store(lo, lane, x - load<D>(hi, lane));
}

// x (a double) rounded to float into hi, its residual into lo, in every
// lane: whole-width stores of the float lanes T.
template <class T>
inline void fill_split(float* hi, float* lo, double x) {
    const float h = float(x), l = float(x - double(h));
    for (int lane = 0; lane < kPacketWidth; lane += lane::width<T>) store(hi, lane, T(h)), store(lo, lane, T(l));
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
// that differs per lane, in double lanes D.
template <class D>
inline void camera_varying(const PacketCamera& c, int x0, int y, RayPacket8& rp, int lane) {
    const D col = columns<D>(x0, lane);
    // In double, 2/width and one reciprocal square root instead of the
    // reference's divisions change the ray by ~1e-16: far below float's u.
    const D sx = ((col + D(0.5)) * D(2.0 / double(c.width)) - D(1)) * D(c.scale_x);
    const double sy = (1.0 - 2.0 * (double(y) + 0.5) / double(c.height)) * c.scale_y;
    const Vec3<D> u{D(c.u[0]), D(c.u[1]), D(c.u[2])};
    if (c.orthographic) {
        // The row's point, eye + v sy, is the same for every lane.
        const Vec3<D> o =
            Vec3<D>{D(c.eye[0] + c.v[0] * sy), D(c.eye[1] + c.v[1] * sy), D(c.eye[2] + c.v[2] * sy)} + u * sx;
        store_split(rp.ox, rp.ox_lo, lane, o.x), store_split(rp.oy, rp.oy_lo, lane, o.y);
        store_split(rp.oz, rp.oz_lo, lane, o.z);
    } else {
        // v sy - w is the row's.
        Vec3<D> d = Vec3<D>{D(c.v[0] * sy - c.w[0]), D(c.v[1] * sy - c.w[1]), D(c.v[2] * sy - c.w[2])} + u * sx;
        d = d * (D(1) / lane::sqrt(fdot(d, d)));
        store_split(rp.dx, rp.dx_lo, lane, d.x), store_split(rp.dy, rp.dy_lo, lane, d.y);
        store_split(rp.dz, rp.dz_lo, lane, d.z);
    }
}

// The interval, activity and pixel keys, in the float lanes T.
template <class T>
inline void camera_flags(const PacketCamera& c, int x0, int y, RayPacket8& rp, int lane) {
    const T col = columns<T>(x0, lane);
    store(rp.tmin, lane, T(0));
    store(rp.tmax, lane, inf<T>());
    store_mask<T>(rp.active, lane, col < T(float(c.width)));
    for (int i = 0; i < lane::width<T>; ++i) rp.pixel[lane + i] = y * c.width + x0 + lane + i;
}

// Precision P does not enter: the camera is exact in every mode (its rounding
// would be every mode's error).
template <class T, Precision P>
void camera_packet(const PacketScene& scene, int x0, int y, RayPacket8& rp) noexcept {
    using D = typename CameraLanes<T>::type;
    const PacketCamera& c = scene.data().camera;
    // What every lane shares: a pinhole's origin, an orthographic camera's direction.
    if (c.orthographic) {
        fill_split<T>(rp.dx, rp.dx_lo, -c.w[0]), fill_split<T>(rp.dy, rp.dy_lo, -c.w[1]);
        fill_split<T>(rp.dz, rp.dz_lo, -c.w[2]);
    } else {
        fill_split<T>(rp.ox, rp.ox_lo, c.eye[0]), fill_split<T>(rp.oy, rp.oy_lo, c.eye[1]);
        fill_split<T>(rp.oz, rp.oz_lo, c.eye[2]);
    }
    for (int lane = 0; lane < kPacketWidth; lane += lane::width<D>) camera_varying<D>(c, x0, y, rp, lane);
    for (int lane = 0; lane < kPacketWidth; lane += lane::width<T>) camera_flags<T>(c, x0, y, rp, lane);
}

}  // namespace octray::kernels::OCTRAY_ISA
