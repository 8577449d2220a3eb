// kernels/packet_kernels.hpp — every packet kernel, for the per-ISA units.
//
// The kernels are written once over a lane type T: `float` (the scalar path:
// one lane at a time), `xsimd::batch<float, A>` (the SIMD path) or a double
// lane type; P is the precision mode (precision.hpp); F is the set of
// features (features.hpp) compiled in: code for a feature outside F is
// removed at compile time, not skipped at run time. One header per concept:
//
//   kernels/trace/packet_io.hpp   lanes <-> packets, per-lane reads of the scene arrays
//   kernels/trace/ray.hpp         loading and masking rays, per-ray setup
//   kernels/geometry/sphere.hpp, kernels/geometry/planar.hpp, kernels/geometry/box.hpp, kernels/geometry/triangle.hpp   the primitive tests
//   kernels/bvh/culling.hpp     which bounded primitives a packet may hit: the BVH8 walk (kernels/bvh/traverse.hpp)
//   kernels/bvh/traverse.hpp  the BVH8 walks: options, the packet walk, traverse_closest/traverse_any
//   kernels/bvh/walk_ray.hpp     a ray as the BVH walks see it, the node child tests for one ray
//   kernels/bvh/walk_single.hpp, kernels/bvh/walk_hull.hpp   the single-ray walk, the hull walk
//   kernels/trace/primitive_tests.hpp   the primitive tests dispatched by type (packet or one ray against a run)
//   kernels/trace/closest_hit.hpp       the nearest hit, kept per lane
//   kernels/trace/hit_record.hpp        the hit finished: normal, ids, HitPacket8
//   kernels/trace/any_hit.hpp           any hit (shadow and occlusion rays)
//   kernels/shading/shade.hpp       Lambertian shading
//   kernels/shading/shadow_ray.hpp  the offset ray from a shaded point (shadow and occlusion rays)
//   kernels/shading/sampling.hpp, kernels/shading/occlusion.hpp   ambient occlusion: the sample generator, the visible fraction
//   kernels/shading/tonemap.hpp     tone mapping and gamma
//   kernels/trace/camera.hpp      camera rays
//
// Each generated unit (dispatch/isa_unit.cpp.in) defines OCTRAY_ISA and includes this.
#pragma once

#include "kernels/trace/camera.hpp"
#include "kernels/trace/any_hit.hpp"
#include "kernels/trace/hit_record.hpp"
#include "kernels/shading/occlusion.hpp"
#include "kernels/shading/shade.hpp"
#include "kernels/shading/tonemap.hpp"
