// tests/support/bvh_traversal_checks.hpp — the BVH walks (kernels/bvh/traverse.hpp)
// against brute force, written over the lane type so each test unit runs
// them at its own ISA (test_bvh.cpp: the default target; test_bvh_avx2.cpp:
// -mavx2 -mfma, 8-float batches). Internal linkage, as lane_checks.hpp.
// The two ISAs build into two binaries (octray_tests, octray_tests_avx2), so
// the std:: templates both instantiate are never merged across ISAs.
//
// The scene's primitives are boxes; a leaf function slab-tests each of its
// primitives' boxes (bvh::slab_enter, the walk's own node test without the
// slack) on each lane. Brute force tests every box on every lane.
#pragma once

#include <doctest/doctest.h>

#include "kernels/bvh/traverse.hpp"
#include "bvh_test_scenes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <cstring>
#include <utility>
#include <vector>

namespace octray::test {
namespace {

template <class T>
struct Lanes {
    using S = lane::Scalar<T>;
    static constexpr int W = lane::width<T>;
    static T load(const S* p) {
        if constexpr (W == 1) return *p;
        else return T::load_unaligned(p);
    }
    static void store(S* p, const T& v) {
        if constexpr (W == 1) *p = v;
        else v.store_unaligned(p);
    }
    static lane::Mask<T> mask(const bool* on) {
        S v[W];
        for (int i = 0; i < W; ++i) v[i] = on[i] ? S(1) : S(0);
        return load(v) != T(S(0));
    }
};

// A BVH over random boxes, and where each kind's position comes from.
struct BoxScene {
    bvh::BuildInput input;
    bvh::Bvh8 tree;
    std::vector<std::vector<std::size_t>> input_of;  // [kind][position] -> input box

    BoxScene(std::size_t n, int max_leaf, std::uint32_t seed) : input(random_boxes(n, 3, seed)) {
        bvh::BuildOptions opt;
        opt.max_leaf_size = max_leaf;
        tree = bvh::build_bvh8(input, opt);
        std::vector<std::vector<std::size_t>> by_index(3);
        for (std::size_t i = 0; i < n; ++i) by_index[input.kind[i]].push_back(i);
        input_of.resize(3);
        for (int k = 0; k < 3; ++k)
            for (std::uint32_t idx : tree.order[std::size_t(k)]) input_of[std::size_t(k)].push_back(by_index[std::size_t(k)][idx]);
    }
    // The leaf holding each input box.
    std::vector<std::size_t> leaf_of() const {
        std::vector<std::size_t> out(input.boxes.size());
        for (std::size_t l = 0; l < tree.leaves.size(); ++l)
            for (int k = 0; k < 3; ++k)
                for (std::uint32_t p = tree.leaves[l].begin[k]; p < tree.leaves[l].begin[k] + tree.leaves[l].count[k]; ++p)
                    out[input_of[std::size_t(k)][p]] = l;
        return out;
    }
    // The index in tree.leaves of the leaf a walk handed over (a walk may
    // hand a copy decoded from the parent's run word, Node8::run); -1 when
    // it is no leaf of the tree.
    std::ptrdiff_t index_of(const bvh::Leaf& l) const {
        for (std::size_t i = 0; i < tree.leaves.size(); ++i)
            if (std::memcmp(tree.leaves[i].count, l.count, sizeof l.count) == 0 && l.size() > 0) {
                bool same = true;
                for (int k = 0; k < bvh::kMaxKinds; ++k)
                    if (l.count[k] > 0 && l.begin[k] != tree.leaves[i].begin[k]) same = false;
                if (same) return std::ptrdiff_t(i);
            }
        return -1;
    }
    template <class Fn>
    void for_each_box(const bvh::Leaf& l, Fn&& fn) const {
        for (int k = 0; k < 3; ++k)
            for (std::uint32_t p = l.begin[k]; p < l.begin[k] + l.count[k]; ++p)
                fn(input.boxes[input_of[std::size_t(k)][p]]);
    }
};

// A packet's rays, lane by lane, in the view's own precision.
template <class T>
struct Packet {
    using S = lane::Scalar<T>;
    static constexpr int W = lane::width<T>;
    S o[3][W], inv[3][W], tmin[W], tmax[W];
    bool on[W];
    bvh::RayView<T> view;

    // Random rays; one in four with a zero direction component, aimed at a
    // box's face centre, mostly from a point on that face's plane (0 * inf
    // = NaN in the slab test there).
    // Coherent: one direction octant, origins and directions close together
    // (a camera's packet), which the hull walk takes.
    Packet(BvhLcg& rng, const bvh::BuildInput& in, bool coherent = false) {
        S d[3][W], org[3][W];
        float base_o[3], base_d[3];
        for (int a = 0; a < 3; ++a) {
            base_o[a] = rng.range(-14.0f, 14.0f);
            base_d[a] = rng.range(0.2f, 1.0f) * ((rng.next() & 1) ? 1.0f : -1.0f);
        }
        for (int i = 0; i < W; ++i) {
            for (int a = 0; a < 3; ++a) {
                org[a][i] = coherent ? S(base_o[a] + rng.range(-0.5f, 0.5f)) : S(rng.range(-14.0f, 14.0f));
                d[a][i] = coherent ? S(base_d[a] + rng.range(-0.1f, 0.1f)) : S(rng.range(-1.0f, 1.0f));
            }
            if (!coherent && rng.next() % 4 == 0) {  // aimed at a box's face centre, in the face's plane or beside it
                const int a = int(rng.next() % 3);
                const bvh::Box& b = in.boxes[rng.next() % in.boxes.size()];
                for (int e = 0; e < 3; ++e) d[e][i] = S(0.5f * (b.lo[e] + b.hi[e])) - org[e][i];
                d[a][i] = (rng.next() & 1) ? S(0.0) : S(-0.0);
                if (rng.next() % 4 != 0) org[a][i] = S((rng.next() & 1) ? b.lo[a] : b.hi[a]);
            }
            tmin[i] = (rng.next() & 1) ? S(0) : S(rng.range(0.0f, 5.0f));
            tmax[i] = (rng.next() % 3 == 0) ? S(rng.range(5.0f, 30.0f)) : std::numeric_limits<S>::infinity();
            on[i] = rng.next() % 8 != 0;
        }
        using L = Lanes<T>;
        view = bvh::make_ray_view(L::load(org[0]), L::load(org[1]), L::load(org[2]), L::load(d[0]), L::load(d[1]),
                                  L::load(d[2]), L::load(tmin));
        L::store(inv[0], view.inv_dx), L::store(inv[1], view.inv_dy), L::store(inv[2], view.inv_dz);
        for (int a = 0; a < 3; ++a)
            for (int i = 0; i < W; ++i) o[a][i] = org[a][i];
    }
    bool enters(int i, const bvh::Box& b, S limit, S& entry) const {
        const S oi[3] = {o[0][i], o[1][i], o[2][i]}, vi[3] = {inv[0][i], inv[1][i], inv[2][i]};
        return bvh::slab_enter(b, oi, vi, tmin[i], limit, entry);
    }
};

// For random packets and every walk mode: the any-hit walk visits every leaf
// with a box the lane's ray enters in [tmin, tmax]; stopping on the first hit
// it blocks exactly the lanes that hit something; the closest-hit walk finds
// exactly the nearest entry, visiting every leaf with a box entered before it.
template <class T>
void check_walks(std::uint32_t seed, int packets) {
    using S = lane::Scalar<T>;
    constexpr int W = lane::width<T>;
    using L = Lanes<T>;
    // 20 boxes in leaves of 8: a root of a few leaf children, which packets
    // walk without the hull even where it is on (WalkOptions::flat_root_children).
    const std::pair<std::size_t, int> scenes[] = {{1500, 1}, {1500, 4}, {1500, 8}, {20, 8}};
    for (const auto& sc : scenes) {
        const std::size_t boxes = sc.first;
        const int max_leaf = sc.second;
        const BoxScene scene(boxes, max_leaf, seed + std::uint32_t(max_leaf) + (boxes == 1500 ? 0u : 1000u));
        if (boxes == 20) REQUIRE(bvh::detail::flat_root(scene.tree, bvh::WalkOptions{}.flat_root_children));
        const std::vector<std::size_t> leaf_of = scene.leaf_of();
        const auto& leaves = scene.tree.leaves;
        BvhLcg rng{seed * 7u + 1u};
        for (int p = 0; p < packets; ++p) {
            const bool coherent = p % 2 == 1;
            const Packet<T> pk(rng, scene.input, coherent);
            for (const int single : {0, 2, W, -1}) {
                bvh::WalkOptions opt;
                opt.single_ray_lanes = std::max(single, 0);
                opt.hull = single < 0;  // the hull walk (coherent packets of float lanes)
                CAPTURE(boxes);
                CAPTURE(max_leaf);
                CAPTURE(p);
                CAPTURE(coherent);
                CAPTURE(single);
                const lane::Mask<T> on = L::mask(pk.on);

                // Any hit, never blocking: the leaves visited per lane.
                std::vector<std::vector<char>> visited(W, std::vector<char>(leaves.size(), 0));
                bool bad_leaf = false;
                auto record = [&](const bvh::Leaf& l, const lane::Mask<T>& lanes) {
                    const std::ptrdiff_t k = scene.index_of(l);
                    if (k < 0 || std::size_t(k) >= leaves.size()) return void(bad_leaf = true);
                    const unsigned bits = lane::bits(lanes);
                    for (int i = 0; i < W; ++i)
                        if ((bits >> i) & 1u) visited[std::size_t(i)][std::size_t(k)] = 1;
                };
                const T tmax = L::load(pk.tmax);
                lane::Mask<T> active = on;
                bvh::traverse_any(scene.tree, pk.view, active, tmax, record, opt);
                CHECK_FALSE(bad_leaf);
                bool any_hit[W];
                S nearest[W];
                for (int i = 0; i < W; ++i) {
                    any_hit[i] = false;
                    nearest[i] = pk.tmax[i];
                    if (!pk.on[i]) continue;
                    int missed = 0;
                    for (std::size_t b = 0; b < scene.input.boxes.size(); ++b) {
                        S entry;
                        if (!pk.enters(i, scene.input.boxes[b], pk.tmax[i], entry)) continue;
                        any_hit[i] = true;
                        if (entry < nearest[i]) nearest[i] = entry;
                        missed += !visited[std::size_t(i)][leaf_of[b]];
                    }
                    CHECK(missed == 0);
                }

                // Any hit, blocking on the first box entered.
                active = on;
                auto block = [&](const bvh::Leaf& l, const lane::Mask<T>& lanes) {
                    const unsigned bits = lane::bits(lanes);
                    bool blocked[W] = {};
                    scene.for_each_box(l, [&](const bvh::Box& b) {
                        for (int i = 0; i < W; ++i) {
                            S entry;
                            if (((bits >> i) & 1u) && pk.enters(i, b, pk.tmax[i], entry)) blocked[i] = true;
                        }
                    });
                    active = active && lane::not_(L::mask(blocked));
                };
                bvh::traverse_any(scene.tree, pk.view, active, tmax, block, opt);
                const unsigned left = lane::bits(active);
                for (int i = 0; i < W; ++i)
                    if (pk.on[i]) CHECK(((left >> i) & 1u) == (any_hit[i] ? 0u : 1u));

                // Closest hit.
                T tbest = tmax;
                for (auto& v : visited) std::fill(v.begin(), v.end(), 0);
                auto nearest_box = [&](const bvh::Leaf& l, const lane::Mask<T>& lanes) {
                    record(l, lanes);
                    const unsigned bits = lane::bits(lanes);
                    S best[W];
                    L::store(best, tbest);
                    scene.for_each_box(l, [&](const bvh::Box& b) {
                        for (int i = 0; i < W; ++i) {
                            S entry;
                            if (((bits >> i) & 1u) && pk.on[i] && pk.enters(i, b, best[i], entry) && entry < best[i])
                                best[i] = entry;
                        }
                    });
                    tbest = L::load(best);
                };
                active = on;
                bvh::traverse_closest(scene.tree, pk.view, active, tbest, nearest_box, opt);
                S found[W];
                L::store(found, tbest);
                for (int i = 0; i < W; ++i) {
                    if (!pk.on[i]) continue;
                    CHECK(found[i] == nearest[i]);
                    int missed = 0;
                    for (std::size_t b = 0; b < scene.input.boxes.size(); ++b) {
                        S entry;
                        if (pk.enters(i, scene.input.boxes[b], found[i], entry))
                            missed += !visited[std::size_t(i)][leaf_of[b]];
                    }
                    CHECK(missed == 0);
                }
            }
        }
    }
}

// The walks' child order (bvh::detail::order_children) against a stable
// sort of the entered slots by entry, farthest first (the nearest last,
// visited first; on a tie the earlier slot nearer the front): every mask of
// entered slots, over entries drawn from a few values (ties, +0 and -0) and
// from a range, and in slot order when not nearest first.
void check_child_order(std::uint32_t seed) {
    BvhLcg rng{seed};
    const float few[] = {0.0f, -0.0f, 1.0f, 2.5f, -3.0f, 1e30f};
    for (int round = 0; round < 64; ++round) {
        alignas(32) float entry[bvh::kWidth];
        for (float& e : entry) e = round % 2 == 0 ? few[rng.next() % 6u] : rng.range(-5.0f, 5.0f);
        for (unsigned bits = 1; bits < (1u << bvh::kWidth); ++bits) {
            std::vector<int> want;
            for (int i = 0; i < bvh::kWidth; ++i)
                if ((bits >> i) & 1u) want.push_back(i);
            std::vector<int> by_slot(want.rbegin(), want.rend());
            std::stable_sort(want.begin(), want.end(), [&](int a, int b) { return entry[a] > entry[b]; });
            int got[bvh::kWidth];
            const int n = bvh::detail::order_children(bits, entry, true, got);
            REQUIRE(n == int(want.size()));
            CHECK(std::vector<int>(got, got + n) == want);
            const int m = bvh::detail::order_children(bits, entry, false, got);
            REQUIRE(m == int(by_slot.size()));
            CHECK(std::vector<int>(got, got + m) == by_slot);
        }
    }
}

}  // namespace
}  // namespace octray::test
