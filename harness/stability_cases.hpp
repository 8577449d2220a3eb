// harness/stability_cases.hpp — the catalogue of stiff and extreme cases (docs/accuracy.md).
//
// One list in code, shared by `octray stability` (tools/cmd_stability.cpp) and
// the tests (tests/test_stability.cpp). Each case builds a small scene and a
// few packets of rays, runs them through a Tracer — a packet kernel (path ×
// precision mode) or the textbook formulation — and measures the result
// against the double reference (reference/reference.cpp) evaluated on exactly
// the float inputs the kernel sees. The cases are defined one family per file
// over the shared checks of stability_check.hpp; stability_cases.cpp lists them.
//
// Error model. u = 2^-24 (float unit roundoff); eps = the mode's stated bound
// for 1/x and 1/sqrt(x) (precision.hpp: div_bound, rsqrt_bound). A ray's
// inputs are floats, so they are only known to their last bit: moving the
// origin by u |o| moves a hit by u |o| / cos(theta). Bounds are stated
// relative to that input precision:
//   t:        |t - t_ref| <= K (eps |t_ref| + u S / max(cos theta, sqrt(u)))
//             S = max(|o|, |p_ref|, the primitive's size and position), theta
//             the angle between ray and normal (sqrt(u): a tangent's double root)
//   radiance: |L - L_ref| <= K (eps L_ref + u sum_k F_k g_k)
//             F_k the light's term at n.l = 1, g_k its condition number (normal
//             error (1 + |p|/R) for a sphere of radius R, 3 |p|/r for a point
//             light at distance r)
// Cases whose inputs are exact (axis-aligned normals, dyadic coordinates) drop
// the u S terms and are held to K eps |t_ref| or K eps L_ref.
// A hit/miss answer may differ from the reference only where the reference's
// own answer flips when the origin moves by 4 u S or the direction by 4 u |d|.
// OCTRAY_STABILITY_DEBUG=1 in the environment prints every lane's error.
#pragma once

#include <octray/kernels.hpp>
#include <octray/precision.hpp>

#include <functional>
#include <string>
#include <vector>

namespace octray::stability {

// What runs a case: a packet kernel or the textbook formulation.
struct Tracer {
    Path path = Path::simd;
    Precision precision = Precision::exact;
    bool naive = false;  // the textbook formulation (stability_naive.cpp), for the naive count only; the
                         // sphere-frame cases run the kernels' formulation before the sphere-frame hit instead
    // Where set, the kernel to run (its general variant) instead of
    // select_kernel's, named by `label` (tests: the perturbed-estimate units).
    Kernel (*kernel)(Precision) = nullptr;
    std::string label = {};
    std::string name() const;  // "scalar/exact", "simd/fast14", "naive", "simd/approx +limit"
};

// Every path × precision mode precision.hpp lists (kPrecisions), scalar first.
std::vector<Tracer> kernel_tracers();
Tracer naive_tracer();

struct Measure {
    double error = 0;  // in the units of Case::bound_text; compared with Case::bound
    bool pass = true;  // error <= bound and every structural check (no NaN, masks, ...) held
    std::string note;  // the first failure, or what ran instead (e.g. a mode's fallback)
};

struct Case {
    std::string name;
    std::string expectation;  // the right behaviour, in a few words
    std::string bound_text;   // what `error` measures and the bound on it
    double bound = 0;
    std::function<Measure(const Tracer&)> run;
};

// The catalogue, in table order.
const std::vector<Case>& catalogue();

// The textbook formulation of the intersect and shade stages, scalar float:
// spheres by t = (-b -+ sqrt(b^2 - 4ac)) / 2a, planes / disks / rectangles with
// |d.n| > 1e-6, Moller-Trumbore triangles with |det| > 1e-8, slabs without the
// NaN cases, every t > 1e-4, no input checks, light sums with n.l and 1/r^2
// straight from the formulas. Used only to count the cases it fails.
int naive_intersect(const PacketScene& scene, const RayPacket8& rays, HitPacket8& hits) noexcept;
void naive_shade(const PacketScene& scene, const RayPacket8& rays, const HitPacket8& hits, ColorPacket8& out) noexcept;

}  // namespace octray::stability
