// tests/support/perturbed_estimates.hpp — the estimate instructions at the limits of
// their specification, for the test-only kernel units (perturbed_unit.cpp.in,
// which define OCTRAY_PERTURBED_ESTIMATES; kernels/lanes/lane.hpp then calls these
// instead of rcpps/rsqrtps/rcp14/rsqrt14). Each returns the IEEE 1/x or
// 1/sqrt(x) moved by a relative `limit` (Intel SDM: 1.5 * 2^-12 for
// rcpps/rsqrtps, 2^-14 for the 14-bit forms): up (+limit), down (-limit) or
// a seeded mix, rounded to a float that stays within the limit, with the
// instructions' special cases (a zero or subnormal input reads as a signed 0:
// +-inf; inf: 0; a negative square root: NaN; a result below the normal
// range: 0). Any CPU's tables lie within these bounds, so what holds here
// holds on every CPU.
#pragma once

#include <xsimd/xsimd.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace octray::perturbed {

enum class Edge { up, down, mix };

struct Setting {
    Edge edge = Edge::up;
    std::uint64_t seed = 0;  // Edge::mix
};
// Read by every estimate of the perturbed units; set it before rendering.
inline Setting setting;

inline const char* edge_name(Edge e) { return e == Edge::up ? "+limit" : e == Edge::down ? "-limit" : "mix"; }

// The relative move for input x: +1, -1, or (mix) a function of x's bits and
// the seed (half the inputs at +-1, the rest uniform in (-1, 1)), so the
// scalar and SIMD paths see the same estimate for the same input.
inline double direction(float x) {
    if (setting.edge != Edge::mix) return setting.edge == Edge::up ? 1.0 : -1.0;
    std::uint32_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    std::uint64_t z = (std::uint64_t(bits) ^ setting.seed) + 0x9e3779b97f4a7c15ull;  // splitmix64
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    const double u = double(z >> 11) * 0x1p-53;
    return u < 0.25 ? 1.0 : u < 0.5 ? -1.0 : 4 * u - 3;
}

// `exact` moved by direction(x) * limit, the float nearest it within the limit.
inline float moved(float x, double exact, double limit) {
    if (std::fabs(exact) < double(std::numeric_limits<float>::min())) return std::copysign(0.0f, float(exact));
    float r = float(exact * (1 + direction(x) * limit));
    while (std::fabs(double(r) / exact - 1) > limit) r = std::nextafter(r, float(exact));
    return r;
}

inline float rcp(float x, double limit) {
    if (std::isnan(x)) return x;
    if (std::fabs(x) < std::numeric_limits<float>::min()) return std::copysign(std::numeric_limits<float>::infinity(), x);
    if (std::isinf(x)) return std::copysign(0.0f, x);
    return moved(x, 1.0 / double(x), limit);
}

inline float rsqrt(float x, double limit) {
    if (std::isnan(x)) return x;
    if (std::fabs(x) < std::numeric_limits<float>::min()) return std::copysign(std::numeric_limits<float>::infinity(), x);
    if (x < 0) return std::numeric_limits<float>::quiet_NaN();
    if (std::isinf(x)) return 0.0f;
    return moved(x, 1.0 / std::sqrt(double(x)), limit);
}

// Lane by lane, for one lane or a batch (double lanes through float, as the
// hardware's float estimates would serve them).
template <class Fn>
inline float each(float x, double limit, Fn fn) { return fn(x, limit); }
template <class Fn>
inline double each(double x, double limit, Fn fn) { return double(fn(float(x), limit)); }
template <class S, class A, class Fn>
inline xsimd::batch<S, A> each(const xsimd::batch<S, A>& x, double limit, Fn fn) {
    using B = xsimd::batch<S, A>;
    alignas(64) S v[B::size];
    x.store_aligned(v);
    for (S& e : v) e = S(fn(float(e), limit));
    return B::load_aligned(v);
}

}  // namespace octray::perturbed
