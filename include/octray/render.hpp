// octray/render.hpp — whole images from the packet kernels: the row loop,
// a threaded render of a whole image, and the 8-bit conversion. Link
// octray::render (render/; the installed package's `render` component).
//
//     octray::PacketScene scene = octray::compile(authoring_scene);
//     octray::Kernel k = octray::select_kernel(scene, octray::Path::simd);
//     octray::Image<float> hdr(scene.width(), scene.height());
//     octray::render_rows(k, scene, 0, scene.height(), hdr, nullptr);
#pragma once

#include <octray/image.hpp>
#include <octray/kernels.hpp>
#include <octray/packet_scene.hpp>
#include <octray/threads.hpp>

#include <cstdint>
#include <functional>
#include <vector>

namespace octray {

struct RenderCounters {
    std::uint64_t rays = 0;    // camera rays traced
    std::uint64_t masked = 0;  // lanes masked off for invalid input
};

// Renders image rows [y0, y1) with 8-pixel camera tiles. `hdr` receives the
// radiance, `display` (optional) the tone-mapped colour. Rows are independent:
// disjoint row ranges may be rendered concurrently into the same images.
// `primitive_ids` (optional, width*height, row-major) receives each pixel's
// Scene::objects index, -1 on a miss.
void render_rows(const Kernel& kernel, const PacketScene& scene, int y0, int y1, Image<float>& hdr,
                 Image<float>* display, RenderCounters* counters = nullptr,
                 std::int32_t* primitive_ids = nullptr) noexcept;

// 8-bit conversion of a display image: floor(255 c + 0.5), c clamped to [0,1].
ImageRGB8 quantize(const Image<float>& display);

// A whole image: HDR radiance and per-pixel primitive ids (-1: a miss).
struct PacketRender {
    Image<float> radiance;
    std::vector<std::int32_t> primitive;
    RenderCounters counters;
    double seconds = 0;  // wall time of the render itself
    int threads = 0;     // the threads it ran on
};
// Renders the whole image, rows spread over `threads` threads (resolve_threads:
// 0 = every core); `row_done` (optional) is called once per row, from any of
// them; `display` (optional, the scene's size) receives the tone-mapped colour.
// The image is the same bit for bit whatever the thread count.
PacketRender render_packet(const Kernel& kernel, const PacketScene& scene, int threads = 1,
                           const std::function<void()>& row_done = {}, Image<float>* display = nullptr);

}  // namespace octray
