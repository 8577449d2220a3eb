// fuzz/model_fuzz_checks.hpp — what the three model-file fuzz targets (ply_fuzz.cpp,
// obj_fuzz.cpp, gltf_fuzz.cpp) check after their reader, shared.
//
// A reader's promise (io/model_formats.hpp): a RawModel or a ModelError whose what() is
// one line. Anything else is a bug: another exception type, a crash, a sanitizer report,
// a hang. What collect_model makes of a RawModel must keep MeshData's invariants (indices
// in range, three per triangle, finite vertices, each used, no zero-area triangle, within
// the triangle limit), pass validate() as a scene's mesh, and trace through every stage of
// the SIMD and scalar kernels within the numerical policy (tests/support/kernel_checks.hpp).
#pragma once

#include "kernel_checks.hpp"
#include "model_formats.hpp"

#include <octray/scene.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

namespace model_fuzz {

[[noreturn]] inline void bug(const std::string& what) {
    std::fprintf(stderr, "model fuzz: %s\n", what.c_str());
    std::abort();
}

inline void check_mesh(const octray::MeshData& m) {
    using namespace octray;
    if (m.indices.size() % 3 != 0) bug("indices not three per triangle");
    if (m.triangle_count() == 0) bug("a MeshData without triangles");
    if (m.triangle_count() > kMaxModelTriangles) bug("more triangles than the limit");
    if (m.format.empty()) bug("no format named");
    std::vector<bool> used(m.vertices.size(), false);
    for (const std::uint32_t i : m.indices) {
        if (i >= m.vertices.size()) bug("index out of range");
        used[i] = true;
    }
    for (std::size_t v = 0; v < m.vertices.size(); ++v) {
        const Vec3d& p = m.vertices[v];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) bug("a vertex is not finite");
        if (!used[v]) bug("vertex " + std::to_string(v) + " is used by no triangle");
    }
    for (std::size_t k = 0; k < m.indices.size(); k += 3) {
        const Vec3d& a = m.vertices[m.indices[k]];
        const Vec3d n = cross(m.vertices[m.indices[k + 1]] - a, m.vertices[m.indices[k + 2]] - a);
        if (n.x == 0 && n.y == 0 && n.z == 0) bug("a zero-area triangle was kept");
    }
}

// The mesh in front of a pinhole camera that sees all of it, lit by a directional light
// with shadows; or no scene when the mesh's extent overflows a double (a camera there
// would not be finite, which validate() rightly rejects).
inline bool scene_of(octray::MeshData&& data, octray::Scene& scene) {
    using namespace octray;
    Vec3d lo = data.vertices[0], hi = lo;
    for (const Vec3d& p : data.vertices)
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)},
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    const Vec3d centre = lo * 0.5 + hi * 0.5;
    const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-30});
    const Vec3d eye = centre + Vec3d{0.3, 0.4, 1.0} * (2 * extent);
    if (!std::isfinite(extent) || !std::isfinite(eye.x) || !std::isfinite(eye.y) || !std::isfinite(eye.z) ||
        (eye.x == centre.x && eye.y == centre.y && eye.z == centre.z))
        return false;
    scene.camera.eye = eye;
    scene.camera.look_at = centre;
    scene.camera.up = {0, 1, 0};
    scene.camera.width = 24;
    scene.camera.height = 16;
    scene.ambient = AmbientLight{{1, 1, 1}, 0.2};
    scene.directional_lights.push_back(DirectionalLight{unit_direction({-1, -2, -1}), {1, 1, 1}, 1.0, true});
    scene.materials.push_back(Material{"m", 0.2, 0.7, {0.8, 0.6, 0.4}});
    Mesh mesh;
    mesh.vertices = std::move(data.vertices);
    mesh.indices = std::move(data.indices);
    mesh.material = 0;
    scene.meshes.push_back(std::move(mesh));
    return true;
}

// One input through `read` (a reader of model_formats.hpp) and everything after it.
template <class Read>
int run(Read read, const char* format) {
    using namespace octray;
    MeshData mesh;
    try {
        const model_formats::RawModel raw = read();
        mesh = model_formats::collect_model(raw, MeshTransform{}.to_matrix(), format);
    } catch (const ModelError& e) {
        const std::string what = e.what();
        if (what.empty() || what.find('\n') != std::string::npos) bug("error message is not one line: " + what);
        return 0;
    } catch (const std::exception& e) {
        bug(std::string("the reader threw something other than ModelError: ") + e.what());
    }
    check_mesh(mesh);
    Scene scene;
    if (!scene_of(std::move(mesh), scene)) return 0;
    try {
        validate(scene);
    } catch (const InvalidScene& e) {
        // A mesh far smaller than its distance from the origin leaves the camera
        // degenerate in double: the harness's camera, not the reader, is at fault.
        if (e.path().rfind("camera.", 0) == 0) return 0;
        bug(std::string("a loaded mesh fails validate(): ") + e.what());
    }
    if (const std::string e = test::trace_camera_tiles(scene); !e.empty()) bug(e);
    return 0;
}

}  // namespace model_fuzz
