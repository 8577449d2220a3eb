// python/hit_record.cpp — what a ray caster gets per hit besides t and the
// shading normal (docs/python.md, intersect): the geometry id, the primitive
// id within that geometry, the barycentrics (uv) and the geometric normal,
// as Open3D's RaycastingScene and Embree report them.
//
// The kernels return the global primitive number only, so these are derived
// here, after the kernel, for hit lanes only and in double from the scene's
// double geometry (Scene, as loaded): hit_records() is the one function to
// replace when a kernel computes them.
#include "octray_module.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <type_traits>
#include <variant>

namespace octray::python {

PrimitiveMap::PrimitiveMap(const Scene& scene, const SceneSources& sources)
    : object_count(std::uint32_t(scene.objects.size())), mesh_faces(sources.mesh_faces) {
    for (std::size_t k = 0; k < scene.objects.size(); ++k)
        object_geometry.push_back(std::int32_t(k < sources.objects.size() ? sources.objects[k] : k));
    std::uint32_t first = object_count;
    for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
        mesh_first.push_back(first);
        first += std::uint32_t(scene.meshes[m].triangle_count());
        mesh_geometry.push_back(std::int32_t(m < sources.meshes.size() ? sources.meshes[m] : scene.objects.size() + m));
    }
    mesh_first.push_back(first);
    mesh_faces.resize(scene.meshes.size());
    for (const auto& f : mesh_faces) any_faces = any_faces || !f.empty();
}

namespace {

struct Answer {
    std::int32_t primitive_id = 0;
    double u = 0, v = 0;
    Vec3d n{0, 0, 0};  // unit, not turned to the ray
};

Vec3d unit(const Vec3d& v) { return v * (1 / std::sqrt(dot(v, v))); }

// (u, v) of p's projection onto the plane of o + u e1 + v e2: the barycentric
// weights of v1 and v2 of a triangle (v0, v0 + e1, v0 + e2), hit = (1 - u - v)
// v0 + u v1 + v v2, as Embree and Open3D give them; and the unit normal
// e1 x e2. A projection rather than a second ray test: it needs no division
// by n.d (grazing rays), and a hit point on the plane to rounding comes back
// from (u, v) to rounding. Inlined, so that the loop over a packet's lanes
// below is one vectorised block.
[[gnu::always_inline]] inline void plane_coordinates(Vec3d o, Vec3d e1, Vec3d e2, Vec3d p, Answer& a) {
    const Vec3d n = cross(e1, e2), w = p - o;
    const double nn = dot(n, n), inv = 1 / nn, length = std::sqrt(nn);  // side by side, not one after the other
    a.u = dot(cross(w, e2), n) * inv;
    a.v = dot(cross(e1, w), n) * inv;
    a.n = n * (length * inv);
}

// A box's outward normal at p: the axis of the face p is nearest, relative
// to the box's extent on that axis.
Vec3d box_normal(const Box& b, const Vec3d& p) {
    const double lo[3] = {b.min.x, b.min.y, b.min.z}, hi[3] = {b.max.x, b.max.y, b.max.z}, q[3] = {p.x, p.y, p.z};
    int axis = 0;
    double best = INFINITY, sign = 1;
    for (int k = 0; k < 3; ++k) {
        const double extent = hi[k] - lo[k];
        const double to_lo = std::fabs(q[k] - lo[k]) / extent, to_hi = std::fabs(hi[k] - q[k]) / extent;
        if (to_lo < best) best = to_lo, axis = k, sign = -1;
        if (to_hi < best) best = to_hi, axis = k, sign = 1;
    }
    Vec3d n{0, 0, 0};
    (axis == 0 ? n.x : axis == 1 ? n.y : n.z) = sign;
    return n;
}

// An analytic object's answer: uv for the shapes with a natural
// parameterisation of their surface (triangle: barycentrics; rectangle: (s, t)
// of corner + s a + t b), 0 for the others; the outward (sphere, box) or
// stated (plane, disk: normal; rectangle: a x b; triangle: its winding) normal.
void object_answer(const Shape& shape, const Vec3d& p, Answer& a) {
    std::visit(
        [&](const auto& s) {
            using S = std::decay_t<decltype(s)>;
            if constexpr (std::is_same_v<S, Sphere>) a.n = unit(p - s.center);
            else if constexpr (std::is_same_v<S, Plane>) a.n = unit_direction(s.normal);
            else if constexpr (std::is_same_v<S, Disk>) a.n = unit_direction(s.normal);
            else if constexpr (std::is_same_v<S, Rectangle>) plane_coordinates(s.corner, s.a, s.b, p, a);
            else if constexpr (std::is_same_v<S, Box>) a.n = box_normal(s, p);
            else plane_coordinates(s.v0, s.v1 - s.v0, s.v2 - s.v0, p, a);
        },
        shape);
}

// A stand-in triangle for the lanes that hit no mesh: the vectorised loop
// computes every lane, and this keeps its arithmetic finite.
const Vec3d kStandIn[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

// Both ends of an object: a triangle's indices (12 bytes) or a vertex (24)
// may straddle two cache lines.
template <class T>
void prefetch(const T* p) {
    __builtin_prefetch(p);
    __builtin_prefetch(reinterpret_cast<const char*>(p + 1) - 1);
}

}  // namespace

// Compiled for AVX-512 and AVX2 besides the baseline, the CPU's pick made at
// load time (GCC's function multiversioning): the loops below take 8 or 4
// double lanes a vector instead of 2.
[[gnu::target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")]]
void hit_records(const SceneHandle& s, const HitChunk& c, const HitArrays& out) noexcept {
    constexpr int N = HitChunk::kRays;
    // Every ray as if it hit a mesh triangle, in straight-line double
    // arithmetic the compiler vectorises (a divide and a square root a hit,
    // one hit after the other, were most of the cost); the other rays are
    // patched after.
    alignas(64) double p[3][N], a[3][N], b[3][N], e[3][N];
    for (int i = 0; i < N; ++i) {
        const double t = c.t[i] < INFINITY ? double(c.t[i]) : 0.0;  // a miss: any finite point
        p[0][i] = double(c.ox[i]) + t * double(c.dx[i]);
        p[1][i] = double(c.oy[i]) + t * double(c.dy[i]);
        p[2][i] = double(c.oz[i]) + t * double(c.dz[i]);
    }
    for (int i = 0; i < N; ++i) {
        const Vec3d &va = *c.vertex[0][i], &vb = *c.vertex[1][i], &vc = *c.vertex[2][i];
        a[0][i] = va.x, a[1][i] = va.y, a[2][i] = va.z;
        b[0][i] = vb.x, b[1][i] = vb.y, b[2][i] = vb.z;
        e[0][i] = vc.x, e[1][i] = vc.y, e[2][i] = vc.z;
    }
    alignas(64) double u[N], v[N], n[3][N];
    for (int i = 0; i < N; ++i) {
        const Vec3d o{a[0][i], a[1][i], a[2][i]};
        Answer r;
        plane_coordinates(o, Vec3d{b[0][i], b[1][i], b[2][i]} - o, Vec3d{e[0][i], e[1][i], e[2][i]} - o,
                          {p[0][i], p[1][i], p[2][i]}, r);
        u[i] = r.u, v[i] = r.v, n[0][i] = r.n.x, n[1][i] = r.n.y, n[2][i] = r.n.z;
    }
    alignas(64) float uv[N][2], normal[N][3];
    for (int i = 0; i < N; ++i) {
        uv[i][0] = float(u[i]), uv[i][1] = float(v[i]);
        normal[i][0] = float(n[0][i]), normal[i][1] = float(n[1][i]), normal[i][2] = float(n[2][i]);
    }
    for (int i = 0; i < c.count; ++i) {
        if (c.mesh[i] != HitChunk::kNoMesh) continue;
        Answer r;  // a miss: 0
        if (c.primitive[i] >= 0)
            object_answer(s.scene->objects[std::size_t(c.primitive[i])].shape, {p[0][i], p[1][i], p[2][i]}, r);
        uv[i][0] = float(r.u), uv[i][1] = float(r.v);
        normal[i][0] = float(r.n.x), normal[i][1] = float(r.n.y), normal[i][2] = float(r.n.z);
    }
    const auto count = std::size_t(c.count);
    const std::size_t first = c.first;
    store_out(out.geometry_id + first, c.geometry_id, count);
    store_out(out.primitive_id + first, c.primitive_id, count);
    store_out(out.uv + 2 * first, &uv[0][0], 2 * count);
    store_out(out.geometric_normal + 3 * first, &normal[0][0], 3 * count);
}

// ---- HitRecorder -------------------------------------------------------------

// find_meshes for a scene of one mesh (and any objects): no search.
[[gnu::target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")]]
static void single_mesh_ids(const PrimitiveMap& map, HitChunk& c) noexcept {
    const std::uint32_t objects = map.object_count, first = map.mesh_first[0];
    const std::int32_t geometry = map.mesh_geometry[0];
    static const std::int32_t kNone = -1;  // a readable address where there are no objects
    const std::int32_t* object_geometry = objects ? map.object_geometry.data() : &kNone;
    for (int i = 0; i < HitChunk::kRays; ++i) {
        const std::int32_t prim = c.primitive[i];
        const bool mesh = prim >= 0 && std::uint32_t(prim) >= objects;
        const bool object = prim >= 0 && !mesh;
        c.mesh[i] = mesh ? 0 : HitChunk::kNoMesh;
        c.local[i] = mesh ? std::uint32_t(prim) - first : 0;
        c.geometry_id[i] = mesh ? geometry : object ? object_geometry[object ? prim : 0] : -1;
        c.primitive_id[i] = prim < 0 ? -1 : std::int32_t(c.local[i]);
    }
}

// A miss's answers, as intersect returns them: t inf, primitive -1, normal 0
// (the kernel leaves its lanes' values unspecified). Also the lanes past the
// chunk's rays.
[[gnu::target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")]]
static void settle_misses(HitChunk& c) noexcept {
    for (int i = 0; i < HitChunk::kRays; ++i) {
        const bool hit = c.hit[i] != 0 && i < c.count;
        c.t[i] = hit ? c.t[i] : INFINITY;
        c.primitive[i] = hit ? c.primitive[i] : -1;
        c.nx[i] = hit ? c.nx[i] : 0.0f, c.ny[i] = hit ? c.ny[i] : 0.0f, c.nz[i] = hit ? c.nz[i] : 0.0f;
    }
}

void HitRecorder::push(const RayPacket8& rays, const HitPacket8& hits, int lanes, std::size_t first) noexcept {
    HitChunk& c = chunk(completed_);
    if (c.count == 0) c.first = first;
    // All 8 lanes as they are (those past the last ray are inactive: misses;
    // only the last packet of all has fewer than 8); settle_misses gives the
    // misses their values.
    const int k = c.count;
    // memcpy of a constant 32 bytes: one vector move each (a loop of element
    // copies stays scalar, the compiler unsure the arrays do not overlap).
    auto copy8 = [](auto* to, const auto* from) { std::memcpy(to, from, 8 * sizeof *from); };
    copy8(c.ox + k, rays.ox), copy8(c.oy + k, rays.oy), copy8(c.oz + k, rays.oz);
    copy8(c.dx + k, rays.dx), copy8(c.dy + k, rays.dy), copy8(c.dz + k, rays.dz);
    copy8(c.t + k, hits.t), copy8(c.primitive + k, hits.primitive), copy8(c.hit + k, hits.hit);
    copy8(c.nx + k, hits.nx), copy8(c.ny + k, hits.ny), copy8(c.nz + k, hits.nz);
    c.count += lanes;
    if (c.count + 8 > HitChunk::kRays) complete();
}

void HitRecorder::complete() noexcept {
    if (completed_ >= 2) write(chunk(completed_ - 2));
    if (completed_ >= 1) find_vertices(chunk(completed_ - 1));
    find_meshes(chunk(completed_));
    ++completed_;
    chunk(completed_).count = 0;
}

void HitRecorder::finish() noexcept {
    if (chunk(completed_).count > 0) complete();
    if (completed_ >= 2) write(chunk(completed_ - 2));
    if (completed_ >= 1) {
        find_vertices(chunk(completed_ - 1));
        write(chunk(completed_ - 1));
    }
    completed_ = 0;
    chunk(0).count = 0;
    _mm_sfence();  // store_out's streaming stores, before another thread reads the arrays
}

void HitRecorder::find_meshes(HitChunk& c) const noexcept {
    const PrimitiveMap& map = s_.primitives;
    const Scene& scene = *s_.scene;
    settle_misses(c);
    if (map.mesh_first.size() == 2) {
        single_mesh_ids(map, c);  // the common case, vectorised
    } else {
        for (int i = 0; i < HitChunk::kRays; ++i) {
            const std::int32_t prim = c.primitive[i];
            const bool mesh = prim >= 0 && std::uint32_t(prim) >= map.object_count;
            const auto m = mesh ? std::uint32_t(map.mesh_of(std::uint32_t(prim))) : HitChunk::kNoMesh;
            c.mesh[i] = m;
            c.local[i] = mesh ? std::uint32_t(prim) - map.mesh_first[m] : 0;
            c.geometry_id[i] = prim < 0 ? -1 : mesh ? map.mesh_geometry[m] : map.object_geometry[std::size_t(prim)];
            c.primitive_id[i] = prim < 0 ? -1 : std::int32_t(c.local[i]);
        }
    }
    for (int i = 0; i < HitChunk::kRays; ++i) {
        if (c.mesh[i] == HitChunk::kNoMesh) continue;
        prefetch(reinterpret_cast<const std::uint32_t(*)[3]>(&scene.meshes[c.mesh[i]].indices[3 * std::size_t(c.local[i])]));
        if (map.any_faces && !map.mesh_faces[c.mesh[i]].empty()) prefetch(&map.mesh_faces[c.mesh[i]][c.local[i]]);
    }
}

// The mesh triangles' vertices (their indices in cache by now), and the
// triangles' numbers as the caller gave them where zero-area ones were dropped.
void HitRecorder::find_vertices(HitChunk& c) const noexcept {
    const PrimitiveMap& map = s_.primitives;
    const Scene& scene = *s_.scene;
    // The last mesh's arrays, looked up again only where a ray hit another.
    std::uint32_t last = HitChunk::kNoMesh;
    const std::uint32_t* indices = nullptr;
    const Vec3d* vertices = nullptr;
    for (int i = 0; i < HitChunk::kRays; ++i) {
        if (c.mesh[i] == HitChunk::kNoMesh) {
            for (int k = 0; k < 3; ++k) c.vertex[k][i] = &kStandIn[k];
            continue;
        }
        if (c.mesh[i] != last) {
            last = c.mesh[i];
            indices = scene.meshes[last].indices.data(), vertices = scene.meshes[last].vertices.data();
        }
        const std::uint32_t* tri = indices + 3 * std::size_t(c.local[i]);
        for (int k = 0; k < 3; ++k) prefetch(c.vertex[k][i] = vertices + tri[k]);
        if (map.any_faces && !map.mesh_faces[c.mesh[i]].empty())
            c.primitive_id[i] = std::int32_t(map.mesh_faces[c.mesh[i]][c.local[i]]);
    }
}

void HitRecorder::write(const HitChunk& c) const noexcept {
    const auto count = std::size_t(c.count);
    const std::size_t r = c.first;
    store_out(out_.t + r, c.t, count);
    store_out(out_.primitive + r, c.primitive, count);
    alignas(64) float normal[HitChunk::kRays][3];
    for (int i = 0; i < HitChunk::kRays; ++i) normal[i][0] = c.nx[i], normal[i][1] = c.ny[i], normal[i][2] = c.nz[i];
    store_out(out_.normal + 3 * r, &normal[0][0], 3 * count);
    hit_records(s_, c, out_);
}

}  // namespace octray::python
