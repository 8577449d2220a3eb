// python/octray_module.hpp — what the module's source files share: the Scene
// handle, the argument checks, the hit record of a ray caster.
#pragma once

#include "scene_loader.hpp"

#include <octray/kernels.hpp>
#include <octray/packet.hpp>
#include <octray/packet_scene.hpp>
#include <octray/scene.hpp>

#include <pybind11/pybind11.h>

#include <emmintrin.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace py = pybind11;
using namespace pybind11::literals;

namespace octray::python {

// How a global primitive number (HitPacket8::primitive: objects, then mesh
// triangles) maps back to the caller's terms: the geometry (its index in the
// JSON's "objects") and the primitive within it (a mesh's triangle as the
// caller's face array or model file numbers it, zero-area ones counted).
struct PrimitiveMap {
    std::uint32_t object_count = 0;             // Scene::objects.size(): numbers below are objects
    std::vector<std::int32_t> object_geometry;  // per Scene object: its geometry id
    std::vector<std::uint32_t> mesh_first;      // per Scene mesh: its first triangle's number; then the end
    std::vector<std::int32_t> mesh_geometry;    // per Scene mesh: its geometry id
    std::vector<std::vector<std::uint32_t>> mesh_faces;  // SceneSources::mesh_faces
    bool any_faces = false;                     // some mesh dropped zero-area triangles

    PrimitiveMap() = default;
    PrimitiveMap(const Scene& scene, const SceneSources& sources);
    // The Scene::meshes index of mesh triangle number p (p >= object_count):
    // a binary search over the meshes' first numbers, none for one mesh.
    std::size_t mesh_of(std::uint32_t p) const {
        if (mesh_first.size() == 2) return 0;
        return std::size_t(std::upper_bound(mesh_first.begin(), mesh_first.end() - 1, p) - mesh_first.begin()) - 1;
    }
};

// octray.Scene's C++ side: the authoring scene (as loaded) and its compiled
// form, made once; immutable, so calls on one Scene may run concurrently.
struct SceneHandle {
    SceneHandle(Scene s, SceneSources src, std::string source_name);
    std::shared_ptr<const Scene> scene;
    std::string source;     // the JSON file, or "" for a dict
    SceneSources sources;   // which parts the JSON gave (camera, materials), where each primitive came from
    PrimitiveMap primitives;
    PacketScene compiled;

    bool has_camera() const { return sources.camera; }
    bool has_materials() const { return sources.materials; }
    // Throws ValueError when this scene lacks what `call` needs (a
    // geometry-only scene has no camera and/or no materials), naming them.
    void require(const char* call, bool camera, bool materials) const;
};

std::shared_ptr<SceneHandle> load(const std::string& path);

// A `threads` argument, checked as the CLI's --threads (0 .. 1024; 0 = every
// core); ValueError naming it otherwise. Returns it unresolved.
int checked_threads(int threads);
// `path` for the packet kernels: "simd" or "scalar"; ValueError otherwise.
Path packet_path(const std::string& path);
// `mode`: a precision mode by the CLI's name (precision_name: exact, fast,
// approx, fast14, approx14, double); ValueError for another name or for a
// mode this CPU does not run.
Precision precision_mode(const std::string& mode);
// select_kernel for path and mode, refusing (ValueError) a kernel that would
// run another mode than asked.
Kernel kernel_for(const SceneHandle& s, const std::string& path, const std::string& mode);

// intersect's output arrays (docs/python.md): one entry a ray.
struct HitArrays {
    float* t;                 // the kernel's answers: t, the global primitive number, the shading normal
    std::int32_t* primitive;
    float* normal;            // 3 a ray
    std::int32_t* geometry_id;  // the hit records (hit_records)
    std::int32_t* primitive_id;
    float* uv;                // 2 a ray
    float* geometric_normal;  // 3 a ray
};

// Copies count elements into an output array. Whole 16-byte blocks go as
// streaming stores: intersect's outputs (12 MB for a million rays) are
// written once and not read here, so they bypass the caches instead of being
// read in first and evicting the scene. The thread that stores must
// _mm_sfence() before another reads them (HitRecorder::finish does).
template <class T>
inline void store_out(T* dst, const T* src, std::size_t count) noexcept {
    // Chunks start at whole packets: every array's slice is 16-byte aligned
    // (OutputBuffer aligns the arrays); a slice that is not goes plainly.
    const std::size_t blocks = reinterpret_cast<std::uintptr_t>(dst) % 16 == 0 ? count * sizeof(T) / 16 : 0;
    for (std::size_t k = 0; k < blocks; ++k)
        _mm_stream_si128(reinterpret_cast<__m128i*>(dst) + k, _mm_loadu_si128(reinterpret_cast<const __m128i*>(src) + k));
    const std::size_t done = blocks * 16 / sizeof(T);
    std::copy_n(src + done, count - done, dst + done);
}

// A run of consecutive intersected rays on their way to the output arrays:
// the kernel's answers (Kernel::intersect_fields) and, found here, each
// hit's geometry and primitive id.
struct HitChunk {
    static constexpr int kRays = 128;  // 16 packets: long loops
    static constexpr std::uint32_t kNoMesh = 0xFFFFFFFFu;
    alignas(64) float t[kRays], nx[kRays], ny[kRays], nz[kRays];  // inf and 0 on a miss
    alignas(64) float u[kRays], v[kRays], ngx[kRays], ngy[kRays], ngz[kRays];  // HitFields8's
    alignas(64) std::int32_t hit[kRays];        // the kernel's HitPacket8::hit
    alignas(64) std::int32_t primitive[kRays];  // the global number; -1: a miss
    alignas(64) std::uint32_t mesh[kRays];      // a mesh triangle's Scene::meshes index; else kNoMesh
    alignas(64) std::uint32_t local[kRays];     // its number in that mesh (as kept)
    alignas(64) std::int32_t geometry_id[kRays], primitive_id[kRays];  // HitRecorder finds them
    int count = 0;
    std::size_t first = 0;                      // the first ray's index
};

// Writes a chunk's geometry_id and primitive_id (found from the global
// primitive number as the chunk filled), uv and geometric_normal (the
// kernel's HitFields8). Misses: -1, -1, (0, 0), (0, 0, 0).
void hit_records(const HitChunk& c, const HitArrays& out) noexcept;

// One thread's intersected packets, in order, on their way to the output
// arrays, a chunk of 16 packets at a time: when a chunk is full, its ids are
// found (a mesh's kept triangle numbered as the caller's face array numbers
// it) and everything is written. push() each intersected packet, then finish().
class HitRecorder {
public:
    HitRecorder(const SceneHandle& s, const HitArrays& out) : s_(s), out_(out), chunk_(new HitChunk()) {}  // zeroed: the loops read whole chunks
    void push(const HitPacket8& hits, const HitFields8& fields, int lanes, std::size_t first) noexcept;
    void finish() noexcept;

private:
    void complete() noexcept;                   // the chunk is full (or the last)
    void find_ids(HitChunk& c) const noexcept;  // its geometry and primitive ids
    void write(const HitChunk& c) const noexcept;  // everything to the output arrays
    const SceneHandle& s_;
    HitArrays out_;
    std::unique_ptr<HitChunk> chunk_;
};

void bind_scene(py::module_& m, py::class_<SceneHandle, std::shared_ptr<SceneHandle>>& cls);
void bind_rays(py::class_<SceneHandle, std::shared_ptr<SceneHandle>>& cls);
void bind_harness(py::module_& m, py::class_<SceneHandle, std::shared_ptr<SceneHandle>>& cls);

}  // namespace octray::python
