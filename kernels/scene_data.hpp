// kernels/scene_data.hpp — what compile() makes and the kernels read: the
// scene as structure of arrays, in float.
//
// One set of arrays per primitive type and per light type, each padded to a
// multiple of the packet width and 64-byte aligned. Only the types a scene
// has are filled. Primitives are renumbered type by type ("compiled id" =
// offset[type] + index within type), and within a type in the order of the
// BVH's leaves (planes: scene order), so a leaf's primitives of a type are
// one run of that type's arrays; `object_of` maps a compiled id back to its
// Scene::objects index. Two primitives hit at exactly the same t (coincident
// faces, a ray through a shared mesh edge) resolve to the one tested first,
// which need not be the lower object index the reference keeps.
#pragma once

#include "kernels/lanes/aligned.hpp"
#include "kernels/bvh/node.hpp"

#include <octray/packet_scene.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>

namespace octray {

// radius: as authored, rounded once (1e6 stays exact; its square would not).
// The centre's rounding residuals, for the normal, in one of two forms (or
// none, when every centre is a float): 16 bits a coordinate, cx_q..
// (residual16), where that keeps each within 2^-27 of its sphere's radius,
// which every sphere whose |c| is below ~2^13 radii meets; else floats,
// cx_lo.. (the authored centre is c + c_lo to ~u^2 |c|).
struct SphereArrays {
    Floats cx, cy, cz, radius, cx_lo, cy_lo, cz_lo;
    AlignedVector<std::int16_t> cx_q, cy_q, cz_q;
};

// A residual of float coordinate c in 16 bits: k units of ulp(c) 2^-16, that
// is 2^(e - 39) for c's exponent e (0 for a zero or subnormal c, whose
// residual is then dropped). The unit is a power of two, so the decoded
// float is exact wherever 2^(e - 39) is a normal float.
inline float residual_unit(float c) {
    std::uint32_t bits;
    std::memcpy(&bits, &c, sizeof bits);
    bits &= 0x7f800000u;  // 2^e, or 0
    float p;
    std::memcpy(&p, &bits, sizeof p);
    return p * 0x1p-39f;
}
inline float residual16(float c, std::int16_t k) { return float(k) * residual_unit(c); }
struct PlaneArrays { Floats px, py, pz, nx, ny, nz; };
struct DiskArrays { Floats cx, cy, cz, nx, ny, nz, radius2; };
// p = corner + s a + t b; s = (p - corner).dual_a, t = (p - corner).dual_b.
struct RectangleArrays { Floats cx, cy, cz, nx, ny, nz, dual_ax, dual_ay, dual_az, dual_bx, dual_by, dual_bz; };
struct BoxArrays { Floats minx, miny, minz, maxx, maxy, maxz; };
// Triangles, meshes' and single ones alike, live in the BVH's node array,
// one block a leaf beside the leaf's parent node (bvh::place_leaf_blocks):
// a header (the leaf's first index k0 within the type, and its count n, as
// 32-bit integers), then kTriangleFields fields of n floats each, so field f
// of the leaf's j-th triangle is data[f n + j]: the vertices v0, v1, v2 (as
// given: the watertight test works in ray-relative space), the unit normal
// and the primitive id (scene.hpp; an exact float). One ray tests a leaf's
// triangles side by side with contiguous loads from a few lines, and the
// closest hit keeps its winner's normal and id from the same lines (the hit
// record reads no scene-wide table for a triangle); block_of[k] finds
// triangle k's block for the tools that start from an index.
inline constexpr int kTriangleHeader = 2;
inline constexpr int kTriangleFields = 13;
enum TriangleField { kV0 = 0, kV1 = 3, kV2 = 6, kNormal = 9, kPrimitiveId = 12 };
struct TriangleBlocks {
    AlignedVector<std::uint32_t> block_of;  // per triangle: its block's float offset into Bvh8::nodes
};

// A leaf's triangles: field f of the j-th is data[f * n + j].
struct TriangleRun {
    const float* data;
    int n;
};

// A map between ids (compiled <-> primitive), read once per hit lane: in 16
// bits where every id fits (a scene of at most 65536 primitives), else as
// floats (exact below 2^24, which compile() enforces). compile() fills
// `wide`, then narrows it where it can (narrow()). Either array carries
// padding past the last id (the 16-bit gathers read 4 bytes an entry).
struct IdMap {
    Floats wide;
    AlignedVector<std::uint16_t> narrow_ids;

    float operator[](std::size_t i) const { return narrow_ids.empty() ? wide[i] : float(narrow_ids[i]); }
    bool operator==(const IdMap& o) const { return wide == o.wide && narrow_ids == o.narrow_ids; }
    std::size_t bytes() const {
        return wide.capacity() * sizeof(float) + narrow_ids.capacity() * sizeof(std::uint16_t);
    }
    void narrow() {
        if (wide.size() > 65536 + 64) return;
        if (!std::all_of(wide.begin(), wide.end(), [](float v) { return v >= 0.0f && v < 65536.0f; })) return;
        narrow_ids.reserve(wide.size() + 1);
        for (const float v : wide) narrow_ids.push_back(std::uint16_t(v));
        narrow_ids.push_back(0);
        Floats().swap(wide);
    }
};

// A hit's material and mesh. The mesh comes from the primitive id (objects
// first, then each mesh's triangles: scene.hpp) and the meshes' first ids;
// the material from the mesh's, or common_material for an object, where
// every object has the same material; only where they differ is there a
// material per compiled id (in leaf order: the hits of a packet read nearby
// entries, where a table by primitive id would miss the cache on a large
// scene). Read once per hit lane.
struct PrimitiveOwners {
    int object_count = 0;
    Floats material_of;  // compiled id -> material; empty: objects' is common_material
    float common_material = 0;
    Floats mesh_first;     // per mesh, ascending
    Floats mesh_material;  // per mesh

    // Scalar forms (the kernels have lane forms); -1 for primitive -1.
    int mesh(int primitive) const {
        if (primitive < object_count) return -1;
        return int(std::upper_bound(mesh_first.begin(), mesh_first.end(), float(primitive)) - mesh_first.begin()) - 1;
    }
    int material(int primitive, int compiled) const {
        if (primitive < 0) return -1;
        if (!material_of.empty()) return int(material_of[std::size_t(compiled)]);
        if (primitive < object_count) return int(common_material);
        return int(mesh_material[std::size_t(mesh(primitive))]);
    }
};

// ls * color premultiplied per light; shadows as 0/1 floats.
struct DirectionalArrays { Floats lx, ly, lz, r, g, b, shadows; };
struct PointArrays { Floats px, py, pz, r, g, b, shadows; };

// Ambient occlusion's parameters (AmbientOcclusion); samples 0: none.
struct OcclusionData {
    int samples = 0;
    float distance = 0, min_amount = 0;
};

struct PacketCamera {
    bool orthographic = false;
    // In double: camera rays are formed in double and rounded once, their
    // residuals kept (RayPacket::ox_lo...), as the reference forms them.
    double eye[3]{}, u[3]{}, v[3]{}, w[3]{};
    double scale_x = 1, scale_y = 1;  // tan(fov/2)*aspect, tan(fov/2)  (or height_world/2 * ...)
    int width = 0, height = 0;
    // The image plane's coordinates as affine functions of the pixel:
    // sx = column * sx_step + sx_first, sy = row * sy_step + sy_first (the
    // pixel centre's (2 (i + 0.5) / width - 1) scale_x, (1 - 2 (j + 0.5) / height) scale_y).
    double sx_step = 0, sx_first = 0, sy_step = 0, sy_first = 0;
    // What every lane shares, rounded to float and its residual: a pinhole's
    // eye, an orthographic camera's direction -w.
    float shared_hi[3]{}, shared_lo[3]{};
};

// A tree of at most this many bounded primitives (one leaf block) is not
// walked: every packet tests them all (by its leaves), closest and any hit alike.
inline constexpr std::size_t kTestAllPrimitives = 8;

struct SceneData {
    Features features;
    std::array<int, kPrimitiveTypeCount> count{};   // primitives per type
    std::array<int, kPrimitiveTypeCount> offset{};  // first compiled id per type
    // One 8-wide BVH over every bounded primitive (kind = PrimitiveType);
    // planes stay outside it. Its leaves are released where every leaf is
    // inline in its parent (bvh::every_leaf_inline) and the tree is walked.
    bvh::Bvh8 bvh;
    SphereArrays spheres;
    PlaneArrays planes;
    DiskArrays disks;
    RectangleArrays rectangles;
    BoxArrays boxes;
    TriangleBlocks triangles;
    IdMap object_of;    // compiled id -> primitive id (scene.hpp)
    IdMap compiled_of;  // primitive id -> compiled id (shading finds a sphere hit's centre)
    PrimitiveOwners owners;  // a hit's mesh and material, from its primitive (or compiled) id

    int directional_count = 0, point_count = 0, point_attenuated_count = 0;
    DirectionalArrays directional;
    PointArrays point;             // attenuation none
    PointArrays point_attenuated;  // attenuation inverse_square

    OcclusionData occlusion;

    // Per material, premultiplied: ka*cd ⋆ ls*cl (ambient) and kd*cd/pi (Lambertian BRDF).
    Floats ambient_r, ambient_g, ambient_b, diffuse_r, diffuse_g, diffuse_b;

    float background[3]{};
    PacketCamera camera;
    ToneMap tonemap = ToneMap::max_to_one;
    float clamp_color[3]{1, 0, 0};
    float inv_gamma = 1;
};

// The layout a compiled scene holds, for the kernels, the tools and the
// tests; not part of the public API (PacketScene keeps it private).
// The BVH's node array as floats: where the triangle blocks are.
inline const float* node_floats(const SceneData& s) { return reinterpret_cast<const float*>(s.bvh.nodes.data()); }

// The block of a leaf whose triangles begin at float offset `block`.
inline TriangleRun triangle_run(const SceneData& s, std::uint32_t block) {
    const float* at = node_floats(s) + block;
    std::uint32_t n;
    std::memcpy(&n, at + 1, sizeof n);
    return {at + kTriangleHeader, int(n)};
}

// Field f (TriangleField) of triangle k (index within the type), component c.
inline float triangle_field(const SceneData& s, int k, int f) {
    const std::uint32_t block = s.triangles.block_of[std::size_t(k)];
    const float* at = node_floats(s) + block;
    std::uint32_t k0, n;
    std::memcpy(&k0, at, sizeof k0);
    std::memcpy(&n, at + 1, sizeof n);
    return at[kTriangleHeader + std::size_t(f) * n + (std::uint32_t(k) - k0)];
}

struct SceneAccess {
    static const SceneData& of(const PacketScene& scene) noexcept { return *scene.data_; }
};
inline const SceneData& scene_data(const PacketScene& scene) noexcept { return SceneAccess::of(scene); }

}  // namespace octray
