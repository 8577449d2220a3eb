// kernels/lanes/lane.hpp — one vocabulary for scalar and SIMD lanes.
//
// Kernels are written once over a lane type T: `float` or `double` (one lane)
// or `xsimd::batch<float|double, A>` (many lanes). Every operation a kernel
// needs is a free function here with the same semantics for every T, so the
// scalar and SIMD instantiations compute the same thing operation by
// operation (xsimd / Highway style). Masks are `bool` or `xsimd::batch_bool`;
// combine them with `&&`, `||` and not_() (none short-circuits on batches).
// Not `!`: xsimd 8.1 spells !m as m == false, which on AVX2 splits into two
// 128-bit integer compares and a lane insert (5 instructions, 7 cycles of
// latency) where not_ is one xor.
//
// min/max follow the x86 minps/maxps rule: min(a, b) = a < b ? a : b, so a NaN
// in `a` yields `b`. Kernels rely on it to flush NaN to a chosen value.
#pragma once

#include <octray/precision.hpp>

#include <xsimd/xsimd.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#if defined(__SSE__) || defined(__x86_64__)
#include <immintrin.h>
#endif
// Test-only units (tests/support/perturbed_unit.cpp.in): every estimate is the IEEE
// result moved to the limit of the instruction's specification.
#if defined(OCTRAY_PERTURBED_ESTIMATES)
#include "perturbed_estimates.hpp"
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
// a where m, else +0: select(m, a, 0), the same bits (see the SIMD form).
template <class S, class = std::enable_if_t<std::is_floating_point_v<S>>>
inline S keep(bool m, S a) { return m ? a : S(0); }
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
// copysign for a >= 0 (or +0): a with b's sign bit, one OR on batches.
template <class S, class = std::enable_if_t<std::is_floating_point_v<S>>>
inline S with_sign_of(S a, S b) { return std::copysign(a, b); }
template <class S, class = std::enable_if_t<std::is_floating_point_v<S>>>
inline bool isfinite(S a) { return std::isfinite(a); }
template <class S, class = std::enable_if_t<std::is_floating_point_v<S>>>
inline bool isnan(S a) { return std::isnan(a); }
template <class S, class = std::enable_if_t<std::is_floating_point_v<S>>>
inline S pow(S a, S b) { return std::pow(a, b); }
inline bool not_(bool m) { return !m; }
inline bool any(bool m) { return m; }
inline bool all(bool m) { return m; }
inline int count(bool m) { return m ? 1 : 0; }
// Hardware estimates (same tables as the packed instructions).
inline float rcp_estimate(float x) { return _mm_cvtss_f32(_mm_rcp_ss(_mm_set_ss(x))); }
inline float rsqrt_estimate(float x) { return _mm_cvtss_f32(_mm_rsqrt_ss(_mm_set_ss(x))); }
// double has no estimate instruction below AVX-512: estimates go through float.
inline double rcp_estimate(double x) { return double(rcp_estimate(float(x))); }
inline double rsqrt_estimate(double x) { return double(rsqrt_estimate(float(x))); }
// AVX-512 14-bit estimates (rel. error < 2^-14); only in units built with -mavx512f -mavx512vl.
#if defined(__AVX512F__) && defined(__AVX512VL__)
inline float rcp14_estimate(float x) { return _mm_cvtss_f32(_mm_rcp14_ss(_mm_setzero_ps(), _mm_set_ss(x))); }
inline float rsqrt14_estimate(float x) { return _mm_cvtss_f32(_mm_rsqrt14_ss(_mm_setzero_ps(), _mm_set_ss(x))); }
#endif
// Indexed load; `index` holds a small non-negative integer as a float (or
// double, for double lanes reading the float scene arrays).
inline float gather(const float* base, float index) { return base[int(index)]; }
inline double gather(const double* base, double index) { return base[long(index)]; }
inline double gather(const float* base, double index) { return double(base[long(index)]); }
// The same from 16-bit unsigned entries (an id map of a small scene); the
// array carries one entry of padding past the last index read (the wide
// loads read 4 bytes at each entry).
template <class E>
inline float gather16(const E* base, float index) { return float(base[int(index)]); }
template <class E>
inline double gather16(const E* base, double index) { return double(base[long(index)]); }
// Does `index` hold one value on every lane of `m`? Then `value` is it (as
// an int); a packet of coherent rays mostly does, and one broadcast load is
// then worth 8 gathered ones. One lane always agrees with itself.
inline bool uniform_on(float index, bool, int& value) { value = int(index); return true; }
inline bool uniform_on(double index, bool, int& value) { value = int(index); return true; }
// Lane bits of a mask (bit i: lane i); every lane's value set to the lowest
// (hmin) or highest (hmax) over the lanes; lane 0's value (lane0). One lane:
// the value itself.
inline unsigned bits(bool m) { return m ? 1u : 0u; }
template <class S, class = std::enable_if_t<std::is_floating_point_v<S>>>
inline S hmin(S a) { return a; }
template <class S, class = std::enable_if_t<std::is_floating_point_v<S>>>
inline S hmax(S a) { return a; }
template <class S, class = std::enable_if_t<std::is_floating_point_v<S>>>
inline S lane0(S a) { return a; }

// ---- SIMD lanes ------------------------------------------------------------
template <class S, class A>
inline xsimd::batch<S, A> select(const xsimd::batch_bool<S, A>& m, const xsimd::batch<S, A>& a, const xsimd::batch<S, A>& b) {
    return xsimd::select(m, a, b);
}
// select(m, a, 0) as one AND where the mask is a vector of all-ones or
// all-zeros lanes: GCC rewrites a blend with zero into a sign compare plus an
// AND (docs/history/performance-2026.md has the count). Masks in
// mask registers (AVX-512 batches) keep the select.
template <class S, class A>
inline xsimd::batch<S, A> keep(const xsimd::batch_bool<S, A>& m, const xsimd::batch<S, A>& a) {
    using B = xsimd::batch<S, A>;
    if constexpr (std::is_base_of_v<xsimd::avx512f, A>) return xsimd::select(m, a, B(S(0)));
    else return B(static_cast<typename xsimd::batch_bool<S, A>::register_type>(m)) & a;
}
// xsimd 8.1 has no AVX-512 fma kernel: its generic one is a * b + c, two
// roundings under -ffp-contract=off, where every other unit fuses.
template <class S, class A>
inline xsimd::batch<S, A> fma(const xsimd::batch<S, A>& a, const xsimd::batch<S, A>& b, const xsimd::batch<S, A>& c) {
#if defined(__AVX512F__)
    if constexpr (std::is_base_of_v<xsimd::avx512f, A> && std::is_same_v<S, double>) return _mm512_fmadd_pd(a, b, c);
    else if constexpr (std::is_base_of_v<xsimd::avx512f, A>) return _mm512_fmadd_ps(a, b, c);
    else
#endif
        return xsimd::fma(a, b, c);
}
// On x86 xsimd's min/max are minps/maxps (and their pd, ymm, zmm forms):
// exactly a < b ? a : b, in one instruction instead of a compare and a blend.
template <class S, class A>
inline xsimd::batch<S, A> min(const xsimd::batch<S, A>& a, const xsimd::batch<S, A>& b) {
#if defined(__SSE2__)
    return xsimd::min(a, b);
#else
    return xsimd::select(a < b, a, b);
#endif
}
template <class S, class A>
inline xsimd::batch<S, A> max(const xsimd::batch<S, A>& a, const xsimd::batch<S, A>& b) {
#if defined(__SSE2__)
    return xsimd::max(a, b);
#else
    return xsimd::select(a > b, a, b);
#endif
}
template <class S, class A>
inline xsimd::batch<S, A> sqrt(const xsimd::batch<S, A>& a) { return xsimd::sqrt(a); }
template <class S, class A>
inline xsimd::batch<S, A> abs(const xsimd::batch<S, A>& a) { return xsimd::abs(a); }
template <class S, class A>
inline xsimd::batch<S, A> copysign(const xsimd::batch<S, A>& a, const xsimd::batch<S, A>& b) { return xsimd::copysign(a, b); }
template <class S, class A>
inline xsimd::batch<S, A> with_sign_of(const xsimd::batch<S, A>& a, const xsimd::batch<S, A>& b) {
    return a | (b & xsimd::batch<S, A>(S(-0.0)));
}
template <class S, class A>
inline xsimd::batch_bool<S, A> isfinite(const xsimd::batch<S, A>& a) { return xsimd::isfinite(a); }
template <class S, class A>
inline xsimd::batch_bool<S, A> isnan(const xsimd::batch<S, A>& a) { return xsimd::isnan(a); }
template <class S, class A>
inline xsimd::batch<S, A> pow(const xsimd::batch<S, A>& a, const xsimd::batch<S, A>& b) { return xsimd::pow(a, b); }
template <class S, class A>
inline xsimd::batch_bool<S, A> not_(const xsimd::batch_bool<S, A>& m) { return ~m; }
template <class S, class A>
inline bool any(const xsimd::batch_bool<S, A>& m) { return xsimd::any(m); }
template <class S, class A>
inline bool all(const xsimd::batch_bool<S, A>& m) { return xsimd::all(m); }
template <class S, class A>
inline int count(const xsimd::batch_bool<S, A>& m) {
#if defined(__AVX__)
    if constexpr (std::is_same_v<S, float> && xsimd::batch<S, A>::size == 8)
        return __builtin_popcount(unsigned(_mm256_movemask_ps(m)));
#endif
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
// (Double batches have no rcpps/rsqrtps estimate: double lanes run the f64
// mode, IEEE only; AVX-512 units have rcp14/rsqrt14 for them below.)
#if defined(__AVX512F__) && defined(__AVX512VL__)
// rcp14/rsqrt14 on whatever register the batch lives in (xmm, ymm or zmm).
template <class S, class A>
inline xsimd::batch<S, A> rcp14_estimate(const xsimd::batch<S, A>& x) {
    using B = xsimd::batch<S, A>;
    if constexpr (std::is_same_v<S, float> && sizeof(B) == 16) return B(_mm_rcp14_ps(x));
    else if constexpr (std::is_same_v<S, float> && sizeof(B) == 32) return B(_mm256_rcp14_ps(x));
    else if constexpr (std::is_same_v<S, float> && sizeof(B) == 64) return B(_mm512_rcp14_ps(x));
    else if constexpr (sizeof(B) == 16) return B(_mm_rcp14_pd(x));
    else if constexpr (sizeof(B) == 32) return B(_mm256_rcp14_pd(x));
    else return B(_mm512_rcp14_pd(x));
}
template <class S, class A>
inline xsimd::batch<S, A> rsqrt14_estimate(const xsimd::batch<S, A>& x) {
    using B = xsimd::batch<S, A>;
    if constexpr (std::is_same_v<S, float> && sizeof(B) == 16) return B(_mm_rsqrt14_ps(x));
    else if constexpr (std::is_same_v<S, float> && sizeof(B) == 32) return B(_mm256_rsqrt14_ps(x));
    else if constexpr (std::is_same_v<S, float> && sizeof(B) == 64) return B(_mm512_rsqrt14_ps(x));
    else if constexpr (sizeof(B) == 16) return B(_mm_rsqrt14_pd(x));
    else if constexpr (sizeof(B) == 32) return B(_mm256_rsqrt14_pd(x));
    else return B(_mm512_rsqrt14_pd(x));
}
#else
template <class T>
inline T rcp14_estimate(const T&) { static_assert(sizeof(T) == 0, "fast14/approx14 need -mavx512f -mavx512vl"); return {}; }
template <class T>
inline T rsqrt14_estimate(const T&) { static_assert(sizeof(T) == 0, "fast14/approx14 need -mavx512f -mavx512vl"); return {}; }
#endif
// Packet I/O for batches: float (or int32) arrays in, float arrays out.
// Double batches convert with one instruction where the unit's ISA has it
// (xsimd 8.1 converts element by element).
template <class B>
inline B load_floats(const float* p) {
    [[maybe_unused]] constexpr std::size_t n = B::size;
    if constexpr (std::is_same_v<typename B::value_type, float>) return B::load_unaligned(p);
#if defined(__AVX512F__)
    else if constexpr (n == 8) return B(_mm512_cvtps_pd(_mm256_loadu_ps(p)));
#endif
#if defined(__AVX__)
    else if constexpr (n == 4) return B(_mm256_cvtps_pd(_mm_loadu_ps(p)));
#endif
    else return B::load_unaligned(p);
}
template <class B>
inline B load_ints(const std::int32_t* p) {
    [[maybe_unused]] constexpr std::size_t n = B::size;
    if constexpr (std::is_same_v<typename B::value_type, float>) return B::load_unaligned(p);
#if defined(__AVX512F__)
    else if constexpr (n == 8) return B(_mm512_cvtepi32_pd(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(p))));
#endif
#if defined(__AVX__)
    else if constexpr (n == 4) return B(_mm256_cvtepi32_pd(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p))));
#endif
    else return B::load_unaligned(p);
}
template <class B>
inline void store_floats(float* p, const B& v) {
    [[maybe_unused]] constexpr std::size_t n = B::size;
    if constexpr (std::is_same_v<typename B::value_type, float>) v.store_unaligned(p);
#if defined(__AVX512F__)
    else if constexpr (n == 8) _mm256_storeu_ps(p, _mm512_cvtpd_ps(v));
#endif
#if defined(__AVX__)
    else if constexpr (n == 4) _mm_storeu_ps(p, _mm256_cvtpd_ps(v));
#endif
    else v.store_unaligned(p);
}

template <class S, class A>
inline xsimd::batch<S, A> gather(const S* base, const xsimd::batch<S, A>& index) {
    using B = xsimd::batch<S, A>;
#if defined(__AVX2__)
    // xsimd 8.1 emulates float gathers with 8 inserts and a chain of blends
    // (~34 instructions); one vgatherdps does it.
    if constexpr (std::is_same_v<S, float> && B::size == 8)
        return B(_mm256_i32gather_ps(base, _mm256_cvttps_epi32(index), 4));
#endif
#if defined(__AVX512F__)
    if constexpr (std::is_same_v<S, float> && B::size == 16)
        return B(_mm512_i32gather_ps(_mm512_cvttps_epi32(index), base, 4));
#endif
    using I = xsimd::as_integer_t<S>;
    return B::gather(base, xsimd::batch_cast<I>(index));
}
// E: std::uint16_t or std::int16_t entries.
template <class E, class S, class A>
inline xsimd::batch<S, A> gather16(const E* base, const xsimd::batch<S, A>& index) {
    using B = xsimd::batch<S, A>;
    static_assert(sizeof(E) == 2, "16-bit entries");
    [[maybe_unused]] constexpr bool kSigned = std::is_signed_v<E>;
#if defined(__AVX2__)
    if constexpr (std::is_same_v<S, float> && B::size == 8) {
        const __m256i v = _mm256_i32gather_epi32(reinterpret_cast<const int*>(base), _mm256_cvttps_epi32(index), 2);
        const __m256i e = kSigned ? _mm256_srai_epi32(_mm256_slli_epi32(v, 16), 16)
                                  : _mm256_and_si256(v, _mm256_set1_epi32(0xffff));
        return B(_mm256_cvtepi32_ps(e));
    }
#endif
#if defined(__AVX512F__)
    if constexpr (std::is_same_v<S, float> && B::size == 16) {
        const __m512i v = _mm512_i32gather_epi32(_mm512_cvttps_epi32(index), base, 2);
        const __m512i e = kSigned ? _mm512_srai_epi32(_mm512_slli_epi32(v, 16), 16)
                                  : _mm512_and_si512(v, _mm512_set1_epi32(0xffff));
        return B(_mm512_cvtepi32_ps(e));
    }
#endif
    alignas(64) S at[B::size], out[B::size];
    index.store_aligned(at);
    for (std::size_t i = 0; i < B::size; ++i) out[i] = S(base[std::size_t(at[i])]);
    return B::load_aligned(out);
}
template <class S, class A>
inline bool uniform_on(const xsimd::batch<S, A>& index, const xsimd::batch_bool<S, A>& m, int& value) {
    using B = xsimd::batch<S, A>;
#if defined(__AVX2__)
    if constexpr (std::is_same_v<S, float> && B::size == 8) {
        const unsigned on = unsigned(_mm256_movemask_ps(m));
        const __m256 first = _mm256_permutevar8x32_ps(index, _mm256_set1_epi32(on ? __builtin_ctz(on) : 0));
        value = int(_mm256_cvtss_f32(first));
        return ((unsigned(_mm256_movemask_ps(_mm256_cmp_ps(index, first, _CMP_EQ_OQ))) | ~on) & 0xffu) == 0xffu;
    }
#endif
    alignas(64) S idx[B::size];
    alignas(64) S on[B::size];
    index.store_aligned(idx);
    xsimd::select(m, B(S(1)), B(S(0))).store_aligned(on);
    std::size_t first = 0;
    while (first + 1 < B::size && on[first] == S(0)) ++first;
    value = int(idx[first]);
    for (std::size_t i = 0; i < B::size; ++i)
        if (on[i] != S(0) && idx[i] != idx[first]) return false;
    return true;
}

template <class S, class A>
inline unsigned bits(const xsimd::batch_bool<S, A>& m) {
#if defined(__AVX__)
    if constexpr (std::is_same_v<S, float> && xsimd::batch<S, A>::size == 8) return unsigned(_mm256_movemask_ps(m));
#endif
    using B = xsimd::batch<S, A>;
    alignas(64) S on[B::size];
    xsimd::select(m, B(S(1)), B(S(0))).store_aligned(on);
    unsigned b = 0;
    for (std::size_t i = 0; i < B::size; ++i) b |= unsigned(on[i] != S(0)) << i;
    return b;
}
namespace detail {
// Every lane set to op over all lanes: log2(width) rotate-and-combine steps.
template <class S, class A, class Op>
inline xsimd::batch<S, A> horizontal(const xsimd::batch<S, A>& a, Op op) {
    using B = xsimd::batch<S, A>;
#if defined(__AVX__)
    if constexpr (std::is_same_v<S, float> && B::size == 8) {
        B v = op(a, B(_mm256_permute2f128_ps(a, a, 1)));
        v = op(v, B(_mm256_permute_ps(v, 0x4e)));
        return op(v, B(_mm256_permute_ps(v, 0xb1)));
    }
#endif
    alignas(64) S tmp[B::size];
    a.store_aligned(tmp);
    S r = tmp[0];
    for (std::size_t i = 1; i < B::size; ++i) r = op(r, tmp[i]);
    return B(r);
}
}  // namespace detail
template <class S, class A>
inline xsimd::batch<S, A> hmin(const xsimd::batch<S, A>& a) {
    return detail::horizontal(a, [](const auto& x, const auto& y) { return lane::min(x, y); });
}
template <class S, class A>
inline xsimd::batch<S, A> hmax(const xsimd::batch<S, A>& a) {
    return detail::horizontal(a, [](const auto& x, const auto& y) { return lane::max(x, y); });
}
template <class S, class A>
inline S lane0(const xsimd::batch<S, A>& v) {
#if defined(__AVX__)
    if constexpr (std::is_same_v<S, float> && xsimd::batch<S, A>::size == 8) return _mm256_cvtss_f32(v);
#endif
    return v.get(0);
}
// Double lanes reading a float scene array.
template <class A>
inline xsimd::batch<double, A> gather(const float* base, const xsimd::batch<double, A>& index) {
    using B = xsimd::batch<double, A>;
    constexpr std::size_t n = B::size;
#if defined(__AVX512F__)
    if constexpr (n == 8) return B(_mm512_cvtps_pd(_mm256_i32gather_ps(base, _mm512_cvttpd_epi32(index), 4)));
#endif
#if defined(__AVX2__)
    if constexpr (n == 4) return B(_mm256_cvtps_pd(_mm_i32gather_ps(base, _mm256_cvttpd_epi32(index), 4)));
#endif
    alignas(64) double idx[n], out[n];
    index.store_aligned(idx);
    for (std::size_t i = 0; i < n; ++i) out[i] = double(base[long(idx[i])]);
    return B::load_aligned(out);
}

// ---- precision-mode arithmetic ---------------------------------------------
// The stated error bound of each function and mode is in precision.hpp.
// exact and f64 use IEEE divide and sqrt (f64 kernels run on double lanes);
// the others start from a hardware estimate: rcpps/rsqrtps (fast, approx) or
// AVX-512 rcp14/rsqrt14 (fast14, approx14), refined by one Newton step in
// the fast modes.
// In the perturbed units these functions live in their own inline namespace,
// so the linker never merges them with the library's of the same lane type.
#if defined(OCTRAY_PERTURBED_ESTIMATES)
inline namespace perturbed_estimates {
// The instructions' specified relative error (precision.hpp's approx bounds).
template <Precision P>
inline constexpr double kEstimateLimit =
    P == Precision::fast14 || P == Precision::approx14 ? rcp_bound(Precision::approx14) : rcp_bound(Precision::approx);
template <Precision P, class T>
inline T estimate_rcp(const T& x) {
    return perturbed::each(x, kEstimateLimit<P>, [](float v, double e) { return perturbed::rcp(v, e); });
}
template <Precision P, class T>
inline T estimate_rsqrt(const T& x) {
    return perturbed::each(x, kEstimateLimit<P>, [](float v, double e) { return perturbed::rsqrt(v, e); });
}
#else
template <Precision P, class T>
inline T estimate_rcp(const T& x) {
    if constexpr (P == Precision::fast14 || P == Precision::approx14) return lane::rcp14_estimate(x);
    else return lane::rcp_estimate(x);
}
template <Precision P, class T>
inline T estimate_rsqrt(const T& x) {
    if constexpr (P == Precision::fast14 || P == Precision::approx14) return lane::rsqrt14_estimate(x);
    else return lane::rsqrt_estimate(x);
}
#endif
inline constexpr bool newton_step(Precision p) { return p == Precision::fast || p == Precision::fast14; }

// 1/x. Newton step r' = r (2 - x r), written r + r (1 - x r) with FMAs.
template <Precision P, class T>
inline T rcp(const T& x) {
    if constexpr (is_ieee(P)) {
        return T(1) / x;
    } else {
        T r = estimate_rcp<P>(x);
        if constexpr (newton_step(P)) r = lane::fma(r, lane::fma(-x, r, T(1)), r);
        return r;
    }
}
// a/b.
template <Precision P, class T>
inline T div(const T& a, const T& b) {
    if constexpr (is_ieee(P)) return a / b;
    else return a * rcp<P>(b);
}
// 1/lane::sqrt(x). Newton step r' = r (1.5 - 0.5 x r^2).
template <Precision P, class T>
inline T rsqrt(const T& x) {
    if constexpr (is_ieee(P)) {
        return T(1) / lane::sqrt(x);
    } else {
        T r = estimate_rsqrt<P>(x);
        if constexpr (newton_step(P)) {
            const T half_x = T(0.5) * x;
            r = r * lane::fma(-half_x, r * r, T(1.5));
        }
        return r;
    }
}
#if defined(OCTRAY_PERTURBED_ESTIMATES)
}  // namespace perturbed_estimates
#endif

}  // namespace octray::lane
