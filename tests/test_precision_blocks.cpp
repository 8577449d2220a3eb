// Precision modes, per building block (reciprocal, rsqrt, divide, normalize,
// n.l, the tone map's x^y): every stated bound of precision.hpp, checked on
// randomized inputs (fixed seeds) for every ISA unit and path built that this
// CPU runs, through the test-only units of precision_blocks.hpp.
#include <doctest/doctest.h>

#include "precision_blocks.hpp"
#include "precision_units.hpp"

#include "kernels/lanes/lane_pow.hpp"
#include <octray/precision.hpp>
#include <octray/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <string>
#include <vector>

using namespace octray;
using namespace octray::precision_test;

namespace {

constexpr int kSamples = 1 << 16;  // per block, mode and unit: a multiple of the packet width

// Unit vectors and general vectors of random direction and length.
void random_vectors(Rng& r, std::vector<float> (&v)[3], double lo, double hi) {
    for (int i = 0; i < kSamples; ++i) {
        double x, y, z, l2;
        do {
            x = r.uniform(-1, 1), y = r.uniform(-1, 1), z = r.uniform(-1, 1);
            l2 = x * x + y * y + z * z;
        } while (l2 > 1 || l2 < 1e-4);
        const double s = std::exp2(r.uniform(lo, hi)) / std::sqrt(l2);
        v[0][std::size_t(i)] = float(x * s), v[1][std::size_t(i)] = float(y * s), v[2][std::size_t(i)] = float(z * s);
    }
}

// Largest |out[i] - exact(i)| / |exact(i)|.
template <class Exact>
double worst_relative(const std::vector<float>& out, Exact&& exact) {
    double worst = 0;
    for (std::size_t i = 0; i < out.size(); ++i) {
        const double e = exact(i);
        worst = std::max(worst, std::fabs(double(out[i]) - e) / std::fabs(e));
    }
    return worst;
}

}  // namespace

TEST_CASE("reciprocal and divide stay within their stated bounds") {
    for_each_unit_mode([](const kernels::Unit& u, Precision p) {
        CAPTURE(unit_name(u, p));
        const kernels::Blocks b = kernels::blocks_of(u, p);
        REQUIRE(bool(b.rcp));
        Rng r(20240501u);
        std::vector<float> x(kSamples), y(kSamples), out(kSamples);
        // Arguments whose reciprocal (and quotient) is a normal float.
        for (int i = 0; i < kSamples; ++i) x[std::size_t(i)] = r.logu(-100, 100, true), y[std::size_t(i)] = r.logu(-20, 20, true);
        b.rcp(x.data(), out.data(), kSamples);
        double worst = worst_relative(out, [&](std::size_t i) { return 1.0 / double(x[i]); });
        MESSAGE(unit_name(u, p) << " rcp: max rel err " << worst / kUnitRoundoff << " u, bound " << rcp_bound(p) / kUnitRoundoff << " u");
        CHECK(worst <= rcp_bound(p));
        CHECK(worst > 0);  // the samples are hard enough to show an error at all

        b.div(y.data(), x.data(), out.data(), kSamples);
        worst = worst_relative(out, [&](std::size_t i) { return double(y[i]) / double(x[i]); });
        CHECK(worst <= div_bound(p));
    });
}

TEST_CASE("rsqrt stays within its stated bound") {
    for_each_unit_mode([](const kernels::Unit& u, Precision p) {
        CAPTURE(unit_name(u, p));
        const kernels::Blocks b = kernels::blocks_of(u, p);
        REQUIRE(bool(b.rsqrt));
        Rng r(20240502u);
        std::vector<float> x(kSamples), out(kSamples);
        for (int i = 0; i < kSamples; ++i) x[std::size_t(i)] = r.logu(-120, 120, false);
        b.rsqrt(x.data(), out.data(), kSamples);
        const double worst = worst_relative(out, [&](std::size_t i) { return 1.0 / std::sqrt(double(x[i])); });
        MESSAGE(unit_name(u, p) << " rsqrt: max rel err " << worst / kUnitRoundoff << " u, bound " << rsqrt_bound(p) / kUnitRoundoff << " u");
        CHECK(worst <= rsqrt_bound(p));
        CHECK(worst > 0);
    });
}

TEST_CASE("the tone map's x^y stays within pow_max_ulp(y) and agrees across paths") {
    // y: gamma 2.2's 1/2.2 and other display gammas, their inverses, and the
    // largest |y| = 16 the bound is measured at; x log-uniform over the normal
    // floats whose x^y is a normal float, and densely near 1 (c = 1 is common).
    const float ys[] = {1 / 2.2f, 0.5f, 1 / 1.8f, 1 / 2.4f, 1.0f, 2.2f, -1.0f, 4.0f, 16.0f};
    std::vector<float> first_unit;  // the first float unit and mode's output: every other must match it
    for_each_unit_mode([&](const kernels::Unit& u, Precision p) {
        CAPTURE(unit_name(u, p));
        const kernels::Blocks b = kernels::blocks_of(u, p);
        REQUIRE(bool(b.pow));
        Rng r(20240503u);
        std::vector<float> x(kSamples), y(kSamples), out(kSamples);
        for (int i = 0; i < kSamples; ++i) {
            const float yi = ys[std::size_t(i) % std::size(ys)];
            const double span = 126.0 / std::max(1.0, double(std::fabs(yi)));
            x[std::size_t(i)] = i % 4 == 0 ? float(1 - r.uniform(0, 1e-3)) : r.logu(-span, i % 2 ? 0 : span, false);
            y[std::size_t(i)] = yi;
        }
        x[0] = 1.0f;
        b.pow(x.data(), y.data(), out.data(), kSamples);
        double worst_ulps = 0, worst_abs = 0;
        for (std::size_t i = 0; i < out.size(); ++i) {
            const double want = std::pow(double(x[i]), double(y[i]));
            int e;
            std::frexp(want, &e);
            const double ulps = std::fabs(double(out[i]) - want) / std::ldexp(1.0, e - 24);
            CAPTURE(x[i]);
            CAPTURE(y[i]);
            CHECK(ulps <= lane::pow_max_ulp(y[i]));
            worst_ulps = std::max(worst_ulps, ulps / lane::pow_max_ulp(y[i]));
            worst_abs = std::max(worst_abs, ulps);
        }
        MESSAGE(unit_name(u, p) << " pow: worst error " << worst_ulps << " of its bound");
        CHECK(out[0] == 1.0f);
        if (p == Precision::f64) {
            CHECK(worst_abs <= 0.5 + 1e-6);  // double lanes: double pow, rounded once to float
            return;
        }
        CHECK(worst_ulps > 0.2);  // the samples reach the bound's order
        // Float lanes: the same code on every unit and path, bit for bit.
        if (first_unit.empty()) first_unit = out;
        else CHECK(out == first_unit);
    });
}

TEST_CASE("normalize and n.l stay within their stated bounds") {
    for_each_unit_mode([](const kernels::Unit& u, Precision p) {
        CAPTURE(unit_name(u, p));
        const kernels::Blocks b = kernels::blocks_of(u, p);
        REQUIRE(bool(b.normalize));
        REQUIRE(bool(b.ndotl));
        Rng r(20240503u);
        std::vector<float> v[3], n[3], o[3], dots(kSamples);
        for (int k = 0; k < 3; ++k) v[k].resize(kSamples), n[k].resize(kSamples), o[k].resize(kSamples);
        random_vectors(r, v, -30, 30);  // light vectors: any length
        random_vectors(r, n, 0, 0);     // normals: unit (to float rounding)
        const float* vp[3] = {v[0].data(), v[1].data(), v[2].data()};
        const float* np[3] = {n[0].data(), n[1].data(), n[2].data()};
        float* op[3] = {o[0].data(), o[1].data(), o[2].data()};

        b.normalize(vp, op, kSamples);
        double worst = 0;
        for (std::size_t i = 0; i < std::size_t(kSamples); ++i) {
            const Vec3d d{v[0][i], v[1][i], v[2][i]};
            const Vec3d e = d * (1.0 / std::sqrt(dot(d, d)));
            for (double err : {o[0][i] - e.x, o[1][i] - e.y, o[2][i] - e.z}) worst = std::max(worst, std::fabs(err));
        }
        MESSAGE(unit_name(u, p) << " normalize: max abs err " << worst / kUnitRoundoff << " u, bound " << normalize_bound(p) / kUnitRoundoff << " u");
        CHECK(worst <= normalize_bound(p));

        b.ndotl(np, vp, dots.data(), kSamples);
        worst = 0;
        for (std::size_t i = 0; i < std::size_t(kSamples); ++i) {
            const Vec3d d{v[0][i], v[1][i], v[2][i]}, nn{n[0][i], n[1][i], n[2][i]};
            const double e = dot(nn, d) / std::sqrt(dot(d, d));
            worst = std::max(worst, std::fabs(dots[i] - e));
        }
        MESSAGE(unit_name(u, p) << " n.l: max abs err " << worst / kUnitRoundoff << " u, bound " << ndotl_bound(p) / kUnitRoundoff << " u");
        CHECK(worst <= ndotl_bound(p));
    });
}
