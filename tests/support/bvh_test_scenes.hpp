// tests/support/bvh_test_scenes.hpp — fixed-seed inputs for the BVH tests. Internal
// linkage, and no std:: templates of their own (the AVX2 test unit includes
// this too: nothing compiled for AVX2 may merge into the default unit).
#pragma once

#include "kernels/bvh/node.hpp"

#include <cstdint>

namespace octray::test {
namespace {

// A fixed-seed linear congruential generator; next() gives the state's high
// 24 bits (its low bits have short periods).
struct BvhLcg {
    std::uint32_t state;
    std::uint32_t next() { return (state = state * 1664525u + 1013904223u) >> 8; }
    float uniform() { return float(next()) * 0x1p-24f; }  // [0, 1)
    float range(float lo, float hi) { return lo + (hi - lo) * uniform(); }
};

// n boxes of random kinds in [-10, 10]^3, sizes up to 2; one in eight is
// flat (zero extent) along some axis, as a disk or rectangle's may be.
bvh::BuildInput random_boxes(std::size_t n, int kinds, std::uint32_t seed) {
    BvhLcg rng{seed};
    bvh::BuildInput in;
    in.kind_count = kinds;
    in.boxes.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        bvh::Box b;
        const int flat = rng.next() % 8 == 0 ? int(rng.next() % 3) : -1;
        for (int a = 0; a < 3; ++a) {
            b.lo[a] = rng.range(-10.0f, 10.0f);
            b.hi[a] = a == flat ? b.lo[a] : b.lo[a] + rng.range(0.0f, 2.0f);
        }
        in.boxes.push_back(b);
        if (kinds > 1) in.kind.push_back(std::uint8_t(rng.next() % std::uint32_t(kinds)));
    }
    return in;
}

}  // namespace
}  // namespace octray::test
