// The thread-safety claim (kernels.hpp, packet_scene.hpp; docs/reliability.md): one
// compiled scene shared by many threads, each rendering disjoint rows or
// tracing its own packets through intersect, occluded, shade and tonemap,
// gives bit for bit what one thread gives. Plain std::thread, no OpenMP, so
// that ThreadSanitizer sees every synchronization (tools/check runs this
// binary, and only it, built with -DOCTRAY_SANITIZE=thread).
#include <doctest/doctest.h>

#include "kernel_checks.hpp"

#include <octray/kernels.hpp>
#include <octray/packet_scene.hpp>
#include <octray/render.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <thread>
#include <vector>

using namespace octray;
using namespace octray::test;

namespace {

constexpr int kThreads = 4;

// Every feature, and enough primitives (a 4 x 4 x 2 grid of spheres, boxes,
// triangles) that the culling trees have inner nodes to walk.
Scene shared_scene() {
    Scene s;
    s.camera.eye = {0.5, 3, 9};
    s.camera.width = 61;  // not a multiple of 8: partial tiles
    s.camera.height = 37;
    s.background = {0.1, 0.2, 0.3};
    s.ambient = AmbientLight{{1, 1, 1}, 0.3};
    s.directional_lights.push_back({{0.48, 0.8, 0.36}, {1, 0.9, 0.8}, 1.5, true});
    s.point_lights.push_back({{-3, 4, 3}, {1, 1, 1}, 1.2, Attenuation::none, true});
    s.point_lights.push_back({{2, 3, 3}, {1, 0.8, 0.6}, 25, Attenuation::inverse_square, true});
    s.materials = {Material{"a", 0.3, 0.6, {0.9, 0.4, 0.2}}, Material{"b", 0.2, 0.7, {0.2, 0.5, 0.9}}};
    s.render.gamma = 2.2;
    auto add = [&](Shape shape) { s.objects.push_back(Object{shape, int(s.objects.size() % 2)}); };
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            const double x = 1.4 * i - 2.1, z = 1.4 * j - 2.1;
            add(Sphere{{x, 0.4, z}, 0.35});
            add(Box{{x - 0.3, -1, z - 0.3}, {x + 0.3, -0.5, z + 0.3}});
            add(Triangle{{x - 0.4, 1.2, z}, {x + 0.4, 1.2, z}, {x, 1.8, z + 0.2}});
        }
    add(Plane{{0, -1, 0}, {0, 1, 0}});
    add(Disk{{-3, 0.5, -3}, {0.24, 0.16, 0.96}, 0.8});
    add(Rectangle{{-3.5, -1, -4}, {7, 0, 0}, {0, 3, 0.3}});
    return s;
}

// Runs body(t) in kThreads threads at once and joins them.
void in_threads(const std::function<void(int)>& body) {
    std::vector<std::thread> pool;
    for (int t = 0; t < kThreads; ++t) pool.emplace_back(body, t);
    for (std::thread& th : pool) th.join();
}

// What one packet's trip through the four stages leaves, compared as bytes.
struct Traced {
    HitPacket8 hits;
    ColorPacket8 radiance, display;
    alignas(32) std::int32_t occluded[kPacketWidth];
    int masked;
};

Traced trace(const Kernel& k, const PacketScene& ps, const RayPacket8& rays) {
    Traced r;
    r.masked = k.intersect(ps, rays, r.hits);
    k.occluded(ps, rays, r.occluded);
    k.shade(ps, rays, r.hits, r.radiance);
    k.tonemap(ps, r.radiance, r.display);
    return r;
}

template <class A>
bool same_bytes(const A& a, const A& b) { return std::memcmp(&a, &b, sizeof(A)) == 0; }

bool same(const Traced& a, const Traced& b) {
    const HitPacket8 &x = a.hits, &y = b.hits;
    return a.masked == b.masked && same_bytes(x.t, y.t) && same_bytes(x.primitive, y.primitive) &&
           same_bytes(x.material, y.material) && same_bytes(x.nx, y.nx) && same_bytes(x.ny, y.ny) &&
           same_bytes(x.nz, y.nz) && same_bytes(x.hit, y.hit) && same_bytes(x.invalid, y.invalid) &&
           same_bytes(a.occluded, b.occluded) && same_bytes(a.radiance.r, b.radiance.r) &&
           same_bytes(a.radiance.g, b.radiance.g) && same_bytes(a.radiance.b, b.radiance.b) &&
           same_bytes(a.display.r, b.display.r) && same_bytes(a.display.g, b.display.g) &&
           same_bytes(a.display.b, b.display.b);
}

}  // namespace

TEST_CASE("threads rendering disjoint rows of one shared scene give the one-thread image bit for bit") {
    const PacketScene ps = compile(shared_scene());
    const int w = ps.width(), h = ps.height();
    for (const Kernel& k : every_kernel()) {
        CAPTURE(k.name());
        Image<float> hdr1(w, h), display1(w, h), hdrN(w, h), displayN(w, h);
        std::vector<std::int32_t> ids1(std::size_t(w) * std::size_t(h)), idsN(ids1.size());
        RenderCounters c1;
        render_rows(k, ps, 0, h, hdr1, &display1, &c1, ids1.data());
        std::vector<RenderCounters> counters(kThreads);
        // Rows interleaved in bands of 3 so neighbouring threads write neighbouring rows.
        in_threads([&](int t) {
            for (int y = 3 * t; y < h; y += 3 * kThreads)
                render_rows(k, ps, y, std::min(y + 3, h), hdrN, &displayN, &counters[std::size_t(t)], idsN.data());
        });
        std::uint64_t rays = 0, masked = 0;
        for (const RenderCounters& c : counters) rays += c.rays, masked += c.masked;
        CHECK(rays == c1.rays);
        CHECK(masked == c1.masked);
        CHECK(std::memcmp(hdr1.rgb.data(), hdrN.rgb.data(), hdr1.rgb.size() * sizeof(float)) == 0);
        CHECK(std::memcmp(display1.rgb.data(), displayN.rgb.data(), display1.rgb.size() * sizeof(float)) == 0);
        CHECK(ids1 == idsN);
        int hit = 0;
        for (std::int32_t id : ids1) hit += id >= 0;
        CHECK(hit > w * h / 4);  // the image shows the scene, not only background
    }
}

TEST_CASE("render_rows gives the kernel stages' results, packet by packet, bit for bit") {
    // render_rows tone-maps a row's packets in groups after shading them;
    // widths of a partial group (61) and of two whole groups and a partial
    // packet (131) against each packet's camera, intersect, shade and tone map.
    for (const int width : {61, 131}) {
        Scene scene = shared_scene();
        scene.camera.width = width;
        const PacketScene ps = compile(scene);
        const int h = ps.height();
        for (const Kernel& k : every_kernel()) {
            CAPTURE(k.name());
            CAPTURE(width);
            Image<float> hdr(width, h), display(width, h);
            std::vector<std::int32_t> ids(std::size_t(width) * std::size_t(h));
            RenderCounters counters;
            render_rows(k, ps, 0, h, hdr, &display, &counters, ids.data());
            RayPacket8 rays;
            HitPacket8 hits;
            ColorPacket8 radiance, shown;
            std::uint64_t masked = 0;
            int differing = 0;
            for (int y = 0; y < h; ++y) {
                for (int x0 = 0; x0 < width; x0 += kPacketWidth) {
                    k.camera(ps, x0, y, rays);
                    masked += std::uint64_t(k.intersect(ps, rays, hits));
                    k.shade(ps, rays, hits, radiance);
                    k.tonemap(ps, radiance, shown);
                    for (int i = 0; i < kPacketWidth && x0 + i < width; ++i) {
                        const float* p = hdr.pixel(x0 + i, y);
                        const float* q = display.pixel(x0 + i, y);
                        const float want[6] = {radiance.r[i], radiance.g[i], radiance.b[i], shown.r[i], shown.g[i], shown.b[i]};
                        const float got[6] = {p[0], p[1], p[2], q[0], q[1], q[2]};
                        differing += std::memcmp(want, got, sizeof want) != 0 ||
                                     ids[std::size_t(y) * std::size_t(width) + std::size_t(x0 + i)] != hits.primitive[i];
                    }
                }
            }
            CHECK(differing == 0);
            CHECK(counters.rays == std::uint64_t(width) * std::uint64_t(h));
            CHECK(counters.masked == masked);
        }
    }
}

TEST_CASE("threads tracing their own packets against one shared scene get the one-thread results bit for bit") {
    const Scene scene = shared_scene();
    const PacketScene shared = compile(scene);
    constexpr int kPackets = 256;
    // Camera rays of the scene mixed with garbage rays (kernel_checks.hpp):
    // hits, misses, shadows and masked lanes.
    std::vector<RayPacket8> rays(kPackets);
    GarbageRays garbage(4);
    const Kernel camera = select_kernel(shared, Path::scalar);
    for (int p = 0; p < kPackets; ++p) {
        if (p % 2 == 0) camera.camera(shared, (8 * p) % shared.width(), (p / 2) % shared.height(), rays[std::size_t(p)]);
        else garbage.fill(rays[std::size_t(p)]);
    }
    for (const Kernel& k : every_kernel()) {
        CAPTURE(k.name());
        std::vector<Traced> one(kPackets), many(kPackets);
        for (int p = 0; p < kPackets; ++p) one[std::size_t(p)] = trace(k, shared, rays[std::size_t(p)]);
        in_threads([&](int t) {
            // Each thread its own copy of the handle (copies share the compiled
            // data) and its own kernel table; packets dealt round robin.
            const PacketScene mine = shared;
            const Kernel kt = k;
            for (int p = t; p < kPackets; p += kThreads) many[std::size_t(p)] = trace(kt, mine, rays[std::size_t(p)]);
        });
        int differ = 0, hits = 0;
        for (int p = 0; p < kPackets; ++p) {
            differ += !same(one[std::size_t(p)], many[std::size_t(p)]);
            for (int i = 0; i < kPacketWidth; ++i) hits += one[std::size_t(p)].hits.hit[i] != 0;
        }
        CHECK(differ == 0);
        CHECK(hits > kPackets);  // on average more than one hit per packet
    }
}

TEST_CASE("threads selecting kernels and compiling scenes concurrently agree") {
    const Scene scene = shared_scene();
    std::vector<int> primitives(kThreads);
    std::vector<IntersectFn> intersect(kThreads);
    in_threads([&](int t) {
        const PacketScene ps = compile(scene);
        primitives[std::size_t(t)] = ps.primitive_count();
        intersect[std::size_t(t)] = select_kernel(ps, Path::simd).intersect;
    });
    for (int t = 1; t < kThreads; ++t) {
        CHECK(primitives[std::size_t(t)] == primitives[0]);
        CHECK((intersect[std::size_t(t)] == intersect[0]));
    }
    CHECK(primitives[0] == int(scene.objects.size()));
}
