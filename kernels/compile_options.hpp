// kernels/compile_options.hpp — the BVH build options compile() uses
// (packet_scene.cpp), as a benchmark hook: bench/bench_scale.cpp sweeps the
// leaf size and SAH costs through it (OCTRAY_SCALE_LEAF, OCTRAY_SCALE_ICOST).
// Internal; set it only while no thread is compiling a scene.
#pragma once

#include "bvh.hpp"

namespace octray {

bvh::BuildOptions& compile_bvh_options();

}  // namespace octray
