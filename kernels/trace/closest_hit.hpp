// kernels/trace/closest_hit.hpp — the nearest hit of a packet over a
// compiled scene: planes in scene order, then the bounded primitives the BVH
// walk yields (kernels/bvh/culling.hpp), each candidate kept by t and id.
#pragma once

#include "kernels/trace/primitive_tests.hpp"

namespace octray::kernels::OCTRAY_ISA {

// ---- the closest hit so far, per lane -----------------------------------------
template <class T>
struct Closest {
    T t;    // tmax until something is hit
    T cid;  // compiled id of the hit primitive (exact float), -1 on a miss
    Mask<T> near = Mask<T>(true);  // a sphere's hit: the near root (sphere_hit), for sphere_normal
    // A triangle's hit: its unit normal and primitive id, from the block the
    // test read (the hit record then reads no scene-wide table for it).
    Vec3<T> tri_n{T(0), T(0), T(0)};
    T tri_id = T(-1);
    T tri_u = T(0), tri_v = T(0);  // its barycentrics, kept where the caller asks (HitFields)

    // Keeps the lanes of `hit` (a test accepted them for t' < t) at t' and id.
    OCTRAY_HOT void take(const Mask<T>& hit, const T& t_hit, int id) {
        if (!lane::any(hit)) return;  // most tests miss on every lane
        t = lane::select(hit, t_hit, t);
        cid = lane::select(hit, T(float(id)), cid);
    }
    // A sphere's hit, with its root.
    OCTRAY_HOT void take(const Mask<T>& hit, const T& t_hit, int id, const Mask<T>& near_hit) {
        if (!lane::any(hit)) return;
        t = lane::select(hit, t_hit, t);
        cid = lane::select(hit, T(float(id)), cid);
        near = (hit && near_hit) || (lane::not_(hit) && near);
    }
    // A triangle's hit: the j-th of `tri`, with its normal and primitive id
    // (read from the block only when some lane takes it).
    OCTRAY_HOT void take(const Mask<T>& hit, const T& t_hit, int id, const TriangleRun& tri, int j) {
        if (!lane::any(hit)) return;
        t = lane::select(hit, t_hit, t);
        cid = lane::select(hit, T(float(id)), cid);
        const float* at = tri.data + std::size_t(j);
        const std::size_t n = std::size_t(tri.n);
        const Vec3<T> m{T(at[kNormal * n]), T(at[(kNormal + 1) * n]), T(at[(kNormal + 2) * n])};
        tri_n = {lane::select(hit, m.x, tri_n.x), lane::select(hit, m.y, tri_n.y), lane::select(hit, m.z, tri_n.z)};
        tri_id = lane::select(hit, T(at[kPrimitiveId * n]), tri_id);
    }
    // The same, with the hit's barycentrics.
    OCTRAY_HOT void take(const Mask<T>& hit, const T& t_hit, int id, const TriangleRun& tri, int j, const T& u,
                         const T& v) {
        if (!lane::any(hit)) return;
        take(hit, t_hit, id, tri, j);
        tri_u = lane::select(hit, u, tri_u);
        tri_v = lane::select(hit, v, tri_v);
    }
};

// The bounded primitives' part of closest_hit, templated on those types alone
// (B = bounded_bits(F)): kernels that differ only in planes share one walk,
// which keeps the number of walk instantiations, and the build, in check.
// Fields: keep a triangle's barycentrics too (HitFields).
template <class T, Precision P, unsigned B, bool Fields>
inline void closest_bounded(const SceneData& s, const Ray<T, P>& r, Closest<T>& best) {
    LaneRay<T, P> lanes(r);
    for_each_candidate<true, B>(s, r, r.valid, best.t, [&](auto tag, int k, const Run& run) OCTRAY_HOT_LAMBDA {
        constexpr PrimitiveType type = decltype(tag)::value;
        Mask<T> hit;
        if constexpr (type == PrimitiveType::sphere) {
            Mask<T> near;
            const T t = test_sphere(s, k, r, hit, best.t, near);
            best.take(hit, t, s.offset[int(type)] + k, near);
        } else if constexpr (type == PrimitiveType::triangle) {
            const int j = k - run.k0;
            if constexpr (Fields) {
                T uv[2];
                const T t = test_triangle(run.tri, j, r, hit, best.t, uv);
                best.take(hit, t, s.offset[int(type)] + k, run.tri, j, uv[0], uv[1]);
            } else {
                const T t = test_triangle(run.tri, j, r, hit, best.t);
                best.take(hit, t, s.offset[int(type)] + k, run.tri, j);
            }
        } else {
            const T t = test_primitive<type, T, P>(s, k, run, r, hit, best.t);
            best.take(hit, t, s.offset[int(type)] + k);
        }
    }, [&](auto tag, const Run& run, int i) OCTRAY_HOT_LAMBDA {
        // Lane i alone: its ray against the run, nearest t kept, the lowest
        // index on a tie (the packet test's order: later ones must be nearer).
        constexpr PrimitiveType type = decltype(tag)::value;
        constexpr int W = lane::width<T>;
        const Ray<T, P>& one = lanes.at(i, type == PrimitiveType::triangle);
        T tbest = bvh::detail::lane_broadcast(best.t, i);
        for (int j = 0; j < run.n; j += W) {
            Mask<T> hit, near;
            T uv[2];
            const T t = test_run<type>(s, run, j, one, hit, tbest, near, Fields ? uv : nullptr);
            hit = hit && run_lanes<T>(run.n - j);
            if (!lane::any(hit)) continue;
            tbest = T(lane::hmin(lane::select(hit, t, inf<T>())));
            const int first = __builtin_ctz(lane::bits(hit && t == tbest));
            const Mask<T> alone = bvh::detail::lane_alone<T>(i);
            if constexpr (type == PrimitiveType::sphere) {
                best.take(alone, tbest, s.offset[int(type)] + run.k0 + j + first,
                          Mask<T>(((lane::bits(near) >> first) & 1u) != 0));
            } else {
                const int jj = j + first;
                if constexpr (Fields)
                    best.take(alone, tbest, s.offset[int(type)] + run.k0 + jj, run.tri, jj,
                              bvh::detail::lane_broadcast(uv[0], first), bvh::detail::lane_broadcast(uv[1], first));
                else
                    best.take(alone, tbest, s.offset[int(type)] + run.k0 + jj, run.tri, jj);
            }
        }
    });
}

template <class T, Precision P, unsigned F, bool Fields = false>
inline Closest<T> closest_hit(const SceneData& s, const Ray<T, P>& r) {
    Closest<T> best{r.tmax, T(-1)};
    if constexpr ((F & kPlane) != 0) {
        const int base = s.offset[int(PrimitiveType::plane)];
        for (int k = 0; k < s.count[int(PrimitiveType::plane)]; ++k) {
            Mask<T> hit;
            const T t = test_primitive<PrimitiveType::plane, T, P>(s, k, Run{}, r, hit, best.t);
            best.take(hit, t, base + k);
        }
    }
    if constexpr (bounded_bits(F) != 0) closest_bounded<T, P, bounded_bits(F), Fields>(s, r, best);
    return best;
}

}  // namespace octray::kernels::OCTRAY_ISA
