// The 8-wide BVH builder (kernels/bvh/node.hpp): structural properties on
// fixed-seed random inputs, determinism across thread counts, degenerate
// inputs; the walks against brute force (bvh_traversal_checks.hpp), here at
// the default target (test_bvh_avx2.cpp runs them at AVX2, in octray_tests_avx2).
#include <doctest/doctest.h>

#include "kernels/bvh/node.hpp"
#include "bvh_test_scenes.hpp"
#include "bvh_traversal_checks.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <stdexcept>
#include <vector>

namespace octray::test {
namespace {

using bvh::Box;
using bvh::BuildInput;
using bvh::BuildOptions;
using bvh::Bvh8;
using bvh::Leaf;
using bvh::Node8;

// Every structural promise of kernels/bvh/node.hpp, checked on one tree.
void check_tree(const BuildInput& in, const Bvh8& t, const BuildOptions& opt) {
    const std::size_t n = in.boxes.size();
    REQUIRE(int(t.order.size()) == in.kind_count);
    REQUIRE(t.primitive_count() == n);
    if (n == 0) {
        CHECK(t.nodes.empty());
        CHECK(t.leaves.empty());
        CHECK(t.depth == 0);
        return;
    }
    // The caller's primitive for (kind, index within kind).
    std::vector<std::uint32_t> index(n);
    std::vector<std::uint32_t> per_kind(std::size_t(in.kind_count), 0);
    for (std::size_t i = 0; i < n; ++i) {
        const int k = in.kind.empty() ? 0 : in.kind[i];
        index[i] = in.index_in_kind.empty() ? per_kind[std::size_t(k)]++ : in.index_in_kind[i];
    }
    std::map<std::pair<int, std::uint32_t>, std::size_t> input_of;
    for (std::size_t i = 0; i < n; ++i) input_of[{in.kind.empty() ? 0 : in.kind[i], index[i]}] = i;
    REQUIRE(input_of.size() == n);

    // Leaves tile each kind's positions in order; each primitive once.
    std::vector<int> seen(n, 0);
    std::vector<std::uint32_t> next(std::size_t(in.kind_count), 0);
    for (const Leaf& l : t.leaves) {
        CHECK(l.size() >= 1);
        CHECK(l.size() <= opt.max_leaf_size);
        for (int k = 0; k < in.kind_count; ++k) {
            CHECK(l.begin[k] == next[std::size_t(k)]);
            next[std::size_t(k)] += l.count[k];
            for (std::uint32_t p = l.begin[k]; p < l.begin[k] + l.count[k]; ++p) {
                const auto it = input_of.find({k, t.order[std::size_t(k)][p]});
                REQUIRE(it != input_of.end());
                ++seen[it->second];
            }
        }
        for (int k = in.kind_count; k < bvh::kMaxKinds; ++k) CHECK(l.count[k] == 0);
    }
    for (int k = 0; k < in.kind_count; ++k) CHECK(next[std::size_t(k)] == t.order[std::size_t(k)].size());
    CHECK(std::count(seen.begin(), seen.end(), 1) == std::ptrdiff_t(n));

    // Walk the tree: each node and leaf reached once; each primitive's box
    // inside every ancestor's bounds; unused slots packed, empty, sentinel.
    std::vector<int> node_seen(t.nodes.size(), 0), leaf_seen(t.leaves.size(), 0);
    int depth = 0;
    struct Frame {
        std::int32_t node;
        int depth;
        std::vector<Box> ancestors;
    };
    std::vector<Frame> stack{{0, 1, {}}};
    while (!stack.empty()) {
        Frame f = std::move(stack.back());
        stack.pop_back();
        REQUIRE(f.node >= 0);
        REQUIRE(std::size_t(f.node) < t.nodes.size());
        ++node_seen[std::size_t(f.node)];
        depth = std::max(depth, f.depth);
        const Node8& node = t.nodes[std::size_t(f.node)];
        const int used = node.child_count();
        CHECK(used >= 1);
        if (f.node != 0) CHECK(used >= 2);  // only the root of a one-leaf tree has one child
        for (int j = 0; j < bvh::kWidth; ++j) {
            const Box b = node.bounds(j);
            if (node.child[j] >= 0 || j >= used) CHECK(node.run[j] == 0);
            if (j >= used) {
                CHECK(node.child[j] == bvh::kEmptySlot);
                for (int a = 0; a < 3; ++a) {
                    CHECK(b.lo[a] == INFINITY);
                    CHECK(b.hi[a] == -INFINITY);
                }
                continue;
            }
            std::vector<Box> chain = f.ancestors;
            chain.push_back(b);
            const std::int32_t c = node.child[j];
            if (c >= 0) {
                stack.push_back({c, f.depth + 1, chain});
                continue;
            }
            REQUIRE(std::size_t(~c) < t.leaves.size());
            ++leaf_seen[std::size_t(~c)];
            const Leaf& l = t.leaves[std::size_t(~c)];
            // The parent's run word: the leaf's one run, or 0 where it has
            // several kinds (or does not fit); decoded, the same primitives.
            Leaf scratch;
            const Leaf& inline_leaf = bvh::leaf_of(t.leaves, c, node.run[j], scratch);
            int kinds = 0;
            for (int k = 0; k < bvh::kMaxKinds; ++k) {
                kinds += l.count[k] > 0;
                CHECK(inline_leaf.count[k] == l.count[k]);
                if (l.count[k] > 0) CHECK(inline_leaf.begin[k] == l.begin[k]);
            }
            CHECK((node.run[j] != 0) == (kinds == 1 && l.size() <= 31 && t.primitive_count() < (1u << 24)));
            for (int k = 0; k < in.kind_count; ++k)
                for (std::uint32_t p = l.begin[k]; p < l.begin[k] + l.count[k]; ++p) {
                    const Box& pb = in.boxes[input_of.at({k, t.order[std::size_t(k)][p]})];
                    for (const Box& a : chain) CHECK(a.contains(pb));
                    CHECK(t.bounds.contains(pb));
                }
        }
    }
    CHECK(std::count(node_seen.begin(), node_seen.end(), 1) == std::ptrdiff_t(t.nodes.size()));
    CHECK(std::count(leaf_seen.begin(), leaf_seen.end(), 1) == std::ptrdiff_t(t.leaves.size()));
    CHECK(depth == t.depth);
    CHECK(t.depth <= bvh::kMaxDepth);
    CHECK(t.bytes() >= t.nodes.size() * sizeof(Node8));
}

bool same_tree(const Bvh8& a, const Bvh8& b) {
    return a.nodes.size() == b.nodes.size() && a.leaves.size() == b.leaves.size() && a.order == b.order &&
           a.depth == b.depth &&
           std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(Node8)) == 0 &&
           std::memcmp(a.leaves.data(), b.leaves.data(), a.leaves.size() * sizeof(Leaf)) == 0 &&
           std::memcmp(&a.bounds, &b.bounds, sizeof(Box)) == 0;
}

TEST_CASE("bvh: random boxes of six kinds: every structural property") {
    for (const int max_leaf : {1, 4, 8}) {
        BuildOptions opt;
        opt.max_leaf_size = max_leaf;
        const BuildInput in = random_boxes(3000, 6, 11u + unsigned(max_leaf));
        CAPTURE(max_leaf);
        check_tree(in, bvh::build_bvh8(in, opt), opt);
    }
}

TEST_CASE("bvh: options at their limits") {
    const BuildInput in = random_boxes(2000, 3, 5u);
    for (const int bins : {2, 64}) {
        BuildOptions opt;
        opt.bins = bins;
        opt.max_leaf_size = 255;
        opt.traversal_cost = 0.0f;
        CAPTURE(bins);
        check_tree(in, bvh::build_bvh8(in, opt), opt);
    }
}

TEST_CASE("bvh: given index_in_kind comes back through order") {
    BuildInput in = random_boxes(500, 2, 7u);
    std::vector<std::uint32_t> count(2, 0);
    for (std::size_t i = 0; i < in.boxes.size(); ++i) count[in.kind[i]]++;
    std::vector<std::uint32_t> next(2, 0);
    in.index_in_kind.resize(in.boxes.size());
    for (std::size_t i = 0; i < in.boxes.size(); ++i)  // reversed numbering within each kind
        in.index_in_kind[i] = count[in.kind[i]] - 1 - next[in.kind[i]]++;
    const BuildOptions opt;
    check_tree(in, bvh::build_bvh8(in, opt), opt);
}

TEST_CASE("bvh: the same tree on 1 and 2 threads") {
    for (const std::size_t n : {std::size_t(100), std::size_t(20000), std::size_t(70000)}) {
        const BuildInput in = random_boxes(n, 4, 3u);
        BuildOptions one, two;
        one.threads = 1;
        two.threads = 2;
        const Bvh8 a = bvh::build_bvh8(in, one), b = bvh::build_bvh8(in, two), c = bvh::build_bvh8(in, two);
        CAPTURE(n);
        CHECK(same_tree(a, b));
        CHECK(same_tree(b, c));
    }
}

TEST_CASE("bvh: no primitive, one primitive") {
    const BuildOptions opt;
    BuildInput none;
    none.kind_count = 3;
    const Bvh8 e = bvh::build_bvh8(none, opt);
    check_tree(none, e, opt);
    CHECK(e.empty());
    CHECK(e.bytes() == 0);

    BuildInput one;
    one.boxes.push_back({{1, 2, 3}, {4, 5, 6}});
    const Bvh8 t = bvh::build_bvh8(one, opt);
    check_tree(one, t, opt);
    REQUIRE(t.nodes.size() == 1);
    CHECK(t.nodes[0].child_count() == 1);
    CHECK(t.nodes[0].child[0] == ~0);
    CHECK(t.depth == 1);
}

TEST_CASE("bvh: coincident primitives, and one centroid for boxes of many sizes") {
    for (const int max_leaf : {1, 4}) {
        BuildOptions opt;
        opt.max_leaf_size = max_leaf;
        BuildInput point;
        point.boxes.assign(5000, Box{{1, 1, 1}, {1, 1, 1}});
        check_tree(point, bvh::build_bvh8(point, opt), opt);

        BuildInput nested;  // every centroid at the origin
        for (int i = 0; i < 3000; ++i) {
            const float s = 1.0f + float(i);
            nested.boxes.push_back({{-s, -s, -s}, {s, s, s}});
        }
        check_tree(nested, bvh::build_bvh8(nested, opt), opt);
    }
}

TEST_CASE("bvh: a geometric series (SAH's worst case) stays within the depth bound") {
    BuildInput in;
    float x = 1.0f;
    for (int i = 0; i < 4000; ++i, x *= 1.01f) in.boxes.push_back({{x, 0, 0}, {x, 0, 0}});
    BuildOptions opt;
    opt.max_leaf_size = 1;
    check_tree(in, bvh::build_bvh8(in, opt), opt);
}

TEST_CASE("bvh: empty and NaN boxes are kept in leaves") {
    BuildInput in = random_boxes(300, 1, 9u);
    in.boxes[10] = Box::empty();
    in.boxes[20].lo[1] = NAN;
    const BuildOptions opt;
    const Bvh8 t = bvh::build_bvh8(in, opt);
    CHECK(t.primitive_count() == in.boxes.size());
    std::vector<int> seen(in.boxes.size(), 0);
    for (std::uint32_t i : t.order[0]) ++seen[i];
    CHECK(std::count(seen.begin(), seen.end(), 1) == std::ptrdiff_t(in.boxes.size()));
}

TEST_CASE("bvh: inconsistent input is refused") {
    BuildInput in = random_boxes(10, 2, 1u);
    BuildInput bad = in;
    bad.kind.pop_back();
    CHECK_THROWS_AS(bvh::build_bvh8(bad, {}), std::invalid_argument);
    bad = in;
    bad.kind[3] = 2;
    CHECK_THROWS_AS(bvh::build_bvh8(bad, {}), std::invalid_argument);
    bad = in;
    bad.kind_count = 9;
    CHECK_THROWS_AS(bvh::build_bvh8(bad, {}), std::invalid_argument);
    BuildOptions opt;
    opt.max_leaf_size = 256;
    CHECK_THROWS_AS(bvh::build_bvh8(in, opt), std::invalid_argument);
    opt = {};
    opt.bins = 1;
    CHECK_THROWS_AS(bvh::build_bvh8(in, opt), std::invalid_argument);
}

TEST_CASE("bvh: SAH cost is lower than a single leaf's") {
    const BuildInput in = random_boxes(4000, 1, 21u);
    const BuildOptions opt;
    const Bvh8 t = bvh::build_bvh8(in, opt);
    const double cost = bvh::sah_cost(t, opt);
    CHECK(cost > 0.0);
    CHECK(cost < 0.1 * double(in.boxes.size()));
}

TEST_CASE("bvh: the SAH collapse costs no more than the greedy one, over the same leaves") {
    for (const std::size_t n : {std::size_t(50), std::size_t(3000), std::size_t(40000)}) {
        for (const int max_leaf : {1, 8}) {
            const BuildInput in = random_boxes(n, 3, 31u + unsigned(n));
            BuildOptions sah, greedy;
            sah.max_leaf_size = greedy.max_leaf_size = max_leaf;
            greedy.sah_collapse = false;
            const Bvh8 a = bvh::build_bvh8(in, sah), b = bvh::build_bvh8(in, greedy);
            CAPTURE(n);
            CAPTURE(max_leaf);
            check_tree(in, a, sah);
            check_tree(in, b, greedy);
            // The same binary tree: the same leaves, in the same order.
            CHECK(a.order == b.order);
            REQUIRE(a.leaves.size() == b.leaves.size());
            CHECK(std::memcmp(a.leaves.data(), b.leaves.data(), a.leaves.size() * sizeof(Leaf)) == 0);
            // The plan is optimal in float sums; sah_cost sums in double.
            const double cost_sah = bvh::sah_cost(a, sah), cost_greedy = bvh::sah_cost(b, greedy);
            CHECK(cost_sah <= cost_greedy * (1.0 + 1e-5));
        }
    }
}

TEST_CASE("bvh walks: single float rays, double lanes, 4-float and 2-double packets (default target)") {
    check_walks<float>(1u, 120);
    check_walks<double>(2u, 60);
    check_walks<xsimd::batch<float, xsimd::sse2>>(3u, 60);
    check_walks<xsimd::batch<double, xsimd::sse2>>(4u, 40);
    check_child_order(5u);
}

}  // namespace
}  // namespace octray::test
