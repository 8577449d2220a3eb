// tools/commands.hpp — the `octray` subcommands, one function each.
// Each returns the process exit status (the contract: 0 ok, 1 a failed
// verification, 2 bad input); bad input is thrown as an exception that
// main() turns into one line on stderr.
#pragma once

#include <octray/kernels.hpp>
#include <octray/scene.hpp>

#include <string>

namespace octray::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailed = 1;
inline constexpr int kExitBadInput = 2;

// `--threads N`: N threads; 0 means all cores, by the one rule of
// octray/threads.hpp (resolve_threads), as the help of every subcommand says.

// What a scene holds, for the first line of verify and errtime: "1 object,
// 3 meshes (1312 triangles), 4 lights". Objects are the analytic primitives
// of "objects"; a mesh object counts as a mesh (and its triangles).
inline std::string scene_contents(const Scene& scene) {
    auto count = [](std::size_t n, const char* one, const char* many) {
        return std::to_string(n) + " " + (n == 1 ? one : many);
    };
    std::string s = count(scene.objects.size(), "object", "objects");
    if (!scene.meshes.empty())
        s += ", " + count(scene.meshes.size(), "mesh", "meshes") + " (" +
             count(scene.mesh_triangle_count(), "triangle", "triangles") + ")";
    return s + ", " + count(scene.directional_lights.size() + scene.point_lights.size(), "light", "lights");
}

// `--path`: a kernel Path by its path_name() (kernels.hpp), or the reference renderer.
inline constexpr const char* kReferencePathName = "reference";

struct RenderArgs {
    std::string scene;
    std::string output;
    std::string hdr;  // empty: no PFM
    std::string path = path_name(Path::simd);
    int threads = 0;  // 0: all cores
    int width = 0;    // > 0: render at this width instead of the scene's, same aspect ratio
};
int run_render(const RenderArgs& args);

struct VerifyArgs {
    std::string scene;
    int threads = 0;  // 0: all cores
    bool packet_rays = false;  // the reference along the packet path's camera rays as the kernels take them (verify.hpp)
};
int run_verify(const VerifyArgs& args);

struct ErrtimeArgs {
    std::string scene;
    std::string csv;   // empty: no CSV
    std::string plot;  // empty: no plot (else F.svg and F.png, by tools/plot.py)
    int threads = 1;   // render threads while timing (0: all cores)
};
int run_errtime(const ErrtimeArgs& args);

struct StabilityArgs {
    bool wide = false;  // every path x mode as a column (wider than 100 columns)
    std::string csv;    // empty: no CSV; else one row per case x path x mode, with notes
};
int run_stability(const StabilityArgs& args);

struct InfoArgs {
    std::string scene;
};
int run_info(const InfoArgs& args);

}  // namespace octray::cli
