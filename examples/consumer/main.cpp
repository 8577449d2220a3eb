// examples/consumer/main.cpp — a program built against the installed octray
// package (find_package(octray) + octray::octray). One packet, one sphere:
// the ray straight at the sphere must hit it at t = 4 and shade to the shading
// model's value (docs/shading-model.md); the other lanes are inactive and must come back as misses.
#include <octray/octray.hpp>

#include <cmath>
#include <cstdio>
#include <limits>

int main() {
    octray::Scene scene;
    octray::DirectionalLight sun;  // direction (0,1,0): straight down onto the sphere's top
    sun.ls = 2.0;
    scene.directional_lights.push_back(sun);
    scene.materials.push_back({"white", 0.25, 0.65, {1, 1, 1}});
    scene.objects.push_back({octray::Sphere{{0, 0, 0}, 1.0}, 0});
    const octray::PacketScene compiled = octray::compile(scene);
    const octray::Kernel k = octray::select_kernel(compiled, octray::Path::simd);

    octray::RayPacket8 rays{};  // every lane inactive ...
    rays.oy[0] = 5, rays.dy[0] = -1;  // ... but lane 0: from (0,5,0) straight down
    rays.tmax[0] = std::numeric_limits<float>::infinity();
    rays.active[0] = 1;
    octray::HitPacket8 hits;
    octray::ColorPacket8 radiance;
    const int masked = k.intersect(compiled, rays, hits);
    k.shade(compiled, rays, hits, radiance);

    // Hit at (0,1,0), n = (0,1,0) = l: L = kd cd / pi * ls * n.l = 0.65 * 2 / pi.
    const double want = 0.65 * 2.0 / octray::kPi;
    const bool ok = masked == 0 && hits.hit[0] == -1 && std::fabs(hits.t[0] - 4.0f) <= 4e-6f &&
                    std::fabs(radiance.g[0] - want) <= 1e-5 * want && hits.hit[1] == 0 && hits.primitive[7] == -1;
    std::printf("%s: t = %.7g, radiance = %.7g (want 4, %.7g): %s\n", k.name().c_str(), hits.t[0], radiance.g[0], want,
                ok ? "ok" : "FAIL");
    return ok ? 0 : 1;
}
