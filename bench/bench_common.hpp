// bench/bench_common.hpp — what every octray benchmark binary shares: the
// synthetic scenes and ray sets, the FLOP accounting of each kernel, the
// counters, the FMA-peak calibration and a common main().
//
// Conventions (all binaries, so every table compares like with like):
// - one thread; the bench-report script pins the process to one core;
// - FTZ and DAZ are set in MXCSR before any benchmark runs (Embree asks for
//   them; octray and Embree are timed under the same setting);
// - exact precision and the kernel select_kernel() picks for the scene (the
//   one the `octray` CLI runs) unless a benchmark's name says otherwise;
// - rays are made by octray's SIMD camera kernel, 8-lane packets, every lane
//   active; every path of a comparison sees exactly the same packets;
// - counters: items_per_second = rays/s; ns_per_ray; GFLOPS (FLOPs per ray,
//   counted in bench_common.cpp, times rays/s); frac_peak = GFLOPS / this
//   core's FP32 FMA peak at 8 lanes, calibrated once at start-up (the
//   bench-report script recomputes it from the fma_peak benchmark's median).
#pragma once

#include <octray/kernels.hpp>
#include <octray/packet.hpp>
#include <octray/packet_scene.hpp>
#include <octray/scene.hpp>

#include "kernels/lanes/aligned.hpp"

#include <benchmark/benchmark.h>

#include <cstdint>
#include <string>
#include <vector>

namespace octray::bench {

template <class T>
using AlignedVec = std::vector<T, AlignedAllocator<T>>;

// ---- synthetic scenes --------------------------------------------------------
// `n` primitives on a square grid (cells 2.5 apart, each primitive about 2
// units across) seen from above and in front, 40 degrees down, fov 45: every
// camera ray points below the horizon, so with `floor` every ray hits the
// floor plane (y = -1.25) when it misses the grid. Layout::mixed cycles the
// six types. Materials cycle over four colours; one ambient and one
// directional light (the intersect stage ignores lights).
enum class Layout { sphere, plane, disk, rectangle, box, triangle, mixed };
const char* layout_name(Layout l);
Scene grid_scene(Layout layout, int n, bool floor, int width, int height);
// n nested spheres that every camera ray's line crosses: every sphere test
// of every packet runs in full (the FLOP count of the sphere is the work done).
Scene nested_spheres_scene(int n, int width, int height);

// ---- ray and hit sets ----------------------------------------------------------
struct RaySet {
    AlignedVec<RayPacket8> packets;
    int width = 0, height = 0;
    std::int64_t active = 0;  // active lanes (width * height)
    std::int64_t rays() const { return active; }
};
// The scene camera's rays, one packet per 8 pixels of a row (lanes past the
// width inactive).
RaySet camera_rays(const PacketScene& scene);
// Closest hits of `rays` with `kernel`, one HitPacket per ray packet.
AlignedVec<HitPacket8> trace(const Kernel& kernel, const PacketScene& scene, const RaySet& rays);
double hit_fraction(const RaySet& rays, const AlignedVec<HitPacket8>& hits);  // hit lanes / active lanes

// The timed loop of every intersect benchmark: one pass of `kernel.intersect`
// over all packets per iteration; sets the label (the kernel's name) and the
// ray counters with intersect_flops_per_ray(scene).
void time_intersect(benchmark::State& state, const Kernel& kernel, const PacketScene& scene, const RaySet& rays);

// ---- FLOPs per ray (counted from kernels/packet_kernels.hpp; see the .cpp) ----
double intersect_flops_per_ray(const PacketScene& scene);
double shade_flops_per_ray(const PacketScene& scene);
double tonemap_flops_per_ray(ToneMap mode, bool gamma);
double camera_flops_per_ray(bool orthographic);

// ---- peak and counters ---------------------------------------------------------
// Sustained FP32 FMA throughput at 8 lanes (AVX2 + FMA): `chains` independent
// accumulator chains, `reps` FMAs per chain. Returns a value the caller feeds to
// DoNotOptimize. Needs AVX2+FMA at run time (simd_supported()).
float fma_chains(int chains, std::int64_t reps);
// The divide/sqrt unit, the other limit of exact-precision kernels: `reps`
// rounds of 8 independent divides (x = m / x) or square roots (x = sqrt(x))
// on 8-lane registers (lanes == 8) or on single floats (lanes == 1).
enum class DividerOp { div, sqrt };
float divider_chains(DividerOp op, int lanes, std::int64_t reps);
inline constexpr double kFmaChainFlops = 2.0 * 8.0;  // one 8-lane FMA = 16 FLOPs
// Best of a few short runs of fma_chains(12, ...), in GFLOP/s; computed once.
double fma_peak_gflops();

// Sets items_per_second (rays/s), ns_per_ray, GFLOPS and frac_peak for a
// benchmark that traced `rays_per_iteration` rays per iteration.
void set_ray_counters(benchmark::State& state, std::int64_t rays_per_iteration, double flops_per_ray);

// Flush-to-zero and denormals-are-zero on in MXCSR (this thread).
void set_ftz_daz();
// set_ftz_daz(); context lines (CPU features, kernels, peak); runs the
// benchmarks `register_all` registers. Returns main()'s exit status.
int run_main(int argc, char** argv, void (*register_all)());

// scenes/default.json (OCTRAY_DEFAULT_SCENE overrides the compiled-in path).
std::string default_scene_path();

}  // namespace octray::bench
