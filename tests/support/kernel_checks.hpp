// tests/support/kernel_checks.hpp — what every kernel output must satisfy whatever the
// rays (docs/shading-model.md, invalid input), checked independently of the kernels,
// and a generator of garbage rays. The garbage-ray test, the thread test and
// the kernel fuzz target (fuzz/) share them.
#pragma once

#include <octray/kernels.hpp>
#include <octray/packet.hpp>
#include <octray/scene.hpp>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace octray::test {

// Every kernel this CPU runs: each ISA unit of the library (dispatch/isa_kernels.hpp,
// kUnits) that the CPU supports, in every precision mode the unit compiles,
// as the variant for the feature set `features` (Features::bits; exact
// precision is specialized on it, the other modes are general).
std::vector<Kernel> every_kernel(unsigned features = kAllFeatures);

// The lanes of a packet that kernels/trace/ray.hpp's load_ray masks off, recomputed
// here: an active lane (active != 0) is valid when its origin and direction
// are finite, d.d lies in [2^-126, 2^126) and tmin < tmax (false when either
// is NaN); an active lane that is not valid is masked ("invalid"). d.d is
// computed the way the kernel computes it, fma(dx, dx, fma(dy, dy, dz * dz)),
// in float for the float modes and in double for Precision::f64 (whose lanes
// are doubles), so a direction within an ulp of either threshold is decided
// exactly as the kernel decides it.
struct LaneMask {
    bool valid[kPacketWidth]{};
    bool invalid[kPacketWidth]{};
    int masked = 0;  // invalid lanes
};
LaneMask expected_mask(const RayPacket8& rays, Precision precision);

// What the checks need to know about the scene, from its authoring form.
struct SceneFacts {
    int primitives = 0;  // objects and mesh triangles
    int meshes = 0;
    int materials = 0;
    float background[3]{};
    bool display_bounded = true;  // tone-mapped output <= 1 (not so for a clamp_color above 1)
};
SceneFacts scene_facts(const Scene& scene);

// Each returns "" when the stage's output obeys the policy, else the first
// violation, naming the lane. check_intersect: the returned count and
// HitPacket8::invalid are exactly expected_mask's; a hit lane is valid, has a
// finite t in [tmin, tmax], a primitive and material in range and a finite
// normal; every other lane is a miss (t = +inf, ids -1, zero normal).
std::string check_intersect(const SceneFacts& scene, const RayPacket8& rays, const HitPacket8& hits, int masked,
                            Precision precision);
// occluded[i] is 0 or -1, and 0 on inactive and masked lanes.
std::string check_occluded(const RayPacket8& rays, const std::int32_t* occluded, Precision precision);
// Radiance is never NaN nor negative; lanes without a hit (or inactive) get
// exactly the background.
std::string check_shade(const SceneFacts& scene, const RayPacket8& rays, const HitPacket8& hits,
                        const ColorPacket8& radiance);
// Display colour is never NaN, never negative, and <= 1 where the scene bounds it.
std::string check_tonemap(const SceneFacts& scene, const ColorPacket8& display);

// Tallies over many packets: what the inputs exercised.
struct StageCounts {
    std::uint64_t lanes = 0, active = 0, masked = 0, hits = 0, occluded = 0;
    StageCounts& operator+=(const StageCounts& o);
};

// Runs intersect, occluded, shade (on intersect's hits) and tonemap (on the
// shaded radiance and on `colours`, raw radiance) with kernel `k` and checks
// each. Returns "" or the first violation, prefixed with the stage.
std::string run_and_check(const Kernel& k, const PacketScene& ps, const SceneFacts& facts, const RayPacket8& rays,
                          const ColorPacket8& colours, StageCounts* counts = nullptr);

// Compiles `scene` and runs a few camera tiles (first, middle and last row;
// first and last packet of each) of the SIMD and scalar paths through
// run_and_check. Returns "" or the first violation, naming kernel and tile.
std::string trace_camera_tiles(const Scene& scene);

// Random bit patterns for ray packets, weighted toward what breaks kernels:
// NaN (quiet, signalling, negative, with payloads), +-inf, +-0, subnormals,
// +-FLT_MAX, huge and tiny normals, directions whose d.d lies within a few
// ulps of 2^-126 or 2^126, tmin > tmax and tmin == tmax, any int32 as the
// active flag; and, in about half the lanes, ordinary rays through the
// scene's neighbourhood so that hits, shading and shadows run too.
class GarbageRays {
  public:
    explicit GarbageRays(std::uint64_t seed) : rng_(seed) {}
    float value();  // one garbage component
    void fill(RayPacket8& rays);
    void fill(ColorPacket8& colours);

  private:
    std::uint32_t bits() { return std::uint32_t(rng_()); }
    double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng_); }
    std::mt19937_64 rng_;
};

}  // namespace octray::test
