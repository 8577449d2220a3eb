// bench/scale_common.hpp — the scenes, rays and Embree scenes of the cost
// curve (docs/performance.md): bench_scale.cpp times them, bench/test_scale_agreement.cpp
// checks that octray and Embree give the same answers on them.
//
// Families (every one without a floor plane: Embree has no infinite plane):
//   spheres      N random spheres in the cube [-4, 4]^3, radius
//                4 N^(-1/3) U(0.5, 1) (about constant coverage), seed 7
//   heightfield  io/mesh_generators height_field(n), 2 n^2 triangles,
//                scaled by 4 ([-4, 4]^2 in x-z, heights within +-1)
//   model        the largest assimp test model octray loads (a mesh)
// Camera: pinhole, fov 45, image x image pixels, the scene in view.
// Rays:
//   camera       octray's camera kernel, a packet per 8 pixels of a row
//   incoherent   from each camera hit, in pixel order, one cosine-weighted
//                direction about the face-forward normal, packed 8 at a time;
//                origin the hit point moved 1e-4 scene sizes along the normal,
//                interval (0, scene size), scene size = the bounds' diagonal
// Embree: one device, threads=1, its default ISA; scenes built with
// RTC_BUILD_QUALITY_HIGH (the quality that favours its traversal); spheres as
// RTC_GEOMETRY_TYPE_SPHERE_POINT (native) or user geometry (embree_spheres.hpp).
#pragma once

#include <octray/kernels.hpp>
#include <octray/packet.hpp>
#include <octray/packet_scene.hpp>
#include <octray/scene.hpp>

#include "kernels/lanes/aligned.hpp"

#include <embree3/rtcore.h>

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace octray::scale {

template <class T>
using AVec = std::vector<T, AlignedAllocator<T>>;

enum class Family { spheres, heightfield, model };
const char* family_name(Family f);

// The primitive count a family gets for a requested n (heightfield: the
// nearest 2 k^2; model: the model's triangles, n ignored).
Scene make_scene(Family f, int n, int image);
// Path of the model the `model` family loads.
std::string model_path();

struct Rays {
    AVec<RayPacket8> packets;
    std::int64_t active = 0;
    std::vector<std::int64_t> pixel;   // per packet lane (k * 8 + i): the pixel it came from, -1 inactive
    // Pristine Embree copies: the same floats.
    AVec<RTCRayHit8> e8;
    AVec<std::array<int, 8>> valid8;
    std::vector<RTCRayHit> e1;  // every packet lane, inactive ones too (never traced)
};

struct World {
    Family family = Family::spheres;
    std::string name;  // e.g. "spheres:4096"
    int primitives = 0;
    float size = 0;    // diagonal of the bounds
    Scene authored;
    PacketScene scene;
    std::vector<float> xyzr;   // spheres: center, radius
    std::vector<float> verts;  // meshes: float3 per vertex
    std::vector<unsigned> tris;
    std::unique_ptr<struct UserData> user;  // Embree's user-geometry spheres
    Rays camera, incoherent;
    std::map<int, RTCScene> embree;  // by user (0/1)
    World();
    World(World&&) noexcept;
    ~World();
};

// compile()'s options for every world: the library's defaults, or for a
// sweep (docs/history/performance-2026.md) OCTRAY_SCALE_LEAF, OCTRAY_SCALE_ICOST,
// OCTRAY_SCALE_TCOST and OCTRAY_SCALE_BLOCK: max_leaf_size, intersection_cost,
// traversal_cost, leaf_block.
CompileOptions compile_options();

// Everything above, made once per (family, n) and kept.
World& world(Family f, int n, int image);
bool is_mesh(const World& w);

RTCDevice device();        // threads=1, with a memory monitor; nullptr if Embree fails
std::int64_t embree_bytes_now();  // Embree's device memory, from its monitor
// A new Embree scene of w's geometry (the caller releases it); the seconds
// rtcCommitScene took in *commit_seconds.
RTCScene build_embree(const World& w, bool user, RTCBuildQuality quality, double* commit_seconds = nullptr);
RTCScene embree_scene(World& w, bool user);  // HIGH quality, kept in w

// Bytes octray holds for the primitives: the BVH (nodes, leaves,
// permutations) plus every per-primitive array of the compiled scene.
std::size_t octray_bytes(const PacketScene& scene);

enum class Engine { octray_simd, octray_scalar, embree8, embree1 };
// Per packet lane (k * 8 + i): closest hit's primitive id (-1: miss or
// inactive) and t; or any hit (1 blocked, 0 free, -1 inactive).
struct Answers {
    std::vector<int> prim;
    std::vector<float> t;
};
Answers closest(World& w, const Rays& r, Engine e, bool user);
std::vector<int> occluded(World& w, const Rays& r, Engine e, bool user);

// The timed passes: one whole ray set per call. Embree's work copies have
// tfar (and geomID) reset from the pristine copy per call, in the pass.
struct Work {
    AVec<RTCRayHit8> e8;
    std::vector<RTCRayHit> e1;
    AVec<std::int32_t> occ;  // 8 per packet
    AVec<HitPacket8> hits;
};
Work make_work(const Rays& r);
void pass_octray(const Kernel& k, const PacketScene& s, const Rays& r, Work& w, bool any);
void pass_embree8(RTCScene s, const Rays& r, Work& w, bool any, bool coherent);
void pass_embree1(RTCScene s, const Rays& r, Work& w, bool any, bool coherent);

}  // namespace octray::scale
