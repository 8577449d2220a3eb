// harness/verify.cpp — reference vs packet path, as numbers.
#include "verify.hpp"

#include <octray/reference.hpp>
#include "reference/reference_parts.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace octray {
namespace {


// Radiance of a hit with every light at n.l = 1 and unshadowed: the scale
// against which float rounding of n.l is an absolute error.
Vec3d full_light_scale(const Scene& scene, const reference::Hit& hit) {
    const Material& m = scene.materials[std::size_t(reference::primitive_material(scene, hit.object))];
    Vec3d e;
    for (const DirectionalLight& l : scene.directional_lights) e += l.color * l.ls;
    for (const PointLight& l : scene.point_lights) {
        double w = 1;
        if (l.attenuation == Attenuation::inverse_square) w = 1.0 / length_squared(l.position - hit.point);
        e += l.color * (l.ls * w);
    }
    return reference::ambient_term(scene, m) + hadamard(reference::lambertian_brdf(m), e);
}

std::int64_t ordered_bits(float f) {
    std::int32_t i;
    std::memcpy(&i, &f, sizeof i);
    return i < 0 ? std::int64_t(std::numeric_limits<std::int32_t>::min()) - i : i;
}

// Which shadow-casting lights facing the hit (n.l > 0) are blocked there, by
// the reference's own test (reference::shadowed).
std::uint64_t blocked_lights(const Scene& scene, const reference::Hit& hit) {
    if (hit.object < 0) return 0;
    std::uint64_t bits = 0;
    unsigned j = 0;
    for (const DirectionalLight& l : scene.directional_lights) {
        if (j < 64 && dot(l.direction, hit.normal) > 0 && reference::shadowed(scene, hit, l)) bits |= std::uint64_t(1) << j;
        ++j;
    }
    for (const PointLight& l : scene.point_lights) {
        if (j < 64 && dot(l.position - hit.point, hit.normal) > 0 && reference::shadowed(scene, hit, l))
            bits |= std::uint64_t(1) << j;
        ++j;
    }
    return bits;
}

}  // namespace

std::uint64_t ulp_distance(float a, float b) {
    if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<std::uint32_t>::max();
    const std::int64_t d = ordered_bits(a) - ordered_bits(b);
    return std::uint64_t(d < 0 ? -d : d);
}

ReferenceTrace trace_reference(const Scene& scene) {
    const Camera& c = scene.camera;
    ReferenceTrace t;
    for (int j = 0; j < c.height; ++j)
        for (int i = 0; i < c.width; ++i) {
            const reference::Ray& ray = t.rays.emplace_back(reference::camera_ray(c, i, j));
            t.hits.push_back(reference::trace(scene, ray));
        }
    return t;
}

ReferenceTrace trace_reference(const Scene& scene, const PacketScene& packet, CameraFn camera) {
    const Camera& c = scene.camera;
    ReferenceTrace t;
    RayPacket8 rp;
    for (int j = 0; j < c.height; ++j)
        for (int i = 0; i < c.width; ++i) {
            if (i % kPacketWidth == 0) camera(packet, i, j, rp);
            const int q = i % kPacketWidth;
            // The ray as the kernels take it: the float ray plus its residuals.
            const Vec3d o{double(rp.ox[q]) + rp.ox_lo[q], double(rp.oy[q]) + rp.oy_lo[q], double(rp.oz[q]) + rp.oz_lo[q]};
            const Vec3d d{double(rp.dx[q]) + rp.dx_lo[q], double(rp.dy[q]) + rp.dy_lo[q], double(rp.dz[q]) + rp.dz_lo[q]};
            const reference::Ray& ray = t.rays.emplace_back(reference::Ray{o, d * (1 / std::sqrt(dot(d, d)))});
            t.hits.push_back(reference::trace(scene, ray));
        }
    return t;
}

ReferenceRender render_reference(const Scene& scene, int threads) {
    return render_reference(scene, trace_reference(scene), threads);
}

ReferenceRender render_reference(const Scene& scene, const ReferenceTrace& traced, int threads) {
    const Camera& c = scene.camera;
    ReferenceRender r;
    r.radiance = Image<double>(c.width, c.height);
    r.scale = Image<double>(c.width, c.height);
    r.primitive.assign(std::size_t(c.width) * std::size_t(c.height), -1);
    r.shadowed.assign(r.primitive.size(), 0);
    r.ambient_occlusion = scene.ambient ? scene.ambient_occlusion : std::nullopt;
    if (r.ambient_occlusion) r.occlusion.assign(r.primitive.size(), OcclusionRange{});
    // Rows are independent (each pixel writes its own entries): a scene with
    // ambient occlusion traces N samples, each five times more (occlusion_range).
#pragma omp parallel for schedule(dynamic, 4) num_threads(resolve_threads(threads))
    for (int j = 0; j < c.height; ++j) {
        for (int i = 0; i < c.width; ++i) {
            const std::size_t k = std::size_t(j) * std::size_t(c.width) + std::size_t(i);
            const reference::Ray& ray = traced.rays[k];
            const reference::Hit& hit = traced.hits[k];
            const Vec3d l = reference::shade(scene, ray, hit, std::uint32_t(k));
            if (r.ambient_occlusion && hit.object >= 0) r.occlusion[k] = occlusion_range(scene, hit, std::uint32_t(k));
            const Vec3d s = hit.object >= 0 ? full_light_scale(scene, hit) : scene.background;
            double* px = r.radiance.pixel(i, j);
            double* sx = r.scale.pixel(i, j);
            px[0] = l.x, px[1] = l.y, px[2] = l.z;
            sx[0] = s.x, sx[1] = s.y, sx[2] = s.z;
            r.primitive[k] = hit.object;
            r.shadowed[k] = blocked_lights(scene, hit);
        }
    }
    return r;
}

Agreement compare(const ReferenceRender& ref, const Image<float>& radiance, const std::vector<std::int32_t>& primitive) {
    const int w = ref.radiance.width, h = ref.radiance.height;
    Agreement a;
    std::vector<double> rels;
    rels.reserve(std::size_t(w) * std::size_t(h) * 3);
    auto id = [&](int i, int j) { return ref.primitive[std::size_t(j) * std::size_t(w) + std::size_t(i)]; };
    auto shadowed = [&](int i, int j) { return ref.shadowed[std::size_t(j) * std::size_t(w) + std::size_t(i)]; };
    for (int j = 0; j < h; ++j) {
        for (int i = 0; i < w; ++i) {
            ++a.lanes;
            const std::int32_t mine = primitive[std::size_t(j) * std::size_t(w) + std::size_t(i)];
            if (mine != id(i, j)) {
                ++a.mismatched;
                bool edge = false;
                for (int dj = -1; dj <= 1; ++dj)
                    for (int di = -1; di <= 1; ++di) {
                        const int x = i + di, y = j + dj;
                        if (x >= 0 && y >= 0 && x < w && y < h && id(x, y) != id(i, j)) edge = true;
                    }
                if (edge) ++a.mismatched_silhouette;
                continue;
            }
            bool shadow_edge = false;
            for (int dj = -1; dj <= 1; ++dj)
                for (int di = -1; di <= 1; ++di) {
                    const int x = i + di, y = j + dj;
                    if (x >= 0 && y >= 0 && x < w && y < h && shadowed(x, y) != shadowed(i, j)) shadow_edge = true;
                }
            if (shadow_edge) {
                ++a.shadow_edges;
                continue;
            }
            ++a.compared;
            const double* r = ref.radiance.pixel(i, j);
            double at_count[3];
            const std::size_t px = std::size_t(j) * std::size_t(w) + std::size_t(i);
            if (!ref.occlusion.empty() && id(i, j) >= 0 &&
                occlusion_count(ref, px, radiance.pixel(i, j), at_count) != ref.occlusion[px].blocked)
                ++a.occlusion_grazing, r = at_count;
            const double* s = ref.scale.pixel(i, j);
            const float* p = radiance.pixel(i, j);
            for (int k = 0; k < 3; ++k) {
                if (!std::isfinite(p[k])) {
                    if (std::isfinite(float(r[k]))) ++a.nonfinite;
                    continue;
                }
                const double err = std::fabs(double(p[k]) - r[k]);
                if (r[k] != 0) {
                    const double rel = err / std::fabs(r[k]);
                    a.max_rel = std::max(a.max_rel, rel);
                    rels.push_back(rel);
                }
                if (s[k] > 0) a.max_scaled = std::max(a.max_scaled, err / s[k]);
                else if (err > 0) a.max_scaled = std::numeric_limits<double>::infinity();
                a.max_ulp = std::max(a.max_ulp, ulp_distance(p[k], float(r[k])));
            }
        }
    }
    if (!rels.empty()) {
        double sum = 0;
        for (double r : rels) sum += r;
        a.mean_rel = sum / double(rels.size());
        const std::size_t k = std::min(rels.size() - 1, std::size_t(0.99 * double(rels.size())));
        std::nth_element(rels.begin(), rels.begin() + std::ptrdiff_t(k), rels.end());
        a.p99_rel = rels[k];
    }
    return a;
}

Tolerance mode_tolerance(Precision p) {
    const double e = rsqrt_bound(p);
    Tolerance tol;
    tol.scaled_error += (1 + e) * (1 + e) * (1 + e) - 1;
    return tol;
}

bool Agreement::within(const Tolerance& tol) const {
    return nonfinite == 0 && max_scaled <= tol.scaled_error && mismatched == mismatched_silhouette &&
           double(mismatched) <= tol.silhouette_fraction * double(lanes);
}

}  // namespace octray
