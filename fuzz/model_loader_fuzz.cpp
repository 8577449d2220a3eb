// fuzz/model_loader_fuzz.cpp — the model loader (io/model_loader.hpp) on any bytes.
//
// The input is one model file. Its format comes from its first bytes, as a model's own
// magic would say: "glTF" -> .glb, "ply" -> .ply, '{' -> .gltf, anything else -> .obj;
// so real model files are seeds as they are. The bytes are written to a scratch file and
// read by load_model(), which talks to assimp through its guards.
//
// The loader's promise: a MeshData or a ModelError whose what() is one line. Anything else
// is a bug: another exception type, a crash, a sanitizer report in octray's code, a hang.
// A MeshData must keep its invariants (indices in range, three per triangle, finite
// vertices, each used, no zero-area triangle, within the triangle limit), pass validate()
// as a scene's mesh, and trace through every stage of the SIMD and scalar kernels within
// the numerical policy (tests/kernel_checks.hpp).
#include "kernel_checks.hpp"
#include "model_loader.hpp"

#include <octray/scene.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

namespace {

[[noreturn]] void bug(const std::string& what) {
    std::fprintf(stderr, "model_loader_fuzz: %s\n", what.c_str());
    std::abort();
}

// One scratch directory per process, removed at exit.
struct ScratchDir {
    std::filesystem::path path;
    ScratchDir() {
        std::string pattern = (std::filesystem::temp_directory_path() / "octray_model_fuzz.XXXXXX").string();
        if (!mkdtemp(pattern.data())) bug("cannot create a scratch directory");
        path = pattern;
    }
    ~ScratchDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
};

const char* extension_of(const std::uint8_t* data, std::size_t size) {
    const std::string head(reinterpret_cast<const char*>(data), std::min<std::size_t>(size, 4));
    if (head == "glTF") return ".glb";
    if (head.rfind("ply", 0) == 0) return ".ply";
    const std::size_t first = std::string(head).find_first_not_of(" \t\r\n");
    if (first != std::string::npos && head[first] == '{') return ".gltf";
    return ".obj";
}

void check_mesh(const octray::MeshData& m) {
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
bool scene_of(octray::MeshData&& data, octray::Scene& scene) {
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

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const ScratchDir scratch;
    const std::filesystem::path file = scratch.path / (std::string("model") + extension_of(data, size));
    {
        std::ofstream out(file, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
        if (!out) bug("cannot write " + file.string());
    }
    octray::MeshData mesh;
    try {
        mesh = octray::load_model(file.string());
    } catch (const octray::ModelError& e) {
        const std::string what = e.what();
        if (what.empty() || what.find('\n') != std::string::npos) bug("error message is not one line: " + what);
        return 0;
    } catch (const std::exception& e) {
        bug(std::string("load_model threw something other than ModelError: ") + e.what());
    }
    check_mesh(mesh);
    octray::Scene scene;
    if (!scene_of(std::move(mesh), scene)) return 0;
    try {
        octray::validate(scene);
    } catch (const octray::InvalidScene& e) {
        // A mesh far smaller than its distance from the origin leaves the camera
        // degenerate in double: the harness's camera, not the loader, is at fault.
        if (e.path().rfind("camera.", 0) == 0) return 0;
        bug(std::string("a loaded mesh fails validate(): ") + e.what());
    }
    if (const std::string e = octray::test::trace_camera_tiles(scene); !e.empty()) bug(e);
    return 0;
}
