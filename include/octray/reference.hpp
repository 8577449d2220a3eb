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
// The boundary rule of each primitive is documented in reference/reference.cpp.
std::optional<double> intersect(const Shape& shape, const Ray& ray, double tmin, double tmax);

// Geometric (not face-forwarded) unit normal of `shape` at surface point p.
Vec3d geometric_normal(const Shape& shape, const Vec3d& p);

// Triangle k of a mesh, in double as authored.
inline Triangle mesh_triangle(const Mesh& m, std::size_t k) {
    return {m.vertices[m.indices[3 * k]], m.vertices[m.indices[3 * k + 1]], m.vertices[m.indices[3 * k + 2]]};
}

// Calls fn(id, shape) for every primitive in id order (objects, then each
// mesh's triangles; scene.hpp) until fn returns true; returns whether it did.
template <class Fn>
bool for_each_primitive(const Scene& scene, Fn&& fn) {
    int id = 0;
    for (const Object& o : scene.objects)
        if (fn(id++, o.shape)) return true;
    for (const Mesh& m : scene.meshes)
        for (std::size_t k = 0; k < m.triangle_count(); ++k)
            if (fn(id++, Shape{mesh_triangle(m, k)})) return true;
    return false;
}

// The shape and material of primitive `id` (objects, then mesh triangles).
Shape primitive_shape(const Scene& scene, int id);
int primitive_material(const Scene& scene, int id);

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

// Ambient occlusion (docs/shading-model.md): sample k of `pixel` at a hit, the
// cosine-weighted direction about the hit's normal from the uniforms of
// kernels/shading/sampling.hpp (Malley's method, polar; the frame of Duff et al. 2017),
// from just off the surface as shadow rays leave it. Its interval is (0, distance).
Vec3d occlusion_direction(const Vec3d& normal, std::uint32_t pixel, int k);
Ray occlusion_ray(const Hit& hit, std::uint32_t pixel, int k);
// max(min_amount, the fraction of the samples nothing blocks); 1 without occlusion.
double occlusion_factor(const Scene& scene, const Hit& hit, std::uint32_t pixel);

// shade()'s parts, for tools and tests that weigh or check its terms; each is
// defined once here and shade() uses them.
// Material m's ambient term ka cd * (ls cl); zero without ambient light.
Vec3d ambient_term(const Scene& scene, const Material& m);
// m's Lambertian BRDF kd cd / pi; a light adds it * (ls cl) * n.l.
Vec3d lambertian_brdf(const Material& m);
// The reference's shadow test at a hit: true when `light` casts shadows and
// its shadow ray meets an object before reaching it. The ray starts at
// p + n * 1e-9 (1 + |p|), just off the surface along the facing normal, so it
// does not re-hit the surface it leaves. shade() asks only for lights with n.l > 0.
bool shadowed(const Scene& scene, const Hit& hit, const DirectionalLight& light);
bool shadowed(const Scene& scene, const Hit& hit, const PointLight& light);

// Display colour in [0,1]^3 from HDR radiance: tone map, then gamma.
Vec3d tonemap(const Vec3d& radiance, const RenderSettings& settings);

// 8-bit quantisation: floor(255 c + 0.5).
std::uint8_t to_8bit(double c);

// The whole image as HDR radiance (rows top to bottom).
Image<double> render(const Scene& scene);

// Tone-mapped 8-bit image of an HDR image.
ImageRGB8 to_display(const Image<double>& hdr, const RenderSettings& settings);

}  // namespace octray::reference
