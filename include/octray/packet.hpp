// octray/packet.hpp — structure-of-arrays ray, hit and colour packets.
//
// An engine fills a RayPacket with its own rays and hands it to the kernels
// (octray/kernels.hpp). Every array is 32-byte aligned so an 8-lane AVX2
// kernel loads each component with one aligned load. A lane takes part only
// where `active[i] != 0`; inactive lanes are never read beyond that flag and
// come out as misses with the background colour.
#pragma once

#include <cstdint>

namespace octray {

inline constexpr int kPacketWidth = 8;

template <int W = kPacketWidth>
struct alignas(32) RayPacket {
    static constexpr int width = W;
    alignas(32) float ox[W], oy[W], oz[W];  // origin
    alignas(32) float dx[W], dy[W], dz[W];  // direction (any non-zero length)
    alignas(32) float tmin[W], tmax[W];     // open interval (tmin, tmax) of valid t
    alignas(32) std::int32_t active[W];     // non-zero: trace this lane
    // The lane's pixel, row-major (y * width + x): the key of its ambient-occlusion
    // samples (docs/shading-model.md), so every path draws the same ones. Read only by shade,
    // and only for a scene whose ambient light has occlusion; camera() fills it.
    alignas(32) std::int32_t pixel[W];
    // Optional: the rounding residuals of origin and direction, so that the
    // ray is exactly (o + o_lo, d + d_lo). camera() computes its rays in
    // double and fills them; zero (the default) says the float ray is exact.
    // Only a sphere's normal reads them: rounding moves a ray's hit by ~u t,
    // which turns the normal of a sphere of radius r by ~u t / r (a small
    // sphere far away through a pinhole). Give a rounding's residual (at most
    // u = 2^-24 of the component) or zero: others give finite normals of no use.
    alignas(32) float ox_lo[W]{}, oy_lo[W]{}, oz_lo[W]{};
    alignas(32) float dx_lo[W]{}, dy_lo[W]{}, dz_lo[W]{};
};

template <int W = kPacketWidth>
struct alignas(32) HitPacket {
    static constexpr int width = W;
    alignas(32) float t[W];                 // hit distance along d (in units of |d|)
    alignas(32) std::int32_t primitive[W];  // primitive id (scene.hpp: objects, then mesh triangles), -1 on a miss
    alignas(32) std::int32_t material[W];   // Scene::materials index, -1 on a miss
    alignas(32) float nx[W], ny[W], nz[W];  // unit normal facing the ray (n.d <= 0)
    alignas(32) std::int32_t hit[W];        // -1 where the lane hit something, else 0
    alignas(32) std::int32_t invalid[W];    // -1 where an active lane was masked off for bad input
    alignas(32) std::int32_t mesh[W];       // Scene::meshes index of a hit mesh triangle, else -1
};

// Fields of a closest hit that a caller asks for (Kernel::intersect_fields),
// lane by lane beside its HitPacket; Kernel::intersect computes none of them.
template <int W = kPacketWidth>
struct alignas(32) HitFields {
    static constexpr int width = W;
    // Where on the primitive: a triangle's barycentrics, the hit being
    // (1 - u - v) v0 + u v1 + v v2 (Embree's and Open3D's convention); a
    // rectangle's (s, t), the hit being corner + s a + t b; 0 for the other
    // shapes and on a miss.
    alignas(32) float u[W], v[W];
    // The unit geometric normal, not turned to face the ray: a triangle's
    // winding, (v1 - v0) x (v2 - v0); a sphere's and a box face's outward; a
    // plane's, disk's or rectangle's as authored (a rectangle's a x b); 0 on a miss.
    alignas(32) float ngx[W], ngy[W], ngz[W];
};

template <int W = kPacketWidth>
struct alignas(32) ColorPacket {
    static constexpr int width = W;
    alignas(32) float r[W], g[W], b[W];
};

using RayPacket8 = RayPacket<8>;
using HitPacket8 = HitPacket<8>;
using HitFields8 = HitFields<8>;
using ColorPacket8 = ColorPacket<8>;

}  // namespace octray
