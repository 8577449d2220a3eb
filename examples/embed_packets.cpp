// examples/embed_packets.cpp — an engine hands its own ray packets to octray.
//
// No JSON and no command line: the engine builds an octray::Scene in code,
// compiles it once, fills RayPacket8 lanes itself and calls intersect ->
// shade -> tonemap on both paths (simd, scalar) in every precision mode. Each
// result is checked against values worked out by hand from docs/shading-model.md
// (docs/API.md quotes this file). Exits non-zero on any mismatch; CTest runs it.
#include <octray/octray.hpp>

#include <cmath>
#include <cstdio>
#include <limits>

namespace {

int failures = 0;

void check(bool ok, const char* what, int lane, double got, double want) {
    if (ok) return;
    ++failures;
    std::printf("FAIL %s (lane %d): got %.9g, want %.9g\n", what, lane, got, want);
}
void check_rel(double got, double want, double rel, const char* what, int lane) {
    check(std::fabs(got - want) <= rel * std::fabs(want), what, lane, got, want);
}


// >>> docs/API.md quotes from here: scene
// The engine's scene, built in code: one clay sphere, ambient light, a
// directional light and an inverse-square point light.
octray::Scene make_scene() {
    octray::Scene scene;
    scene.background = {0.1, 0.2, 0.3};
    scene.ambient = octray::AmbientLight{{1, 1, 1}, 0.2};  // colour, ls
    octray::DirectionalLight sun;
    sun.direction = {0, 0, 1};  // unit, from the surface toward the light
    sun.ls = 6.0;
    scene.directional_lights.push_back(sun);
    octray::PointLight lamp;
    lamp.position = {0, 3, 5};
    lamp.ls = 10.0;
    lamp.attenuation = octray::Attenuation::inverse_square;
    scene.point_lights.push_back(lamp);
    scene.materials.push_back({"clay", /*ka*/ 0.25, /*kd*/ 0.65, /*cd*/ {1.0, 0.5, 0.25}});
    scene.objects.push_back({octray::Sphere{{0, 0, 0}, 1.0}, /*material*/ 0});
    return scene;
}
// <<< docs/API.md quotes up to here: scene

// >>> docs/API.md quotes from here: set_ray
// Writes one lane of an engine-owned packet. tmin/tmax bound the open
// interval of accepted t; t is measured in units of |d|.
void set_ray(octray::RayPacket8& rays, int i, octray::Vec3f o, octray::Vec3f d, float tmin = 0.0f,
             float tmax = std::numeric_limits<float>::infinity()) {
    rays.ox[i] = o.x, rays.oy[i] = o.y, rays.oz[i] = o.z;
    rays.dx[i] = d.x, rays.dy[i] = d.y, rays.dz[i] = d.z;
    rays.tmin[i] = tmin, rays.tmax[i] = tmax;
    rays.active[i] = 1;
}
// <<< docs/API.md quotes up to here: set_ray

// The shading equation (docs/shading-model.md) for the clay material: ka cd * (ls cl)_ambient + kd cd / pi * E,
// where E = sum over lights of ls * max(0, n.l) [/ r^2] (all light colours white).
octray::Vec3d eq8(double e) {
    const octray::Vec3d cd{1.0, 0.5, 0.25};
    const double ka = 0.25, kd = 0.65, ambient_ls = 0.2;
    return cd * (ka * ambient_ls) + cd * (kd / octray::kPi * e);
}

// max_to_one: divide by the largest component when it exceeds 1.
octray::Vec3d max_to_one(const octray::Vec3d& c) {
    const double m = std::fmax(c.x, std::fmax(c.y, c.z));
    return m > 1.0 ? c * (1.0 / m) : c;
}

// Relative tolerance of every check for the precision mode a kernel runs.
// IEEE modes and the Newton-refined estimates: 1e-5. The raw estimates carry
// their hardware error (rcpps/rsqrtps 1.5 * 2^-12, rcp14/rsqrt14 2^-14) through
// a few operations; measured here at <= 1e-3 and <= 3e-5.
double tolerance(octray::Precision p) {
    if (p == octray::Precision::approx) return 2e-3;
    if (p == octray::Precision::approx14) return 2e-4;
    return 1e-5;
}

void run(octray::Path path, octray::Precision precision) {
    const octray::Scene scene = make_scene();
    // >>> docs/API.md quotes from here: trace
    // Compile once. The PacketScene owns SoA copies of everything the kernels
    // read: the authoring Scene may go away; the PacketScene must outlive
    // every call that uses it.
    const octray::PacketScene compiled = octray::compile(scene);
    const octray::Kernel k = octray::select_kernel(compiled, path, precision);

    octray::RayPacket8 rays{};  // value-initialised: every lane inactive
    const float nan = std::numeric_limits<float>::quiet_NaN();
    set_ray(rays, 0, {0, 0, 5}, {0, 0, -1});              // straight at the sphere: t = 4
    set_ray(rays, 1, {0, 0, 5}, {0, 0, -2});              // unnormalized: t = 2 (units of |d|)
    set_ray(rays, 2, {3, 0, 5}, {0, 0, -1});              // passes beside it: a miss
    /* lane 3 stays inactive */                           // not traced, not counted
    set_ray(rays, 4, {0, 0, 5}, {nan, 0, -1});            // NaN direction: masked, counted
    set_ray(rays, 5, {0, 0, 5}, {0, 0, 0});               // zero direction: masked, counted
    set_ray(rays, 6, {0, 0, 0}, {1, 0, 0});               // from inside: exits at t = 1
    set_ray(rays, 7, {0, 0, 5}, {0, 0, -1}, 0.0f, 3.0f);  // interval ends before the sphere

    octray::HitPacket8 hits;
    octray::ColorPacket8 radiance, display;
    const int masked = k.intersect(compiled, rays, hits);  // active lanes it could not trace
    k.shade(compiled, rays, hits, radiance);                // HDR radiance, background on misses
    k.tonemap(compiled, radiance, display);                 // scene's tone map and gamma
    // <<< docs/API.md quotes up to here: trace

    // Without AVX-512 a 14-bit mode runs as `fast`; k.precision says what ran.
    const double rel = tolerance(k.precision);
    std::printf("%-55s masked=%d\n", k.name().c_str(), masked);
    check(masked == 2, "masked lane count", -1, masked, 2);

    // Hits: lanes 0, 1, 6. t by hand: |o - c| = 5, r = 1 -> t = 4 (|d| = 1),
    // t = 2 (|d| = 2); from the centre along +x: t = 1.
    const int hit_lanes[] = {0, 1, 6};
    const double want_t[] = {4.0, 2.0, 1.0};
    // Face-forward normals: (0,0,1) at p = (0,0,1); at p = (1,0,0) the outward
    // normal (1,0,0) points along the ray, so it is flipped to (-1,0,0).
    const octray::Vec3d want_n[] = {{0, 0, 1}, {0, 0, 1}, {-1, 0, 0}};
    // E by hand. At p = (0,0,1), n = (0,0,1): sun n.l = 1 -> 6; lamp v = (0,3,4),
    // r = 5, n.l = 4/5 -> 10 * 0.8 / 25. At p = (1,0,0), n = (-1,0,0): sun n.l = 0;
    // lamp v = (-1,3,5), r^2 = 35, n.l = 1/sqrt(35) -> 10 / (35 sqrt(35)).
    const double e_front = 6.0 + 10.0 * 0.8 / 25.0, e_inside = 10.0 / (35.0 * std::sqrt(35.0));
    const octray::Vec3d want_l[] = {eq8(e_front), eq8(e_front), eq8(e_inside)};
    for (int j = 0; j < 3; ++j) {
        const int i = hit_lanes[j];
        check(hits.hit[i] == -1, "hit mask", i, hits.hit[i], -1);
        check(hits.primitive[i] == 0 && hits.material[i] == 0, "primitive/material", i, hits.primitive[i], 0);
        check_rel(hits.t[i], want_t[j], rel, "t", i);
        const double n_err = std::fabs(hits.nx[i] - want_n[j].x) + std::fabs(hits.ny[i] - want_n[j].y) +
                             std::fabs(hits.nz[i] - want_n[j].z);
        check(n_err <= rel, "normal", i, n_err, 0);
        check_rel(radiance.r[i], want_l[j].x, rel, "radiance r", i);
        check_rel(radiance.g[i], want_l[j].y, rel, "radiance g", i);
        check_rel(radiance.b[i], want_l[j].z, rel, "radiance b", i);
        const octray::Vec3d shown = max_to_one(want_l[j]);
        check_rel(display.r[i], shown.x, rel, "display r", i);
        check_rel(display.g[i], shown.y, rel, "display g", i);
        check_rel(display.b[i], shown.z, rel, "display b", i);
    }
    // The front hit is over-exposed (r = 0.05 + 0.65 * 6.32 / pi > 1), so
    // max_to_one scaled it; in exact mode the largest component is exactly 1.
    check(want_l[0].x > 1.0, "front hit over-exposed", 0, want_l[0].x, 1.0);
    if (k.precision == octray::Precision::exact)
        check(display.r[0] == 1.0f, "max_to_one keeps the largest component at 1", 0, display.r[0], 1.0);

    // Misses (2, 7), the inactive lane (3) and masked lanes (4, 5): no hit,
    // primitive -1, exactly the background colour, which is in gamut.
    for (int i : {2, 3, 4, 5, 7}) {
        check(hits.hit[i] == 0 && hits.primitive[i] == -1 && hits.material[i] == -1, "miss", i, hits.primitive[i], -1);
        check(radiance.r[i] == 0.1f && radiance.g[i] == 0.2f && radiance.b[i] == 0.3f, "background radiance", i,
              radiance.b[i], 0.3f);
        check(display.r[i] == 0.1f && display.g[i] == 0.2f && display.b[i] == 0.3f, "background display", i,
              display.b[i], 0.3f);
    }
}

}  // namespace

int main() {
    for (octray::Path path : {octray::Path::simd, octray::Path::scalar})
        for (octray::Precision precision : octray::kPrecisions) run(path, precision);
    std::printf("simd_supported: %s\n", octray::simd_supported() ? "yes" : "no (simd path runs the scalar kernel)");
    if (failures != 0) {
        std::printf("%d check(s) failed\n", failures);
        return 1;
    }
    std::printf("all checks passed\n");
    return 0;
}
