// compile/primitive_bounds.hpp — the box around what the kernels test of a
// bounded primitive (compile/primitive_bounds.cpp), for the BVH build.
#pragma once

#include "kernels/bvh/node.hpp"

#include <octray/scene.hpp>

namespace octray {

// An axis-aligned box around what the kernels test of a bounded primitive
// (its float-rounded data), rounded outward to floats and widened by 2^-20 of
// its size and position: the tests' own rounding never reaches past it.
bvh::Box box_of(const Shape& shape);

}  // namespace octray
