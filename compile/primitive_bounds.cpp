// compile/primitive_bounds.cpp — the box around what the kernels test of a
// bounded primitive, for the BVH build.
#include "compile/primitive_bounds.hpp"

#include <octray/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

namespace octray {
namespace {

// The float next to f towards -inf (down) or +inf (up), for f not NaN and
// not already the end it moves to: std::nextafter without the library call
// (every bounded primitive's box takes six of these).
float float_below(float f) {
    if (f == 0.0f) return -std::numeric_limits<float>::denorm_min();
    std::uint32_t b;
    std::memcpy(&b, &f, sizeof b);
    b = f > 0.0f ? b - 1u : b + 1u;  // magnitudes order like their bits
    std::memcpy(&f, &b, sizeof f);
    return f;
}
float float_above(float f) { return -float_below(-f); }

// x rounded to a float no greater (down) or no smaller (up) than x.
float round_down(double x) {
    const float f = float(x);
    return double(f) > x ? float_below(f) : f;
}
float round_up(double x) {
    const float f = float(x);
    return double(f) < x ? float_above(f) : f;
}

}  // namespace

bvh::Box box_of(const Shape& shape) {
    Vec3d lo, hi;
    auto span = [&](const Vec3d& c, const Vec3d& half) { lo = c - half, hi = c + half; };
    std::visit(
        [&](const auto& p) {
            using P = std::decay_t<decltype(p)>;
            if constexpr (std::is_same_v<P, Sphere>) {
                const double r = round_to_float(p.radius);
                span(round_to_float(p.center), Vec3d{r, r, r});
            } else if constexpr (std::is_same_v<P, Disk>) {
                const double r = std::sqrt(round_to_float(p.radius * p.radius));
                span(round_to_float(p.center), Vec3d{r, r, r});
            } else if constexpr (std::is_same_v<P, Rectangle>) {
                lo = hi = p.corner;
                for (const Vec3d& q : {p.corner + p.a, p.corner + p.b, p.corner + p.a + p.b})
                    lo = {std::min(lo.x, q.x), std::min(lo.y, q.y), std::min(lo.z, q.z)},
                    hi = {std::max(hi.x, q.x), std::max(hi.y, q.y), std::max(hi.z, q.z)};
            } else if constexpr (std::is_same_v<P, Box>) {
                lo = round_to_float(p.min), hi = round_to_float(p.max);
            } else if constexpr (std::is_same_v<P, Triangle>) {
                const Vec3d a = round_to_float(p.v0), b = round_to_float(p.v1), c = round_to_float(p.v2);
                lo = {std::min({a.x, b.x, c.x}), std::min({a.y, b.y, c.y}), std::min({a.z, b.z, c.z})};
                hi = {std::max({a.x, b.x, c.x}), std::max({a.y, b.y, c.y}), std::max({a.z, b.z, c.z})};
            }
        },
        shape);
    const Vec3d size = hi - lo;
    const double slack = 0x1p-20 * (std::max({size.x, size.y, size.z}) +
                                    std::max({std::fabs(lo.x), std::fabs(lo.y), std::fabs(lo.z), std::fabs(hi.x),
                                              std::fabs(hi.y), std::fabs(hi.z)}));
    return {{round_down(lo.x - slack), round_down(lo.y - slack), round_down(lo.z - slack)},
            {round_up(hi.x + slack), round_up(hi.y + slack), round_up(hi.z + slack)}};
}


}  // namespace octray
