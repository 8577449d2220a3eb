// tools/cmd_render.cpp — `octray render SCENE -o OUT.png [--hdr OUT.pfm] [--path ...] [--threads N]`.
#include "commands.hpp"
#include "image_io.hpp"
#include "progress.hpp"
#include "scene_loader.hpp"

#include <octray/kernels.hpp>
#include <octray/render.hpp>
#include <octray/reference.hpp>

#include <chrono>
#include <algorithm>
#include <cmath>
#include <cstdio>

namespace octray::cli {

int run_render(const RenderArgs& args) {
    Scene scene = load_scene(args.scene);
    if (args.width > 0) {
        const double aspect = double(scene.camera.height) / scene.camera.width;
        scene.camera.height = std::max(1, int(std::lround(args.width * aspect)));
        scene.camera.width = args.width;
        validate(scene);  // the image-size limits
    }
    const int threads = resolve_threads(args.threads);
    const bool use_reference = args.path == kReferencePathName;
    const auto start = std::chrono::steady_clock::now();
    ImageRGB8 display;
    std::string kernel_name = "reference (scalar double)";
    RenderCounters counters;
    double render_seconds = 0;  // camera rays to display colour, without file I/O
    if (use_reference) {
        const Image<double> hdr = reference::render(scene);
        display = reference::to_display(hdr, scene.render);
        if (!args.hdr.empty()) write_pfm(args.hdr, hdr);
    } else {
        CompileOptions options;
        options.threads = threads;
        const PacketScene packet = compile(scene, options);
        const Kernel kernel = select_kernel(packet, args.path == path_name(Path::simd) ? Path::simd : Path::scalar);
        kernel_name = kernel.name();
        Image<float> shown(scene.camera.width, scene.camera.height);
        Progress progress("rendering", scene.camera.height);
        const PacketRender out = render_packet(kernel, packet, threads, [&progress] { progress.tick(); }, &shown);
        progress.finish();
        counters = out.counters;
        render_seconds = out.seconds;
        display = quantize(shown);
        if (!args.hdr.empty()) write_pfm(args.hdr, out.radiance);
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    write_png(args.output, display);
    std::printf("wrote %s%s%s (%dx%d, %s, %d thread%s, %.1f ms)\n", args.output.c_str(),
                args.hdr.empty() ? "" : " and ", args.hdr.c_str(), scene.camera.width, scene.camera.height,
                kernel_name.c_str(), use_reference ? 1 : threads,
                (use_reference || threads == 1) ? "" : "s", seconds * 1e3);
    if (render_seconds > 0)
        std::printf("packet render: %.1f ms, %.2f Mrays/s\n", render_seconds * 1e3,
                    double(counters.rays) / render_seconds * 1e-6);
    if (counters.masked) std::printf("%llu lanes masked off for invalid input\n", (unsigned long long)counters.masked);
    return kExitOk;
}

}  // namespace octray::cli
