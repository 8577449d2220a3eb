// kernels/bvh/walk_hull.hpp — the hull walk of the 8-wide BVH
// (kernels/bvh/traverse.hpp): a packet of float lanes in one direction octant tests
// each node's children once, against the interval hull of its rays.
#pragma once

#include "kernels/bvh/walk_ray.hpp"
#include "kernels/bvh/walk_single.hpp"

#include <cstdint>
#include <limits>
#include <type_traits>

namespace octray::bvh {

inline namespace OCTRAY_BVH_ISA {

namespace detail {

// A coherent packet's walk (float lanes, every active lane in one direction
// octant, finite reciprocals): each node's 8 children are tested once for
// the whole packet, against the interval hull of its rays (origins in
// [o_lo, o_hi], reciprocal directions in [inv_lo, inv_hi] per axis). By the
// monotonicity of rounding, the hull's entry bound is no greater, and its
// exit bound no smaller, than any lane's own float slab values, so a child
// the hull misses is one no lane enters. Children are visited nearest hull
// entry first. A leaf's lanes are found exactly (its box against each lane)
// before its leaf function runs; at most leaf_lanes_alone of them
// (WalkOptions::leaf_lanes_alone) go alone (LaneOf).
struct Hull {
    float o_lo[3], o_hi[3], inv_lo[3], inv_hi[3], tmin;
    bool neg[3];
    // The node test's operands, broadcast once a walk, and each axis' near
    // and far child bounds as offsets into a Node8 (chosen by the octant
    // once, not by a blend at every node): o_near is the origin bound the
    // near plane is measured from (o_hi where d > 0, o_lo where d < 0),
    // o_far the other.
    NodeBatch o_near[3], o_far[3], inv_lo_n[3], inv_hi_n[3], tmin_n;
    std::uint32_t near[3], far[3];
};

}  // namespace detail

// What a hull walk hands a leaf function that takes it, with the lanes: the
// packet's hull and the greatest tbest of its active lanes (hull_boxes).
struct InHull {
    const detail::Hull& hull;
    float limit;
};

namespace detail {

template <class T>
inline bool make_hull(const RayView<T>& r, const Mask<T>& active, Hull& h) {
    const T inf(std::numeric_limits<float>::infinity());
    const T* o[3] = {&r.ox, &r.oy, &r.oz};
    const T* inv[3] = {&r.inv_dx, &r.inv_dy, &r.inv_dz};
    for (int a = 0; a < 3; ++a) {
        const Mask<T> neg = *inv[a] < T(0);
        if (lane::any(active && neg) && lane::any(active && lane::not_(neg))) return false;  // octants differ
        if (lane::any(active && lane::not_(lane::abs(*inv[a]) < inf))) return false;     // an axis-parallel ray
        h.neg[a] = lane::any(active && neg);
        h.o_lo[a] = lane::lane0(lane::hmin(lane::select(active, *o[a], inf)));
        h.o_hi[a] = lane::lane0(lane::hmax(lane::select(active, *o[a], T(0) - inf)));
        h.inv_lo[a] = lane::lane0(lane::hmin(lane::select(active, *inv[a], inf)));
        h.inv_hi[a] = lane::lane0(lane::hmax(lane::select(active, *inv[a], T(0) - inf)));
    }
    h.tmin = lane::lane0(lane::hmin(lane::select(active, r.tmin, inf)));
    for (int a = 0; a < 3; ++a) {
        h.o_near[a] = NodeBatch(h.neg[a] ? h.o_lo[a] : h.o_hi[a]);
        h.o_far[a] = NodeBatch(h.neg[a] ? h.o_hi[a] : h.o_lo[a]);
        h.inv_lo_n[a] = NodeBatch(h.inv_lo[a]);
        h.inv_hi_n[a] = NodeBatch(h.inv_hi[a]);
        h.near[a] = h.neg[a] ? kUpperBounds[a] : kLowerBounds[a];
        h.far[a] = h.neg[a] ? kLowerBounds[a] : kUpperBounds[a];
    }
    h.tmin_n = NodeBatch(h.tmin);
    return true;
}

// Narrows a batch of boxes' interval [enter, leave] by one axis of the hull:
// near_d, far_d are the boxes' near and far bounds on that axis (hi and lo
// where d < 0) less the origin bound each is measured from (o_hi and o_lo
// where d > 0; o_lo and o_hi where d < 0); inv_lo, inv_hi the hull's
// reciprocal directions. The result: the smallest entry and the greatest
// exit any ray of the hull has there (d > 0: t falls as o grows; d < 0: it
// rises, near - o and 1/d being of opposite signs there).
template <class N>
[[gnu::always_inline]] inline void hull_axis(const N& near_d, const N& far_d, const N& inv_lo, const N& inv_hi, N& enter,
                                             N& leave) {
    enter = lane::max(lane::min(near_d * inv_lo, near_d * inv_hi), enter);
    leave = lane::min(lane::max(far_d * inv_lo, far_d * inv_hi), leave);
}

// The children the hull enters before `limit` (the greatest tbest of the
// active lanes), with the hull's entry bounds in `entry`, on the operands
// make_hull broadcast.
[[gnu::always_inline]] inline unsigned hull_children(const Node8& node, const Hull& h, float limit,
                                                     float entry[kWidth]) {
    using N = NodeBatch;
    return test_children(h.tmin_n, limit, entry, node, [&](int a, int i, N& enter, N& leave) {
        hull_axis(child_bounds(node, h.near[a], i) - h.o_near[a], child_bounds(node, h.far[a], i) - h.o_far[a],
                  h.inv_lo_n[a], h.inv_hi_n[a], enter, leave);
    });
}

}  // namespace detail

// The boxes of a batch (lane j: [lo[.][j], hi[.][j]]) that some ray of the
// hull enters within [tmin, limit], with the walks' slack: a leaf function
// handed the hull (see walk_hull) skips the primitives whose boxes, as
// conservative as the tree's, no lane of the packet can enter.
template <class N>
inline unsigned hull_boxes(const detail::Hull& h, float limit, const N lo[3], const N hi[3]) {
    N enter(h.tmin), leave(limit);
    for (int a = 2; a >= 0; --a) {  // the octant's sides by a branch (the same for the whole walk), not a blend
        const N o_near(h.neg[a] ? h.o_lo[a] : h.o_hi[a]), o_far(h.neg[a] ? h.o_hi[a] : h.o_lo[a]);
        const N inv_lo(h.inv_lo[a]), inv_hi(h.inv_hi[a]);
        if (h.neg[a]) detail::hull_axis(hi[a] - o_near, lo[a] - o_far, inv_lo, inv_hi, enter, leave);
        else detail::hull_axis(lo[a] - o_near, hi[a] - o_far, inv_lo, inv_hi, enter, leave);
    }
    return unsigned(lane::bits(enter <= detail::grow(leave)));
}

namespace detail {

// The lanes of `on` that enter child c of `node` before their tbest, with
// the packet walk's slab values. A hull walk's reciprocals are finite
// (make_hull), so each axis' near and far t are the min and max of the two
// planes' (lo <= hi: rounding is monotone), no blend by each lane's sign.
template <class T>
inline Mask<T> lanes_entering(const Node8& node, int c, const RayView<T>& r, const Mask<T>& on, const T& tbest) {
    using S = lane::Scalar<T>;
    auto axis = [&](float lo, float hi, const T& o, const T& inv, T& enter, T& leave) {
        const T t_lo = (T(S(lo)) - o) * inv, t_hi = (T(S(hi)) - o) * inv;
        enter = lane::max(lane::min(t_lo, t_hi), enter);
        leave = lane::min(lane::max(t_lo, t_hi), leave);
    };
    T enter = r.tmin, leave = tbest;
    axis(node.lo_z[c], node.hi_z[c], r.oz, r.inv_dz, enter, leave);
    axis(node.lo_y[c], node.hi_y[c], r.oy, r.inv_dy, enter, leave);
    axis(node.lo_x[c], node.hi_x[c], r.ox, r.inv_dx, enter, leave);
    return on && enter <= grow(leave);
}

// A leaf reached by the lanes `on` of a hull walk: with the hull and the
// walk's limit where the leaf function takes them (InHull).
template <class T, class LeafFn>
inline void visit_hull(LeafFn& leaf, const Leaf& l, const Mask<T>& on, const Hull& h, float limit) {
    if constexpr (std::is_invocable_v<LeafFn&, const Leaf&, const Mask<T>&, const InHull&>) leaf(l, on, InHull{h, limit});
    else leaf(l, on);
}

template <bool Closest, class T, class LeafFn>
bool walk_hull(const Bvh8& bvh, const RayView<T>& r, const Mask<T>& active, const T& tbest, LeafFn& leaf,
               int leaf_lanes_alone) {
    Hull h;
    if (!make_hull(r, active, h)) return false;
    const T ninf(-std::numeric_limits<float>::infinity());
    auto farthest = [&]() { return float(lane::lane0(lane::hmax(lane::select(active, tbest, ninf)))); };
    struct Entry {
        std::int32_t node;  // the parent of the child to visit
        std::int8_t slot;
        float t;
    };
    Entry stack[kStackSize];
    int top = 0;
    float limit = farthest();
    alignas(32) float entry[kWidth];
    std::int32_t ref = 0;
    std::int32_t parent = -1;
    int slot = 0;
    for (;;) {
        if (ref >= 0) {
            const Node8& node = bvh.nodes[std::size_t(ref)];
            unsigned bits = hull_children(node, h, limit, entry);
            if (bits != 0) {
                int idx[kWidth];
                const int n = order_children(bits, entry, Closest, idx);
                for (int a = 0; a + 1 < n; ++a) stack[top++] = {ref, std::int8_t(idx[a]), entry[idx[a]]};
                if (n > 1) prefetch_child(bvh, node.child[idx[n - 2]]);
                parent = ref, slot = idx[n - 1];
                ref = node.child[slot];
                continue;
            }
        } else {
            const Node8& up = bvh.nodes[std::size_t(parent)];
            const Mask<T> on = lanes_entering(up, slot, r, active, tbest);
            if (lane::any(on)) {
                Leaf scratch;
                const Leaf& l = leaf_of(bvh.leaves, ref, up.run[slot], scratch);
                if constexpr (takes_lanes<T, LeafFn>) {
                    if (lane::count(on) <= leaf_lanes_alone) {
                        for (unsigned bits = lane::bits(on); bits != 0; bits &= bits - 1) {
                            leaf(l, LaneOf{__builtin_ctz(bits)});
                            if (!Closest && !lane::any(active)) return true;
                        }
                    } else {
                        visit_hull<T>(leaf, l, on, h, limit);
                    }
                } else {
                    visit_hull<T>(leaf, l, on, h, limit);
                }
                if (!Closest && !lane::any(active)) return true;
                limit = farthest();
            }
        }
        for (;;) {
            if (top == 0) return true;
            --top;
            if (!(stack[top].t > grow(limit))) break;
        }
        parent = stack[top].node, slot = stack[top].slot;
        ref = bvh.nodes[std::size_t(parent)].child[slot];
    }
}

}  // namespace detail

}  // namespace OCTRAY_BVH_ISA
}  // namespace octray::bvh
