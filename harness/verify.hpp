// harness/verify.hpp — agreement of a packet-path image with the reference, in numbers.
#pragma once

#include <octray/kernels.hpp>
#include <octray/render.hpp>
#include <octray/reference.hpp>
#include <octray/scene.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace octray {

// Ambient occlusion at a pixel (verify_occlusion.cpp): the reference's count
// of blocked samples, and the counts a packet path may get instead where
// samples graze an occluder; the ambient term at visible fraction 1.
struct OcclusionRange {
    int blocked = 0, low = 0, high = 0;
    Vec3d ambient;
};

// Reference image and per-pixel data the comparisons need, computed once.
struct ReferenceRender {
    Image<double> radiance;
    std::vector<std::int32_t> primitive;  // Scene::objects index per pixel, -1 = miss
    Image<double> scale;  // per channel: the pixel's radiance with every light at n.l = 1
    // Per pixel, bit j set when shadow-casting light j (directional lights, then
    // point lights; the first 64) is blocked at the pixel's hit point.
    std::vector<std::uint64_t> shadowed;
    // Scenes with ambient occlusion: its settings and, per pixel hit, the range of counts.
    std::optional<AmbientOcclusion> ambient_occlusion;
    std::vector<OcclusionRange> occlusion;
};
// The reference's camera ray and nearest hit of every pixel, row-major: the
// one full trace a render, an error bound (errtime.hpp) and a test share.
struct ReferenceTrace {
    std::vector<reference::Ray> rays;
    std::vector<reference::Hit> hits;
};
ReferenceTrace trace_reference(const Scene& scene);
// The same along the camera rays `camera` makes, as the kernels take them:
// float plus residual (RayPacket::ox_lo...), read into double, the direction
// normalized in double. The camera kernel forms its rays in double, so they
// are the reference's own to ~u^2; a camera that rounded them (a user's
// CameraFn) would move a hit at distance t by ~u t, a normal change of
// ~u t / (R cos) on a sphere of radius R (precision.hpp, dn_in), and this
// trace leaves that input out, so the comparison measures the kernels alone.
ReferenceTrace trace_reference(const Scene& scene, const PacketScene& packet, CameraFn camera);
// Rows spread over `threads` threads (octray/threads.hpp: 0 = every core).
ReferenceRender render_reference(const Scene& scene, int threads = 0);
ReferenceRender render_reference(const Scene& scene, const ReferenceTrace& traced, int threads = 0);
OcclusionRange occlusion_range(const Scene& scene, const reference::Hit& hit, std::uint32_t pixel);
// The count in the pixel's range whose radiance (the reference's, at that
// count, into at_count) is nearest `radiance`; the reference's own on a tie.
int occlusion_count(const ReferenceRender& ref, std::size_t pixel, const float* radiance, double at_count[3]);

// Tolerances of `octray verify` for exact precision. Radiance error is
// measured relative to the pixel's full-light radiance S (see DESIGN of
// verify in README): float rounding of n.l is absolute, ~1e-7 |n||l|, so
// |L - L_ref| <= tol * S is the bound that holds at the terminator too.
struct Tolerance {
    double scaled_error = 1e-4;          // max |L - L_ref| / S
    double silhouette_fraction = 0.005;  // mismatched hits allowed, as a fraction of lanes, all on silhouettes
};

// The tolerance a precision mode is held to on a whole image (`octray
// errtime`'s verdict, tests/test_scene_bounds.cpp): verify's, which covers
// exact's rounding and the sphere term at the scenes' sizes, plus what the
// mode's 1/sqrt adds. Its estimates enter only the point lights' shading
// (precision.hpp, "Where the modes differ"): n.l = (n.v)/|v| once, an
// attenuated light's 1/r^2 twice more, so each light's term is off by at most
// (1 + E)^3 - 1 of its share of S, E = rsqrt_bound(mode).
Tolerance mode_tolerance(Precision p);

struct Agreement {
    std::uint64_t lanes = 0;             // pixels
    std::uint64_t compared = 0;          // pixels where both hit the same primitive (or both missed)
    double max_rel = 0, mean_rel = 0;    // |L - L_ref| / |L_ref| per channel, over channels with L_ref != 0
    double p99_rel = 0;
    double max_scaled = 0;               // |L - L_ref| / S per channel
    std::uint64_t max_ulp = 0;           // float ULPs between L and float(L_ref)
    std::uint64_t mismatched = 0;        // hit/miss or different primitive
    std::uint64_t mismatched_silhouette = 0;  // of those, on an id edge of the reference image
    // Lanes whose 3x3 neighbourhood in the reference sees a light blocked on one
    // side and not the other: a shadow boundary, where the kernels' shadow-ray
    // offset may legally decide the other way. Like silhouettes, they are
    // counted and left out of the error columns.
    std::uint64_t shadow_edges = 0;
    std::uint64_t nonfinite = 0;         // NaN/inf radiance where the reference is finite
    // Lanes whose count of blocked occlusion samples differs from the
    // reference's by samples that graze an occluder (occlusion_range): like
    // silhouettes, counted; their error is measured against the reference
    // radiance at their own count.
    std::uint64_t occlusion_grazing = 0;

    bool within(const Tolerance& tol) const;
};

Agreement compare(const ReferenceRender& ref, const Image<float>& radiance, const std::vector<std::int32_t>& primitive);

// ULP distance between two floats (0 when equal, huge across NaN).
std::uint64_t ulp_distance(float a, float b);

}  // namespace octray
