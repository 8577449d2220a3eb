// kernels/bvh/walk_single.hpp — the single-ray walk of the 8-wide BVH
// (kernels/bvh/traverse.hpp): one lane of float, or a subtree that few lanes of a
// packet reach, walked lane by lane; and how a leaf is handed to the leaf
// function for one lane alone (LaneOf).
#pragma once

#include "kernels/bvh/walk_ray.hpp"

#include <cstdint>
#include <type_traits>

namespace octray::bvh {

inline namespace OCTRAY_BVH_ISA {

// What a walk hands a leaf function visited by one lane of a packet alone,
// where the function has an overload for it: the function may then test that
// lane's ray against the leaf's primitives side by side in the lanes (one
// instruction for up to 8 primitives) instead of each primitive against the
// whole packet with one useful lane.
struct LaneOf {
    int lane;
};

namespace detail {

// Lane i's visit of leaf `l`: with LaneOf where the leaf function takes it
// (packets only: one lane of float has nothing to put side by side).
template <class T, class LeafFn>
inline void visit_lane(LeafFn& leaf, const Leaf& l, int i, const Mask<T>& alone) {
    if constexpr (lane::width<T> > 1 && std::is_invocable_v<LeafFn&, const Leaf&, LaneOf>) {
        (void)alone;
        leaf(l, LaneOf{i});
    } else {
        (void)i;
        leaf(l, alone);
    }
}
// The same, out of line: for a lane of a packet, the single-ray walk's node
// loop then keeps fewer values live across an inlined leaf test (one lane
// of float keeps it inline: there the call cost more than it saved).
template <class T, class LeafFn>
[[gnu::noinline]] void visit_leaf_out_of_line(LeafFn& leaf, const AlignedVector<Leaf>& leaves, std::int32_t ref,
                                              std::uint32_t run, int i, const Mask<T>& alone) {
    Leaf scratch;
    visit_lane<T>(leaf, leaf_of(leaves, ref, run, scratch), i, alone);
}
template <class T, class LeafFn>
inline constexpr bool takes_lanes = lane::width<T> > 1 && std::is_invocable_v<LeafFn&, const Leaf&, LaneOf>;

// The subtree `start` walked by lane i of the packet alone, as a single ray:
// each node's 8 children slab-tested at once; the nearest entered child is
// visited next without a trip through the stack, the others pushed farthest
// first (closest hit; any hit: in slot order); a popped entry whose entry t
// lies beyond the ray's current best is dropped unvisited.
template <bool Closest, class T, class LeafFn>
void walk_single(const Bvh8& bvh, std::int32_t start, float start_t, const SingleRay& r, int i,
                 const Mask<T>& active, const T& tbest, LeafFn& leaf) {
    std::int32_t stack_ref[kStackSize];
    std::uint32_t stack_run[kStackSize];  // a leaf's run word (Node8::run)
    float stack_t[kStackSize];
    int top = 0;
    const Mask<T> alone = lane_alone<T>(i);
    float limit = float(lane_value(tbest, i));
    alignas(32) float entry[kWidth];
    std::int32_t ref = start;
    std::uint32_t run = 0;
    if (start_t > grow(limit)) return;
    for (;;) {
        if (ref >= 0) {
            const Node8& node = bvh.nodes[std::size_t(ref)];
            unsigned bits = enter_children(node, r, limit, entry);
            if (bits != 0) {
                const int first = __builtin_ctz(bits);
                bits &= bits - 1;
                if (bits == 0) {  // one child: straight on
                    ref = node.child[first], run = node.run[first];
                    continue;
                }
                if (!Closest) {  // any order: the first slot next, the rest pushed
                    for (; bits != 0; bits &= bits - 1) {
                        const int c = __builtin_ctz(bits);
                        stack_ref[top] = node.child[c];
                        stack_run[top] = node.run[c];
                        stack_t[top++] = entry[c];
                    }
                    ref = node.child[first], run = node.run[first];
                    continue;
                }
                const int second = __builtin_ctz(bits);
                bits &= bits - 1;
                if (bits == 0) {  // two: the nearer next (the later slot on a tie), the farther pushed
                    const bool keep = entry[first] < entry[second];
                    const int near = keep ? first : second, far = keep ? second : first;
                    stack_ref[top] = node.child[far];
                    stack_run[top] = node.run[far];
                    stack_t[top++] = entry[far];
                    ref = node.child[near], run = node.run[near];
                    continue;
                }
                // Three or more: insertion sort, farthest first onto the
                // stack; the nearest is taken straight off again.
                int idx[kWidth];
                const int n = order_children(bits | (1u << first) | (1u << second), entry, true, idx);
                for (int a = 0; a + 1 < n; ++a) {
                    stack_ref[top] = node.child[idx[a]];
                    stack_run[top] = node.run[idx[a]];
                    stack_t[top++] = entry[idx[a]];
                }
                ref = node.child[idx[n - 1]], run = node.run[idx[n - 1]];
                continue;
            }
        } else {
            if constexpr (lane::width<T> > 1) {
                visit_leaf_out_of_line<T>(leaf, bvh.leaves, ref, run, i, alone);
            } else {
                Leaf scratch;
                visit_lane<T>(leaf, leaf_of(bvh.leaves, ref, run, scratch), i, alone);
            }
            if constexpr (Closest) limit = float(lane_value(tbest, i));
            else if (!lane_on(lane::bits(active), i)) return;
        }
        // Next: the top of the stack that is still nearer than the best hit.
        for (;;) {
            if (top == 0) return;
            --top;
            if (!(stack_t[top] > grow(limit))) break;
        }
        ref = stack_ref[top], run = stack_run[top];
    }
}

}  // namespace detail

}  // namespace OCTRAY_BVH_ISA
}  // namespace octray::bvh
