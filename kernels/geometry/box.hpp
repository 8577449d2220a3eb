// kernels/geometry/box.hpp — the axis-aligned box: the slab test (Kay & Kajiya,
// "Ray tracing complex scenes", SIGGRAPH 1986), with the NaN cases of a zero
// direction component resolved explicitly.
#pragma once

#include "kernels/trace/ray.hpp"

namespace octray::kernels::OCTRAY_ISA {

// Axis-aligned box. Boundary rule: the box is closed (faces, edges and
// corners hit). A ray with a zero direction component whose origin lies on
// that slab's plane is inside the slab (0 * inf = NaN there becomes the whole
// line). From inside, the exit point is the hit. Needs make_slabs(r) first
// (for_each_candidate makes it).
template <class T, Precision P>
OCTRAY_HOT T intersect_box(const Ray<T, P>& r, const Vec3<T>& lo, const Vec3<T>& hi, Mask<T>& hit, const T& tbest) {
    auto slab = [&](const T& o, const T& inv, const T& a, const T& b, T& enter, T& leave) {
        const T t1 = (a - o) * inv, t2 = (b - o) * inv;
        const Mask<T> nan = lane::isnan(t1) || lane::isnan(t2);
        enter = lane::max(enter, lane::select(nan, T(0) - inf<T>(), lane::min(t1, t2)));
        leave = lane::min(leave, lane::select(nan, inf<T>(), lane::max(t1, t2)));
    };
    T enter = T(0) - inf<T>(), leave = inf<T>();
    slab(r.o.x, r.inv_d.x, lo.x, hi.x, enter, leave);
    slab(r.o.y, r.inv_d.y, lo.y, hi.y, enter, leave);
    slab(r.o.z, r.inv_d.z, lo.z, hi.z, enter, leave);
    const T t = lane::select(enter > r.tmin, enter, leave);
    hit = enter <= leave && t > r.tmin && t < tbest;
    return t;
}

}  // namespace octray::kernels::OCTRAY_ISA
