// python/hit_record.cpp — what a ray caster gets per hit besides t and the
// shading normal (docs/python.md, intersect): the geometry id and the
// primitive id within that geometry, found here from the kernel's global
// primitive number, and the barycentrics (uv) and the geometric normal, the
// kernel's own (Kernel::intersect_fields, HitFields8), as Open3D's
// RaycastingScene and Embree report them.
#include "octray_module.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

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

// Writes the chunk's ids, uv and geometric normal (interleaved for numpy).
void hit_records(const HitChunk& c, const HitArrays& out) noexcept {
    constexpr int N = HitChunk::kRays;
    alignas(64) float uv[N][2], normal[N][3];
    for (int i = 0; i < N; ++i) {
        uv[i][0] = c.u[i], uv[i][1] = c.v[i];
        normal[i][0] = c.ngx[i], normal[i][1] = c.ngy[i], normal[i][2] = c.ngz[i];
    }
    const auto count = std::size_t(c.count);
    const std::size_t first = c.first;
    store_out(out.geometry_id + first, c.geometry_id, count);
    store_out(out.primitive_id + first, c.primitive_id, count);
    store_out(out.uv + 2 * first, &uv[0][0], 2 * count);
    store_out(out.geometric_normal + 3 * first, &normal[0][0], 3 * count);
}

// ---- HitRecorder -------------------------------------------------------------

// find_ids for a scene of one mesh (and any objects): no search.
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
static void settle_misses(HitChunk& c) noexcept {
    for (int i = 0; i < HitChunk::kRays; ++i) {
        const bool hit = c.hit[i] != 0 && i < c.count;
        c.t[i] = hit ? c.t[i] : INFINITY;
        c.primitive[i] = hit ? c.primitive[i] : -1;
        c.nx[i] = hit ? c.nx[i] : 0.0f, c.ny[i] = hit ? c.ny[i] : 0.0f, c.nz[i] = hit ? c.nz[i] : 0.0f;
        c.u[i] = hit ? c.u[i] : 0.0f, c.v[i] = hit ? c.v[i] : 0.0f;
        c.ngx[i] = hit ? c.ngx[i] : 0.0f, c.ngy[i] = hit ? c.ngy[i] : 0.0f, c.ngz[i] = hit ? c.ngz[i] : 0.0f;
    }
}

void HitRecorder::push(const HitPacket8& hits, const HitFields8& fields, int lanes, std::size_t first) noexcept {
    HitChunk& c = *chunk_;
    if (c.count == 0) c.first = first;
    // All 8 lanes as they are (those past the last ray are inactive: misses;
    // only the last packet of all has fewer than 8); settle_misses gives the
    // misses their values.
    const int k = c.count;
    // memcpy of a constant 32 bytes: one vector move each (a loop of element
    // copies stays scalar, the compiler unsure the arrays do not overlap).
    auto copy8 = [](auto* to, const auto* from) { std::memcpy(to, from, 8 * sizeof *from); };
    copy8(c.t + k, hits.t), copy8(c.primitive + k, hits.primitive), copy8(c.hit + k, hits.hit);
    copy8(c.nx + k, hits.nx), copy8(c.ny + k, hits.ny), copy8(c.nz + k, hits.nz);
    copy8(c.u + k, fields.u), copy8(c.v + k, fields.v);
    copy8(c.ngx + k, fields.ngx), copy8(c.ngy + k, fields.ngy), copy8(c.ngz + k, fields.ngz);
    c.count += lanes;
    if (c.count + 8 > HitChunk::kRays) complete();
}

void HitRecorder::complete() noexcept {
    find_ids(*chunk_);
    write(*chunk_);
    chunk_->count = 0;
}

void HitRecorder::finish() noexcept {
    if (chunk_->count > 0) complete();
    _mm_sfence();  // store_out's streaming stores, before another thread reads the arrays
}

// Each hit's geometry and its primitive's number in that geometry: a mesh's
// kept triangle renumbered as the caller's face array numbers it where
// zero-area triangles were dropped.
void HitRecorder::find_ids(HitChunk& c) const noexcept {
    const PrimitiveMap& map = s_.primitives;
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
    if (!map.any_faces) return;
    for (int i = 0; i < c.count; ++i)
        if (c.mesh[i] != HitChunk::kNoMesh && !map.mesh_faces[c.mesh[i]].empty())
            c.primitive_id[i] = std::int32_t(map.mesh_faces[c.mesh[i]][c.local[i]]);
}

void HitRecorder::write(const HitChunk& c) const noexcept {
    const auto count = std::size_t(c.count);
    const std::size_t r = c.first;
    store_out(out_.t + r, c.t, count);
    store_out(out_.primitive + r, c.primitive, count);
    alignas(64) float normal[HitChunk::kRays][3];
    for (int i = 0; i < HitChunk::kRays; ++i) normal[i][0] = c.nx[i], normal[i][1] = c.ny[i], normal[i][2] = c.nz[i];
    store_out(out_.normal + 3 * r, &normal[0][0], 3 * count);
    hit_records(c, out_);
}

}  // namespace octray::python
