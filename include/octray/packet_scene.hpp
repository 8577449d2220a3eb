// octray/packet_scene.hpp — a scene compiled for the packet kernels.
//
// Structure of arrays per primitive type and per light type, in float, each
// array padded to a multiple of the packet width and 64-byte aligned. Only the
// types a scene has are filled. Primitives are renumbered type by type
// ("compiled id" = offset[type] + index within type), and within a type along
// a Morton curve of their bounding spheres (planes: scene order), so clusters
// are compact; `object_of` maps a compiled id back to its Scene::objects index.
// Two primitives hit at exactly the same t (coincident faces, a ray through a
// shared mesh edge) resolve to the one earlier in compiled order, which need
// not be the lower object index the reference keeps.
// A PacketScene is immutable after compile(): share one across threads freely.
#pragma once

#include <octray/features.hpp>
#include <octray/scene.hpp>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <new>
#include <vector>

namespace octray {

template <class T, std::size_t Align = 64>
struct AlignedAllocator {
    using value_type = T;
    template <class U>
    struct rebind { using other = AlignedAllocator<U, Align>; };
    AlignedAllocator() = default;
    template <class U>
    AlignedAllocator(const AlignedAllocator<U, Align>&) noexcept {}
    T* allocate(std::size_t n) {
        std::size_t bytes = (n * sizeof(T) + Align - 1) / Align * Align;
        if (void* p = std::aligned_alloc(Align, bytes == 0 ? Align : bytes)) return static_cast<T*>(p);
        throw std::bad_alloc();
    }
    void deallocate(T* p, std::size_t) noexcept { std::free(p); }
    friend bool operator==(const AlignedAllocator&, const AlignedAllocator&) { return true; }
    friend bool operator!=(const AlignedAllocator&, const AlignedAllocator&) { return false; }
};
template <class T>
using AlignedVector = std::vector<T, AlignedAllocator<T>>;
using Floats = AlignedVector<float>;

// radius: as authored, rounded once (1e6 stays exact; its square would not).
struct SphereArrays { Floats cx, cy, cz, radius2, inv_radius, radius; };
struct PlaneArrays { Floats px, py, pz, nx, ny, nz; };
struct DiskArrays { Floats cx, cy, cz, nx, ny, nz, radius2; };
// p = corner + s a + t b; s = (p - corner).dual_a, t = (p - corner).dual_b.
struct RectangleArrays { Floats cx, cy, cz, nx, ny, nz, dual_ax, dual_ay, dual_az, dual_bx, dual_by, dual_bz; };
struct BoxArrays { Floats minx, miny, minz, maxx, maxy, maxz; };
// Vertices kept as given: the watertight test works in ray-relative space.
struct TriangleArrays { Floats x0, y0, z0, x1, y1, z1, x2, y2, z2, nx, ny, nz; };

// ls * color premultiplied per light; shadows as 0/1 floats.
struct DirectionalArrays { Floats lx, ly, lz, r, g, b, shadows; };
struct PointArrays { Floats px, py, pz, r, g, b, shadows; };

struct PacketCamera {
    bool orthographic = false;
    float eye[3]{}, u[3]{}, v[3]{}, w[3]{};
    float scale_x = 1, scale_y = 1;  // tan(fov/2)*aspect, tan(fov/2)  (or height_world/2 * ...)
    int width = 0, height = 0;
};

// A tree of bounding spheres over one type's primitives (in compiled, i.e.
// Morton, order), so a packet skips every region none of its rays comes near.
// Leaves are clusters of kClusterSize consecutive primitives; an inner node
// splits its run of clusters into up to kTreeWidth runs of equal length (a
// power of kTreeWidth clusters each, the last shorter), whose nodes are
// consecutive: node j's children are first_child[j] .. first_child[j] +
// child_count[j] - 1 (first_child -1 for a leaf, whose cluster is cluster[j]:
// primitives from cluster[j] * kClusterSize on). Node 0 is the root. Radii are
// rounded up: every primitive lies inside each node above it. The node arrays
// are padded by kTreeWidth entries, so the bounds of a node's children load as
// one block of kTreeWidth floats.
// kTreeWidth and kClusterSize 8: one AVX register of children, or of a
// leaf's primitives, per beam test (packet_kernels.hpp, for_each_candidate).
// Callgrind against leaves of 4 (instructions per run of intersect_packet):
// Embree peer spheres:64 18.2M vs 20.5M, spheres:16 16.1M vs 15.5M,
// intersect/mixed:256 18.1M vs 21.8M, sphere:256_full_tests 119M vs 138M.
inline constexpr int kClusterSize = 8;
inline constexpr int kTreeWidth = 8;
struct ClusterTree {
    Floats cx, cy, cz, radius;              // per node (then kTreeWidth of padding)
    std::vector<std::int32_t> first_child;  // -1 for a leaf
    std::vector<std::int32_t> child_count;  // 0 for a leaf
    std::vector<std::int32_t> cluster;      // a leaf's cluster (-1 for an inner node)
    Floats px, py, pz, pradius;             // per primitive, its bounding sphere (then padding)
    int size() const { return int(first_child.size()); }
    // Every bound infinite: the walk then skips nothing and tests every
    // primitive in compiled order (tests and benchmarks compare against it).
    void disable_culling() {
        for (Floats* r : {&radius, &pradius}) std::fill(r->begin(), r->end(), std::numeric_limits<float>::infinity());
    }
};

struct PacketScene {
    Features features;
    std::array<int, kPrimitiveTypeCount> count{};   // primitives per type
    std::array<int, kPrimitiveTypeCount> offset{};  // first compiled id per type
    // Per type, the bounding-sphere tree over its clusters; planes have none.
    std::array<ClusterTree, kPrimitiveTypeCount> clusters;
    SphereArrays spheres;
    PlaneArrays planes;
    DiskArrays disks;
    RectangleArrays rectangles;
    BoxArrays boxes;
    TriangleArrays triangles;
    Floats object_of;    // compiled id -> Scene::objects index (exact in float below 2^24)
    Floats material_of;  // compiled id -> Scene::materials index

    int directional_count = 0, point_count = 0, point_attenuated_count = 0;
    DirectionalArrays directional;
    PointArrays point;             // attenuation none
    PointArrays point_attenuated;  // attenuation inverse_square

    // Per material, premultiplied: ka*cd ⋆ ls*cl (seed eq. 7) and kd*cd/pi (eq. 8).
    Floats ambient_r, ambient_g, ambient_b, diffuse_r, diffuse_g, diffuse_b;

    float background[3]{};
    PacketCamera camera;
    ToneMap tonemap = ToneMap::max_to_one;
    float clamp_color[3]{1, 0, 0};
    float inv_gamma = 1;

    int primitive_count() const { return count[0] + count[1] + count[2] + count[3] + count[4] + count[5]; }
};

// Compiles a scene. Throws std::invalid_argument when validate() rejects it or
// it has 2^24 or more primitives or materials (indices travel as exact floats).
PacketScene compile(const Scene& scene);

}  // namespace octray
