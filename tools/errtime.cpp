// tools/errtime.cpp — error against run time, per path and precision mode.
#include "errtime.hpp"

#include <octray/reference.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <variant>

namespace octray {

double scene_condition(const Scene& scene) {
    const Camera& c = scene.camera;
    double worst = 0;
    for (int j = 0; j < c.height; ++j)
        for (int i = 0; i < c.width; ++i) {
            const reference::Ray ray = reference::camera_ray(c, i, j);
            const reference::Hit hit = reference::trace(scene, ray);
            if (hit.object < 0) continue;
            const double t = hit.t * std::sqrt(dot(ray.direction, ray.direction));
            if (const auto* s = std::get_if<Sphere>(&scene.objects[std::size_t(hit.object)].shape))
                worst = std::max(worst, t / s->radius);
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
    const PacketScene packet = compile(scene);
    const ReferenceRender ref = render_reference(scene);
    report.kappa = scene_condition(scene);
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
                 "of max rel error against ns/ray\n\n",
                 r.width, r.height, r.kappa);
    std::fprintf(out, "%-6s %-6s %-8s %8s %5s %9s %9s %9s %9s %9s %10s %s\n", "path", "isa", "mode", "ns/ray", "reps",
                 "max rel", "mean rel", "p99 rel", "max ULP", "max L/S", "mismatched", "front");
    for (const ErrtimePoint& p : r.points) {
        const Agreement& a = p.agreement;
        std::fprintf(out, "%-6s %-6s %-8s %8.2f %5d %9.2e %9.2e %9.2e %9llu %9.2e %10llu %s\n", path_name(p.path),
                     p.isa.c_str(), precision_name(p.precision), p.ns_per_ray, p.repetitions, a.max_rel, a.mean_rel,
                     a.p99_rel, (unsigned long long)a.max_ulp, a.max_scaled, (unsigned long long)a.mismatched,
                     p.pareto ? "*" : "");
        if (a.nonfinite) std::fprintf(out, "       %llu non-finite radiance values\n", (unsigned long long)a.nonfinite);
    }
    for (const std::string& s : r.skipped) std::fprintf(out, "not run: %s\n", s.c_str());
}

std::string errtime_csv(const ErrtimeReport& r) {
    std::ostringstream o;
    o.precision(6);
    o << "path,isa,mode,kernel,ns_per_ray,ns_min,ns_max,repetitions,max_rel,mean_rel,p99_rel,max_ulp,max_scaled,"
         "mismatched,mismatched_silhouette,nonfinite,compared,lanes,kappa,pareto\n";
    for (const ErrtimePoint& p : r.points) {
        const Agreement& a = p.agreement;
        o << path_name(p.path) << ',' << p.isa << ',' << precision_name(p.precision) << ",\"" << p.kernel << "\","
          << p.ns_per_ray << ',' << p.ns_min << ',' << p.ns_max << ',' << p.repetitions << ',' << a.max_rel << ','
          << a.mean_rel << ',' << a.p99_rel << ',' << a.max_ulp << ',' << a.max_scaled << ','
          << a.mismatched << ',' << a.mismatched_silhouette << ',' << a.nonfinite << ',' << a.compared << ','
          << a.lanes << ',' << r.kappa << ',' << (p.pareto ? 1 : 0) << '\n';
    }
    return o.str();
}

namespace {

std::string xml_escape(const std::string& s) {
    std::string o;
    for (char c : s) {
        if (c == '<') o += "&lt;";
        else if (c == '>') o += "&gt;";
        else if (c == '&') o += "&amp;";
        else if (c == '"') o += "&quot;";
        else o += c;
    }
    return o;
}

// A "nice" tick step (1, 2 or 5 times a power of ten) for about `n` ticks over `span`.
double nice_step(double span, int n) {
    const double raw = span / n, p = std::pow(10.0, std::floor(std::log10(raw)));
    const double m = raw / p;
    return (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10) * p;
}

}  // namespace

std::string errtime_svg(const ErrtimeReport& r, const std::string& title) {
    constexpr double W = 760, H = 500, left = 80, right = 170, top = 50, bottom = 60;
    constexpr double kFloor = 1e-12;  // where an error of exactly 0 is drawn
    const double pw = W - left - right, ph = H - top - bottom;
    double tmax = 0, emin = 1, emax = 1e-9;
    for (const ErrtimePoint& p : r.points) {
        tmax = std::max(tmax, p.ns_max);
        for (double e : {p.agreement.max_rel, p.agreement.p99_rel}) {
            e = std::max(e, kFloor);
            emin = std::min(emin, e), emax = std::max(emax, e);
        }
    }
    if (tmax <= 0) tmax = 1;
    const double step_x = nice_step(tmax, 6), xmax = std::ceil(tmax * 1.08 / step_x) * step_x;
    const double dlo = std::floor(std::log10(emin)), dhi = std::max(dlo + 1, std::ceil(std::log10(emax)));
    auto X = [&](double ns) { return left + pw * ns / xmax; };
    auto Y = [&](double e) { return top + ph * (dhi - std::log10(std::max(e, kFloor))) / (dhi - dlo); };

    std::ostringstream o;
    o.setf(std::ios::fixed);
    o.precision(1);
    o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H << "\" viewBox=\"0 0 " << W
      << ' ' << H << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
    o << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    o << "<text x=\"" << left << "\" y=\"24\" font-size=\"15\" font-weight=\"bold\">" << xml_escape(title) << "</text>\n";
    // Grid and axes.
    for (double x = 0; x <= xmax * (1 + 1e-9); x += step_x) {
        o << "<line x1=\"" << X(x) << "\" y1=\"" << top << "\" x2=\"" << X(x) << "\" y2=\"" << top + ph
          << "\" stroke=\"#e4e4e4\"/>\n";
        o << "<text x=\"" << X(x) << "\" y=\"" << top + ph + 18 << "\" text-anchor=\"middle\">" << x << "</text>\n";
    }
    for (double d = dlo; d <= dhi; d += 1) {
        const double y = top + ph * (dhi - d) / (dhi - dlo);
        o << "<line x1=\"" << left << "\" y1=\"" << y << "\" x2=\"" << left + pw << "\" y2=\"" << y
          << "\" stroke=\"#e4e4e4\"/>\n";
        o << "<text x=\"" << left - 8 << "\" y=\"" << y + 4 << "\" text-anchor=\"end\">1e" << int(d) << "</text>\n";
    }
    o << "<rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << pw << "\" height=\"" << ph
      << "\" fill=\"none\" stroke=\"black\"/>\n";
    o << "<text x=\"" << left + pw / 2 << "\" y=\"" << H - 18 << "\" text-anchor=\"middle\">ns per ray (median, "
      << r.width << "x" << r.height << " image, lower is faster)</text>\n";
    o << "<text transform=\"translate(22," << top + ph / 2
      << ") rotate(-90)\" text-anchor=\"middle\">relative radiance error vs reference (log)</text>\n";
    // The front: a staircase through the Pareto points, fastest first.
    std::vector<const ErrtimePoint*> front;
    for (const ErrtimePoint& p : r.points)
        if (p.pareto) front.push_back(&p);
    std::sort(front.begin(), front.end(), [](auto* a, auto* b) { return a->ns_per_ray < b->ns_per_ray; });
    if (!front.empty()) {
        o << "<polyline fill=\"none\" stroke=\"#d62728\" stroke-width=\"2\" stroke-opacity=\"0.6\" points=\"";
        for (std::size_t i = 0; i < front.size(); ++i) {
            if (i > 0) o << X(front[i]->ns_per_ray) << ',' << Y(front[i - 1]->agreement.max_rel) << ' ';
            o << X(front[i]->ns_per_ray) << ',' << Y(front[i]->agreement.max_rel) << ' ';
        }
        o << "\"/>\n";
    }
    // Points: max relative error (circle), p99 (tick) joined by a line; timing spread as a horizontal bar.
    for (const ErrtimePoint& p : r.points) {
        const std::string colour = p.path == Path::simd ? "#1f77b4" : "#2ca02c";
        const double x = X(p.ns_per_ray), y = Y(p.agreement.max_rel), y99 = Y(p.agreement.p99_rel);
        o << "<line x1=\"" << x << "\" y1=\"" << y << "\" x2=\"" << x << "\" y2=\"" << y99 << "\" stroke=\"" << colour
          << "\" stroke-dasharray=\"3,2\"/>\n";
        o << "<line x1=\"" << x - 5 << "\" y1=\"" << y99 << "\" x2=\"" << x + 5 << "\" y2=\"" << y99 << "\" stroke=\""
          << colour << "\" stroke-width=\"2\"/>\n";
        o << "<line x1=\"" << X(p.ns_min) << "\" y1=\"" << y << "\" x2=\"" << X(p.ns_max) << "\" y2=\"" << y
          << "\" stroke=\"" << colour << "\" stroke-opacity=\"0.5\"/>\n";
        o << "<circle cx=\"" << x << "\" cy=\"" << y << "\" r=\"" << (p.pareto ? 6 : 4.5) << "\" fill=\""
          << (p.pareto ? "#d62728" : "white") << "\" stroke=\"" << colour << "\" stroke-width=\"2\"><title>"
          << xml_escape(p.kernel) << "</title></circle>\n";
        o << "<text x=\"" << x + 8 << "\" y=\"" << y - 6 << "\" font-size=\"11\""
          << (p.pareto ? " font-weight=\"bold\"" : "") << ">" << path_name(p.path) << '/' << precision_name(p.precision)
          << "</text>\n";
    }
    // Legend: one marker and its text per row.
    const double lx = left + pw + 16;
    double ly = top + 10;
    auto row = [&](const std::string& text) {
        o << "<text x=\"" << lx + 18 << "\" y=\"" << ly + 4 << "\">" << text << "</text>\n";
        ly += 22;
    };
    auto circle = [&](double radius, const char* fill, const char* stroke, const std::string& text) {
        o << "<circle cx=\"" << lx + 5 << "\" cy=\"" << ly << "\" r=\"" << radius << "\" fill=\"" << fill
          << "\" stroke=\"" << stroke << "\" stroke-width=\"2\"/>";
        row(text);
    };
    auto dash = [&](double x0, double x1, const char* style, const std::string& text) {
        o << "<line x1=\"" << lx + x0 << "\" y1=\"" << ly << "\" x2=\"" << lx + x1 << "\" y2=\"" << ly
          << "\" stroke=\"black\" " << style << "/>";
        row(text);
    };
    circle(4.5, "white", "#2ca02c", "scalar path");
    circle(4.5, "white", "#1f77b4", "simd path");
    circle(6, "#d62728", "#1f77b4", "Pareto front");
    circle(3, "black", "black", "max rel. error");
    dash(0, 10, "stroke-width=\"2\"", "p99 rel. error");
    dash(-2, 12, "stroke-opacity=\"0.5\"", "timing min..max");
    o << "</svg>\n";
    return o.str();
}

}  // namespace octray
