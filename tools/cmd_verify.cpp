// tools/cmd_verify.cpp — `octray verify SCENE`: the packet paths against the
// reference, as a table of numbers; exit 1 when a path is over tolerance.
#include "commands.hpp"
#include "scene_loader.hpp"
#include "verify.hpp"

#include <octray/kernels.hpp>

#include <algorithm>
#include <cstdio>

namespace octray::cli {

int run_verify(const VerifyArgs& args) {
    const Scene scene = load_scene(args.scene);
    CompileOptions options;
    options.threads = args.threads;
    const PacketScene packet = compile(scene, options);
    const ReferenceRender ref =
        args.packet_rays ? render_reference(scene, trace_reference(scene, packet, select_kernel(packet, Path::simd).camera),
                                            args.threads)
                         : render_reference(scene, args.threads);
    const Tolerance tol;
    std::printf("scene %s: %dx%d, %s\n", args.scene.c_str(), scene.camera.width, scene.camera.height,
                scene_contents(scene).c_str());
    std::printf("tolerance: |L - L_ref| <= %.0e * S per channel (S: the pixel's radiance with every light at n.l = 1);\n"
                "           mismatched hits only on silhouettes, at most %.1f%% of lanes\n\n",
                tol.scaled_error, 100 * tol.silhouette_fraction);
    if (args.packet_rays)
        std::printf("reference: along the packet path's camera rays (--packet-rays: float plus residual, as the kernels take them)\n");
    std::printf("%-7s %-6s %8s %10s %10s %10s %10s %8s %10s %11s  %s\n", "path", "isa", "lanes", "max rel", "mean rel",
                "p99 rel", "max L/S", "max ULP", "mismatched", "silhouette", "verdict");
    bool ok = true;
    int threads = 0;  // as the renders report it
    for (Path path : {Path::scalar, Path::simd}) {
        const Kernel kernel = select_kernel(packet, path);
        const PacketRender out = render_packet(kernel, packet, args.threads);
        threads = std::max(threads, out.threads);
        const Agreement a = compare(ref, out.radiance, out.primitive);
        const bool pass = a.within(tol);
        ok = ok && pass;
        std::printf("%-7s %-6s %8llu %10.2e %10.2e %10.2e %10.2e %8llu %10llu %11llu  %s\n", path_name(path),
                    kernel.isa, (unsigned long long)a.compared, a.max_rel, a.mean_rel, a.p99_rel, a.max_scaled,
                    (unsigned long long)a.max_ulp, (unsigned long long)a.mismatched,
                    (unsigned long long)a.mismatched_silhouette, pass ? "ok" : "OVER TOLERANCE");
        if (a.shadow_edges)
            std::printf("        %llu lanes on shadow boundaries, left out of the error columns\n",
                        (unsigned long long)a.shadow_edges);
        if (a.occlusion_grazing)
            std::printf("        %llu lanes whose occlusion samples graze an occluder: compared at their own count\n",
                        (unsigned long long)a.occlusion_grazing);
        if (a.nonfinite) std::printf("        %llu non-finite radiance values\n", (unsigned long long)a.nonfinite);
    }
    std::printf("packet renders on %d thread%s\n", threads, threads == 1 ? "" : "s");
    return ok ? kExitOk : kExitFailed;
}

}  // namespace octray::cli
