// kernels/lanes/lane_pow.hpp — x^y for positive float lanes, one code for every T.
//
// The tone map's gamma step (docs/shading-model.md: c^(1/gamma)) on float lanes. libm's
// powf (the scalar path) and xsimd 8.1's pow (the SIMD path) are different
// algorithms, and xsimd's is slow (about a hundred cycles a batch): the same exp2/log2
// reduction here serves both paths, so they agree bit for bit and the
// SIMD/scalar ratio compares like with like. (Cody & Waite argument
// reduction; Muller, "Elementary Functions", 3rd ed., ch. 11.)
//
//   x = 2^e m, m in [sqrt(1/2), sqrt(2));  log2 m = 2/ln2 atanh(s), s = (m-1)/(m+1),
//   |s| <= 0.1716, odd series to s^9 (truncation < 2^-31 relative);
//   both polynomials by Estrin's scheme: the function is latency-bound;
//   y log2 x = y e + y log2 m, with y e split exactly by an FMA, so the
//   reduced argument f = (y e - n) + ... carries no error from the size of
//   y log2 x; 2^f on [-1/2, 1/2] by its Taylor polynomial of degree 7
//   (truncation < 2^-27 relative); 2^n applied as two exact powers of two, so
//   results overflow to +inf and underflow gradually.
// Error: <= pow_max_ulp(y) = 2 + 1.25 |y| ulp against x^y in double, for
// normal x > 0 and normal results (tests/test_precision.cpp measures it on
// every unit; measured 1.3 ulp at y = 1/2.2, 17.0 at y = 16): the error of
// log2 m, ~1.5 u, is scaled by y. x^y is exactly 1 for x == 1. Inputs
// outside x > 0 finite are the caller's (the tone map maps c <= 0 to 0
// before, NaN never reaches it).
#pragma once

#include "kernels/lanes/lane.hpp"

#include <cstdint>
#include <cstring>
#include <type_traits>

namespace octray::lane {

inline constexpr double pow_max_ulp(double y) { return 2 + 1.25 * (y < 0 ? -y : y); }

// Bits of a float lane as int32 lanes and back, and int <-> float conversion.
inline std::int32_t float_bits(float x) {
    std::int32_t i;
    std::memcpy(&i, &x, sizeof i);
    return i;
}
inline float bits_float(std::int32_t i) {
    float x;
    std::memcpy(&x, &i, sizeof x);
    return x;
}
template <class A>
inline xsimd::batch<std::int32_t, A> float_bits(const xsimd::batch<float, A>& x) {
    return xsimd::bitwise_cast<xsimd::batch<std::int32_t, A>>(x);
}
template <class A>
inline xsimd::batch<float, A> bits_float(const xsimd::batch<std::int32_t, A>& i) {
    return xsimd::bitwise_cast<xsimd::batch<float, A>>(i);
}
inline float int_to_float(std::int32_t i) { return float(i); }
template <class A>
inline xsimd::batch<float, A> int_to_float(const xsimd::batch<std::int32_t, A>& i) { return xsimd::to_float(i); }
inline std::int32_t float_to_int(float x) { return std::int32_t(x); }  // x integral
template <class A>
inline xsimd::batch<std::int32_t, A> float_to_int(const xsimd::batch<float, A>& x) { return xsimd::to_int(x); }
// Round to nearest integer, ties away or to even (either: the reduction only
// needs |x - round(x)| <= 1/2). x + 1.5 * 2^23 - 1.5 * 2^23 for |x| < 2^22.
template <class T>
inline T round_small(const T& x) {
    const T magic(12582912.0f);  // 1.5 * 2^23
    return (x + magic) - magic;
}

// 2^k as a float for integral k in [-126, 127] (carried as an exact float).
template <class T>
inline T exp2_int(const T& k) {
    const auto i = float_to_int(k);
    return bits_float((i + decltype(i)(127)) << 23);
}

// x^y for x > 0 finite, float lanes (see the header comment for the error).
template <class T>
inline T pow_positive(const T& x, const T& y) {
    static_assert(std::is_same_v<Scalar<T>, float>, "float lanes; double lanes use lane::pow");
    // Subnormal x: scale by 2^24 first (exact) and take 24 off the exponent.
    const Mask<T> tiny = x < T(0x1p-126f);
    const T xs = lane::select(tiny, x * T(0x1p24f), x);
    const auto bits = float_bits(xs);
    using Ints = std::decay_t<decltype(bits)>;
    T e = int_to_float((bits >> 23) - Ints(127)) - lane::keep(tiny, T(24));
    T m = bits_float((bits & Ints(0x007fffff)) | Ints(0x3f800000));  // [1, 2)
    const Mask<T> upper = m > T(1.41421356f);
    m = lane::select(upper, m * T(0.5f), m);  // exact
    e = lane::select(upper, e + T(1), e);
    // log2 m = s (c1 + c3 s^2 + ... + c9 s^8), c_k = 2 / (k ln 2); m - 1 is exact.
    constexpr double c1 = 2 / 0.6931471805599453, c3 = c1 / 3, c5 = c1 / 5, c7 = c1 / 7, c9 = c1 / 9;
    const T s = (m - T(1)) / (m + T(1)), s2 = s * s, s4 = s2 * s2;
    const T poly = lane::fma(s4, lane::fma(s4, T(float(c9)), lane::fma(s2, T(float(c7)), T(float(c5)))),
                             lane::fma(s2, T(float(c3)), T(float(c1))));
    const T log2m = s * poly;
    // y log2 x = ye + (ye_lo + y log2m), ye + ye_lo = y e exactly; n is the
    // nearest integer. ye - n is exact where |ye| >= |y log2m| + 1/2 (Sterbenz),
    // else off by at most u |y log2m|, as is the bracket: f carries an error of
    // a few u |y| whatever the size of y log2 x.
    const T ye = y * e, ye_lo = lane::fma(y, e, T(0) - ye), rest = lane::fma(y, log2m, ye_lo);
    // 2^n with n in [-252, 254] spans every float result (beyond, the product
    // below is 0 or +inf); clamping f to [-1, 1] then keeps 2^f positive
    // there and changes nothing elsewhere (|f| <= 1/2 + a few ulp).
    const T n = round_small(lane::min(lane::max(ye + rest, T(-252)), T(254)));
    const T f = lane::min(lane::max((ye - n) + rest, T(-1)), T(1));
    // 2^f = 1 + f q(f), q(f) = sum_k (ln2)^k f^(k-1) / k!, k = 1..7, by
    // Estrin's scheme (four levels deep instead of Horner's seven: the chain
    // is latency-bound); the 1 is added last, in one rounding.
    constexpr double l1 = 0.6931471805599453, l2 = l1 * l1 / 2, l3 = l2 * l1 / 3, l4 = l3 * l1 / 4, l5 = l4 * l1 / 5,
                     l6 = l5 * l1 / 6, l7 = l6 * l1 / 7;
    const T f2 = f * f, f4 = f2 * f2;
    const T q12 = lane::fma(f, T(float(l2)), T(float(l1))), q34 = lane::fma(f, T(float(l4)), T(float(l3)));
    const T q56 = lane::fma(f, T(float(l6)), T(float(l5))), q7 = lane::fma(f2, T(float(l7)), q56);
    const T p = lane::fma(f, lane::fma(f4, q7, lane::fma(f2, q34, q12)), T(1));
    // 2^n = 2^n1 2^n2, n1 = round(n / 2): both in [-126, 127], normal floats.
    const T n1 = round_small(n * T(0.5f));
    return (p * exp2_int(n1)) * exp2_int(n - n1);
}

}  // namespace octray::lane
