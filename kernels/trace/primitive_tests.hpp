// kernels/trace/primitive_tests.hpp — the six primitive tests dispatched by
// type over a compiled scene's arrays: a packet against one primitive
// (broadcast), or one ray against a leaf's run of primitives side by side in
// the lanes. What closest hit and any hit share.
#pragma once

#include "kernels/bvh/culling.hpp"
#include "kernels/geometry/box.hpp"
#include "kernels/geometry/planar.hpp"
#include "kernels/geometry/sphere.hpp"
#include "kernels/geometry/triangle.hpp"

namespace octray::kernels::OCTRAY_ISA {

// Calls body(TypeTag<type>, count) for each primitive type in F. Absent types
// are removed at compile time; present ones loop over s.count.
template <unsigned F, class Body>
inline void for_each_primitive_type(const SceneData& s, Body&& body) {
    if constexpr ((F & kSphere) != 0) body(TypeTag<PrimitiveType::sphere>{}, s.count[0]);
    if constexpr ((F & kPlane) != 0) body(TypeTag<PrimitiveType::plane>{}, s.count[1]);
    if constexpr ((F & kDisk) != 0) body(TypeTag<PrimitiveType::disk>{}, s.count[2]);
    if constexpr ((F & kRectangle) != 0) body(TypeTag<PrimitiveType::rectangle>{}, s.count[3]);
    if constexpr ((F & kBox) != 0) body(TypeTag<PrimitiveType::box>{}, s.count[4]);
    if constexpr ((F & kTriangle) != 0) body(TypeTag<PrimitiveType::triangle>{}, s.count[5]);
}

// The j-th triangle of a run: three fields from f on, broadcast.
template <class T>
inline Vec3<T> broadcast_run3(const TriangleRun& tri, int f, int j) {
    const float* at = tri.data + std::size_t(f) * std::size_t(tri.n) + std::size_t(j);
    return {T(at[0]), T(at[tri.n]), T(at[2 * tri.n])};
}

// The j-th triangle of a run, its vertices broadcast; `uv` (where given)
// gets the hit's barycentrics.
template <class T, Precision P>
OCTRAY_HOT T test_triangle(const TriangleRun& tri, int j, const Ray<T, P>& r, Mask<T>& hit, const T& tbest,
                           T uv[2] = nullptr) {
    return intersect_triangle(r, broadcast_run3<T>(tri, kV0, j), broadcast_run3<T>(tri, kV1, j),
                              broadcast_run3<T>(tri, kV2, j), hit, tbest, uv);
}

// Sphere k; `near`: which root is the hit (sphere_hit).
template <class T, Precision P>
OCTRAY_HOT T test_sphere(const SceneData& s, int k, const Ray<T, P>& r, Mask<T>& hit, const T& tbest, Mask<T>& near) {
    const SphereArrays& a = s.spheres;
    return intersect_sphere(r, broadcast3<T>(a.cx, a.cy, a.cz, k), SphereRadius<T>{broadcast<T>(a.radius, k)}, hit, tbest,
                            near);
}

// ---- one ray against a leaf's run, side by side in the lanes ----------------
// Lane i of a packet's ray, broadcast to every lane: the same values the
// packet tests use, so each (ray, primitive) pair computes bit for bit what
// the packet test computes. Made once per lane and reused while the walk
// stays on that lane; the triangle shear is copied once the packet has it.
template <class T, Precision P>
struct LaneRay {
    explicit LaneRay(const Ray<T, P>& r) : packet(r) {}
    const Ray<T, P>& packet;
    int lane = -1;
    bool shear = false;
    Ray<T, P> one;

    const Ray<T, P>& at(int i, bool need_shear) {
        auto b = [i](const T& v) { return bvh::detail::lane_broadcast(v, i); };
        auto b3 = [&](const Vec3<T>& v) { return Vec3<T>{b(v.x), b(v.y), b(v.z)}; };
        if (i != lane) {
            one.o = b3(packet.o), one.d = b3(packet.d);
            one.tmin = b(packet.tmin), one.tmax = b(packet.tmax);
            one.valid = Mask<T>(true), one.invalid = Mask<T>(false);
            one.dd = b(packet.dd), one.inv_dd = b(packet.inv_dd), one.neg_inv_dd = b(packet.neg_inv_dd);
            one.exit_scale = b(packet.exit_scale), one.len_d = b(packet.len_d);
            lane = i, shear = false;
        }
        if (need_shear && !shear)
            one.proj_a = b3(packet.proj_a), one.proj_b = b3(packet.proj_b), one.proj_z = b3(packet.proj_z), shear = true;
        return one;
    }
};

// One ray (`one`, broadcast) against a run's primitives j .. j + width - 1,
// in the lanes; only the lanes of run_lanes(run.n - j) count.
template <PrimitiveType Type, class T, Precision P>
OCTRAY_HOT T test_run(const SceneData& s, const Run& run, int j, const Ray<T, P>& one, Mask<T>& hit, const T& tbest,
                      Mask<T>& near, T uv[2] = nullptr) {
    if constexpr (Type == PrimitiveType::sphere) {
        const SphereArrays& a = s.spheres;
        const int k = run.k0 + j;
        const Vec3<T> c{load<T>(a.cx.data(), k), load<T>(a.cy.data(), k), load<T>(a.cz.data(), k)};
        (void)uv;
        return intersect_sphere(one, c, SphereRadius<T>{load<T>(a.radius.data(), k)}, hit, tbest, near);
    } else {
        static_assert(Type == PrimitiveType::triangle, "run tests: spheres and triangles");
        (void)s, (void)near;
        return intersect_triangle(one, load_run3<T>(run.tri, kV0, j), load_run3<T>(run.tri, kV1, j),
                                  load_run3<T>(run.tri, kV2, j), hit, tbest, uv);
    }
}

// Tests primitive k of type `Type` (parameters broadcast from the scene
// arrays; a triangle's from its run's block).
template <PrimitiveType Type, class T, Precision P>
OCTRAY_HOT T test_primitive(const SceneData& s, int k, const Run& run, const Ray<T, P>& r, Mask<T>& hit,
                            const T& tbest) {
    if constexpr (Type == PrimitiveType::sphere) {
        Mask<T> near;
        return test_sphere(s, k, r, hit, tbest, near);
    } else if constexpr (Type == PrimitiveType::plane) {
        const PlaneArrays& a = s.planes;
        return intersect_plane(r, broadcast3<T>(a.px, a.py, a.pz, k), broadcast3<T>(a.nx, a.ny, a.nz, k), hit, tbest);
    } else if constexpr (Type == PrimitiveType::disk) {
        const DiskArrays& a = s.disks;
        return intersect_disk(r, broadcast3<T>(a.cx, a.cy, a.cz, k), broadcast3<T>(a.nx, a.ny, a.nz, k),
                      broadcast<T>(a.radius2, k), hit, tbest);
    } else if constexpr (Type == PrimitiveType::rectangle) {
        const RectangleArrays& a = s.rectangles;
        return intersect_rectangle(r, broadcast3<T>(a.cx, a.cy, a.cz, k), broadcast3<T>(a.nx, a.ny, a.nz, k),
                           broadcast3<T>(a.dual_ax, a.dual_ay, a.dual_az, k),
                           broadcast3<T>(a.dual_bx, a.dual_by, a.dual_bz, k), hit, tbest);
    } else if constexpr (Type == PrimitiveType::box) {
        const BoxArrays& a = s.boxes;
        return intersect_box(r, broadcast3<T>(a.minx, a.miny, a.minz, k), broadcast3<T>(a.maxx, a.maxy, a.maxz, k), hit,
                     tbest);
    } else {
        return test_triangle(run.tri, k - run.k0, r, hit, tbest);
    }
}

}  // namespace octray::kernels::OCTRAY_ISA
