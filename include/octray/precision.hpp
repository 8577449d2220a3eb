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
// Where the modes differ. Whatever decides which primitive a ray hits is
// IEEE in every mode: the box test's slab reciprocals, the t of planes,
// disks, rectangles and triangles, and the sphere's root c/q (kernels/ray.hpp,
// planar.hpp, triangle.hpp, sphere.hpp), as are the BVH walks' reciprocals
// and 1/(d.d). An estimate there (2^-12 of t, a different error per slab)
// chose the slab of entry, the nearer of a box and the plane it stands on,
// a disk's rim and the face a box normal takes, far from any silhouette:
// rows of pixels on the wrong primitive or face (0.1-0.7 S). So the modes
// differ in the shading's point lights (1/|v|, n.l, 1/r^2) and the tone map's
// reciprocal only, and their hits, t and normals are exact's; a shadow ray
// toward a point light ends at the light's own t (kernels/shade.hpp).
//
// Not a mode's choice: the tone map's gamma step c^(1/gamma) is
// lane_pow.hpp's x^y in every float mode (within 2 + 1.25|y| ulp, measured
// 1.3 ulp at gamma 2.2), libm's / xsimd's double pow in f64.
//
// Composite building blocks (normalize(v) = v * rsqrt(v.v); n.l = (n.v) * rsqrt(v.v)
// for unit n, as the point-light shading computes it): absolute error
// <= rsqrt bound + 2^-21 (the FMA dot product and the final product add < 6u).
//
// Sphere normals. The kernels form a sphere hit's p - c in the
// sphere's own frame (kernels/sphere.hpp, sphere_offset), not from
// p = o + t d, whose float alone is off by u t / 2 (and t by a few u t): for
// the float inputs o, d, c, r taken as exact,
//     |n - n_exact| <= sphere_normal_bound(cos) = u (16 + 4 / cos),
//     cos = |n.d| / |d|, plus 42 u^2 |o - c| / r (below 1u while |o - c| < 4e5 r),
// in every precision mode (only IEEE sqrt and the IEEE 1/(d.d) and 1/r enter).
// Derivation: f = o - c is held exactly as fh + fl (TwoSum). The foot
// q1 = fh - d (f.d)/(d.d) + fl: 1/(d.d) and f.d carry ~6u, which moves q1
// along d only, by e1 <= 7u |f|; across d each component is rounded once from
// its own size (an FMA, then + fl): <= u |q1|. The second projection leaves
// along d e2 <= 5u |q1| and rounds u/2 |q| more across. So q = perp + (across,
// <= 1.5u r) + (along d, <= 5u r), with |q1| <= r + e1 giving the u^2 |f|
// terms. h^2 = r^2 - |q|^2 (r^2 split exactly): the dot product's 1.5u r^2,
// 2 perp.(across error) <= 3u r^2 and two roundings of at most u/2 h^2 each,
// so |h - h_exact| <= 2.25u r^2 / h + 2.5u h (sqrt, 1/(d.d) and their product
// the 2.5u h); h / r = cos. (From an origin near the surface, where
// b^2/a + |c| < r^2 / 2, h^2 = b^2/a - c instead, c = |f|^2 - r^2 compensated
// from the exact f: ~5u (b^2/a + |c|) < 2.5u r^2, so 1.25u r^2 / h.) The final FMA, 1/r (u/2) and the product add
// <= 1.5u. Sum: 1.5 + 5 + 2.25/cos + 2.5 cos + 1.5 + the along-d scaling of
// h (3u cos), under 16 + 4/cos. The one 1/cos is h's: q holds r's length to
// ~u r, and h = r cos takes it as an error u r / cos along d, as a ray moved
// across by ~u r would: a backward error of a few u r whatever the distance.
// (Before the sphere-frame hit the kernels had p - c = o + t d - c, off by a few u t:
// |n - n_exact| ~ u t / r, and t / r (1 / cos) near the outline.)
//
// End to end (radiance of a render against the double reference): the error
// of a mode is its building-block error amplified by the geometry: a point
// light's direction moves by (t/r) dt/t where the hit point is off by a
// relative dt/t. With S the pixel's radiance with every light at n.l = 1
// (tools/verify.hpp) and
//     kappa = 1 + max over the image's hits of t/r (hit distance over the
//             distance of a point light),
// the stated bound is, lane by lane,
//     |L - L_ref| / S  <=  end_to_end_bound(mode) * kappa  +  sphere term,
//     end_to_end_bound(mode) = 8 * max(rsqrt_bound(mode), 2u) + 32 u,
//     sphere term (sphere hits) = (dn_in + sphere_normal_bound(cos)) (1 + 2 min(R, t) / r_min),
//     dn_in = (e / R) (1 + 1 / cos),
// where e is how far the sphere the kernels see sits from the reference's at
// the hit: the kernels' ray's distance from the reference's hit point, plus
// what the compiled scene leaves of the centre and radius. A normal off by dn
// changes every n.l by at most dn (so L by dn S); where the sphere is
// smaller than the hit distance (R < t), the kernels shade at c + R n
// (kernels/shade.hpp), which it moves by R dn, and a point light's direction
// by 2 R dn / r (r_min: the nearest point light); elsewhere at o + t d, which
// kappa covers. e is the inputs' part, and it is where t/R would come back
// for a general camera: a direction rounded to float is off by up to u/2 per
// component, so a float ray misses the reference's hit by up to
// (u/2) sqrt(3) t |d|, and a ray that passes the sphere at cos moves its hit
// by e / cos along the surface: dn_in = (e / R)(1 + 1 / cos), whatever
// formulation the kernel uses (R = 0.04 at t = 12: ~1.5e-5 (1 + 1/cos);
// R = 1e-3 at t = 100: ~5e-3 (1 + 1/cos)). A centre rounded to float moves
// the sphere by up to (u/2) sqrt(3) |c| likewise. So neither is rounded
// alone: the camera kernel forms its rays in double from a double frame and
// passes each as float + residual (RayPacket::ox_lo..., exact to ~u^2 |x|),
// the compiled scene keeps each centre's residual (SphereArrays: in 16 bits
// where that is within 2^-27 R, an eighth of u R, else as a float), and
// sphere_offset takes both into the foot of the perpendicular, to first
// order in u: the residuals move q by ~u t, the products they are rounded in
// by ~u^2 t, so e <= u^2 (t |d| + |c|) + 2^-27 R + the radius's rounding, u/2 R, which
// enters h as u R / (2 cos): under sphere_normal_bound's own 4/cos. Measured
// on the pinhole fields of scripts/make_sphere_fields.py, before and after:
// docs/accuracy.md, "Small spheres through a pinhole camera". A ray an
// engine passes without residuals is taken as exact: e is then its own
// rounding. It
// vanishes where the rays and the scene are exact in float (an
// orthographic camera on a power-of-two grid, coordinates written as
// floats: the sphere_field scenes scripts/make_sphere_fields.py writes), and there the bound holds with no
// t/R in it. The bound holds on every lane where the packet path and the
// reference hit the same primitive, except on the edges of box faces and of
// shadows: lanes with a 3x3 neighbour on the same object where the reference
// shows another face of the box or another set of visible lights, box hits
// within the mode's position error (end_to_end_bound(mode) * t) of their
// face's border, and sphere hits whose ray passes within e + 2u (t |d| + 4 R)
// of the sphere's outline (the rounding of f = o - c and of |perp| in the
// hit/miss test, which no precision mode changes). There a hit point off by
// that much may take the other face or visibility, or the ray miss, a legal
// answer as on a silhouette. The other lanes (hit/miss or primitive differs)
// lie on silhouettes. The bands are in world units, not pixels: a 3x3
// neighbourhood alone shrinks with the pixel, and at 1920x1440 lanes 1e-4
// from a box edge (approx: 0.22 S) slipped past it. kappa is the scene's
// condition for point lights; the float modes' error grows with it; f64
// keeps its arithmetic error small but still reads a float scene and float
// packets.
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
// (every mode; see the header comment), cos = |n.d| / |d| at the hit; add
// 42 u^2 |o - c| / r for |o - c| beyond ~4e5 r.
inline constexpr double sphere_normal_bound(double cos_theta) { return kUnitRoundoff * (16 + 4 / cos_theta); }
// max |L - L_ref| / S per unit of kappa (see the header comment): the radiance
// error of a whole render on lanes where both paths hit the same primitive,
// besides the sphere term. f64 has exact's: it reads and writes the same
// float scene and packets.
inline constexpr double end_to_end_bound(Precision p) {
    return 8 * (rsqrt_bound(p) > 2 * kUnitRoundoff ? rsqrt_bound(p) : 2 * kUnitRoundoff) + 32 * kUnitRoundoff;
}

}  // namespace octray
