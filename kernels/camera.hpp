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
// scalar path, a double batch of the same instruction set for the SIMD paths.
template <class T>
struct CameraLanes {
    using type = double;
};
template <class S, class A>
struct CameraLanes<xsimd::batch<S, A>> {
    using type = xsimd::batch<double, A>;
};

// x rounded to float into hi, x - hi (exact in double, rounded once more to
// float) into lo: hi + lo is x to ~u^2 |x|.
template <class D>
inline void store_split(float* hi, float* lo, int lane, const D& x) {
    store(hi, lane, x);
    store(lo, lane, x - load<D>(hi, lane));
}

// ---- camera rays (docs/scene-format.md convention) --------------------------
template <class D>
inline void camera_lanes(const SceneData& s, int x0, int y, RayPacket8& rp, int lane) {
    const PacketCamera& c = s.camera;
    D col;
    if constexpr (lane::width<D> == 1) {
        col = D(x0 + lane);
    } else {
        alignas(64) double idx[lane::width<D>];
        for (int i = 0; i < lane::width<D>; ++i) idx[i] = double(x0 + lane + i);
        col = D::load_aligned(idx);
    }
    const D sx = (D(2) * (col + D(0.5)) / D(double(c.width)) - D(1)) * D(c.scale_x);
    const D sy = D((1.0 - 2.0 * (double(y) + 0.5) / double(c.height)) * c.scale_y);
    const Vec3<D> u{D(c.u[0]), D(c.u[1]), D(c.u[2])}, v{D(c.v[0]), D(c.v[1]), D(c.v[2])};
    const Vec3<D> w{D(c.w[0]), D(c.w[1]), D(c.w[2])}, eye{D(c.eye[0]), D(c.eye[1]), D(c.eye[2])};
    Vec3<D> o, d;
    if (c.orthographic) {
        o = eye + u * sx + v * sy;
        d = {D(0) - w.x, D(0) - w.y, D(0) - w.z};
    } else {
        o = eye;
        d = u * sx + v * sy - w;
        const D len = lane::sqrt(fdot(d, d));
        d = {d.x / len, d.y / len, d.z / len};
    }
    store_split(rp.ox, rp.ox_lo, lane, o.x), store_split(rp.oy, rp.oy_lo, lane, o.y);
    store_split(rp.oz, rp.oz_lo, lane, o.z);
    store_split(rp.dx, rp.dx_lo, lane, d.x), store_split(rp.dy, rp.dy_lo, lane, d.y);
    store_split(rp.dz, rp.dz_lo, lane, d.z);
    store(rp.tmin, lane, D(0));
    store(rp.tmax, lane, inf<D>());
    store_mask<D>(rp.active, lane, col < D(double(c.width)));
    for (int i = 0; i < lane::width<D>; ++i) rp.pixel[lane + i] = y * c.width + x0 + lane + i;
}

// Precision P does not enter: the camera is exact in every mode (its share of
// a packet's work is small, and its rounding would be every mode's error).
template <class T, Precision P>
void camera_packet(const PacketScene& scene, int x0, int y, RayPacket8& rp) noexcept {
    using D = typename CameraLanes<T>::type;
    const SceneData& s = scene.data();
    for (int lane = 0; lane < kPacketWidth; lane += lane::width<D>) camera_lanes<D>(s, x0, y, rp, lane);
}

}  // namespace octray::kernels::OCTRAY_ISA
