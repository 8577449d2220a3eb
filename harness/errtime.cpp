// harness/errtime.cpp — error against run time, per path and precision mode.
#include "errtime.hpp"

#include <octray/reference.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <variant>

namespace octray {

double scene_condition(const Scene& scene, const ReferenceTrace& traced) {
    double worst = 0;
    for (std::size_t k = 0; k < traced.hits.size(); ++k) {
        const reference::Hit& hit = traced.hits[k];
        if (hit.object < 0) continue;
        const double t = hit.t * std::sqrt(dot(traced.rays[k].direction, traced.rays[k].direction));
        for (const PointLight& l : scene.point_lights) {
            const double r = std::sqrt(length_squared(l.position - hit.point));
            if (r > 0) worst = std::max(worst, t / r);
        }
    }
    return 1 + worst;
}

namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Where the kernel that runs is not the one asked for: why.
std::string unavailable(const Kernel& k, Path path, Precision precision) {
    if (k.path != path) return "no AVX2+FMA on this CPU";
    if (k.precision != precision) return std::string("needs AVX-512 F+VL (would run ") + precision_name(k.precision) + ")";
    return "";
}

}  // namespace

ErrtimeReport measure_errtime(const Scene& scene, const ErrtimeOptions& options, std::FILE* log) {
    ErrtimeReport report;
    report.width = scene.camera.width;
    report.height = scene.camera.height;
    CompileOptions compile_options;
    compile_options.threads = options.threads;
    const PacketScene packet = compile(scene, compile_options);
    const ReferenceTrace traced = trace_reference(scene);
    const ReferenceRender ref = render_reference(scene, traced);
    report.kappa = scene_condition(scene, traced);
    const double rays = double(scene.camera.width) * double(scene.camera.height);
    std::vector<Kernel> kernels;
    for (Path path : {Path::scalar, Path::simd})
        for (Precision precision : kPrecisions) {
            const Kernel k = general_kernel(path, precision);
            const std::string label = std::string(path_name(path)) + "/" + precision_name(precision);
            if (const std::string why = unavailable(k, path, precision); !why.empty()) {
                report.skipped.push_back(label + ": " + why);
                continue;
            }
            ErrtimePoint p;
            p.path = path;
            p.precision = precision;
            p.isa = k.isa;
            p.kernel = k.name();
            const PacketRender warm = render_packet(k, packet, options.threads);  // warm-up; its image is checked
            p.agreement = compare(ref, warm.radiance, warm.primitive);
            p.tolerance = mode_tolerance(precision);
            p.within = p.agreement.within(p.tolerance);
            report.points.push_back(std::move(p));
            kernels.push_back(k);
        }
    // Timed rounds, each rendering once with every kernel: a machine whose
    // load changes during the run slows every kernel alike.
    const int min_rounds = std::max(5, options.min_repetitions);
    std::vector<std::vector<double>> ns(kernels.size());
    double timed = 0;
    for (int round = 0; round < min_rounds || (timed < options.min_seconds && round < options.max_repetitions); ++round)
        for (std::size_t i = 0; i < kernels.size(); ++i) {
            const PacketRender r = render_packet(kernels[i], packet, options.threads);
            ns[i].push_back(r.seconds * 1e9 / rays);
            timed += r.seconds / double(kernels.size());
        }
    for (std::size_t i = 0; i < kernels.size(); ++i) {
        ErrtimePoint& p = report.points[i];
        p.repetitions = int(ns[i].size());
        p.ns_per_ray = median(ns[i]);
        p.ns_min = *std::min_element(ns[i].begin(), ns[i].end());
        p.ns_max = *std::max_element(ns[i].begin(), ns[i].end());
        if (log)
            std::fprintf(log, "  %s/%-9s %8.2f ns/ray  max rel %.2e\n", path_name(p.path), precision_name(p.precision),
                         p.ns_per_ray, p.agreement.max_rel);
    }
    mark_pareto(report.points);
    return report;
}

bool ErrtimeReport::all_within() const {
    return std::all_of(points.begin(), points.end(), [](const ErrtimePoint& p) { return p.within; });
}

void mark_pareto(std::vector<ErrtimePoint>& points) {
    for (ErrtimePoint& p : points) {
        p.pareto = true;
        for (const ErrtimePoint& q : points) {
            if (&q == &p) continue;
            const double pe = p.agreement.max_rel, qe = q.agreement.max_rel;
            const bool dominates = q.ns_per_ray <= p.ns_per_ray && qe <= pe && (q.ns_per_ray < p.ns_per_ray || qe < pe);
            if (dominates) {
                p.pareto = false;
                break;
            }
        }
    }
}

void print_errtime_table(std::FILE* out, const ErrtimeReport& r) {
    std::fprintf(out,
                 "%dx%d rays, single kernel per row (general variant: only the precision differs), kappa %.3g\n"
                 "ns/ray: median of the timed renders; errors against the double reference on every lane where both\n"
                 "hit the same primitive (L/S: error over the pixel's full-light radiance); front: * on the Pareto front\n"
                 "of max rel error against ns/ray; bound: the mode's max L/S (verdict as verify's: within it, NaN-free,\n"
                 "mismatched hits only on silhouettes, at most %.1f%% of lanes)\n\n",
                 r.width, r.height, r.kappa, 100 * Tolerance().silhouette_fraction);
    std::fprintf(out, "%-6s %-6s %-8s %8s %5s %9s %9s %9s %9s %9s %10s %5s %9s %s\n", "path", "isa", "mode", "ns/ray",
                 "reps", "max rel", "mean rel", "p99 rel", "max ULP", "max L/S", "mismatched", "front", "bound",
                 "verdict");
    for (const ErrtimePoint& p : r.points) {
        const Agreement& a = p.agreement;
        std::fprintf(out, "%-6s %-6s %-8s %8.2f %5d %9.2e %9.2e %9.2e %9llu %9.2e %10llu %5s %9.2e %s\n",
                     path_name(p.path), p.isa.c_str(), precision_name(p.precision), p.ns_per_ray, p.repetitions,
                     a.max_rel, a.mean_rel, a.p99_rel, (unsigned long long)a.max_ulp, a.max_scaled,
                     (unsigned long long)a.mismatched, p.pareto ? "*" : "", p.tolerance.scaled_error,
                     p.within ? "ok" : "OVER BOUND");
        if (a.nonfinite) std::fprintf(out, "       %llu non-finite radiance values\n", (unsigned long long)a.nonfinite);
    }
    for (const std::string& s : r.skipped) std::fprintf(out, "not run: %s\n", s.c_str());
}

std::string errtime_csv(const ErrtimeReport& r) {
    std::ostringstream o;
    o.precision(6);
    o << "path,isa,mode,kernel,ns_per_ray,ns_min,ns_max,repetitions,max_rel,mean_rel,p99_rel,max_ulp,max_scaled,"
         "mismatched,mismatched_silhouette,nonfinite,compared,lanes,kappa,pareto,bound,within\n";
    for (const ErrtimePoint& p : r.points) {
        const Agreement& a = p.agreement;
        o << path_name(p.path) << ',' << p.isa << ',' << precision_name(p.precision) << ",\"" << p.kernel << "\","
          << p.ns_per_ray << ',' << p.ns_min << ',' << p.ns_max << ',' << p.repetitions << ',' << a.max_rel << ','
          << a.mean_rel << ',' << a.p99_rel << ',' << a.max_ulp << ',' << a.max_scaled << ','
          << a.mismatched << ',' << a.mismatched_silhouette << ',' << a.nonfinite << ',' << a.compared << ','
          << a.lanes << ',' << r.kappa << ',' << (p.pareto ? 1 : 0) << ',' << p.tolerance.scaled_error << ','
          << (p.within ? 1 : 0) << '\n';
    }
    return o.str();
}

}  // namespace octray
