// examples/shared_scene_threads.cpp — one compiled scene shared by many threads.
//
// A PacketScene is read-only after compile() and a Kernel is a table of
// function pointers, so engine threads share both and only own their packets.
// This program traces the same 4096 engine rays with 1 thread and with 4
// threads (each thread its own packets and its own slice of the output) and
// requires bit-identical results; then renders the scene's camera image with
// render_rows() on disjoint row ranges in 4 threads and compares it with a
// one-thread render. docs/API.md quotes this file. Exits non-zero on failure.
#include <octray/octray.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <thread>
#include <vector>

namespace {

octray::Scene make_scene() {
    octray::Scene scene;
    scene.camera.eye = {0, 1, 6};
    scene.camera.width = 67;  // not a multiple of 8: the last tile of each row is partial
    scene.camera.height = 41;
    scene.ambient = octray::AmbientLight{{1, 1, 1}, 0.25};
    octray::DirectionalLight sun;
    sun.direction = octray::Vec3d{1, 2, 1} * (1.0 / std::sqrt(6.0));
    sun.ls = 2.0;
    sun.shadows = true;
    scene.directional_lights.push_back(sun);
    scene.materials.push_back({"red", 0.25, 0.65, {1, 0, 0}});
    scene.materials.push_back({"grey", 0.25, 0.65, {0.5, 0.5, 0.5}});
    scene.objects.push_back({octray::Sphere{{0, 0, 0}, 1.0}, 0});
    scene.objects.push_back({octray::Sphere{{1.5, 0.2, -1}, 0.7}, 0});
    scene.objects.push_back({octray::Plane{{0, -1, 0}, {0, 1, 0}}, 1});
    scene.objects.push_back({octray::Box{{-2.5, -1, -0.5}, {-1.5, 0, 0.5}}, 1});
    return scene;
}

// Engine rays: a fan from (0, 1, 6) toward a 64 x 64 grid on the plane z = 0.
constexpr int kRays = 64 * 64;
constexpr int kPackets = kRays / octray::kPacketWidth;

void fill_packet(octray::RayPacket8& rays, int packet) {
    for (int i = 0; i < octray::kPacketWidth; ++i) {
        const int r = packet * octray::kPacketWidth + i;
        const float x = -3.0f + 6.0f * float(r % 64) / 63.0f, y = -2.0f + 4.0f * float(r / 64) / 63.0f;
        rays.ox[i] = 0, rays.oy[i] = 1, rays.oz[i] = 6;
        rays.dx[i] = x, rays.dy[i] = y - 1, rays.dz[i] = -6;
        rays.tmin[i] = 0, rays.tmax[i] = std::numeric_limits<float>::infinity();
        rays.active[i] = 1;
    }
}

// >>> docs/API.md quotes from here: worker
// One engine thread: its own packets on the stack, the shared scene and
// kernel by const reference, results into its own slice [first, last).
void trace_packets(const octray::PacketScene& scene, const octray::Kernel& k, int first, int last,
                   std::vector<float>& out_rgb, std::vector<int>& out_primitive) {
    octray::RayPacket8 rays;
    octray::HitPacket8 hits;
    octray::ColorPacket8 radiance;
    for (int p = first; p < last; ++p) {
        fill_packet(rays, p);
        k.intersect(scene, rays, hits);
        k.shade(scene, rays, hits, radiance);
        for (int i = 0; i < octray::kPacketWidth; ++i) {
            const std::size_t r = std::size_t(p) * octray::kPacketWidth + std::size_t(i);
            out_rgb[3 * r + 0] = radiance.r[i], out_rgb[3 * r + 1] = radiance.g[i], out_rgb[3 * r + 2] = radiance.b[i];
            out_primitive[r] = hits.primitive[i];
        }
    }
}
// <<< docs/API.md quotes up to here: worker

}  // namespace

int main() {
    int failures = 0;
    const octray::PacketScene scene = octray::compile(make_scene());
    const octray::Kernel k = octray::select_kernel(scene, octray::Path::simd);
    std::printf("kernel: %s\n", k.name().c_str());

    std::vector<float> rgb1(3 * kRays), rgbN(3 * kRays);
    std::vector<int> prim1(kRays), primN(kRays);
    trace_packets(scene, k, 0, kPackets, rgb1, prim1);

    // >>> docs/API.md quotes from here: threads
    constexpr int kThreads = 4;
    std::vector<std::thread> pool;
    for (int t = 0; t < kThreads; ++t) {
        const int first = kPackets * t / kThreads, last = kPackets * (t + 1) / kThreads;
        pool.emplace_back(trace_packets, std::cref(scene), std::cref(k), first, last, std::ref(rgbN), std::ref(primN));
    }
    for (std::thread& th : pool) th.join();
    // <<< docs/API.md quotes up to here: threads

    int hits = 0, finite = 0;
    for (int r = 0; r < kRays; ++r) hits += prim1[std::size_t(r)] >= 0;
    for (float c : rgb1) finite += std::isfinite(c);
    std::printf("engine rays: %d, hits: %d\n", kRays, hits);
    if (std::memcmp(rgb1.data(), rgbN.data(), rgb1.size() * sizeof(float)) != 0 || prim1 != primN) {
        std::printf("FAIL: 4 threads differ from 1 thread\n");
        ++failures;
    }
    if (hits < kRays / 4 || hits == kRays || finite != 3 * kRays) {
        std::printf("FAIL: expected a mix of hits and misses and finite radiance (hits %d, finite %d)\n", hits, finite);
        ++failures;
    }

    // The library's own tile loop, rows split across threads.
    const int w = scene.width(), h = scene.height();
    octray::Image<float> hdr1(w, h), hdrN(w, h);
    octray::RenderCounters c1;
    octray::render_rows(k, scene, 0, h, hdr1, nullptr, &c1);
    // >>> docs/API.md quotes from here: render_rows
    std::vector<octray::RenderCounters> counters(kThreads);  // one per thread: no shared writes
    std::vector<std::thread> rows;
    for (int t = 0; t < kThreads; ++t)
        rows.emplace_back([&, t] {
            octray::render_rows(k, scene, h * t / kThreads, h * (t + 1) / kThreads, hdrN, nullptr, &counters[t]);
        });
    for (std::thread& th : rows) th.join();
    // <<< docs/API.md quotes up to here: render_rows
    std::uint64_t rays = 0;
    for (const octray::RenderCounters& c : counters) rays += c.rays;
    std::printf("camera rays: %llu (1 thread) / %llu (4 threads)\n", (unsigned long long)c1.rays,
                (unsigned long long)rays);
    if (hdr1.rgb != hdrN.rgb || c1.rays != std::uint64_t(w) * std::uint64_t(h) || rays != c1.rays) {
        std::printf("FAIL: render_rows in 4 threads differs from 1 thread\n");
        ++failures;
    }

    if (failures != 0) return 1;
    std::printf("all checks passed\n");
    return 0;
}
