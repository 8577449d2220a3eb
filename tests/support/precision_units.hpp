// tests/support/precision_units.hpp — what the precision tests share
// (test_precision.cpp, test_precision_blocks.cpp): every ISA unit and mode
// this CPU runs, their names, a seeded random source.
#pragma once

#include "dispatch/isa_kernels.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <random>
#include <string>

namespace octray::precision_test {

// Every (unit, mode) this CPU runs; at least one (the generic unit runs anywhere).
template <class Fn>
inline void for_each_unit_mode(Fn&& fn) {
    int ran = 0;
    for (int i = 0; i < kernels::kUnitCount; ++i) {
        const kernels::Unit& u = kernels::kUnits[i];
        if (!u.supported()) continue;
        for (Precision p : kPrecisions)
            if ((u.modes & kernels::mode_bit(p)) != 0) fn(u, p), ++ran;
    }
    REQUIRE(ran > 0);
}

inline std::string unit_name(const kernels::Unit& u, Precision p) {
    return std::string(path_name(u.path)) + "/" + u.isa + "/" + precision_name(p);
}

struct Rng {
    std::mt19937_64 g;
    explicit Rng(unsigned seed) : g(seed) {}
    double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(g); }
    // |x| log-uniform in [2^lo, 2^hi], random sign when `sign`.
    float logu(double lo, double hi, bool sign) {
        const float x = float(std::exp2(uniform(lo, hi)));
        return sign && uniform(0, 1) < 0.5 ? -x : x;
    }
};

}  // namespace octray::precision_test
