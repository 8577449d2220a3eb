// kernels/bvh/traverse.hpp — walks of the 8-wide BVH (kernels/bvh/node.hpp), written once
// over a lane type T as the packet kernels are: `float` (one ray), `double`,
// or an xsimd batch of float or double lanes (a packet).
//
// A walk calls leaf(const Leaf&, const Mask<T>& lanes) for every leaf whose
// box one of `lanes` enters before its current best t; the function tests
// the leaf's primitives and records what they hit. It may test more lanes
// than `lanes` (a true hit on any active lane is a true hit) but must record
// hits only on lanes of the caller's active mask.
//
//   traverse_closest: the leaf function lowers `tbest` (the caller's
//     variable, passed by reference and re-read after every leaf) on the
//     lanes it hits; children are visited nearest first, and a child whose
//     entry t exceeds every active lane's tbest is skipped.
//   traverse_any: the leaf function clears the lanes of `active` (the
//     caller's variable, re-read too) whose rays are blocked; the walk ends
//     when none is left. No ordering.
//
// Node tests. A ray enters a child when its slab interval, clipped to
// [tmin, tbest], is non-empty, tested with a relative slack of 2^-20 of t
// (Ize 2013, "Robust BVH ray traversal", takes 1 + 2 gamma_3 ~ 1 + 2^-21):
// a primitive test whose rounded t lies a few ulps beyond its box still finds
// its leaf entered. Each axis uses the near and far plane of its direction's
// sign, t = (plane - o) * inv_d: a zero direction component (inv_d = +-inf)
// whose origin lies on a plane gives 0 * inf = NaN there, and the NaN is
// dropped by min/max (the ray lies in the plane: inside the closed slab), as
// the box test of kernels/packet_kernels.hpp resolves it. Rounding is monotone in the
// plane, so a child's box, which contains its primitives' boxes, is entered
// whenever one of those boxes is.
//
//   one lane of float: a single ray; each node's 8 children in one 8-float
//     batch (two 4-float ones without AVX), the nearest entered child next.
//   a packet of float lanes in one direction octant: its hull (walk_hull)
//     tests each node's 8 children once for all lanes; a leaf's own lanes
//     are then found exactly. Not in a tree of one node with a few leaf
//     children (WalkOptions::flat_root_children): it walks as below.
//   any other packet: each child is tested against every lane (the child's
//     bounds broadcast), its per-lane entry t kept on the stack; children
//     are visited in the order of their nearest lane's entry t. A subtree
//     that at most WalkOptions::single_ray_lanes lanes reach is walked lane
//     by lane as single rays (float lanes only: double lanes always walk as
//     one packet, f64 is a checking mode whose node tests stay in double).
//   A packet's leaf that few lanes reach, and every leaf of a single-ray
//     walk inside a packet, is handed to the leaf function as LaneOf (where
//     it takes one): that lane's ray against the leaf's primitives in the
//     lanes.
//     The thresholds and orders were chosen by measurement
//     (docs/history/performance-2026.md).
//
// Filling the view from the kernels' Ray<T, P> (kernels/packet_kernels.hpp):
//   const auto view = bvh::make_ray_view(r.o.x, r.o.y, r.o.z, r.d.x, r.d.y, r.d.z, r.tmin);
//   Closest<T> best{r.tmax, T(-1)};
//   bvh::traverse_closest(tree, view, r.valid, best.t, leaf_fn);
// make_ray_view divides (IEEE, whatever the precision mode: an estimate's
// 2^-12 error in 1/d would move slab t's by more than the slack), as Ray's
// inv_d (make_slabs) now does too. d need not be normalized; t is in units
// of d, as every primitive test's.
//
// The parts, one header each (this one includes them all and keeps the
// options, the packet walk, the dispatch and traverse_closest/traverse_any):
//   kernels/bvh/walk_ray.hpp          RayView, make_ray_view, slab_enter; the slack, lane
//                        helpers, a single ray's node child tests and order
//   kernels/bvh/walk_single.hpp  walk_single, LaneOf
//   kernels/bvh/walk_hull.hpp    walk_hull
//
// ISA: the templates live in an inline namespace named after the including
// unit's OCTRAY_ISA (else `native`), as kernels/packet_kernels.hpp's do, so
// instantiations compiled with different -m flags never merge at link time.
// OCTRAY_BVH_ISA names it; kernels/bvh/walk_ray.hpp, which every part includes, defines it.
#pragma once

#include "kernels/bvh/node.hpp"
#include "kernels/bvh/walk_ray.hpp"
#include "kernels/bvh/walk_hull.hpp"
#include "kernels/bvh/walk_single.hpp"

#include "kernels/lanes/lane.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <type_traits>

namespace octray::bvh {

inline namespace OCTRAY_BVH_ISA {

struct WalkOptions {
    // A packet's subtree reached by at most this many lanes is walked lane by
    // lane (float lanes; 0: never). See bench/bench_bvh.cpp for the measure.
    int single_ray_lanes = 2;
    // Closest hit, packets: visit a node's children in the order of their
    // nearest lane's entry t (else in slot order).
    bool order_packet_children = true;
    // Packets of float lanes: walk the lanes of each direction octant as a
    // packet of their own (an incoherent packet's octants hold a lane or
    // two each, which then walk as single rays from the root). Off: on the
    // kernels' own primitive tests the whole packet walking together until
    // it diverges was faster at every size of the cost curve, incoherent
    // rays most of all (docs/history/performance-2026.md, the cost curve).
    bool split_octants = false;
    // A packet's leaf reached by at most this many lanes (float lanes, with
    // a leaf function that takes LaneOf) is tested lane by lane, each ray
    // against the leaf's primitives in the lanes.
    int leaf_lanes_alone = 2;
    // Packets of float lanes in one direction octant walk by their hull,
    // except in a tree that is one node of at most flat_root_children
    // children (all leaves): there each child's test on every lane costs
    // less than making the hull (13 horizontal reductions), and the hull's
    // cull of a leaf's run saves little with so few leaves.
    bool hull = true;
    int flat_root_children = 4;
};

namespace detail {

// The walk of a packet (or of one double lane).
template <bool Closest, class T, class LeafFn>
void walk_packet(const Bvh8& bvh, const RayView<T>& r, const Mask<T>& group, const Mask<T>& active, const T& tbest,
                 LeafFn& leaf, const WalkOptions& opt) {
    using S = lane::Scalar<T>;
    constexpr int W = lane::width<T>;
    constexpr bool kFloat = std::is_same_v<S, float>;
    const int single_lanes = kFloat ? opt.single_ray_lanes : 0;
    const S nan = std::numeric_limits<S>::quiet_NaN(), inf = std::numeric_limits<S>::infinity();
    // Per lane, the near plane of each axis is hi where d < 0.
    const Mask<T> neg_x = r.inv_dx < T(0), neg_y = r.inv_dy < T(0), neg_z = r.inv_dz < T(0);

    std::int32_t stack_ref[kStackSize];
    std::uint32_t stack_run[kStackSize];  // a leaf's run word (Node8::run)
    alignas(64) S stack_t[kStackSize][W];  // per lane entry t; NaN: the lane did not enter
    int top = 0;
    auto push = [&](std::int32_t ref, std::uint32_t run, const T& t) {
        stack_ref[top] = ref;
        stack_run[top] = run;
        if constexpr (W == 1) stack_t[top][0] = t;
        else t.store_aligned(stack_t[top]);
        ++top;
    };
    auto pop_t = [&]() -> T {
        if constexpr (W == 1) return stack_t[top][0];
        else return T::load_aligned(stack_t[top]);
    };
    // The entry being visited: popped, or the nearest child of the node just
    // tested, taken straight on (the pop would find the same lanes: nothing
    // lowers tbest between the test and the visit).
    std::int32_t ref = 0;
    std::uint32_t run = 0;
    T entry_t(-inf);
    Mask<T> on = group && active && entry_t <= grow(tbest);
    if (!lane::any(on)) return;
    bool taken = true;
    for (;;) {
        if (!taken) {
            if (top == 0) return;
            --top;
            ref = stack_ref[top], run = stack_run[top], entry_t = pop_t();
            on = group && active && entry_t <= grow(tbest);
            if (!lane::any(on)) continue;
        }
        taken = false;
        if (ref < 0) {  // a leaf: one call for all its lanes, or one per lane where few reach it
            Leaf scratch;
            const Leaf& l = leaf_of(bvh.leaves, ref, run, scratch);
            if constexpr (takes_lanes<T, LeafFn>) {
                if (lane::count(on) <= opt.leaf_lanes_alone) {
                    for (unsigned bits = lane::bits(on); bits != 0; bits &= bits - 1) {
                        leaf(l, LaneOf{__builtin_ctz(bits)});
                        if (!Closest && !lane::any(active)) return;
                    }
                    continue;
                }
            }
            leaf(l, on);
            if (!Closest && !lane::any(active)) return;
            continue;
        }
        if constexpr (kFloat && W > 1) {
            if (lane::count(on) <= single_lanes) {
                for (unsigned bits = lane::bits(on); bits != 0; bits &= bits - 1) {
                    const int i = __builtin_ctz(bits);
                    walk_single<Closest>(bvh, ref, float(lane_value(entry_t, i)), single_ray(r, i), i, active, tbest,
                                         leaf);
                    if (!Closest && !lane::any(active)) return;
                }
                continue;
            }
        }
        const Node8& node = bvh.nodes[std::size_t(ref)];
        const T limit = tbest;
        std::int32_t hit_ref[kWidth];
        std::uint32_t hit_run[kWidth];
        T hit_t[kWidth];
        Mask<T> hit_on[kWidth];
        float key[kWidth];
        int hits = 0;
        for (int c = 0; c < kWidth && node.child[c] != kEmptySlot; ++c) {
            auto axis = [&](const float* lo, const float* hi, const T& o, const T& inv, const Mask<T>& neg, T& enter,
                            T& leave) {
                const T l = T(S(lo[c])), h = T(S(hi[c]));  // not l(S(lo[c])): Clang reads that as a function declaration
                enter = lane::max((lane::select(neg, h, l) - o) * inv, enter);  // max(t, acc): NaN t dropped
                leave = lane::min((lane::select(neg, l, h) - o) * inv, leave);
            };
            T enter = r.tmin, leave = limit;
            axis(node.lo_z, node.hi_z, r.oz, r.inv_dz, neg_z, enter, leave);
            axis(node.lo_y, node.hi_y, r.oy, r.inv_dy, neg_y, enter, leave);
            axis(node.lo_x, node.hi_x, r.ox, r.inv_dx, neg_x, enter, leave);
            const Mask<T> in = on && enter <= grow(leave);
            if (!lane::any(in)) continue;
            hit_ref[hits] = node.child[c];
            hit_run[hits] = node.run[c];
            hit_t[hits] = lane::select(in, enter, T(nan));
            hit_on[hits] = in;
            if (Closest && opt.order_packet_children)
                key[hits] = float(lane::lane0(lane::hmin(lane::select(in, enter, T(inf)))));
            else
                key[hits] = float(c);  // the first slot first
            ++hits;
        }
        if (hits == 0) continue;
        // The nearest (or the first slot) next, the rest pushed by key,
        // descending (insertion sort; the later slot first on a tie).
        int next = 0;
        if (hits == 2) {
            next = key[0] < key[1] ? 0 : 1;
            push(hit_ref[1 - next], hit_run[1 - next], hit_t[1 - next]);
        } else if (hits > 2) {
            int order[kWidth];
            for (int i = 0; i < hits; ++i) {
                int j = i;
                for (; j > 0 && key[order[j - 1]] < key[i]; --j) order[j] = order[j - 1];
                order[j] = i;
            }
            for (int i = 0; i + 1 < hits; ++i) push(hit_ref[order[i]], hit_run[order[i]], hit_t[order[i]]);
            next = order[hits - 1];
        }
        ref = hit_ref[next], run = hit_run[next], entry_t = hit_t[next], on = hit_on[next];
        taken = true;
    }
}

// Whether the tree is its root alone with at most `children` children
// (used slots come first: slot `children` is empty).
inline bool flat_root(const Bvh8& bvh, int children) {
    return bvh.depth == 1 && (children >= kWidth || bvh.nodes[0].child[std::max(children, 0)] == kEmptySlot);
}

template <bool Closest, class T, class LeafFn>
void walk(const Bvh8& bvh, const RayView<T>& r, const Mask<T>& active, const T& tbest, LeafFn& leaf,
          const WalkOptions& opt) {
    if (bvh.empty() || !lane::any(active)) return;
    if constexpr (lane::width<T> == 1 && std::is_same_v<T, float>) {
        walk_single<Closest>(bvh, 0, -std::numeric_limits<float>::infinity(), single_ray(r, 0), 0, active, tbest, leaf);
    } else if (std::is_same_v<lane::Scalar<T>, float> && lane::width<T> > 1 && opt.split_octants) {
        // One walk per direction octant among the active lanes.
        const unsigned neg[3] = {lane::bits(r.inv_dx < T(0)), lane::bits(r.inv_dy < T(0)), lane::bits(r.inv_dz < T(0))};
        for (unsigned left = lane::bits(active); left != 0;) {
            const int first = __builtin_ctz(left);
            unsigned group = left;
            for (const unsigned n : neg) group &= lane_on(n, first) ? n : ~n;
            left &= ~group;
            walk_packet<Closest>(bvh, r, lanes_of<T>(group), active, tbest, leaf, opt);
            if (!Closest && !lane::any(active)) return;
        }
    } else {
        if constexpr (std::is_same_v<lane::Scalar<T>, float> && lane::width<T> > 1)
            if (opt.hull && !flat_root(bvh, opt.flat_root_children) &&
                walk_hull<Closest>(bvh, r, active, tbest, leaf, opt.leaf_lanes_alone))
                return;
        walk_packet<Closest>(bvh, r, lanes_of<T>(~0u), active, tbest, leaf, opt);
    }
}

}  // namespace detail

// Nearest hit: see the top of this file. `tbest` is the caller's variable
// (tmax before any hit) that leaf(const Leaf&, const Mask<T>&) lowers.
template <class T, class LeafFn>
void traverse_closest(const Bvh8& bvh, const RayView<T>& ray, const Mask<T>& active, const T& tbest, LeafFn&& leaf,
                      const WalkOptions& opt = {}) {
    detail::walk<true>(bvh, ray, active, tbest, leaf, opt);
}

// Any hit (shadow rays): `active` is the caller's variable whose lanes the
// leaf function clears when blocked; the walk ends when none is left.
template <class T, class LeafFn>
void traverse_any(const Bvh8& bvh, const RayView<T>& ray, const Mask<T>& active, const T& tmax, LeafFn&& leaf,
                  const WalkOptions& opt = {}) {
    detail::walk<false>(bvh, ray, active, tmax, leaf, opt);
}

}  // namespace OCTRAY_BVH_ISA
}  // namespace octray::bvh
