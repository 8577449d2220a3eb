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
// triangle of the fan. lo/hi: the least and greatest of the three.
template <class T, Precision P>
inline void triangle_edges(const Ray<T, P>& r, const Vec3<T>& v0, const Vec3<T>& v1, const Vec3<T>& v2, T& lo, T& hi) {
    const T x0 = fdot(r.proj_a, v0), y0 = fdot(r.proj_b, v0);
    const T x1 = fdot(r.proj_a, v1), y1 = fdot(r.proj_b, v1);
    const T x2 = fdot(r.proj_a, v2), y2 = fdot(r.proj_b, v2);
    const T e0 = x1 * y2 - y1 * x2, e1 = x2 * y0 - y2 * x0, e2 = x0 * y1 - y0 * x1;
    lo = lane::min(e0, lane::min(e1, e2)), hi = lane::max(e0, lane::max(e1, e2));
}

// Triangle, watertight (see triangle_edges). Boundary rule: edges and
// vertices hit (closed edge tests); a ray in the triangle's plane misses.
// Needs make_shear(r) first (for_each_candidate makes it).
// t comes from the compiled unit normal n (rounded once from double), not
// from cross products of the ray-relative vertices: those lose |v|/edge ulps
// for a triangle far from the origin, and their cube overflows float sooner.
// Huge coordinates: the edge functions are of degree 2 in v = vertex - o;
// where one is not finite (|v| beyond ~1e18) the lane is re-evaluated in units
// of 2^72 — exact, and only signs count, so an edge shared with an unscaled
// neighbour keeps its exactly opposite sign (rare branch).
template <class T, Precision P>
OCTRAY_HOT T intersect_triangle(const Ray<T, P>& r, const Vec3<T>& a, const Vec3<T>& b, const Vec3<T>& c, const Vec3<T>& n,
                    Mask<T>& hit, const T& tbest) {
    const Vec3<T> v0 = a - r.o;
    T lo, hi;
    triangle_edges(r, v0, b - r.o, c - r.o, lo, hi);
    const Mask<T> huge = lane::not_(lane::isfinite(lo + hi));
    if (lane::any(huge)) {
        // A compiler barrier: without it GCC keeps this branch's inputs
        // spilled to the stack across every test, for a branch almost never
        // taken.
        asm volatile("" ::: "memory");
        const T k = lane::select(huge, T(0x1p-72f), T(1));
        const Vec3<T> ok = r.o * k;
        triangle_edges(r, a * k - ok, b * k - ok, c * k - ok, lo, hi);
    }
    // In the plane (or degenerate): all three are 0, or d.n = 0.
    const Mask<T> inside = (lo >= T(0) || hi <= T(0)) && (lo != T(0) || hi != T(0));
    const T den = fdot(n, r.d);
    const Mask<T> facing = den != T(0);
    // IEEE in every mode: t decides the nearest primitive (intersect_plane).
    const T t = fdot(n, v0) / lane::select(facing, den, T(1));
    hit = inside && facing && t > r.tmin && t < tbest;
    return t;
}

}  // namespace octray::kernels::OCTRAY_ISA
