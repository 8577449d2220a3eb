// kernels/geometry/triangle.hpp — the watertight ray-triangle test (Woop, Benthin &
// Wald, "Watertight ray/triangle intersection", JCGT 2(1), 2013): vertices
// projected per ray onto the plane across the ray, then 2D edge functions
// whose sign is exact or zero, so no ray through a shared edge or vertex
// misses every triangle.
#pragma once

#include "kernels/trace/ray.hpp"

namespace octray::kernels::OCTRAY_ISA {

// Edge functions of the watertight test: the vertices' coordinates across the
// ray (projections shared by every triangle that has the vertex), then 2D
// cross products fl(fl(a b) - fl(c d)). Rounding is monotone, so each sign
// is the exact sign for the projected points or 0; a shared edge gives
// exactly opposite values; and around a shared vertex the signs are those of
// one exact 2D configuration, in which the ray's point lies in some closed
// triangle of the fan. e0 is opposite v0 (the weight of v0), e1 of v1, e2 of v2.
template <class T, Precision P>
inline void triangle_edges(const Ray<T, P>& r, const Vec3<T>& v0, const Vec3<T>& v1, const Vec3<T>& v2, T e[3]) {
    const T x0 = fdot(r.proj_a, v0), y0 = fdot(r.proj_b, v0);
    const T x1 = fdot(r.proj_a, v1), y1 = fdot(r.proj_b, v1);
    const T x2 = fdot(r.proj_a, v2), y2 = fdot(r.proj_b, v2);
    e[0] = x1 * y2 - y1 * x2, e[1] = x2 * y0 - y2 * x0, e[2] = x0 * y1 - y0 * x1;
}

// Triangle, watertight (see triangle_edges). Boundary rule: edges and
// vertices hit (closed edge tests); a ray in the triangle's plane misses.
// Needs make_shear(r) first (for_each_candidate makes it).
// t from the edge functions (Woop et al.): the barycentric weights
// b_i = e_i / (e0 + e1 + e2) and t = sum b_i z_i, z_i the vertices' depths
// along the ray (Ray::proj_z); the weights of a hit lie in [0, 1], so t is a
// convex combination and cannot overflow where the edge functions do not.
// No normal is read: a leaf's test touches its vertices' lines alone, and
// the hit record takes the compiled normal of the winner only. `bary` gets
// (b1, b2): Embree's (u, v), the hit being (1 - u - v) v0 + u v1 + v v2.
// Huge coordinates: the edge functions are of degree 2 in v = vertex - o;
// where one is not finite (|v| beyond ~1e18) the lane is re-evaluated in units
// of 2^72 — exact, and only signs and their ratios count, so an edge shared
// with an unscaled neighbour keeps its exactly opposite sign (rare branch).
template <class T, Precision P>
OCTRAY_HOT T intersect_triangle(const Ray<T, P>& r, const Vec3<T>& a, const Vec3<T>& b, const Vec3<T>& c,
                                Mask<T>& hit, const T& tbest, T bary[2] = nullptr) {
    const Vec3<T> v0 = a - r.o, v1 = b - r.o, v2 = c - r.o;
    T e[3];
    triangle_edges(r, v0, v1, v2, e);
    const Mask<T> huge = lane::not_(lane::isfinite(e[0] + e[1] + e[2]));
    if (lane::any(huge)) {
        // A compiler barrier: without it GCC keeps this branch's inputs
        // spilled to the stack across every test, for a branch almost never
        // taken.
        asm volatile("" ::: "memory");
        const T k = lane::select(huge, T(0x1p-72f), T(1));
        const Vec3<T> ok = r.o * k;
        triangle_edges(r, a * k - ok, b * k - ok, c * k - ok, e);
    }
    const T lo = lane::min(e[0], lane::min(e[1], e[2])), hi = lane::max(e[0], lane::max(e[1], e[2]));
    // In the plane (or degenerate): all three are 0.
    const Mask<T> inside = (lo >= T(0) || hi <= T(0)) && (lo != T(0) || hi != T(0));
    if (!lane::any(inside)) {  // most tests of a walk: no division, no depth
        hit = Mask<T>(false);
        if (bary) bary[0] = T(0), bary[1] = T(0);
        return tbest;
    }
    const T det = e[0] + e[1] + e[2];
    // IEEE in every mode: t decides the nearest primitive (intersect_plane).
    const T inv_det = T(1) / lane::select(inside, det, T(1));
    const T b0 = e[0] * inv_det, b1 = e[1] * inv_det, b2 = e[2] * inv_det;
    const T t = lane::fma(b0, fdot(r.proj_z, v0), lane::fma(b1, fdot(r.proj_z, v1), b2 * fdot(r.proj_z, v2)));
    hit = inside && t > r.tmin && t < tbest;
    if (bary) bary[0] = b1, bary[1] = b2;
    return t;
}

}  // namespace octray::kernels::OCTRAY_ISA
