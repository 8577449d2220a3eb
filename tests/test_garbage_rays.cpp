// Garbage rays at volume (docs/reliability.md): random bit patterns through intersect,
// occluded, shade and tonemap of every ISA unit this CPU runs, in every
// precision mode the unit compiles. No NaN in any output, and the masked-lane
// count exactly the one kernel_checks.hpp computes independently.
//
// The default suite (and the sanitizer builds) push 10^5 rays per unit and
// mode; the CTest test garbage_rays.volume (label `volume`, run by tools/check
// in the sanitizer-free build only) sets OCTRAY_GARBAGE_RAYS=10000000.
#include <doctest/doctest.h>

#include "kernel_checks.hpp"
#include "support.hpp"

#include <octray/kernels.hpp>
#include <octray/packet_scene.hpp>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

using namespace octray;
using namespace octray::test;

namespace {

std::uint64_t rays_per_kernel() {
    const char* env = std::getenv("OCTRAY_GARBAGE_RAYS");
    return env != nullptr && *env != '\0' ? std::strtoull(env, nullptr, 10) : 100'000;
}

// Every feature (all six primitive types, ambient, directional, point and
// attenuated point lights, shadows), under each tone map, with and without gamma.
std::vector<Scene> garbage_scenes() {
    std::mt19937 rng(19);
    std::vector<Scene> scenes;
    const std::pair<ToneMap, double> renders[] = {
        {ToneMap::max_to_one, 2.2}, {ToneMap::clamp_to_color, 1.0}, {ToneMap::saturate, 0.45}};
    for (const auto& [tonemap, gamma] : renders) {
        Scene s = scene_with_features(kAllFeatures, rng);
        s.render.tonemap = tonemap;
        s.render.gamma = gamma;
        scenes.push_back(s);
    }
    return scenes;
}

}  // namespace

TEST_CASE("garbage rays: every unit and precision mode masks exactly the invalid lanes and emits no NaN") {
    const std::uint64_t packets = (rays_per_kernel() + kPacketWidth - 1) / kPacketWidth;
    const std::vector<Scene> scenes = garbage_scenes();
    std::vector<PacketScene> compiled;
    std::vector<SceneFacts> facts;
    for (const Scene& s : scenes) compiled.push_back(compile(s)), facts.push_back(scene_facts(s));
    REQUIRE(compiled.front().features().bits == kAllFeatures);

    const std::vector<Kernel> kernels = every_kernel();
    // Every unit the CPU runs, every mode it compiles: at least the generic unit's four.
    CHECK(kernels.size() >= 4);
    for (std::size_t i = 0; i < kernels.size(); ++i) {
        const Kernel& k = kernels[i];
        CAPTURE(k.name());
        GarbageRays garbage(0x19u + i);
        StageCounts counts;
        std::string failure;
        std::uint64_t failures = 0;
        RayPacket8 rays;
        ColorPacket8 colours;
        for (std::uint64_t n = 0; n < packets; ++n) {
            const std::size_t s = std::size_t(n % compiled.size());
            garbage.fill(rays);
            garbage.fill(colours);
            const std::string e = run_and_check(k, compiled[s], facts[s], rays, colours, &counts);
            if (!e.empty() && failures++ == 0) failure = "packet " + std::to_string(n) + ", " + e;
        }
        MESSAGE(k.name() << ": " << counts.lanes << " rays, " << counts.active << " active, " << counts.masked
                         << " masked, " << counts.hits << " hits, " << counts.occluded << " occluded");
        CHECK_MESSAGE(failures == 0, failures << " failing packets; the first: " << failure);
        // The rays exercise every branch: masked lanes, hits, shadow tests.
        CHECK(counts.masked > counts.lanes / 8);
        CHECK(counts.hits > counts.lanes / 20);
        CHECK(counts.occluded > counts.lanes / 20);
    }
}

TEST_CASE("expected_mask decides d.d at the limits as the kernel does") {
    // |d|^2 = 2^-126 exactly: usable; one ulp below in every component: not.
    RayPacket8 r{};
    for (int i = 0; i < kPacketWidth; ++i) r.tmax[i] = 1, r.active[i] = 1;
    r.dx[0] = 0x1p-63f;                                  // d.d = 2^-126: valid
    r.dx[1] = std::nextafter(0x1p-63f, 0.0f);            // d.d < 2^-126: masked
    r.dx[2] = 0x1p63f;                                   // d.d = 2^126: masked
    r.dx[3] = std::nextafter(0x1p63f, 0.0f);             // just below: valid
    r.dx[4] = 1, r.tmin[4] = 1;                          // tmin == tmax: masked
    r.dx[5] = 1, r.active[5] = 0;                        // inactive: neither
    r.dx[6] = 1, r.oy[6] = INFINITY;                     // infinite origin: masked
    r.dx[7] = 1, r.tmax[7] = NAN;                        // NaN interval: masked
    const LaneMask m = expected_mask(r, Precision::exact);
    const bool valid[8] = {true, false, false, true, false, false, false, false};
    for (int i = 0; i < kPacketWidth; ++i) CHECK(m.valid[i] == valid[i]);
    CHECK(m.masked == 5);
    // The kernels agree, every unit and mode.
    std::mt19937 rng(1);
    const PacketScene ps = compile(scene_with_features(kSphere, rng));
    for (const Kernel& k : every_kernel()) {
        CAPTURE(k.name());
        const LaneMask km = expected_mask(r, k.precision);
        HitPacket8 h;
        CHECK(k.intersect(ps, r, h) == km.masked);
        for (int i = 0; i < kPacketWidth; ++i) CHECK(h.invalid[i] == (km.invalid[i] ? -1 : 0));
    }
}

TEST_CASE("a hit beyond the largest float is a miss in every mode, f64 included (found by the garbage-ray test)") {
    // A ray from the origin along x, dropping 2^-130 per unit: it meets the
    // plane y = -1 at t = 2^130 > FLT_MAX. The float modes overflow t to
    // +inf and miss; the f64 mode computed t in double and reported a hit
    // at t = +inf (and, with tmin = -inf, one at t = -inf going backwards).
    Scene s;
    s.materials.push_back(Material{"m", 0.25, 0.65, {1, 1, 1}});
    s.objects.push_back(Object{Plane{{0, -1, 0}, {0, 1, 0}}, 0});
    s.directional_lights.push_back({{0, 1, 0}, {1, 1, 1}, 1, false});
    const PacketScene ps = compile(s);
    RayPacket8 r{};
    for (int i = 0; i < kPacketWidth; ++i) {
        r.dx[i] = 1, r.dy[i] = -0x1p-130f, r.tmax[i] = INFINITY, r.active[i] = 1;
        r.oy[i] = float(i);  // lane i meets the plane at t = (i + 1) 2^130
    }
    r.dy[6] = 0x1p-130f, r.tmin[6] = -INFINITY;  // backwards: t = -7 2^130
    r.dy[7] = -1;  // one lane hits at t = 8: the packet is not all misses
    for (const Kernel& k : every_kernel(ps.features().bits)) {
        CAPTURE(k.name());
        HitPacket8 h;
        CHECK(k.intersect(ps, r, h) == 0);
        for (int i = 0; i < 7; ++i) CHECK(h.hit[i] == 0);
        CHECK(h.hit[7] == -1);
        CHECK(h.t[7] == doctest::Approx(8).epsilon(1e-3));  // the estimate modes' t is approximate
    }
}

TEST_CASE("a scene without objects traces to misses and background (found by the kernel fuzz target's seeds)") {
    // compile() left the id arrays empty, and intersect looks them up for
    // every lane before selecting -1 for the misses: the SIMD path read
    // through a null pointer (`octray render` crashed on "objects": []).
    for (const bool with_material : {false, true}) {
        CAPTURE(with_material);
        Scene s;
        if (with_material) s.materials.push_back(Material{"m", 0.25, 0.65, {1, 1, 1}});
        s.background = {0.25, 0.5, 0.75};
        s.ambient = AmbientLight{{1, 1, 1}, 0.5};
        s.point_lights.push_back({{0, 2, 0}, {1, 1, 1}, 1, Attenuation::inverse_square, true});
        const PacketScene ps = compile(s);
        const SceneFacts facts = scene_facts(s);
        GarbageRays garbage(7);
        for (const Kernel& k : every_kernel(ps.features().bits)) {
            CAPTURE(k.name());
            for (int n = 0; n < 16; ++n) {
                RayPacket8 rays;
                ColorPacket8 colours;
                if (n == 0) k.camera(ps, 0, 0, rays);
                else garbage.fill(rays);
                garbage.fill(colours);
                CHECK(run_and_check(k, ps, facts, rays, colours) == "");
            }
        }
    }
}

TEST_CASE("shadow rays from a hit point that overflows float (found by the garbage-ray test)") {
    // With tmin = -inf the ray meets the plane y = -1 behind its origin, at
    // t = -2^70, a finite t, but the hit point's x = 2^62 * -2^70 overflows
    // to -inf. The shadow ray's offset max(|p| 1e-4, (|p| + t |d|) ...) is
    // max(inf, NaN) = NaN, so its origin is NaN: every slab term of the BVH
    // walk is NaN and dropped, every child "entered", and the single-ray
    // walk pushed the unused slots' kEmptySlot too: leaf number INT32_MAX,
    // a crash (the packet walk skips unused slots).
    Scene s;
    s.materials.push_back(Material{"m", 0.25, 0.65, {1, 1, 1}});
    s.objects.push_back(Object{Plane{{0, -1, 0}, {0, 1, 0}}, 0});
    s.objects.push_back(Object{Sphere{{0, 0, 0}, 1}, 0});
    s.objects.push_back(Object{Box{{2, -1, -1}, {3, 0, 1}}, 0});
    s.directional_lights.push_back({{0.6, -0.8, 0}, {1, 1, 1}, 1, true});  // lights the plane's underside
    const PacketScene ps = compile(s);
    const SceneFacts facts = scene_facts(s);
    RayPacket8 r{};
    for (int i = 0; i < kPacketWidth; ++i) {
        r.oz[i] = float(i), r.dx[i] = 0x1p62f, r.dy[i] = 0x1p-70f, r.tmin[i] = -INFINITY, r.tmax[i] = INFINITY;
        r.active[i] = i < 2 ? 1 : 0;  // two lanes: the packet walk hands them to the single-ray walk
    }
    ColorPacket8 colours{};
    for (const Kernel& k : every_kernel(ps.features().bits)) {
        CAPTURE(k.name());
        CHECK(run_and_check(k, ps, facts, r, colours) == "");
    }
}

TEST_CASE("tone map with a gamma near 0 (found by fuzz/kernels_fuzz.cpp)") {
    // 1/gamma = 1e300 rounds to +inf in float: the f64 mode's xsimd pow
    // converted y log c = -inf to an integer (undefined behaviour; UBSan in
    // the sanitizer builds). (The fuzzer's clamp colour of 1e300 is no longer
    // a valid scene: validate() keeps clamp colours in [0, 1].)
    for (const ToneMap tonemap : {ToneMap::max_to_one, ToneMap::clamp_to_color, ToneMap::saturate}) {
        Scene s;
        s.render.tonemap = tonemap;
        s.render.gamma = 1e-300;
        s.render.clamp_color = {1, 0.5, 0.25};
        const PacketScene ps = compile(s);
        const SceneFacts facts = scene_facts(s);
        ColorPacket8 in{}, out;
        const float values[kPacketWidth] = {0, 0x1p-149f, 0.25f, 0.5f, 1, 2, 1e30f, INFINITY};
        for (int i = 0; i < kPacketWidth; ++i) in.r[i] = values[i], in.g[i] = 0.5f, in.b[i] = NAN;
        for (const Kernel& k : every_kernel()) {
            CAPTURE(k.name());
            k.tonemap(ps, in, out);
            CHECK(check_tonemap(facts, out) == "");
            // c^(1/gamma) for c = 0.5 is 0; NaN radiance is 0.
            for (int i = 0; i < 4; ++i) CHECK(out.b[i] == 0);
            if (tonemap == ToneMap::saturate) CHECK(out.g[0] == 0);
        }
    }
}

TEST_CASE("the tone map over a group of packets is each packet's own tone map, bit for bit") {
    // Kernel::tonemap_group runs packets two at a time in lockstep; 5 packets
    // (two pairs and one alone) of special and ordinary radiance, every tone
    // map and gamma, every kernel.
    constexpr int kCount = 5;
    const float special[] = {NAN, -NAN, INFINITY, -INFINITY, 3e38f, 0x1p-149f, 0, -1, 0.2f, 0.5f, 1, 2, 8, 1e30f};
    constexpr int kSpecial = int(sizeof special / sizeof special[0]);
    ColorPacket8 in[kCount];
    for (int p = 0; p < kCount; ++p)
        for (int i = 0; i < kPacketWidth; ++i) {
            const int j = p * kPacketWidth + i;
            in[p].r[i] = special[j % kSpecial], in[p].g[i] = special[(j * 5 + 3) % kSpecial];
            in[p].b[i] = special[(j * 11 + 7) % kSpecial];
        }
    for (const ToneMap tonemap : {ToneMap::max_to_one, ToneMap::clamp_to_color, ToneMap::saturate}) {
        for (const double gamma : {1.0, 2.2}) {
            Scene s;
            s.render.tonemap = tonemap;
            s.render.gamma = gamma;
            s.render.clamp_color = {1, 0.5, 0.25};
            const PacketScene ps = compile(s);
            for (const Kernel& k : every_kernel()) {
                CAPTURE(k.name());
                CAPTURE(gamma);
                REQUIRE(static_cast<bool>(k.tonemap_group));
                ColorPacket8 group[kCount], one;
                k.tonemap_group(ps, in, group, kCount);
                int differing = 0;
                for (int p = 0; p < kCount; ++p) {
                    k.tonemap(ps, in[p], one);
                    differing += std::memcmp(&one, &group[p], sizeof one) != 0;
                }
                CHECK(differing == 0);
            }
        }
    }
}

TEST_CASE("sphere normal for the shortest directions load_ray accepts (found by fuzz/kernels_fuzz.cpp)") {
    // d = (0, 2^-63, 0): d.d = 2^-126, and h^2 / (d.d) for a sphere of radius 5
    // overflowed float, so the normal came out (NaN, inf, NaN) at t ~ 2^65.
    Scene s;
    s.materials = {{"m", 0.25, 0.65, {1, 1, 1}}};
    s.objects = {{Sphere{{0.75, 1.5, -3}, 5}, 0}};
    const PacketScene ps = compile(s);
    const SceneFacts facts = scene_facts(s);
    RayPacket8 rays{};
    const float scales[kPacketWidth] = {0x1p-63f, 0x1p-62f, 0x1p-40f, 0x1p-20f, 1, 0x1p20f, 0x1p40f, 0x1p62f};
    for (int i = 0; i < kPacketWidth; ++i)
        rays.ox[i] = 0x1p-149f, rays.dy[i] = scales[i], rays.tmax[i] = INFINITY, rays.active[i] = -1;
    for (const Kernel& k : every_kernel()) {
        CAPTURE(k.name());
        HitPacket8 hits;
        CHECK(k.intersect(ps, rays, hits) == 0);
        CHECK(check_intersect(facts, rays, hits, 0, k.precision) == "");
        // The same line at every scale: the same point, so the same normal.
        for (int i = 0; i < kPacketWidth; ++i) {
            CAPTURE(i);
            REQUIRE(hits.primitive[i] == 0);
            CHECK(hits.nx[i] == doctest::Approx(hits.nx[4]).epsilon(1e-5));
            CHECK(hits.ny[i] == doctest::Approx(hits.ny[4]).epsilon(1e-5));
            CHECK(hits.nz[i] == doctest::Approx(hits.nz[4]).epsilon(1e-5));
        }
    }
}
