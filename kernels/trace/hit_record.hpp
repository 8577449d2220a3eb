// kernels/trace/hit_record.hpp — the closest hit finished into a HitPacket8:
// the hit's unit normal (a sphere's from its own frame), turned to face the
// ray, its primitive, material and mesh ids (intersect_packet).
#pragma once

#include "kernels/trace/closest_hit.hpp"

namespace octray::kernels::OCTRAY_ISA {

// The 16-bit residuals of the lanes' sphere centres c (SphereArrays::cx_q),
// decoded as residual16 does: k times 2^(e - 39), e = c's exponent (float
// lanes: the exponent bits masked out of c; double lanes: lane by lane).
template <class T>
inline T centre_residual16(const AlignedVector<std::int16_t>& q, const Lookup<T>& at, const T& c) {
    using S = lane::Scalar<T>;
    const T k = at.uniform ? T(S(q[std::size_t(at.first)])) : lane::gather16(q.data(), at.idx);
    if constexpr (std::is_same_v<T, float>) {
        return k * residual_unit(c);
    } else if constexpr (std::is_same_v<S, float>) {
        // +inf's bits are the exponent field's mask, 0x7f800000
        const T exponent = xsimd::bitwise_and(c, T(std::numeric_limits<float>::infinity()));
        return k * (exponent * T(0x1p-39f));
    } else {
        constexpr int W = lane::width<T>;
        alignas(64) S ks[W], cs[W];
        if constexpr (W == 1) {
            return k * S(residual_unit(float(c)));
        } else {
            k.store_aligned(ks), c.store_aligned(cs);
            for (int i = 0; i < W; ++i) ks[i] *= S(residual_unit(float(cs[i])));
            return T::load_aligned(ks);
        }
    }
}

// The normal of compiled spheres hit by r (their data read through `at`),
// with the ray's residuals and the centres' (SphereArrays: 16-bit or float).
template <class T, Precision P>
inline Vec3<T> compiled_sphere_normal(const SceneData& s, const Lookup<T>& at, const Ray<T, P>& r,
                                      const RayResidual<T>& res, const Mask<T>& near) {
    const SphereArrays& a = s.spheres;
    const Vec3<T> c = at(a.cx, a.cy, a.cz);
    Vec3<T> f_lo = res.o;
    if (!a.cx_q.empty())
        f_lo = res.o - Vec3<T>{centre_residual16(a.cx_q, at, c.x), centre_residual16(a.cy_q, at, c.y),
                               centre_residual16(a.cz_q, at, c.z)};
    else if (!a.cx_lo.empty())
        f_lo = res.o - at(a.cx_lo, a.cy_lo, a.cz_lo);
    return sphere_normal(r, c, at(a.radius), near, SphereResidual<T>{f_lo, res.d});
}

// Unit geometric normal of a primitive of type `Type` at the closest hit
// `best` of ray r (p = o + t d), its data read through `at` (the lanes'
// indices within the type). A sphere's comes from its own frame
// (sphere_normal), not from p; the ray direction breaks ties on box edges.
template <PrimitiveType Type, class T, Precision P>
inline Vec3<T> type_normal(const SceneData& s, const Lookup<T>& at, const Ray<T, P>& r, const RayResidual<T>& res,
                           const Closest<T>& best, const Vec3<T>& p) {
    if constexpr (Type == PrimitiveType::sphere) {
        return compiled_sphere_normal(s, at, r, res, best.near);
    } else if constexpr (Type == PrimitiveType::plane) {
        return at(s.planes.nx, s.planes.ny, s.planes.nz);
    } else if constexpr (Type == PrimitiveType::disk) {
        return at(s.disks.nx, s.disks.ny, s.disks.nz);
    } else if constexpr (Type == PrimitiveType::rectangle) {
        return at(s.rectangles.nx, s.rectangles.ny, s.rectangles.nz);
    } else if constexpr (Type == PrimitiveType::box) {
        // The face is the axis where p sits farthest out relative to the
        // half extent. On an edge or corner (a tie) it is the face the ray
        // crosses most steeply (largest |d| component; then x, then y): a
        // ray gliding along one face into an edge enters through the other,
        // as the reference's deciding slab says.
        const BoxArrays& a = s.boxes;
        const Vec3<T> lo = at(a.minx, a.miny, a.minz), hi = at(a.maxx, a.maxy, a.maxz);
        const Vec3<T> c = (lo + hi) * T(0.5f), h = (hi - lo) * T(0.5f);
        const Vec3<T> q = p - c;
        const T rx = lane::abs(q.x) / h.x, ry = lane::abs(q.y) / h.y, rz = lane::abs(q.z) / h.z;
        const T dx = lane::abs(r.d.x), dy = lane::abs(r.d.y), dz = lane::abs(r.d.z);
        const Mask<T> ax = (rx > ry || (rx == ry && dx >= dy)) && (rx > rz || (rx == rz && dx >= dz));
        const Mask<T> ay = lane::not_(ax) && (ry > rz || (ry == rz && dy >= dz)), az = lane::not_(ax || ay);
        return {lane::keep(ax, lane::copysign(T(1), q.x)), lane::keep(ay, lane::copysign(T(1), q.y)),
                lane::keep(az, lane::copysign(T(1), q.z))};
    } else {
        (void)at;
        return best.tri_n;  // kept by the closest hit from the triangle's block
    }
}

// Unit geometric normal at the closest hit `best` of r (p = o + t d) for the
// lanes of `hit`, whose hits' compiled ids `at` looks up (at.idx; the
// caller's id stores share the lookup); other lanes get an unspecified normal
// (the caller drops them).
// A coherent packet's hit lanes mostly share one primitive: then only that
// type's normal is computed, from its broadcast data; else each type present
// computes its lanes' normals from gathered data.
template <class T, Precision P, unsigned F>
inline Vec3<T> hit_normal(const SceneData& s, const Lookup<T>& at, const Ray<T, P>& r, const RayResidual<T>& res,
                          const Closest<T>& best, const Vec3<T>& p, const Mask<T>& hit) {
    Vec3<T> n{T(0), T(0), T(1)};
    if (!lane::any(hit)) return n;
    if (at.uniform) {
        const int shared = at.first;
        for_each_primitive_type<F>(s, [&](auto tag, int count) {
            constexpr PrimitiveType type = decltype(tag)::value;
            const int base = s.offset[int(type)];
            if (shared >= base && shared < base + count)
                n = type_normal<type>(s, Lookup<T>::at_index(shared - base), r, res, best, p);
        });
        return n;
    }
    const T& cid = at.idx;
    for_each_primitive_type<F>(s, [&](auto tag, int count) {
        constexpr PrimitiveType type = decltype(tag)::value;
        const int base = s.offset[int(type)];
        const Mask<T> mine = hit && cid >= T(float(base)) && cid < T(float(base + count));
        if (count == 0 || !lane::any(mine)) return;
        const Vec3<T> m = type_normal<type>(s, Lookup<T>(lane::keep(mine, cid - T(float(base))), mine), r, res, best, p);
        n = {lane::select(mine, m.x, n.x), lane::select(mine, m.y, n.y), lane::select(mine, m.z, n.z)};
    });
    return n;
}

// Two-sided shading: the normal n of the closest hit `best` turned to oppose
// the ray. A sphere's by the root that was hit (the near root: outward; the
// far root, from inside: inward), not by the sign of n.d: on a ray that grazes
// the sphere (cos = |n.d| below n's own error, a few u / cos) that sign is
// noise, and a wrong one turns the whole normal around.
template <class T, Precision P>
inline Vec3<T> face_forward(const SceneData& s, const Vec3<T>& n, const Ray<T, P>& r, const Closest<T>& best) {
    const Mask<T> sphere = best.cid >= T(0) && best.cid < T(float(s.count[0]));  // spheres are compiled first
    const Mask<T> away = (sphere && lane::not_(best.near)) || (lane::not_(sphere) && fdot(n, r.d) > T(0));
    return {lane::select(away, T(0) - n.x, n.x), lane::select(away, T(0) - n.y, n.y),
            lane::select(away, T(0) - n.z, n.z)};
}

// The material and mesh of each hit lane's primitive (PrimitiveOwners), -1
// elsewhere; `at` reads by the lanes' compiled ids. Mesh triangles only where
// F has triangles.
template <class T, unsigned F>
inline void owners_of(const PrimitiveOwners& o, const Lookup<T>& at, const T& primitive, const Mask<T>& hit,
                      T& material, T& mesh) {
    const Mask<T> object = hit && primitive < T(float(o.object_count));
    const bool per_primitive = !o.material_of.empty();
    material = per_primitive ? lane::select(hit, at(o.material_of), T(-1))
                             : lane::select(object, T(o.common_material), T(-1));
    mesh = T(-1);
    if constexpr ((F & kTriangle) != 0) {
        const Mask<T> in_mesh = hit && lane::not_(object);
        if (!lane::any(in_mesh)) return;
        // The last mesh whose first id is at or below the primitive's: a
        // count of comparisons for a few meshes, a search per lane for many.
        const std::size_t count = o.mesh_first.size();
        T m(0);
        if (count <= 16) {
            for (std::size_t j = 1; j < count; ++j) m = m + lane::keep(primitive >= T(o.mesh_first[j]), T(1));
        } else {
            std::int32_t id[lane::width<T>];
            store_index(id, 0, primitive);
            for (int i = 0; i < lane::width<T>; ++i) id[i] = o.mesh(id[i]);  // -1 for objects and misses: zeroed below
            m = load_index<T>(id, 0);
        }
        m = lane::keep(in_mesh, m);
        if (!per_primitive) material = lane::select(in_mesh, Lookup<T>(m, in_mesh)(o.mesh_material), material);
        mesh = lane::select(in_mesh, m, T(-1));
    }
}

// The fields of HitFields for the lanes of `hit`: (u, v) of triangles (from
// the closest hit) and rectangles (from the hit point), the geometric normal.
template <class T, unsigned F>
inline void store_fields(const SceneData& s, const Closest<T>& best, const T& cid, const Mask<T>& hit, const Vec3<T>& p,
                         const Vec3<T>& ng, HitFields8& out, int lane) {
    T u(0), v(0);
    if constexpr ((F & kTriangle) != 0) {
        const Mask<T> tri = hit && cid >= T(float(s.offset[int(PrimitiveType::triangle)]));
        u = lane::keep(tri, best.tri_u), v = lane::keep(tri, best.tri_v);
    }
    if constexpr ((F & kRectangle) != 0) {
        const int base = s.offset[int(PrimitiveType::rectangle)], count = s.count[int(PrimitiveType::rectangle)];
        const Mask<T> rect = hit && cid >= T(float(base)) && cid < T(float(base + count));
        if (count > 0 && lane::any(rect)) {
            const RectangleArrays& a = s.rectangles;
            const Lookup<T> at(lane::keep(rect, cid - T(float(base))), rect);
            const Vec3<T> q = p - at(a.cx, a.cy, a.cz);
            u = lane::select(rect, fdot(q, at(a.dual_ax, a.dual_ay, a.dual_az)), u);
            v = lane::select(rect, fdot(q, at(a.dual_bx, a.dual_by, a.dual_bz)), v);
        }
    }
    store(out.u, lane, u);
    store(out.v, lane, v);
    store(out.ngx, lane, lane::keep(hit, ng.x));
    store(out.ngy, lane, lane::keep(hit, ng.y));
    store(out.ngz, lane, lane::keep(hit, ng.z));
}

// Lanes [lane, lane + width) of a packet: the closest hit finished into hp,
// and where Fields, into *fields too.
template <class T, Precision P, unsigned F, bool Fields = false>
inline int intersect_lanes(const SceneData& s, const RayPacket8& rp, HitPacket8& hp, int lane,
                           HitFields8* fields = nullptr) {
    int masked = 0;
    const Ray<T, P> r = load_ray<T, P>(rp, lane, masked);
    const Closest<T> best = closest_hit<T, P, F, Fields>(s, r);
    const Mask<T> hit = r.valid && best.cid >= T(0);
    const T cid = lane::keep(hit, best.cid);
    const Vec3<T> p = r.o + r.d * best.t;
    const Lookup<T> at(cid, hit);
    const Vec3<T> ng = hit_normal<T, P, F>(s, at, r, load_residual<T>(rp, lane), best, p, hit);
    const Vec3<T> n = face_forward(s, ng, r, best);
    if constexpr (Fields) store_fields<T, F>(s, best, cid, hit, p, ng, *fields, lane);
    store(hp.t, lane, lane::select(hit, best.t, inf<T>()));
    T primitive = T(-1);
    if constexpr ((F & kTriangle) != 0) {
        // Triangles' ids come with the closest hit; only other hits read the map.
        const Mask<T> tri = hit && cid >= T(float(s.offset[int(PrimitiveType::triangle)]));
        const Mask<T> other = hit && lane::not_(tri);
        if (lane::any(other)) primitive = lane::select(other, Lookup<T>(cid, other)(s.object_of), primitive);
        primitive = lane::select(tri, best.tri_id, primitive);
    } else {
        primitive = lane::select(hit, at(s.object_of), T(-1));
    }
    store_index(hp.primitive, lane, primitive);
    T material, mesh;
    owners_of<T, F>(s.owners, at, primitive, hit, material, mesh);
    store_index(hp.material, lane, material);
    store_index(hp.mesh, lane, mesh);
    store(hp.nx, lane, lane::keep(hit, n.x));
    store(hp.ny, lane, lane::keep(hit, n.y));
    store(hp.nz, lane, lane::keep(hit, n.z));
    store_mask<T>(hp.hit, lane, hit);
    store_mask<T>(hp.invalid, lane, r.invalid);
    return masked;
}

// Every lane group of a packet through intersect_lanes, with the fields
// where a caller asks for them.
template <class T, Precision P, unsigned F, bool Fields>
inline int intersect_lane_groups(const PacketScene& scene, const RayPacket8& rp, HitPacket8& hp, HitFields8* fields) {
    const SceneData& s = scene_data(scene);
    int masked = 0;
    for (int lane = 0; lane < kPacketWidth; lane += lane::width<T>)
        masked += intersect_lanes<T, P, F, Fields>(s, rp, hp, lane, fields);
    return masked;
}

template <class T, Precision P, unsigned F>
int intersect_packet(const PacketScene& scene, const RayPacket8& rp, HitPacket8& hp) noexcept {
    return intersect_lane_groups<T, P, F, false>(scene, rp, hp, nullptr);
}

// intersect_packet with the fields a caller asks for (HitFields).
template <class T, Precision P, unsigned F>
int intersect_fields_packet(const PacketScene& scene, const RayPacket8& rp, HitPacket8& hp, HitFields8& fields) noexcept {
    return intersect_lane_groups<T, P, F, true>(scene, rp, hp, &fields);
}

}  // namespace octray::kernels::OCTRAY_ISA
