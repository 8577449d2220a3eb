// kernels/geometry/planar.hpp — the flat primitives: plane, disk, rectangle
// (parallelogram), each a plane test and a bound on the hit point.
#pragma once

#include "kernels/trace/ray.hpp"

namespace octray::kernels::OCTRAY_ISA {

// Plane. Boundary rule: a ray parallel to the plane (d.n == 0), including one
// lying in it, misses.
// t is an IEEE division in every precision mode: t decides which primitive is
// nearest (a box on this plane: the crease) and, for disks and rectangles,
// the rim and edge tests; an estimate's 2^-12 error in t moves the hit point
// by 2^-12 t, past a crease or an edge many pixels long.
template <class T, Precision P>
OCTRAY_HOT T intersect_plane(const Ray<T, P>& r, const Vec3<T>& point, const Vec3<T>& n, Mask<T>& hit, const T& tbest) {
    const T den = fdot(r.d, n);
    const T num = fdot(point - r.o, n);
    const Mask<T> facing = den != T(0);
    const T t = num / lane::select(facing, den, T(1));
    hit = facing && t > r.tmin && t < tbest;
    return t;
}

// p - c for the hit at t, formed relative to c: (o - c) + t d, one rounding
// of o - c and one FMA per component, rather than o + t d (rounded at the
// size of p) minus c. t's own error (a few u t, along d) stays.
template <class T, Precision P>
OCTRAY_HOT Vec3<T> offset_from(const Ray<T, P>& r, const T& t, const Vec3<T>& c) {
    const Vec3<T> f = r.o - c;
    return {lane::fma(r.d.x, t, f.x), lane::fma(r.d.y, t, f.y), lane::fma(r.d.z, t, f.z)};
}

// Disk. Boundary rule: the rim |p - c| = r is a hit; parallel rays miss.
template <class T, Precision P>
OCTRAY_HOT T intersect_disk(const Ray<T, P>& r, const Vec3<T>& center, const Vec3<T>& n, const T& radius2, Mask<T>& hit,
                const T& tbest) {
    const T t = intersect_plane(r, center, n, hit, tbest);
    const Vec3<T> q = offset_from(r, t, center);
    hit = hit && fdot(q, q) <= radius2;
    return t;
}

// Rectangle (parallelogram corner + s a + t b). Boundary rule: s, t in the
// closed [0, 1]: edges and corners are hits; parallel rays miss.
template <class T, Precision P>
OCTRAY_HOT T intersect_rectangle(const Ray<T, P>& r, const Vec3<T>& corner, const Vec3<T>& n, const Vec3<T>& dual_a,
                     const Vec3<T>& dual_b, Mask<T>& hit, const T& tbest) {
    const T t = intersect_plane(r, corner, n, hit, tbest);
    const Vec3<T> q = offset_from(r, t, corner);
    const T s = fdot(q, dual_a), u = fdot(q, dual_b);
    hit = hit && s >= T(0) && s <= T(1) && u >= T(0) && u <= T(1);
    return t;
}

}  // namespace octray::kernels::OCTRAY_ISA
