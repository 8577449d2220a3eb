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
// Where the modes differ. Whatever decides which primitive a ray hits is
// IEEE in every mode: the box test's slab reciprocals, the t of planes,
// disks, rectangles and triangles, and the sphere's root c/q
// (kernels/trace/ray.hpp, kernels/geometry/), as are the BVH walks'
// reciprocals and 1/(d.d). So the modes differ in the shading's point lights
// (1/|v|, n.l, 1/r^2) and the tone map's reciprocal only; their hits, t and
// normals are exact's, and a shadow ray toward a point light ends at the
// light's own t (kernels/shading/shade.hpp). Why: docs/accuracy.md.
//
// Composite bounds (every mode; the functions below): normalize(v) and n.l
// within normalize_bound; a sphere hit's unit normal within
// sphere_normal_bound(cos) = u (16 + 4 / cos); a whole render's radiance
// within end_to_end_bound(mode) * kappa plus a sphere term, relative to the
// pixel's radiance with every light at n.l = 1, on lanes where the packet path
// and the reference hit the same primitive. Their derivations, and where each
// holds: docs/accuracy-derivations.md.
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
// lit surface never shadows itself (no "shadow acne"). A sphere's hit point
// c + R n carries no t-sized error: there relative to |p| alone.
// (The kernels use the larger of this and 1e-4 |p|.)
// The hit point is IEEE in every mode: the primitive tests divide exactly in
// every mode (see "Where the modes differ" above), so the estimate modes'
// point carries exact's error and their shadow rays take exact's offset. An
// offset scaled to the estimate's own error (8 * 1.5 * 2^-12 (|p| + t) for
// approx) lifted the ray past nearby geometry (a crease, a thin wall) and
// flipped shadows on meshes.
inline constexpr double shadow_offset(Precision p) {
    return 8 * rsqrt_bound(p == Precision::f64 ? Precision::f64 : Precision::exact);
}
// |n - n_exact| of a sphere hit's unit normal on float inputs taken as exact
// (every mode; docs/accuracy.md derives it), cos = |n.d| / |d| at the hit; add
// 42 u^2 |o - c| / r for |o - c| beyond ~4e5 r.
inline constexpr double sphere_normal_bound(double cos_theta) { return kUnitRoundoff * (16 + 4 / cos_theta); }
// max |L - L_ref| / S per unit of kappa (docs/accuracy.md): the radiance
// error of a whole render on lanes where both paths hit the same primitive,
// besides the sphere term. f64 has exact's: it reads and writes the same
// float scene and packets.
inline constexpr double end_to_end_bound(Precision p) {
    return 8 * (rsqrt_bound(p) > 2 * kUnitRoundoff ? rsqrt_bound(p) : 2 * kUnitRoundoff) + 32 * kUnitRoundoff;
}

}  // namespace octray
