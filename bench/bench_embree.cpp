// bench/bench_embree.cpp — the peer: Intel Embree 3 against octray's
// intersect kernel on the same scenes and exactly the same rays.
//
// Scenes: N spheres (N = 1, 4, 16, 64, 256) on the grid of bench_common, and
// the same spheres over a floor plane (N = 1, 16, 64). Rays: octray's pinhole
// camera, 256 x 256 = 65536 rays (8192 packets), all active, every ray below
// the horizon. The same RayPacket8s feed octray; Embree gets the same floats
// copied once into RTCRayHit8 / RTCRayHit arrays.
//
// Rules, identical for both: one thread (Embree device "threads=1"), FTZ/DAZ
// on (bench_common run_main), closest hit only, the hit primitive is the
// answer. Per call Embree needs tfar and geomID reset (two stores per ray);
// that is in its timed loop, as an application would have to do it.
//
// Embree variants (names peer/SCENE/VARIANT):
//   embree8_native  rtcIntersect8, spheres as RTC_GEOMETRY_TYPE_SPHERE_POINT
//   embree8_user    rtcIntersect8, spheres as user geometry (the callback below:
//                   8 lanes with AVX2+FMA when Embree hands it a packet,
//                   one lane otherwise; same stable quadratic as octray)
//   embree1_native, embree1_user    the same with rtcIntersect1, ray by ray
//   embree8_{native,user}_isa_avx2  device "threads=1,isa=avx2": Embree held
//                   to octray's instruction set (its default here may be AVX-512)
// The floor plane is one RTC_GEOMETRY_TYPE_QUAD, large enough to hold every
// floor hit of the ray set (octray's plane is infinite; the cross-check proves
// the quad is large enough). Build quality HIGH, context flag COHERENT: the
// settings that favour Embree on camera rays.
// octray variants: octray_simd, octray_scalar (select_kernel for the scene).
//
// Cross-check before timing counts: every variant's hit primitive per ray is
// compared with octray's SIMD kernel; a benchmark whose match is below 99.99%
// stops with SkipWithError. `octray_bench_embree --crosscheck` prints the
// whole table and exits 1 on any failure (a CTest test).
#include "bench_common.hpp"
#include "embree_spheres.hpp"

#include <embree3/rtcore.h>
#include <immintrin.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace octray::bench {
namespace {

constexpr int kPeerImage = 256;
constexpr double kRequiredMatch = 0.9999;
constexpr float kInf = std::numeric_limits<float>::infinity();

// ---- Embree devices --------------------------------------------------------------
void on_embree_error(void* user, RTCError code, const char* message) {
    std::fprintf(stderr, "embree (%s): error %d: %s\n", static_cast<const char*>(user), int(code), message ? message : "");
}

RTCDevice device(bool isa_avx2) {
    static std::map<bool, RTCDevice> devices;
    auto it = devices.find(isa_avx2);
    if (it != devices.end()) return it->second;
    const char* config = isa_avx2 ? "threads=1,isa=avx2" : "threads=1";
    RTCDevice d = rtcNewDevice(config);
    if (d) rtcSetDeviceErrorFunction(d, on_embree_error, const_cast<char*>(config));
    devices[isa_avx2] = d;
    return d;
}

std::string embree_isa_guess(RTCDevice d) {
    if (!d) return "unavailable";
    if (rtcGetDeviceProperty(d, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED)) return "avx512 (native ray16)";
    if (rtcGetDeviceProperty(d, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED)) return "avx/avx2 (native ray8)";
    return "sse (native ray4)";
}

// ---- scenes ------------------------------------------------------------------
enum class Variant { octray_simd, octray_scalar, embree8_native, embree8_user, embree1_native, embree1_user,
                     embree8_native_avx2, embree8_user_avx2 };
constexpr const char* kVariantNames[] = {"octray_simd",    "octray_scalar", "embree8_native", "embree8_user",
                                         "embree1_native", "embree1_user",  "embree8_native_isa_avx2",
                                         "embree8_user_isa_avx2"};
bool is_embree(Variant v) { return v != Variant::octray_simd && v != Variant::octray_scalar; }
bool is_user(Variant v) { return v == Variant::embree8_user || v == Variant::embree1_user || v == Variant::embree8_user_avx2; }
bool is_avx2(Variant v) { return v == Variant::embree8_native_avx2 || v == Variant::embree8_user_avx2; }
bool is_packet(Variant v) { return v != Variant::embree1_native && v != Variant::embree1_user; }

struct Peer {
    std::string name;
    int n = 0;
    bool floor = false;
    PacketScene scene;
    RaySet rays;
    std::vector<int> reference;  // octray SIMD hit primitive per ray (-1: miss)
    float quad_half = 0;         // half side of Embree's floor quad
    UserSpheres spheres;
    AlignedVec<RTCRayHit8> rays8;  // pristine Embree copies of the ray set
    std::vector<RTCRayHit> rays1;
    AlignedVec<std::array<int, 8>> valid8;
    std::map<int, RTCScene> embree;           // by (user, avx2) key
    std::map<int, std::pair<double, std::int64_t>> crosscheck;  // by variant: match, mismatches
};

Peer& peer(bool floor, int n) {
    static std::map<std::pair<bool, int>, std::unique_ptr<Peer>> cache;
    auto& slot = cache[{floor, n}];
    if (slot) return *slot;
    slot = std::make_unique<Peer>();
    Peer& p = *slot;
    p.n = n;
    p.floor = floor;
    p.name = std::string(floor ? "spheres+plane:" : "spheres:") + std::to_string(n);
    p.scene = compile(grid_scene(Layout::sphere, n, floor, kPeerImage, kPeerImage));
    p.rays = camera_rays(p.scene);
    const AlignedVec<HitPacket8> hits = trace(select_kernel(p.scene, Path::simd), p.scene, p.rays);
    double far = 10;
    for (std::size_t k = 0; k < hits.size(); ++k)
        for (int i = 0; i < kPacketWidth; ++i) {
            p.reference.push_back(hits[k].hit[i] ? hits[k].primitive[i] : -1);
            if (hits[k].hit[i] && hits[k].primitive[i] == n) {  // a floor hit
                const RayPacket8& r = p.rays.packets[k];
                const float t = hits[k].t[i];
                far = std::max({far, std::fabs(double(r.ox[i] + r.dx[i] * t)), std::fabs(double(r.oz[i] + r.dz[i] * t))});
            }
        }
    p.quad_half = float(2 * far);
    const Scene authored = grid_scene(Layout::sphere, n, floor, kPeerImage, kPeerImage);
    for (int k = 0; k < n; ++k) {
        const Sphere& s = std::get<Sphere>(authored.objects[std::size_t(k)].shape);
        p.spheres.xyzr.insert(p.spheres.xyzr.end(), {float(s.center.x), float(s.center.y), float(s.center.z), float(s.radius)});
    }
    // Embree copies of the rays.
    p.rays8.resize(p.rays.packets.size());
    p.valid8.resize(p.rays.packets.size());
    for (std::size_t k = 0; k < p.rays.packets.size(); ++k) {
        to_embree(p.rays.packets[k], k, p.rays8[k], p.valid8[k], p.rays1);
    }
    return p;
}

// Embree scene for a peer: geometry 0 = spheres, geometry 1 = the floor quad.
RTCScene embree_scene(Peer& p, bool user, bool avx2) {
    const int key = int(user) * 2 + int(avx2);
    if (auto it = p.embree.find(key); it != p.embree.end()) return it->second;
    RTCScene scene = sphere_scene(device(avx2), p.spheres, user, user_intersect, nullptr, -1.25f, p.floor ? p.quad_half : 0.0f);
    p.embree[key] = scene;
    return scene;
}

RTCIntersectContext coherent_context() { return intersect_context(RTC_INTERSECT_CONTEXT_FLAG_COHERENT); }

// One pass of Embree over the whole ray set, working copies in place.
void embree_pass8(RTCScene scene, AlignedVec<RTCRayHit8>& rh, const AlignedVec<std::array<int, 8>>& valid) {
    RTCIntersectContext ctx = coherent_context();
    const std::size_t n = rh.size();
    for (std::size_t k = 0; k < n; ++k) {
        RTCRayHit8& r = rh[k];
        for (int i = 0; i < 8; ++i) r.ray.tfar[i] = kInf, r.hit.geomID[i] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect8(valid[k].data(), scene, &ctx, &r);
    }
}
void embree_pass1(RTCScene scene, std::vector<RTCRayHit>& rh) {
    RTCIntersectContext ctx = coherent_context();
    for (RTCRayHit& r : rh) {
        r.ray.tfar = kInf, r.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &ctx, &r);
    }
}

int object_of(const Peer& p, unsigned geom, unsigned prim) {
    if (geom == 0) return int(prim);
    if (geom == 1) return p.n;  // the floor is the last object
    return -1;
}

// Per-ray hit primitive of a variant (untimed).
std::vector<int> answers(Peer& p, Variant v) {
    std::vector<int> out;
    if (!is_embree(v)) {
        const Kernel k = select_kernel(p.scene, v == Variant::octray_simd ? Path::simd : Path::scalar);
        for (const HitPacket8& h : trace(k, p.scene, p.rays))
            for (int i = 0; i < kPacketWidth; ++i) out.push_back(h.hit[i] ? h.primitive[i] : -1);
        return out;
    }
    RTCScene scene = embree_scene(p, is_user(v), is_avx2(v));
    if (!scene) return out;
    if (is_packet(v)) {
        AlignedVec<RTCRayHit8> rh = p.rays8;
        embree_pass8(scene, rh, p.valid8);
        for (const RTCRayHit8& r : rh)
            for (int i = 0; i < 8; ++i) out.push_back(object_of(p, r.hit.geomID[i], r.hit.primID[i]));
    } else {
        std::vector<RTCRayHit> rh = p.rays1;
        embree_pass1(scene, rh);
        for (const RTCRayHit& r : rh) out.push_back(object_of(p, r.hit.geomID, r.hit.primID));
    }
    return out;
}

// Fraction of rays on which `v` hits the same primitive as octray's SIMD kernel.
std::pair<double, std::int64_t> crosscheck(Peer& p, Variant v) {
    if (auto it = p.crosscheck.find(int(v)); it != p.crosscheck.end()) return it->second;
    const std::vector<int> got = answers(p, v);
    std::int64_t same = 0;
    if (got.size() == p.reference.size())
        for (std::size_t i = 0; i < got.size(); ++i) same += got[i] == p.reference[i];
    const std::int64_t total = std::int64_t(p.reference.size());
    const auto result = std::make_pair(total ? double(same) / double(total) : 0.0, total - same);
    p.crosscheck[int(v)] = result;
    return result;
}

// ---- the benchmark -------------------------------------------------------------
void bm_peer(benchmark::State& st, bool floor, int n, Variant v) {
    Peer& p = peer(floor, n);
    if (is_embree(v) && !embree_scene(p, is_user(v), is_avx2(v))) {
        st.SkipWithError("Embree device or scene could not be created");
        return;
    }
    const auto [match, mismatches] = crosscheck(p, v);
    st.counters["xcheck_match"] = match;
    st.counters["xcheck_mismatch"] = double(mismatches);
    if (match < kRequiredMatch) {
        const std::string msg = "cross-check failed: same primitive on " + std::to_string(100 * match) + "% of rays (< 99.99%)";
        st.SkipWithError(msg.c_str());
        return;
    }
    if (!is_embree(v)) {
        time_intersect(st, select_kernel(p.scene, v == Variant::octray_simd ? Path::simd : Path::scalar), p.scene, p.rays);
        return;
    }
    if (is_packet(v)) {
        RTCScene scene = embree_scene(p, is_user(v), is_avx2(v));
        AlignedVec<RTCRayHit8> rh = p.rays8;
        for (auto _ : st) {
            embree_pass8(scene, rh, p.valid8);
            benchmark::ClobberMemory();
        }
        st.SetLabel(std::string("embree ") + RTC_VERSION_STRING + " rtcIntersect8 " + (is_avx2(v) ? "isa=avx2" : embree_isa_guess(device(false))));
    } else {
        RTCScene scene = embree_scene(p, is_user(v), false);
        std::vector<RTCRayHit> rh = p.rays1;
        for (auto _ : st) {
            embree_pass1(scene, rh);
            benchmark::ClobberMemory();
        }
        st.SetLabel(std::string("embree ") + RTC_VERSION_STRING + " rtcIntersect1 " + embree_isa_guess(device(false)));
    }
    // Embree's FLOPs are not ours to count: no GFLOPS for its rows.
    set_ray_counters(st, p.rays.rays(), 0);
    for (const char* c : {"GFLOPS", "frac_peak", "flops_per_ray"}) st.counters.erase(c);
}

struct PeerCase { bool floor; int n; };
constexpr PeerCase kCases[] = {{false, 1}, {false, 4}, {false, 16}, {false, 64}, {false, 256},
                               {true, 1},  {true, 16}, {true, 64}};
constexpr Variant kVariants[] = {Variant::octray_simd,    Variant::octray_scalar, Variant::embree8_native,
                                 Variant::embree8_user,   Variant::embree1_native, Variant::embree1_user,
                                 Variant::embree8_native_avx2, Variant::embree8_user_avx2};

void register_all() {
    for (const PeerCase& c : kCases)
        for (Variant v : kVariants) {
            const std::string name = std::string("peer/") + (c.floor ? "spheres+plane:" : "spheres:") + std::to_string(c.n) + "/" +
                                     kVariantNames[int(v)];
            benchmark::RegisterBenchmark(name.c_str(), [c, v](benchmark::State& st) { bm_peer(st, c.floor, c.n, v); });
        }
    benchmark::AddCustomContext("embree_version", RTC_VERSION_STRING);
    benchmark::AddCustomContext("embree_default_isa", embree_isa_guess(device(false)));
}

int run_crosscheck() {
    int failures = 0;
    std::printf("%-18s %-24s %10s %10s %s\n", "scene", "variant", "match %", "mismatch", "verdict");
    for (const PeerCase& c : kCases)
        for (Variant v : kVariants) {
            if (v == Variant::octray_simd) continue;
            Peer& p = peer(c.floor, c.n);
            if (is_embree(v) && !embree_scene(p, is_user(v), is_avx2(v))) {
                std::printf("%-18s %-24s %10s %10s FAIL (no Embree scene)\n", p.name.c_str(), kVariantNames[int(v)], "-", "-");
                ++failures;
                continue;
            }
            const auto [match, mismatches] = crosscheck(p, v);
            const bool ok = match >= kRequiredMatch;
            failures += !ok;
            std::printf("%-18s %-24s %10.4f %10lld %s\n", p.name.c_str(), kVariantNames[int(v)], 100 * match,
                        static_cast<long long>(mismatches), ok ? "ok" : "FAIL");
        }
    // Control: the check must have teeth. Embree's native spheres with radii
    // 2% too large must fail it.
    {
        Peer& p = peer(false, 16);
        Peer wrong;
        wrong.n = p.n;
        wrong.spheres = p.spheres;
        for (std::size_t k = 3; k < wrong.spheres.xyzr.size(); k += 4) wrong.spheres.xyzr[k] *= 1.02f;
        RTCScene scene = embree_scene(wrong, false, false);
        std::int64_t same = 0;
        if (scene) {
            AlignedVec<RTCRayHit8> rh = p.rays8;
            embree_pass8(scene, rh, p.valid8);
            for (std::size_t k = 0; k < rh.size(); ++k)
                for (int i = 0; i < 8; ++i) same += object_of(p, rh[k].hit.geomID[i], rh[k].hit.primID[i]) == p.reference[k * 8 + std::size_t(i)];
            rtcReleaseScene(scene);
        }
        const double match = double(same) / double(p.reference.size());
        const bool ok = scene && match < kRequiredMatch;
        failures += !ok;
        std::printf("%-18s %-24s %10.4f %10lld %s\n", "control", "radii+2% (must fail)", 100 * match,
                    static_cast<long long>(std::int64_t(p.reference.size()) - same), ok ? "ok (rejected)" : "FAIL (accepted)");
    }
    std::printf("%s: every variant must hit the same primitive as octray simd on >= 99.99%% of %d rays\n",
                failures ? "FAILED" : "passed", kPeerImage * kPeerImage);
    return failures ? 1 : 0;
}

}  // namespace
}  // namespace octray::bench

int main(int argc, char** argv) {
    for (int i = 1; i < argc; ++i)
        if (std::strcmp(argv[i], "--crosscheck") == 0) {
            octray::bench::set_ftz_daz();
            return octray::bench::run_crosscheck();
        }
    return octray::bench::run_main(argc, argv, octray::bench::register_all);
}
