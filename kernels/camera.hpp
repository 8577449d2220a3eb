// kernels/camera.hpp — a row's camera rays, 8 pixels a packet, pinhole or
// orthographic (docs/scene-format.md, camera convention).
#pragma once

#include "packet_io.hpp"

namespace octray::kernels::OCTRAY_ISA {

// ---- camera rays (docs/scene-format.md convention) --------------------------
template <class T, Precision P>
inline void camera_lanes(const SceneData& s, int x0, int y, RayPacket8& rp, int lane) {
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
    for (int i = 0; i < lane::width<T>; ++i) rp.pixel[lane + i] = y * c.width + x0 + lane + i;
}

template <class T, Precision P>
void camera_packet(const PacketScene& scene, int x0, int y, RayPacket8& rp) noexcept {
    const SceneData& s = scene.data();
    for (int lane = 0; lane < kPacketWidth; lane += lane::width<T>) camera_lanes<T, P>(s, x0, y, rp, lane);
}

}  // namespace octray::kernels::OCTRAY_ISA
