// harness/verify_occlusion.cpp — verify on a scene with ambient occlusion: the
// counts of blocked samples a packet path may legally differ in.
//
// The kernels draw the reference's samples (same keys, same u's), but build
// each direction in float about a float normal, and lift the ray's origin off
// the surface by their own rule (kernels/shading/shade.hpp, shadow_ray). A sample ray that
// grazes an occluder may then go either way, as a camera ray at a silhouette
// does. Such samples are found by tracing the reference's sample ray again,
// perturbed well past those differences: turned by kTurn radians two ways
// across itself, and lifted by kLift (1 + |p|) along the normal; a sample
// whose answer changes under one of them is grazing. The pixel's count may
// then lie anywhere between the reference's count less its blocked grazing
// samples and plus its visible ones.
#include "verify.hpp"

#include <octray/reference.hpp>
#include "reference/reference_parts.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace octray {
namespace {

constexpr double kTurn = 1e-5;  // the kernels' directions: within ~1e-6 (float normal, frame and polynomials)
constexpr double kLift = 1e-3;  // the kernels' lift: 1e-4 max(1, |p|_inf) in exact precision
// |n.z| below this: the frame's sign choice (n.z >= 0) may differ between
// float and double normals, and with it every direction: any count is legal.
constexpr double kFrameFlip = 1e-6;

Vec3d unit(const Vec3d& v) { return v * (1.0 / std::sqrt(dot(v, v))); }

}  // namespace

OcclusionRange occlusion_range(const Scene& scene, const reference::Hit& hit, std::uint32_t pixel) {
    OcclusionRange range;
    const AmbientOcclusion& ao = *scene.ambient_occlusion;
    const Material& m = scene.materials[std::size_t(scene.objects[std::size_t(hit.object)].material)];
    range.ambient = hadamard(m.cd * m.ka, scene.ambient->color * scene.ambient->ls);
    const double lift = kLift * (1.0 + std::sqrt(dot(hit.point, hit.point)));
    auto blocked = [&](const reference::Ray& ray) {
        return reference::trace(scene, ray, 0.0, ao.distance).object >= 0;
    };
    int grazing_blocked = 0, grazing_visible = 0;
    for (int k = 0; k < ao.samples; ++k) {
        const reference::Ray ray = reference::occlusion_ray(hit, pixel, k);
        const bool base = blocked(ray);
        range.blocked += base;
        const Vec3d& d = ray.direction;
        const Vec3d across = unit(std::fabs(d.x) < 0.5 ? cross(d, {1, 0, 0}) : cross(d, {0, 1, 0}));
        const Vec3d across2 = cross(d, across);
        bool grazing = blocked({ray.origin + hit.normal * lift, d}) != base;
        for (const Vec3d& e : {across, across2})
            for (double sign : {-1.0, 1.0})
                grazing = grazing || blocked({ray.origin, d + e * (sign * kTurn)}) != base;
        if (grazing) ++(base ? grazing_blocked : grazing_visible);
    }
    const bool flips = std::fabs(hit.normal.z) < kFrameFlip;
    range.low = flips ? 0 : range.blocked - grazing_blocked;
    range.high = flips ? ao.samples : range.blocked + grazing_visible;
    return range;
}

int occlusion_count(const ReferenceRender& ref, std::size_t pixel, const float* radiance, double at_count[3]) {
    const OcclusionRange& o = ref.occlusion[pixel];
    const AmbientOcclusion& ao = *ref.ambient_occlusion;
    const double* r = ref.radiance.rgb.data() + 3 * pixel;
    const double* s = ref.scale.rgb.data() + 3 * pixel;
    const double a[3] = {o.ambient.x, o.ambient.y, o.ambient.z};
    auto factor = [&](int k) { return std::max(ao.min_amount, double(ao.samples - k) / double(ao.samples)); };
    // The reference's radiance with k samples blocked, and the lane's error against it (relative to S).
    auto at = [&](int k, double l[3]) {
        double err = 0;
        for (int c = 0; c < 3; ++c) {
            l[c] = r[c] + a[c] * (factor(k) - factor(o.blocked));
            err = std::max(err, std::fabs(double(radiance[c]) - l[c]) / (s[c] > 0 ? s[c] : 1.0));
        }
        return err;
    };
    int best = o.blocked;
    double best_err = at(best, at_count);  // the reference's own count wins ties
    for (int k = o.low; k <= o.high; ++k) {
        double l[3];
        const double err = k == o.blocked ? best_err : at(k, l);
        if (err < best_err) best_err = err, best = k, std::copy(l, l + 3, at_count);
    }
    return best;
}

}  // namespace octray
