// tests/support/lane_checks.hpp — checks of kernels/lanes/lane.hpp's batch
// functions, written over the batch type so each test binary runs them at its
// own ISA (test_lane.cpp: the default target; test_lane_avx2.cpp, in
// octray_tests_avx2: -mavx2 -mfma, where lane.hpp takes its intrinsic paths).
#pragma once

#include <doctest/doctest.h>

#include "kernels/lanes/lane.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>

namespace octray::test {
namespace {

// Kernels flush NaN with max(x, 0): min/max must keep x86's a < b ? a : b.
template <class B>
void check_min_max_nan_rule() {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    CHECK(lane::max(B(nan), B(0.0f)).get(0) == 0.0f);
    CHECK(std::isnan(lane::max(B(0.0f), B(nan)).get(0)));
    CHECK(lane::min(B(nan), B(2.0f)).get(0) == 2.0f);
    CHECK(std::isnan(lane::min(B(2.0f), B(nan)).get(0)));
    CHECK(lane::min(B(1.0f), B(2.0f)).get(0) == 1.0f);
    CHECK(lane::max(B(1.0f), B(2.0f)).get(0) == 2.0f);
}

// A fixed-seed linear congruential generator (no <random>: see above).
struct Lcg {
    std::uint32_t state;
    std::uint32_t operator()() { return (state = state * 1664525u + 1013904223u) >> 8; }
};

// uniform_on: true iff the lanes of the mask share one index (then `value` is
// it); lanes off the mask never matter.
template <class B>
void check_uniform_on() {
    using BB = typename B::batch_bool_type;
    constexpr std::size_t n = B::size;
    Lcg rng{7};
    for (int trial = 0; trial < 4000; ++trial) {
        alignas(64) float idx[n];
        alignas(64) float on[n];
        for (std::size_t i = 0; i < n; ++i) idx[i] = float(rng() % 3), on[i] = rng() % 4 != 0 ? 1.0f : 0.0f;
        bool want = true;
        int first = -1;
        for (std::size_t i = 0; i < n; ++i)
            if (on[i] != 0) {
                if (first < 0) first = int(idx[i]);
                else if (int(idx[i]) != first) want = false;
            }
        int value = -1;
        const BB mask = B::load_aligned(on) != B(0.0f);
        CHECK(lane::uniform_on(B::load_aligned(idx), mask, value) == want);
        if (want && first >= 0) CHECK(value == first);
    }
}

// keep(m, x): the bits of select(m, x, 0) and of the scalar keep on every
// lane, for masks from compares and from && of compares, on values that
// include -0, NaN, infinities and subnormals.
template <class B>
void check_keep() {
    using S = typename B::value_type;
    using Bits = std::conditional_t<sizeof(S) == 4, std::uint32_t, std::uint64_t>;
    constexpr std::size_t n = B::size;
    const S special[] = {S(-0.0), S(0), std::numeric_limits<S>::quiet_NaN(), std::numeric_limits<S>::infinity(),
                         -std::numeric_limits<S>::infinity(), std::numeric_limits<S>::denorm_min(), S(-1.5), S(3)};
    auto bits_of = [](S v) {
        Bits u;
        std::memcpy(&u, &v, sizeof u);
        return u;
    };
    Lcg rng{13};
    for (int trial = 0; trial < 2000; ++trial) {
        alignas(64) S v[n], a[n], b[n], got[n], by_select[n];
        for (std::size_t i = 0; i < n; ++i)
            v[i] = special[rng() % 8], a[i] = S(int(rng() % 5) - 2), b[i] = S(int(rng() % 5) - 2);
        const B x = B::load_aligned(v), ba = B::load_aligned(a), bb = B::load_aligned(b);
        const auto mask = trial % 2 == 0 ? ba > bb : (ba > bb) && (ba != B(S(0)));
        lane::keep(mask, x).store_aligned(got);
        lane::select(mask, x, B(S(0))).store_aligned(by_select);
        for (std::size_t i = 0; i < n; ++i) {
            const bool on = trial % 2 == 0 ? a[i] > b[i] : a[i] > b[i] && a[i] != 0;
            CHECK(bits_of(got[i]) == bits_of(by_select[i]));
            CHECK(bits_of(got[i]) == bits_of(lane::keep(on, v[i])));
        }
    }
}

// bits, hmin, hmax, lane0 against a loop over the lanes.
template <class B>
void check_horizontal() {
    constexpr std::size_t n = B::size;
    Lcg rng{11};
    for (int trial = 0; trial < 2000; ++trial) {
        alignas(64) float v[n];
        alignas(64) float on[n];
        unsigned want_bits = 0;
        float lo = INFINITY, hi = -INFINITY;
        for (std::size_t i = 0; i < n; ++i) {
            v[i] = float(int(rng() % 2001) - 1000) / 8.0f;
            on[i] = rng() % 3 != 0 ? 1.0f : 0.0f;
            lo = v[i] < lo ? v[i] : lo, hi = v[i] > hi ? v[i] : hi;
            if (on[i] != 0) want_bits |= 1u << i;
        }
        const B x = B::load_aligned(v);
        const auto mask = B::load_aligned(on) != B(0.0f);
        CHECK(lane::bits(mask) == want_bits);
        CHECK(lane::lane0(x) == v[0]);
        for (std::size_t i = 0; i < n; ++i) {
            CHECK(lane::hmin(x).get(i) == lo);
            CHECK(lane::hmax(x).get(i) == hi);
        }
    }
}

}  // namespace
}  // namespace octray::test
