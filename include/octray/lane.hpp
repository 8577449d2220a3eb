// octray/lane.hpp — one vocabulary for scalar and SIMD lanes.
//
// Kernels are written once over a lane type T: `float` or `double` (one lane)
// or `xsimd::batch<float|double, A>` (many lanes). Every operation a kernel
// needs is a free function here with the same semantics for every T, so the
// scalar and SIMD instantiations compute the same thing operation by
// operation (xsimd / Highway style). Masks are `bool` or `xsimd::batch_bool`;
// combine them with `&&`, `||`, `!` (these do not short-circuit on batches).
//
// min/max follow the x86 minps/maxps rule: min(a, b) = a < b ? a : b, so a NaN
// in `a` yields `b`. Kernels rely on it to flush NaN to a chosen value.
#pragma once

#include <octray/precision.hpp>

#include <xsimd/xsimd.hpp>

#include <cmath>
#include <cstdint>
#if defined(__SSE__) || defined(__x86_64__)
#include <immintrin.h>
#endif

namespace octray::lane {

template <class T>
struct traits {
    using scalar = T;
    using mask = bool;
    static constexpr int width = 1;
};
template <class S, class A>
struct traits<xsimd::batch<S, A>> {
    using scalar = S;
    using mask = xsimd::batch_bool<S, A>;
    static constexpr int width = int(xsimd::batch<S, A>::size);
};
template <class T>
using Mask = typename traits<T>::mask;
template <class T>
using Scalar = typename traits<T>::scalar;
template <class T>
inline constexpr int width = traits<T>::width;

// ---- scalar lanes ----------------------------------------------------------
template <class S, class = std::enable_if_t<std::is_floating_point_v<S>>>
inline S select(bool m, S a, S b) { return m ? a : b; }
inline float fma(float a, float b, float c) { return std::fma(a, b, c); }
inline double fma(double a, double b, double c) { return std::fma(a, b, c); }
template <class S, class = std::enable_if_t<std::is_floating_point_v<S>>>
inline S min(S a, S b) { return a < b ? a : b; }
template <class S, class = std::enable_if_t<std::is_floating_point_v<S>>>
inline S max(S a, S b) { return a > b ? a : b; }
template <class S, class = std::enable_if_t<std::is_floating_point_v<S>>>
inline S sqrt(S a) { return std::sqrt(a); }
template <class S, class = std::enable_if_t<std::is_floating_point_v<S>>>
inline S abs(S a) { return std::fabs(a); }
template <class S, class = std::enable_if_t<std::is_floating_point_v<S>>>
inline S copysign(S a, S b) { return std::copysign(a, b); }
template <class S, class = std::enable_if_t<std::is_floating_point_v<S>>>
inline bool isfinite(S a) { return std::isfinite(a); }
template <class S, class = std::enable_if_t<std::is_floating_point_v<S>>>
inline bool isnan(S a) { return std::isnan(a); }
template <class S, class = std::enable_if_t<std::is_floating_point_v<S>>>
inline S pow(S a, S b) { return std::pow(a, b); }
inline bool any(bool m) { return m; }
inline bool all(bool m) { return m; }
inline int count(bool m) { return m ? 1 : 0; }
// Hardware estimates (same tables as the packed instructions).
inline float rcp_estimate(float x) { return _mm_cvtss_f32(_mm_rcp_ss(_mm_set_ss(x))); }
inline float rsqrt_estimate(float x) { return _mm_cvtss_f32(_mm_rsqrt_ss(_mm_set_ss(x))); }
// double has no estimate instruction below AVX-512: estimates go through float.
inline double rcp_estimate(double x) { return double(rcp_estimate(float(x))); }
inline double rsqrt_estimate(double x) { return double(rsqrt_estimate(float(x))); }
// Indexed load; `index` holds a small non-negative integer as a float.
inline float gather(const float* base, float index) { return base[int(index)]; }
inline double gather(const double* base, double index) { return base[long(index)]; }

// ---- SIMD lanes ------------------------------------------------------------
template <class S, class A>
inline xsimd::batch<S, A> select(const xsimd::batch_bool<S, A>& m, const xsimd::batch<S, A>& a, const xsimd::batch<S, A>& b) {
    return xsimd::select(m, a, b);
}
template <class S, class A>
inline xsimd::batch<S, A> fma(const xsimd::batch<S, A>& a, const xsimd::batch<S, A>& b, const xsimd::batch<S, A>& c) {
    return xsimd::fma(a, b, c);
}
template <class S, class A>
inline xsimd::batch<S, A> min(const xsimd::batch<S, A>& a, const xsimd::batch<S, A>& b) { return xsimd::select(a < b, a, b); }
template <class S, class A>
inline xsimd::batch<S, A> max(const xsimd::batch<S, A>& a, const xsimd::batch<S, A>& b) { return xsimd::select(a > b, a, b); }
template <class S, class A>
inline xsimd::batch<S, A> sqrt(const xsimd::batch<S, A>& a) { return xsimd::sqrt(a); }
template <class S, class A>
inline xsimd::batch<S, A> abs(const xsimd::batch<S, A>& a) { return xsimd::abs(a); }
template <class S, class A>
inline xsimd::batch<S, A> copysign(const xsimd::batch<S, A>& a, const xsimd::batch<S, A>& b) { return xsimd::copysign(a, b); }
template <class S, class A>
inline xsimd::batch_bool<S, A> isfinite(const xsimd::batch<S, A>& a) { return xsimd::isfinite(a); }
template <class S, class A>
inline xsimd::batch_bool<S, A> isnan(const xsimd::batch<S, A>& a) { return xsimd::isnan(a); }
template <class S, class A>
inline xsimd::batch<S, A> pow(const xsimd::batch<S, A>& a, const xsimd::batch<S, A>& b) { return xsimd::pow(a, b); }
template <class S, class A>
inline bool any(const xsimd::batch_bool<S, A>& m) { return xsimd::any(m); }
template <class S, class A>
inline bool all(const xsimd::batch_bool<S, A>& m) { return xsimd::all(m); }
template <class S, class A>
inline int count(const xsimd::batch_bool<S, A>& m) {
    alignas(64) S tmp[xsimd::batch<S, A>::size];
    xsimd::select(m, xsimd::batch<S, A>(S(1)), xsimd::batch<S, A>(S(0))).store_aligned(tmp);
    int n = 0;
    for (S v : tmp) n += int(v);
    return n;
}
template <class A>
inline xsimd::batch<float, A> rcp_estimate(const xsimd::batch<float, A>& x) { return xsimd::reciprocal(x); }
template <class A>
inline xsimd::batch<float, A> rsqrt_estimate(const xsimd::batch<float, A>& x) { return xsimd::rsqrt(x); }
template <class A>
inline xsimd::batch<double, A> rcp_estimate(const xsimd::batch<double, A>& x) {
    return xsimd::batch_cast<double>(xsimd::reciprocal(xsimd::batch_cast<float>(x)));
}
template <class A>
inline xsimd::batch<double, A> rsqrt_estimate(const xsimd::batch<double, A>& x) {
    return xsimd::batch_cast<double>(xsimd::rsqrt(xsimd::batch_cast<float>(x)));
}
template <class S, class A>
inline xsimd::batch<S, A> gather(const S* base, const xsimd::batch<S, A>& index) {
    using I = xsimd::as_integer_t<S>;
    return xsimd::batch<S, A>::gather(base, xsimd::batch_cast<I>(index));
}

// ---- precision-mode arithmetic ---------------------------------------------
// 1/x. fast: one Newton step r' = r (2 - x r), written r + r (1 - x r) with FMAs.
template <Precision P, class T>
inline T rcp(const T& x) {
    if constexpr (P == Precision::exact) {
        return T(1) / x;
    } else {
        T r = lane::rcp_estimate(x);
        if constexpr (P == Precision::fast) r = lane::fma(r, lane::fma(-x, r, T(1)), r);
        return r;
    }
}
// a/b.
template <Precision P, class T>
inline T div(const T& a, const T& b) {
    if constexpr (P == Precision::exact) return a / b;
    else return a * rcp<P>(b);
}
// 1/lane::sqrt(x). fast: one Newton step r' = r (1.5 - 0.5 x r^2).
template <Precision P, class T>
inline T rsqrt(const T& x) {
    if constexpr (P == Precision::exact) {
        return T(1) / lane::sqrt(x);
    } else {
        T r = lane::rsqrt_estimate(x);
        if constexpr (P == Precision::fast) {
            const T half_x = T(0.5) * x;
            r = r * lane::fma(-half_x, r * r, T(1.5));
        }
        return r;
    }
}

}  // namespace octray::lane
