// bench/bench_common.cpp — scenes, ray sets, FLOP accounting, counters, main.
#include "bench_common.hpp"

#include "kernels/scene_data.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <immintrin.h>
#include <xmmintrin.h>
#include <pmmintrin.h>

namespace octray::bench {

// =============================================================================
// FLOPs per ray, counted by hand from the kernels' source (kernels/
// kernels/packet_kernels.hpp lists it): the robust sphere test with its early-out and
// its normal from the sphere's frame, the watertight triangle. Occlusion rays
// are not counted: the aobench benchmarks report no FLOPs.
// A kernel change that adds or removes arithmetic must update the
// counts below (kTestFlops, kNormalFlops, kIntersectSetup, the shade, tone-map
// and camera functions), or GFLOP/s and % of peak go wrong.
//
// How we count: one FLOP per lane for each add, sub, mul, div and sqrt the
// kernel source writes; two for each fma() (the peak counts an FMA as two).
// Compares, selects, min/max, abs, copysign, masks, loads, stores, gathers and
// conversions count zero (they are not arithmetic; they still take issue slots,
// which is part of why a kernel falls short of the FMA peak). The library is
// built with -ffp-contract=off, so `a * b + c` stays a mul and an add, exactly
// as written. Helpers: fdot(a, b) = fma(ax, bx, fma(ay, by, az * bz)) = 2 fma +
// 1 mul = 5 FLOPs; dot(a, b) (vec3.hpp) = 3 mul + 2 add = 5; cross = 6 mul +
// 3 sub = 9; a Vec3 add/sub/scale = 3. Exact precision: rcp = 1 div; rsqrt =
// 1 sqrt + 1 div. Values uniform over a whole packet (per-row camera terms) are
// not counted. We count what the source asks for, not what the compiler keeps
// after hoisting loop invariants: see the disassembly check below the
// sphere count.
//
// ---- intersect (intersect_packet -> intersect_lanes) --------------------------
// load_ray: dd = fdot(d, d) 5; inv_dd = 1 div; -inv_dd 1; exit_scale 1;
//           len_d = 1 sqrt                                               =  9
//   only with boxes: inv_d = 3 rcp (+3); only with triangles: the shear
//   1/d_kz 1, two ratios 2, two negations 2 (+5). Both are made only for
//   packets that get past the type's root (for_each_candidate), so counting
//   them for every ray is an upper bound.
// p = o + d * t (3 mul, 3 add)                                           =  6
// face-forward: fdot(n, d) 5; 0 - n (3 sub, computed then selected)      =  8
//                                                          per-ray setup  = 21 (+3, +5)
// hit_normal, for the lanes of the hit's type (k = cid - base: 1):
//   sphere (sphere_normal, the hit in the sphere's frame): f = o - c 3,
//     fdot(f,f) 5, r*r 1 (the huge-coordinate check) = 9; sphere_offset:
//     fh = o - c 3; fl: 0 - c and two_sum_error (5) per axis 18; b = fdot 5;
//     nb_a 1; q = fma + add per axis 9; back = fdot * 6; q again 3 fma 6;
//     r2 1, r2_lo fma and sub 3; h2 = r2 - fdot(q,q) + r2_lo 7; s2 = fdot 5;
//     the cancels test 2; h_t = sqrt(h2 * inv_dd) 2; along 1; p - c 3 fma 6
//     = 75; 1/r 1; * 1/r 3; + 1 = 89 (the compensated branch for origins
//     near the surface and the huge-coordinate recompute are not counted);
//   box: (lo+hi)*0.5 6, (hi-lo)*0.5 6,
//   p - c 3, |q|/h 3 div, + 1 = 19; plane, disk, rectangle, triangle: 1.
//   We add the dearest normal among the types present (an upper bound).
// Per primitive tested (closest_hit runs every test on every ray; the
// selects that keep the nearest hit count zero):
//   sphere_t:    r2 = r*r 1; f = o - c 3; b = fdot(f,d) 5; s2 = fdot(f,f) 5;
//                c = s2 - r2 1; exit test b*b 1, dd*c 1, difference 1,
//                margin exit_scale * (s2 + r2) 2
//                -- a packet where every lane misses by far stops here (20) --
//                b*(-inv_dd) 1; perp = fma(d, .., f) 3 fma 6; fdot(perp,perp) 5;
//                r2 - .. 1; 0.25 * size2 1; sqrt 1; * len_d 1;
//                0 - b 1; - sign(b) sd 1; t0 = q*inv_dd 1; t1 = c/q 1  = 40
//                (the near-surface compensation and the huge-coordinate
//                recompute run only on packets that need them: not counted)
//   plane_t:     den = fdot(d,n) 5; point - o 3; fdot(..,n) 5; div 1     = 14
//   disk_t:      plane 14; q = o + d*t - c 9; fdot(q,q) 5                 = 28
//   rectangle_t: plane 14; q 9; two fdot 10                               = 33
//   box_t:       per slab (a-o)*inv, (b-o)*inv: 4; three slabs             = 12
//   triangle_t:  v0,v1,v2 9; six projections fdot 30; three 2D edge
//                functions (2 mul, 1 sub) 9; lo + hi 1; den = fdot(n,d) 5;
//                fdot(n, v0) 5; div 1                                      = 60
//
// The sphere count is an upper bound per test: packets that take the miss
// exit do 20 of the 40, so the GFLOP/s and % of peak of sphere scenes overstate
// the arithmetic done; they say how fast the work the test stands for is
// finished, not how busy the FMA units are. intersect/sphere:256_full_tests
// is the exception: every lane of every packet reaches every test's full path
// (nested_spheres_scene), so there the count is the work done.
// =============================================================================

namespace {

constexpr double kIntersectSetup = 9 + 6 + 8;
constexpr double kBoxSetup = 3, kTriangleSetup = 5;
constexpr double kTestFlops[kPrimitiveTypeCount] = {40, 14, 28, 33, 12, 60};
constexpr double kNormalFlops[kPrimitiveTypeCount] = {89, 1, 1, 1, 19, 1};

double all_tests(const SceneData& s) {
    double f = 0;
    for (int t = 0; t < kPrimitiveTypeCount; ++t) f += double(s.count[std::size_t(t)]) * kTestFlops[t];
    return f;
}

}  // namespace

double intersect_flops_per_ray(const PacketScene& scene) {
    const SceneData& s = scene_data(scene);
    double normal = 0;
    for (int t = 0; t < kPrimitiveTypeCount; ++t)
        if (s.count[std::size_t(t)] > 0) normal = std::max(normal, kNormalFlops[t]);
    return kIntersectSetup + (s.count[4] > 0 ? kBoxSetup : 0) + (s.count[5] > 0 ? kTriangleSetup : 0) + normal +
           all_tests(s);
}

// ---- shade (shade_lanes) ------------------------------------------------------
// Counted by hand from shade_lanes, shadowed, shadow_ray and finish_ray, before
// the sphere-frame hit point and ambient occlusion (neither is counted).
// p = fma(d, t, o) x3                                                   =  6
// directional light: ndl = fdot(n, l) 5; accumulate 3 fma 6              = 11
// point light: v = pos - p 3; r2 = fdot 5; rsqrt 2; fdot(n,v) * inv_r 6;
//              accumulate 6                                              = 22
//   (the rescaling for r^2 outside [2^-100, 2^100] is a rare branch: not counted)
// inverse-square point light: as point + the weight
//              inv_dist = inv_r * scale 1, inv_dist * inv_dist 1, weight * .. 1  = 25
// final: hadamard(diffuse, E) 3; + ambient 3 (when the scene has ambient)
// shadows: reach = t * max|d| 1 (once per ray); a light with shadows adds its
// shadow ray (shadow_ray): eps = max(scale*1e-4, (scale + reach)*k) 3,
// o = p + n*eps 6, dd = fdot(l,l) 5, and finish_ray's 1/dd 1, -inv_dd 1,
// exit_scale 1, len_d = sqrt(dd) 1                                       = 18
// (point: its arguments v * inv_r 3 and (r2 * inv_r) * unscale 2         = 23),
// the box and triangle setups of intersect (+3, +5: made inside any_hit for
// packets whose walk reaches a leaf with the type, counted as there), and any_hit's tests of every
// primitive (counted in full: an upper bound, any_hit stops early once all
// lanes are blocked).
double shade_flops_per_ray(const PacketScene& scene) {
    const SceneData& s = scene_data(scene);
    double f = 6 + 3;
    if (s.features.has(kAmbient)) f += 3;
    f += 11.0 * s.directional_count + 22.0 * s.point_count + 25.0 * s.point_attenuated_count;
    if (s.features.has(kShadows)) {
        f += 1;
        const double walk = (s.count[4] > 0 ? kBoxSetup : 0) + (s.count[5] > 0 ? kTriangleSetup : 0) + all_tests(s);
        for (int k = 0; k < s.directional_count; ++k)
            if (s.directional.shadows[std::size_t(k)] != 0.0f) f += 18 + walk;
        for (int k = 0; k < s.point_count; ++k)
            if (s.point.shadows[std::size_t(k)] != 0.0f) f += 23 + walk;
        for (int k = 0; k < s.point_attenuated_count; ++k)
            if (s.point_attenuated.shadows[std::size_t(k)] != 0.0f) f += 23 + walk;
    }
    return f;
}

// ---- tone map (tonemap_lanes) ---------------------------------------------------
// max_to_one: scale = rcp(max) 1 div; c * scale x3 3                      =  4
// clamp_to_color, saturate: compares, selects and min only                =  0
// gamma: lane::pow_positive (kernels/lanes/lane_pow.hpp) per channel: subnormal scale 1,
//   exponent 1 + 2 (halving m, e + 1), s = (m-1)/(m+1) 3, s^2 s^4 2, log
//   polynomial 4 fma 8, s * poly 1, y e and its error (mul, sub, fma) 4,
//   rest fma 2, ye + rest 1, two round_small 4, f = (ye - n) + rest 2,
//   f^2 f^4 2, exp polynomial 7 fma 14, n * 0.5 1, n - n1 1, two scalings 2
//                                                          per channel = 51, x3 = 153
double tonemap_flops_per_ray(ToneMap mode, bool gamma) { return (mode == ToneMap::max_to_one ? 4 : 0) + (gamma ? 153 : 0); }

// ---- camera (kernels/trace/camera.hpp, in double) -------------------------------------
// sx = column * step + first: 1 fma                                       =  2
// pinhole: d = u*sx + (v*sy - w): 3 fma 6; fdot(d,d) 5; 1/sqrt 2; d * k 3;
//          the float + residual split 3                                    = 21
// orthographic: o = u*sx + (eye + v*sy): 3 fma 6; the split 3            = 11
// (sy, v*sy - w and eye + v*sy are one value per packet: not counted.)
double camera_flops_per_ray(bool orthographic) { return orthographic ? 13 : 23; }

// =============================================================================
// Scenes and rays
// =============================================================================

const char* layout_name(Layout l) {
    return l == Layout::mixed ? "mixed" : primitive_type_name(PrimitiveType(int(l)));  // the first six are the types
}

namespace {

Vec3d unit(const Vec3d& v) { return v * (1.0 / std::sqrt(dot(v, v))); }

Shape grid_shape(PrimitiveType type, int i, double x, double z) {
    switch (type) {
    case PrimitiveType::sphere: return Sphere{{x, 0, z}, 1.0};
    case PrimitiveType::plane:
        // Stacked, slightly tilted planes under the grid.
        return Plane{{x, -1.1 - 0.001 * i, z}, unit({0.05 * std::sin(i), 1, 0.05 * std::cos(i)})};
    case PrimitiveType::disk: return Disk{{x, 0, z}, unit({0, 1, 0.6}), 1.0};
    case PrimitiveType::rectangle: return Rectangle{{x - 0.9, -0.5, z + 0.8}, {1.8, 0, 0}, {0, 0.9, -1.56}};
    case PrimitiveType::box: return Box{{x - 0.8, -0.8, z - 0.8}, {x + 0.8, 0.8, z + 0.8}};
    case PrimitiveType::triangle: return Triangle{{x - 1, -0.5, z + 0.9}, {x + 1, -0.5, z + 0.9}, {x, 0.8, z - 0.9}};
    }
    return Sphere{};
}

}  // namespace

Scene grid_scene(Layout layout, int n, bool floor, int width, int height) {
    Scene s;
    const int cols = std::max(1, int(std::ceil(std::sqrt(double(n)))));
    const int rows = (n + cols - 1) / cols;
    constexpr double kCell = 2.5;
    const double extent = std::max(cols, rows) * kCell / 2;
    const double dist = 1.5 + 2.8 * extent;
    const double down = 40.0 * kPi / 180.0;
    s.camera.type = CameraType::pinhole;
    s.camera.look_at = {0, 0, 0};
    s.camera.eye = {0, dist * std::sin(down), dist * std::cos(down)};
    s.camera.up = {0, 1, 0};
    s.camera.fov_y = 45;
    s.camera.width = width;
    s.camera.height = height;
    s.background = {0.1, 0.1, 0.15};
    s.ambient = AmbientLight{{1, 1, 1}, 0.25};
    s.directional_lights.push_back(DirectionalLight{unit({1, 2, 1}), {1, 1, 1}, 2.0, false});
    const Vec3d colours[4] = {{1, 0.2, 0.2}, {0.2, 1, 0.2}, {0.2, 0.3, 1}, {0.9, 0.9, 0.9}};
    for (int m = 0; m < 4; ++m) s.materials.push_back(Material{"m" + std::to_string(m), 0.25, 0.65, colours[m]});
    for (int i = 0; i < n; ++i) {
        const double x = (i % cols - (cols - 1) / 2.0) * kCell;
        const double z = (i / cols - (rows - 1) / 2.0) * kCell;
        const PrimitiveType type = layout == Layout::mixed ? PrimitiveType(i % kPrimitiveTypeCount) : PrimitiveType(int(layout));
        s.objects.push_back(Object{grid_shape(type, i, x, z), i % 4});
    }
    if (floor) s.objects.push_back(Object{Plane{{0, -1.25, 0}, {0, 1, 0}}, 3});
    return s;
}

Scene nested_spheres_scene(int n, int width, int height) {
    // Radii 10 to ~12.6 around centres within 0.4 of the origin, seen from 50
    // away through a 10 degree field: the view's half width at the centres,
    // 50 tan 5 = 4.4, is well inside every sphere, so every camera ray's line
    // crosses every sphere (no miss exit), and the origin is far outside
    // them all (no near-surface compensation).
    Scene s = grid_scene(Layout::sphere, 0, false, width, height);
    s.camera.eye = {0, 0, 50};
    s.camera.look_at = {0, 0, 0};
    s.camera.fov_y = 10;
    for (int i = 0; i < n; ++i) {
        const Vec3d c{(i % 16 - 7.5) * 0.05, (i / 16 % 16 - 7.5) * 0.05, 0};
        s.objects.push_back(Object{Sphere{c, 10 + 0.01 * i}, i % 4});
    }
    return s;
}

RaySet camera_rays(const PacketScene& scene) {
    RaySet set;
    set.width = scene.width();
    set.height = scene.height();
    const Kernel k = select_kernel(scene, Path::simd);
    for (int y = 0; y < set.height; ++y)
        for (int x0 = 0; x0 < set.width; x0 += kPacketWidth) {
            set.packets.emplace_back();
            k.camera(scene, x0, y, set.packets.back());
            for (int i = 0; i < kPacketWidth; ++i) set.active += set.packets.back().active[i] != 0;
        }
    return set;
}

AlignedVec<HitPacket8> trace(const Kernel& kernel, const PacketScene& scene, const RaySet& rays) {
    AlignedVec<HitPacket8> hits(rays.packets.size());
    for (std::size_t p = 0; p < rays.packets.size(); ++p) kernel.intersect(scene, rays.packets[p], hits[p]);
    return hits;
}

void time_intersect(benchmark::State& state, const Kernel& kernel, const PacketScene& scene, const RaySet& rays) {
    HitPacket8 hits;
    for (auto _ : state) {
        for (const RayPacket8& rp : rays.packets) {
            kernel.intersect(scene, rp, hits);
            benchmark::DoNotOptimize(hits);
        }
    }
    state.SetLabel(kernel.name());
    set_ray_counters(state, rays.rays(), intersect_flops_per_ray(scene));
}

double hit_fraction(const RaySet& rays, const AlignedVec<HitPacket8>& hits) {
    std::int64_t n = 0;
    for (const HitPacket8& h : hits)
        for (int i = 0; i < kPacketWidth; ++i) n += h.hit[i] != 0;
    return rays.active == 0 ? 0.0 : double(n) / double(rays.active);
}

// =============================================================================
// Peak: sustained FP32 FMA throughput at 8 lanes.
//
// Each chain is acc = acc * m + a (one vfmadd231ps ymm, dependent on itself).
// An FMA has a latency of 4 cycles and these cores issue two per cycle (ports
// 0 and 1), so 8 chains in flight saturate both pipes; we run 12 (they fit in
// the 16 ymm registers with m and a) for slack. acc converges to a/(1-m) ~ 1.7:
// no overflow, no denormals.
// =============================================================================
namespace {

template <int C>
__attribute__((target("avx2,fma"))) float fma_chains_n(std::int64_t reps) {
    __m256 acc[C];
#pragma GCC unroll 16
    for (int c = 0; c < C; ++c) acc[c] = _mm256_set1_ps(1.0f + 0.001f * float(c));
    const __m256 m = _mm256_set1_ps(0.99999994f), a = _mm256_set1_ps(1e-7f);
    for (std::int64_t i = 0; i < reps; ++i) {
#pragma GCC unroll 16
        for (int c = 0; c < C; ++c) acc[c] = _mm256_fmadd_ps(acc[c], m, a);
    }
    __m256 sum = acc[0];
#pragma GCC unroll 16
    for (int c = 1; c < C; ++c) sum = _mm256_add_ps(sum, acc[c]);
    alignas(32) float out[8];
    _mm256_store_ps(out, sum);
    return out[0] + out[1] + out[2] + out[3] + out[4] + out[5] + out[6] + out[7];
}

// One divider operation on a whole ymm register (8 lanes) or on the low
// float of an xmm register (1 lane: divss, sqrtss).
struct Ymm {
    using V = __m256;
    __attribute__((target("avx2,fma"))) static V set(float x) { return _mm256_set1_ps(x); }
    __attribute__((target("avx2,fma"))) static V div(V a, V b) { return _mm256_div_ps(a, b); }
    __attribute__((target("avx2,fma"))) static V sqrt(V a) { return _mm256_sqrt_ps(a); }
    __attribute__((target("avx2,fma"))) static V add(V a, V b) { return _mm256_add_ps(a, b); }
    __attribute__((target("avx2,fma"))) static float first(V a) { return _mm256_cvtss_f32(a); }
};
struct Ss {
    using V = __m128;
    __attribute__((target("avx2,fma"))) static V set(float x) { return _mm_set_ss(x); }
    __attribute__((target("avx2,fma"))) static V div(V a, V b) { return _mm_div_ss(a, b); }
    __attribute__((target("avx2,fma"))) static V sqrt(V a) { return _mm_sqrt_ss(a); }
    __attribute__((target("avx2,fma"))) static V add(V a, V b) { return _mm_add_ss(a, b); }
    __attribute__((target("avx2,fma"))) static float first(V a) { return _mm_cvtss_f32(a); }
};

template <class R, DividerOp Op>
__attribute__((target("avx2,fma"))) float divider_chains_n(std::int64_t reps) {
    typename R::V x[8];
    const typename R::V m = R::set(2.0f);
#pragma GCC unroll 8
    for (int c = 0; c < 8; ++c) x[c] = R::set(1.5f + 0.01f * float(c));
    for (std::int64_t i = 0; i < reps; ++i) {
#pragma GCC unroll 8
        for (int c = 0; c < 8; ++c) x[c] = Op == DividerOp::div ? R::div(m, x[c]) : R::sqrt(x[c]);
    }
    typename R::V sum = x[0];
#pragma GCC unroll 8
    for (int c = 1; c < 8; ++c) sum = R::add(sum, x[c]);
    return R::first(sum);
}

}  // namespace

float divider_chains(DividerOp op, int lanes, std::int64_t reps) {
    if (op == DividerOp::div) return lanes == 8 ? divider_chains_n<Ymm, DividerOp::div>(reps) : divider_chains_n<Ss, DividerOp::div>(reps);
    return lanes == 8 ? divider_chains_n<Ymm, DividerOp::sqrt>(reps) : divider_chains_n<Ss, DividerOp::sqrt>(reps);
}

float fma_chains(int chains, std::int64_t reps) {
    switch (chains) {
    case 1: return fma_chains_n<1>(reps);
    case 4: return fma_chains_n<4>(reps);
    case 8: return fma_chains_n<8>(reps);
    case 10: return fma_chains_n<10>(reps);
    default: return fma_chains_n<12>(reps);
    }
}

double fma_peak_gflops() {
    static const double peak = [] {
        if (!simd_supported()) return 0.0;
        constexpr std::int64_t kReps = 1 << 18;
        double best = 0;
        for (int trial = 0; trial < 15; ++trial) {
            const auto t0 = std::chrono::steady_clock::now();
            benchmark::DoNotOptimize(fma_chains(12, kReps));
            const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            best = std::max(best, 12.0 * kFmaChainFlops * double(kReps) / s * 1e-9);
        }
        return best;
    }();
    return peak;
}

void set_ray_counters(benchmark::State& state, std::int64_t rays_per_iteration, double flops_per_ray) {
    using benchmark::Counter;
    const double rays = double(state.iterations()) * double(rays_per_iteration);
    state.SetItemsProcessed(std::int64_t(rays));
    state.counters["ns_per_ray"] = Counter(rays * 1e-9, Counter::kIsRate | Counter::kInvert);
    state.counters["flops_per_ray"] = Counter(flops_per_ray);
    state.counters["GFLOPS"] = Counter(rays * flops_per_ray * 1e-9, Counter::kIsRate);
    const double peak = fma_peak_gflops();
    if (peak > 0) state.counters["frac_peak"] = Counter(rays * flops_per_ray * 1e-9 / peak, Counter::kIsRate);
}

std::string default_scene_path() {
    if (const char* p = std::getenv("OCTRAY_DEFAULT_SCENE"); p && *p) return p;
#ifdef OCTRAY_DEFAULT_SCENE_PATH
    return OCTRAY_DEFAULT_SCENE_PATH;
#else
    return "scenes/default.json";
#endif
}

void set_ftz_daz() {
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
}

int run_main(int argc, char** argv, void (*register_all)()) {
    set_ftz_daz();  // for octray and Embree alike
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    register_all();
    char peak[64];
    std::snprintf(peak, sizeof peak, "%.2f", fma_peak_gflops());
    benchmark::AddCustomContext("octray_fma_peak_gflops_calibration", peak);
    benchmark::AddCustomContext("octray_simd_supported", simd_supported() ? "yes" : "no");
    benchmark::AddCustomContext("octray_ftz_daz", "on");
    benchmark::AddCustomContext("octray_simd_kernel_isa", general_kernel(Path::simd).isa);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}

}  // namespace octray::bench
