// kernels/packet_kernels.hpp — every packet kernel, for the per-ISA units.
//
// The kernels are written once over a lane type T: `float` (the scalar path:
// one lane at a time), `xsimd::batch<float, A>` (the SIMD path) or a double
// lane type; P is the precision mode (precision.hpp); F is the set of
// features (features.hpp) compiled in: code for a feature outside F is
// removed at compile time, not skipped at run time. One header per concept:
//
//   packet_io.hpp   lanes <-> packets, per-lane reads of the scene arrays
//   ray.hpp         loading and masking rays, per-ray setup
//   sphere.hpp, planar.hpp, box.hpp, triangle.hpp   the primitive tests
//   culling.hpp     which bounded primitives a packet may hit: the BVH8 walk (bvh_traverse.hpp)
//   bvh_traverse.hpp  the BVH8 walks: options, the packet walk, traverse_closest/traverse_any
//   bvh_ray.hpp     a ray as the BVH walks see it, the node child tests for one ray
//   bvh_walk_single.hpp, bvh_walk_hull.hpp   the single-ray walk, the hull walk
//   intersect.hpp   closest hit, normals, any hit (shadow rays)
//   shade.hpp       Lambertian shading
//   shadow_ray.hpp  the offset ray from a shaded point (shadow and occlusion rays)
//   sampling.hpp, occlusion.hpp   ambient occlusion: the sample generator, the visible fraction
//   tonemap.hpp     tone mapping and gamma
//   camera.hpp      camera rays
//
// Each generated unit (isa_unit.cpp.in) defines OCTRAY_ISA and includes this.
#pragma once

#include "camera.hpp"
#include "intersect.hpp"
#include "occlusion.hpp"
#include "shade.hpp"
#include "tonemap.hpp"
