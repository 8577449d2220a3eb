// octray/reference.hpp — the scalar double reference renderer (the oracle).
//
// Written straight from the equations of docs/shading-model.md: for each
// pixel a camera ray, the nearest hit over all objects, then
// Matte::shade = ambient term + for each light with n.l > 0 the
// Lambertian term kd*cd/pi * ls*cl * n.l (point lights with
// optional 1/r^2). Deliberately simple; every faster path is checked against it.
#pragma once

#include <octray/image.hpp>
#include <octray/scene.hpp>

#include <cstdint>
#include <optional>

namespace octray::reference {

struct Ray {
    Vec3d origin;
    Vec3d direction;  // unit for camera rays; intersectors accept any non-zero length
};

// Camera ray through the centre of pixel (i, j), docs/scene-format.md convention.
Ray camera_ray(const Camera& camera, int i, int j);

// Nearest intersection parameter t in the open interval (tmin, tmax), if any.
// The boundary rule of each primitive is documented in docs/scene-format.md.
std::optional<double> intersect(const Shape& shape, const Ray& ray, double tmin, double tmax);

// Geometric (not face-forwarded) unit normal of `shape` at surface point p.
Vec3d geometric_normal(const Shape& shape, const Vec3d& p);

struct Hit {
    double t = 0;
    int object = -1;  // primitive id (objects, then mesh triangles; scene.hpp); -1 = miss
    Vec3d point;
    Vec3d normal;     // unit, faces the incoming ray (n.d <= 0)
};

// Nearest hit over all objects in (tmin, tmax). Ties keep the lower index.
Hit trace(const Scene& scene, const Ray& ray, double tmin = 0.0, double tmax = 1e300);

// HDR radiance of a hit (docs/shading-model.md), or the background on a miss.
// `pixel` (row-major, j * width + i) keys the ambient-occlusion samples; it is
// read only when the scene's ambient light has occlusion.
Vec3d shade(const Scene& scene, const Ray& ray, const Hit& hit, std::uint32_t pixel = 0);

// Display colour in [0,1]^3 from HDR radiance: tone map, then gamma.
Vec3d tonemap(const Vec3d& radiance, const RenderSettings& settings);

// 8-bit quantisation: floor(255 c + 0.5).
std::uint8_t to_8bit(double c);

// The whole image as HDR radiance (rows top to bottom).
Image<double> render(const Scene& scene);

// Tone-mapped 8-bit image of an HDR image.
ImageRGB8 to_display(const Image<double>& hdr, const RenderSettings& settings);

}  // namespace octray::reference
