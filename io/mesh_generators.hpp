// io/mesh_generators.hpp — triangle meshes made in code, for tests and benchmarks:
// a tessellated unit sphere and a height field. Both are closed-form, so a test knows
// every vertex; save_ply (model_loader.hpp) writes them as binary PLY for scenes.
#pragma once

#include "model_loader.hpp"

namespace octray {

// The unit sphere about the origin, in `rings` bands of latitude (>= 2) and `segments`
// bands of longitude (>= 3): one vertex at each pole (+y first, -y last) and
// (rings - 1) * segments between them, 2 * segments * (rings - 1) triangles, wound
// counter-clockwise seen from outside (cross(b - a, c - a) points outward). Vertex
// (ring r, segment s) is (sin θ cos φ, cos θ, sin θ sin φ), θ = π r / rings,
// φ = 2π s / segments. Throws std::invalid_argument on counts out of range.
MeshData uv_sphere(int rings, int segments);

// A height field over the square [-1, 1]² of the x-z plane, n (>= 1) cells a side:
// (n + 1)² vertices, row-major in z then x, at y = 0.25 · sin(πx) · cos(πz);
// 2n² triangles wound counter-clockwise seen from +y. Throws std::invalid_argument on n < 1.
MeshData height_field(int n);

}  // namespace octray
