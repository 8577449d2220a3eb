// reference/reference_parts.hpp — the reference renderer's parts
// (reference/reference.cpp), for compile(), the harnesses and the tests: not
// part of the public API (octray/reference.hpp has what an engine calls).
#pragma once

#include <octray/reference.hpp>

namespace octray::reference {

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

// Ambient occlusion (docs/shading-model.md): sample k of `pixel` at a hit, the
// cosine-weighted direction about the hit's normal from the uniforms of
// kernels/shading/sampling.hpp (Malley's method, polar; the frame of Duff et al. 2017),
// from just off the surface as shadow rays leave it. Its interval is (0, distance).
Vec3d occlusion_direction(const Vec3d& normal, std::uint32_t pixel, int k);
Ray occlusion_ray(const Hit& hit, std::uint32_t pixel, int k);
// max(min_amount, the fraction of the samples nothing blocks); 1 without occlusion.
double occlusion_factor(const Scene& scene, const Hit& hit, std::uint32_t pixel);

// shade()'s parts, for the harnesses and tests that weigh or check its terms,
// and for compile(), which premultiplies the same terms; each is defined once
// (reference/reference.cpp) and shade() uses them.
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

}  // namespace octray::reference
