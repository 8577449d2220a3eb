// render/packet_render.cpp — render_packet (octray/render.hpp): a whole
// image, its rows spread over threads.
#include <octray/render.hpp>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <algorithm>
#include <chrono>

namespace octray {

PacketRender render_packet(const Kernel& kernel, const PacketScene& scene, int threads,
                           const std::function<void()>& row_done, Image<float>* display) {
    const int w = scene.width(), h = scene.height();
    PacketRender out;
    out.radiance = Image<float>(w, h);
    out.primitive.assign(std::size_t(w) * std::size_t(h), -1);
    const auto start = std::chrono::steady_clock::now();
    std::uint64_t rays = 0, masked = 0;
    int team = 1;
    [[maybe_unused]] const int asked = resolve_threads(threads);
#pragma omp parallel for schedule(dynamic, 4) num_threads(asked) reduction(+ : rays, masked) reduction(max : team)
    for (int y = 0; y < h; ++y) {
#ifdef _OPENMP
        team = std::max(team, omp_get_num_threads());
#endif
        RenderCounters c;
        render_rows(kernel, scene, y, y + 1, out.radiance, display, &c, out.primitive.data());
        if (row_done) row_done();
        rays += c.rays;
        masked += c.masked;
    }
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    out.counters.rays = rays;
    out.counters.masked = masked;
    out.threads = team;
    return out;
}

}  // namespace octray
