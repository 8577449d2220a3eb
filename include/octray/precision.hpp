// octray/precision.hpp — precision modes of the packet kernels and their stated error bounds.
//
// A mode decides how a kernel divides and takes (reciprocal) square roots,
// and for `f64` in which type it computes. It is a template parameter of
// every kernel: the mode costs nothing at run time and each mode is a
// separate, separately tested instantiation.
//
// Stated bounds (u = 2^-24, the unit roundoff of float). They hold for
// arguments and results in the normal float range; tests/test_precision.cpp
// checks each on randomized inputs (fixed seed) for every ISA and path built.
//
//   mode      how                                   1/x (rel.)     1/sqrt(x) (rel.)
//   exact     IEEE divide, sqrt                     2^-24  (0.5 ulp)  2^-23  (sqrt, then divide)
//   fast      rcpps/rsqrtps + one Newton step       2^-22          2^-21
//   approx    rcpps/rsqrtps raw                     1.5*2^-12      1.5*2^-12
//   fast14    AVX-512 rcp14/rsqrt14 + Newton        2^-22          2^-22
//   approx14  AVX-512 rcp14/rsqrt14 raw             2^-14          2^-14
//   f64       8 double lanes, IEEE; float only at   2^-24 + 2^-51  2^-24 + 2^-51  (double result
//             the packet interface                                                   rounded to float)
//
// Derivations. A raw estimate r0 = (1+e)/x, |e| <= E (Intel SDM: E = 1.5*2^-12
// for rcpps/rsqrtps, E = 2^-14 for rcp14/rsqrt14). The reciprocal's Newton
// step r0 + r0*(1 - x*r0) in two FMAs leaves e^2 plus three roundings:
// 2.25u + 3u (fast) or 0.02u + 3u (fast14) < 4u = 2^-22. The rsqrt step
// r0*(1.5 - 0.5*x*r0^2) leaves 1.5*e^2 plus four roundings: 3.4u + 3u (fast)
// < 2^-21, 3.1u (fast14) < 2^-22.
//
// Not a mode's choice: the tone map's gamma step c^(1/gamma) is
// lane_pow.hpp's x^y in every float mode (within 2 + 1.25|y| ulp, measured
// 1.3 ulp at gamma 2.2), libm's / xsimd's double pow in f64.
//
// Composite building blocks (normalize(v) = v * rsqrt(v.v); n.l = (n.v) * rsqrt(v.v)
// for unit n, as the point-light shading computes it): absolute error
// <= rsqrt bound + 2^-21 (the FMA dot product and the final product add < 6u).
//
// End to end (radiance of a render against the double reference): the error
// of a mode is its building-block error amplified by the geometry — a hit
// point off by a relative dt/t moves a sphere's normal by (t/R) dt/t, and a
// point light's direction by (t/r) dt/t. With S the pixel's radiance with
// every light at n.l = 1 (tools/verify.hpp) and
//     kappa = 1 + max over the image's hits of t/R (spheres: hit distance over
//             radius) and t/r (point lights: hit distance over light distance),
// the stated bound is
//     max |L - L_ref| / S  <=  end_to_end_bound(mode) * kappa,
//     end_to_end_bound(mode) = 8 * max(rsqrt_bound(mode), 2u) + 32 u,
// on every lane where the packet path and the reference hit the same
// primitive, except on the edges of box faces and of shadows: lanes with a
// 3x3 neighbour on the same object where the reference shows another face of
// the box or another set of visible lights, box hits within the mode's
// position error (end_to_end_bound(mode) * t) of their face's border, and
// sphere hits whose ray passes that close to the sphere's outline. There a
// hit point off by the mode's position error may take the other face or
// visibility, or the ray miss, a legal answer as on a silhouette. The other
// lanes (hit/miss or primitive differs) lie on silhouettes. The bands are in
// world units, not pixels: a 3x3 neighbourhood alone shrinks with the pixel,
// and at 1920x1440 lanes 1e-4 from a box edge (approx: 0.22 S) and sphere
// lanes at |n.d| = 0.006 (exact: 4.2e-5 S, 1.04x the bound) slipped past it.
// Not proven: outside the sphere band the normal still carries a grazing
// factor 1/|n.d| (a ray moved across by e moves the normal by e/(R |n.d|)),
// which kappa's t/R does not hold; the band keeps |n.d| >= ~sqrt(2 band t/R),
// and the tests measure the margin (default at 1920x1440, exact: 0.81 of the
// bound at |n.d| = 0.010). kappa is the scene's condition: stiff scenes
// (a small sphere far away, a planet seen from close) have a large one, and
// the float modes' error grows with it; f64 keeps its arithmetic error small
// but still reads a float scene and float packets.
#pragma once

namespace octray {

enum class Precision {
    exact,     // IEEE-754 division and sqrt (correctly rounded)
    fast,      // hardware rcp/rsqrt estimates refined by one Newton-Raphson step
    approx,    // raw hardware estimates (rcpps/rsqrtps: rel. error <= 1.5 * 2^-12)
    fast14,    // AVX-512 rcp14/rsqrt14 estimates refined by one Newton-Raphson step
    approx14,  // raw AVX-512 rcp14/rsqrt14 estimates (rel. error < 2^-14)
    f64,       // the kernel in double lanes (8 per packet), IEEE divide and sqrt
};
inline constexpr int kPrecisionCount = 6;
inline constexpr Precision kPrecisions[kPrecisionCount] = {Precision::exact,  Precision::fast,     Precision::approx,
                                                            Precision::fast14, Precision::approx14, Precision::f64};

inline constexpr const char* precision_name(Precision p) {
    switch (p) {
    case Precision::exact: return "exact";
    case Precision::fast: return "fast";
    case Precision::approx: return "approx";
    case Precision::fast14: return "fast14";
    case Precision::approx14: return "approx14";
    case Precision::f64: return "double";
    }
    return "?";
}

// Modes that need AVX-512 (F + VL) at run time.
inline constexpr bool needs_avx512(Precision p) { return p == Precision::fast14 || p == Precision::approx14; }
// Modes that divide and take square roots the IEEE way (in float or double).
inline constexpr bool is_ieee(Precision p) { return p == Precision::exact || p == Precision::f64; }

// ---- stated bounds (see the table above) ------------------------------------
inline constexpr double kUnitRoundoff = 1.0 / 16777216.0;  // 2^-24

// Relative error of 1/x, float result.
inline constexpr double rcp_bound(Precision p) {
    switch (p) {
    case Precision::exact: return kUnitRoundoff;
    case Precision::fast: return 4 * kUnitRoundoff;
    case Precision::approx: return 1.5 / 4096.0;
    case Precision::fast14: return 4 * kUnitRoundoff;
    case Precision::approx14: return 1.0 / 16384.0;
    case Precision::f64: return kUnitRoundoff + 0x1p-51;  // double result rounded to float
    }
    return 1;
}
// Relative error of 1/sqrt(x), float result.
inline constexpr double rsqrt_bound(Precision p) {
    switch (p) {
    case Precision::exact: return 2 * kUnitRoundoff;
    case Precision::fast: return 8 * kUnitRoundoff;
    case Precision::approx: return 1.5 / 4096.0;
    case Precision::fast14: return 4 * kUnitRoundoff;
    case Precision::approx14: return 1.0 / 16384.0;
    case Precision::f64: return kUnitRoundoff + 0x1p-51;
    }
    return 1;
}
// Relative error of a/b: the reciprocal's error plus one rounding (IEEE modes: one rounding).
inline constexpr double div_bound(Precision p) { return is_ieee(p) ? rcp_bound(p) : rcp_bound(p) + kUnitRoundoff; }
// Absolute error of each component of normalize(v), and of n.l = (n.v) * rsqrt(v.v) for unit n.
inline constexpr double normalize_bound(Precision p) { return rsqrt_bound(p) + 8 * kUnitRoundoff; }
inline constexpr double ndotl_bound(Precision p) { return normalize_bound(p); }
// Shadow rays start off the surface by this much relative to |p| + |p - o|
// (hit point and camera ray origin): more than the hit point's error, so a
// lit surface never shadows itself (no "shadow acne").
// (The kernels use the larger of this and 1e-4 |p|.)
inline constexpr double shadow_offset(Precision p) { return 8 * rsqrt_bound(p); }
// max |L - L_ref| / S per unit of kappa (see the header comment): the radiance
// error of a whole render on lanes where both paths hit the same primitive.
// f64 has exact's: it reads and writes the same float scene and packets.
inline constexpr double end_to_end_bound(Precision p) {
    return 8 * (rsqrt_bound(p) > 2 * kUnitRoundoff ? rsqrt_bound(p) : 2 * kUnitRoundoff) + 32 * kUnitRoundoff;
}

}  // namespace octray
