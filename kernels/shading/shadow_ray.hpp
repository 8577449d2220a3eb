// kernels/shading/shadow_ray.hpp — the ray from a shaded point toward a light (or an
// occlusion sample), offset off the surface: what kernels/shading/shade.hpp and kernels/shading/occlusion.hpp share.
#pragma once

#include "kernels/trace/ray.hpp"

namespace octray::kernels::OCTRAY_ISA {

// Fills r with the shadow ray from p toward a light at distance `dist` along
// unit `l`. The origin moves off the surface along the facing normal so the
// surface does not shadow itself: by 1e-4 |p|, or by more than the hit point's error where the
// precision mode's error over the camera ray's length `reach` (|p - o|, max
// norm; 0 where p carries no t-sized error) is larger (precision.hpp, shadow_offset).
template <class T, Precision P>
inline void shadow_ray(Ray<T, P>& r, const Vec3<T>& p, const Vec3<T>& n, const Vec3<T>& l, const T& dist,
                       const Mask<T>& valid, const T& reach) {
    const T scale = lane::max(lane::max(lane::abs(p.x), lane::abs(p.y)), lane::max(lane::abs(p.z), T(1)));
    const T eps = lane::max(scale * T(1e-4f), (scale + reach) * T(float(shadow_offset(P))));
    r.o = p + n * eps;
    r.d = l;
    r.tmin = T(0);
    r.tmax = dist;
    r.valid = valid;
    r.invalid = Mask<T>(false);
    finish_ray(r, fdot(l, l));
}

}  // namespace octray::kernels::OCTRAY_ISA
