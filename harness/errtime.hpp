// harness/errtime.hpp — error against run time, per path and precision mode
// (`octray errtime`): measurement, Pareto front, table and CSV (tools/plot.py
// draws the plot from the CSV).
#pragma once

#include "verify.hpp"

#include <octray/kernels.hpp>
#include <octray/scene.hpp>

#include <cstdio>
#include <string>
#include <vector>

namespace octray {

struct ErrtimeOptions {
    int threads = 1;            // render threads while timing (octray/threads.hpp: 0 = every core)
    int min_repetitions = 5;    // timed renders per kernel after one warm-up render (at least 5)
    int max_repetitions = 50;
    double min_seconds = 0.5;   // per kernel: keep repeating (up to max_repetitions) until this much is timed
};

struct ErrtimePoint {
    Path path = Path::simd;
    Precision precision = Precision::exact;
    std::string isa;
    std::string kernel;         // Kernel::name()
    double ns_per_ray = 0;      // median over the timed repetitions
    double ns_min = 0, ns_max = 0;
    int repetitions = 0;
    Agreement agreement;        // against the reference (harness/verify.hpp)
    Tolerance tolerance;        // the mode's (mode_tolerance)
    bool within = false;        // agreement.within(tolerance): the verdict
    bool pareto = false;        // no other point is at least as fast and strictly more accurate (max rel)
};

struct ErrtimeReport {
    int width = 0, height = 0;
    double kappa = 1;                     // the scene's condition (precision.hpp)
    std::vector<ErrtimePoint> points;     // one per path x mode this CPU runs
    std::vector<std::string> skipped;     // "scalar/fast14: needs AVX-512 (F+VL)" ...
    bool all_within() const;              // every point's verdict is ok
};

// kappa = 1 + the largest t/r over (hit, point light) pairs of the
// reference's hits, t the hit distance (precision.hpp). Sphere normals are
// not in it: their error has its own bound, lane by lane (precision.hpp,
// sphere_normal_bound).
double scene_condition(const Scene& scene, const ReferenceTrace& traced);

// Renders the scene with every path x mode this CPU runs (general kernels,
// so the precision is the only difference), compares each warm-up render
// with the reference, then times rounds of one render per kernel (so a change
// of machine load hits every kernel alike). `log` (optional) gets one line per point.
ErrtimeReport measure_errtime(const Scene& scene, const ErrtimeOptions& options, std::FILE* log = nullptr);

// Marks the Pareto front on (ns_per_ray, agreement.max_rel): a point is on it
// when no other point is at least as fast and at least as accurate, and
// strictly better in one of the two.
void mark_pareto(std::vector<ErrtimePoint>& points);

void print_errtime_table(std::FILE* out, const ErrtimeReport& report);
std::string errtime_csv(const ErrtimeReport& report);

}  // namespace octray
