// kernels/lanes/lane.hpp's batch functions at the default target; the same
// checks at AVX2, where lane.hpp takes intrinsic paths, are test_lane_avx2.cpp's
// (a binary of their own: octray_tests_avx2).
#include "lane_checks.hpp"

using namespace octray;

TEST_CASE("lane::min and lane::max keep the x86 rule on NaN: the second operand") {
    CHECK(lane::max(std::numeric_limits<float>::quiet_NaN(), 0.0f) == 0.0f);
    test::check_min_max_nan_rule<xsimd::batch<float>>();
}

TEST_CASE("lane::uniform_on finds one index shared by the masked lanes, ignoring the others") {
    int value = -1;
    CHECK(lane::uniform_on(5.0f, false, value));
    CHECK(value == 5);
    test::check_uniform_on<xsimd::batch<float>>();
}

TEST_CASE("lane::bits, hmin, hmax and lane0 agree with a loop over the lanes") {
    CHECK(lane::bits(true) == 1u);
    CHECK(lane::hmax(3.0f) == 3.0f);
    test::check_horizontal<xsimd::batch<float>>();
    test::check_horizontal<xsimd::batch<double>>();
}

TEST_CASE("lane::keep gives select(m, x, 0)'s bits, on SIMD and scalar lanes") {
    CHECK(lane::keep(true, -0.0f) == 0.0f);
    CHECK(std::signbit(lane::keep(true, -0.0f)));
    CHECK(!std::signbit(lane::keep(false, -1.0f)));
    test::check_keep<xsimd::batch<float>>();
    test::check_keep<xsimd::batch<double>>();
}
