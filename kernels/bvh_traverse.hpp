// kernels/bvh_traverse.hpp — walks of the 8-wide BVH (bvh.hpp), written once
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
// the box test of packet_kernels.hpp resolves it. Rounding is monotone in the
// plane, so a child's box, which contains its primitives' boxes, is entered
// whenever one of those boxes is.
//
//   one lane of float: a single ray; each node's 8 children in one 8-float
//     batch (two 4-float ones without AVX), the nearest entered child next.
//   a packet of float lanes in one direction octant: its hull (walk_hull)
//     tests each node's 8 children once for all lanes; a leaf's own lanes
//     are then found exactly.
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
//     (docs/performance.md).
//
// Filling the view from the kernels' Ray<T, P> (packet_kernels.hpp):
//   const auto view = bvh::make_ray_view(r.o.x, r.o.y, r.o.z, r.d.x, r.d.y, r.d.z, r.tmin);
//   Closest<T> best{r.tmax, T(-1)};
//   bvh::traverse_closest(tree, view, r.valid, best.t, leaf_fn);
// make_ray_view divides (IEEE, whatever the precision mode: an estimate's
// 2^-12 error in 1/d would move slab t's by more than the slack); Ray's
// inv_d (make_slabs) uses rcp<P> and must not be used for the view in the
// fast modes. d need not be normalized; t is in units of d, as every
// primitive test's.
//
// ISA: the templates live in an inline namespace named after the including
// unit's OCTRAY_ISA (else `native`), as packet_kernels.hpp's do, so
// instantiations compiled with different -m flags never merge at link time.
#pragma once

#include "bvh.hpp"

#include "lane.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <utility>

#ifdef OCTRAY_ISA
#define OCTRAY_BVH_ISA OCTRAY_ISA
#else
#define OCTRAY_BVH_ISA native
#endif

namespace octray::bvh {

inline namespace OCTRAY_BVH_ISA {

using lane::Mask;

// What a walk needs of a ray (one lane or a packet).
template <class T>
struct RayView {
    T ox, oy, oz;              // origin
    T inv_dx, inv_dy, inv_dz;  // 1 / d per axis, IEEE; +-inf (d's sign) for a zero or subnormal component
    T tmin;                    // the interval starts here; tbest (or tmax) is the walk's argument
};

// 1 / d, IEEE, with a zero or subnormal component as a signed infinity (as
// make_slabs does: estimates read subnormals as zero).
template <class T>
inline T inverse_direction(const T& d) {
    const T tiny(std::numeric_limits<float>::min());
    return lane::select(lane::abs(d) < tiny, lane::copysign(T(std::numeric_limits<float>::infinity()), d), T(1) / d);
}

template <class T>
inline RayView<T> make_ray_view(const T& ox, const T& oy, const T& oz, const T& dx, const T& dy, const T& dz,
                                const T& tmin) {
    return {ox, oy, oz, inverse_direction(dx), inverse_direction(dy), inverse_direction(dz), tmin};
}

// What a walk hands a leaf function visited by one lane of a packet alone,
// where the function has an overload for it: the function may then test that
// lane's ray against the leaf's primitives side by side in the lanes (one
// instruction for up to 8 primitives) instead of each primitive against the
// whole packet with one useful lane.
struct LaneOf {
    int lane;
};

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
    // rays most of all (docs/performance.md, the cost curve).
    bool split_octants = false;
    // A packet's leaf reached by at most this many lanes (float lanes, with
    // a leaf function that takes LaneOf) is tested lane by lane, each ray
    // against the leaf's primitives in the lanes.
    int leaf_lanes_alone = 2;
    // Packets of float lanes in one direction octant walk by their hull.
    bool hull = true;
};

namespace detail {

// The slack: t + |t| 2^-20 (+inf stays +inf).
template <class T>
inline T grow(const T& t) {
    return t + lane::abs(t) * T(0x1p-20f);
}

template <class T>
inline lane::Scalar<T> lane_value(const T& v, int i) {
    if constexpr (lane::width<T> == 1) {
        (void)i;
        return v;
    } else {
        alignas(64) lane::Scalar<T> tmp[lane::width<T>];
        v.store_aligned(tmp);
        return tmp[i];
    }
}

// The mask of the lanes whose bits are set.
template <class T>
inline Mask<T> lanes_of(unsigned bits) {
    if constexpr (lane::width<T> == 1) {
        return (bits & 1u) != 0;
    } else {
        using S = lane::Scalar<T>;
        alignas(64) S on[lane::width<T>];
        for (int j = 0; j < lane::width<T>; ++j) on[j] = S((bits >> j) & 1u);
        return T::load_aligned(on) != T(S(0));
    }
}
template <class T>
inline Mask<T> lane_alone(int i) {
    return lanes_of<T>(1u << i);
}

inline bool lane_on(unsigned bits, int i) { return ((bits >> i) & 1u) != 0; }

// Node children a batch at a time for a single ray. The same type as
// packet_kernels.hpp's NodeLanes (not included here: that file is being
// split); one definition should serve both once this walk is integrated.
#if defined(__AVX__)
using NodeBatch = xsimd::batch<float, xsimd::avx>;
#else
using NodeBatch = xsimd::batch<float, xsimd::sse2>;
#endif
static_assert(kWidth % NodeBatch::size == 0, "a node's children fill whole batches");

// One ray in float, with each axis' near and far bounds chosen by its sign.
struct SingleRay {
    float o[3], inv[3], tmin;
    bool neg[3];
};

// The bits of a node's used child slots.
inline unsigned used_children(const Node8& node) {
#if defined(__AVX2__)
    const __m256i c = _mm256_load_si256(reinterpret_cast<const __m256i*>(node.child));
    const __m256i empty = _mm256_set1_epi32(kEmptySlot);
    return ~unsigned(_mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(c, empty)))) & 0xffu;
#else
    return (1u << node.child_count()) - 1u;
#endif
}

// The bits of the used children whose slab interval, clipped to [tmin,
// limit], is non-empty (with the slack), and their entry t in `entry`:
// axis(a, lo, hi, enter, leave) narrows a batch of children's interval by
// axis a (lo, hi: the batch's bounds on that axis).
template <class Axis>
inline unsigned test_children(const Node8& node, float tmin, float limit, float entry[kWidth], Axis&& axis) {
    using N = NodeBatch;
    constexpr int w = int(N::size);
    const float* lo[3] = {node.lo_x, node.lo_y, node.lo_z};
    const float* hi[3] = {node.hi_x, node.hi_y, node.hi_z};
    unsigned bits = 0;
    for (int i = 0; i < kWidth; i += w) {
        N enter = N(tmin), leave = N(limit);
        for (int a = 2; a >= 0; --a) axis(a, lo[a] + i, hi[a] + i, enter, leave);
        enter.store_aligned(entry + i);
        bits |= lane::bits(enter <= grow(leave)) << i;
    }
    // Unused slots have empty bounds, which no slab test enters, except a ray
    // whose every slab term is NaN and dropped (a NaN origin: a shadow ray
    // from a hit point that overflowed): never hand out their kEmptySlot.
    return bits & used_children(node);
}

// The children a single ray enters before `limit` (its tbest).
inline unsigned enter_children(const Node8& node, const SingleRay& r, float limit, float entry[kWidth]) {
    using N = NodeBatch;
    return test_children(node, r.tmin, limit, entry, [&](int a, const float* lo, const float* hi, N& enter, N& leave) {
        const N o(r.o[a]), inv(r.inv[a]);  // max(t, acc): a NaN t is dropped
        enter = lane::max((N::load_aligned(r.neg[a] ? hi : lo) - o) * inv, enter);
        leave = lane::min((N::load_aligned(r.neg[a] ? lo : hi) - o) * inv, leave);
    });
}

// The entered children `bits` in visiting order, last first: by entry,
// farthest first (the later slot first on a tie), when `nearest_first`,
// else the last slot first. Returns how many.
inline int order_children(unsigned bits, const float entry[kWidth], bool nearest_first, int idx[kWidth]) {
    int n = 0;
    for (; bits != 0; bits &= bits - 1) idx[n++] = __builtin_ctz(bits);
    if (nearest_first) {  // insertion sort
        for (int i = 1; i < n; ++i) {
            const int v = idx[i];
            int j = i;
            for (; j > 0 && entry[idx[j - 1]] < entry[v]; --j) idx[j] = idx[j - 1];
            idx[j] = v;
        }
    } else {
        for (int i = 0, j = n - 1; i < j; ++i, --j) std::swap(idx[i], idx[j]);
    }
    return n;
}

template <class T>
inline SingleRay single_ray(const RayView<T>& r, int i) {
    SingleRay s;
    s.o[0] = float(lane_value(r.ox, i)), s.o[1] = float(lane_value(r.oy, i)), s.o[2] = float(lane_value(r.oz, i));
    s.inv[0] = float(lane_value(r.inv_dx, i)), s.inv[1] = float(lane_value(r.inv_dy, i));
    s.inv[2] = float(lane_value(r.inv_dz, i));
    s.tmin = float(lane_value(r.tmin, i));
    for (int a = 0; a < 3; ++a) s.neg[a] = std::signbit(s.inv[a]);
    return s;
}

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
    float stack_t[kStackSize];
    int top = 0;
    const Mask<T> alone = lane_alone<T>(i);
    float limit = float(lane_value(tbest, i));
    alignas(32) float entry[kWidth];
    std::int32_t ref = start;
    if (start_t > grow(limit)) return;
    for (;;) {
        if (ref >= 0) {
            const Node8& node = bvh.nodes[std::size_t(ref)];
            unsigned bits = enter_children(node, r, limit, entry);
            if (bits != 0) {
                const int first = __builtin_ctz(bits);
                bits &= bits - 1;
                if (bits == 0) {  // one child: straight on
                    ref = node.child[first];
                    continue;
                }
                if (!Closest) {  // any order: the first slot next, the rest pushed
                    for (; bits != 0; bits &= bits - 1) {
                        const int c = __builtin_ctz(bits);
                        stack_ref[top] = node.child[c];
                        stack_t[top++] = entry[c];
                    }
                    ref = node.child[first];
                    continue;
                }
                const int second = __builtin_ctz(bits);
                bits &= bits - 1;
                if (bits == 0) {  // two: the nearer next (the later slot on a tie), the farther pushed
                    const bool keep = entry[first] < entry[second];
                    const int near = keep ? first : second, far = keep ? second : first;
                    stack_ref[top] = node.child[far];
                    stack_t[top++] = entry[far];
                    ref = node.child[near];
                    continue;
                }
                // Three or more: insertion sort, farthest first onto the
                // stack; the nearest is taken straight off again.
                int idx[kWidth];
                const int n = order_children(bits | (1u << first) | (1u << second), entry, true, idx);
                for (int a = 0; a + 1 < n; ++a) {
                    stack_ref[top] = node.child[idx[a]];
                    stack_t[top++] = entry[idx[a]];
                }
                ref = node.child[idx[n - 1]];
                continue;
            }
        } else {
            visit_lane<T>(leaf, bvh.leaves[std::size_t(~ref)], i, alone);
            if constexpr (Closest) limit = float(lane_value(tbest, i));
            else if (!lane_on(lane::bits(active), i)) return;
        }
        // Next: the top of the stack that is still nearer than the best hit.
        for (;;) {
            if (top == 0) return;
            --top;
            if (!(stack_t[top] > grow(limit))) break;
        }
        ref = stack_ref[top];
    }
}

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
    alignas(64) S stack_t[kStackSize][W];  // per lane entry t; NaN: the lane did not enter
    int top = 0;
    auto push = [&](std::int32_t ref, const T& t) {
        stack_ref[top] = ref;
        if constexpr (W == 1) stack_t[top][0] = t;
        else t.store_aligned(stack_t[top]);
        ++top;
    };
    auto pop_t = [&]() -> T {
        if constexpr (W == 1) return stack_t[top][0];
        else return T::load_aligned(stack_t[top]);
    };
    push(0, T(-inf));
    while (top > 0) {
        --top;
        const std::int32_t ref = stack_ref[top];
        const Mask<T> on = group && active && pop_t() <= grow(tbest);
        if (!lane::any(on)) continue;
        if (ref < 0) {  // a leaf: one call for all its lanes, or one per lane where few reach it
            const Leaf& l = bvh.leaves[std::size_t(~ref)];
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
                const T t = pop_t();
                const unsigned bits = lane::bits(on);
                for (int i = 0; i < W; ++i) {
                    if (!lane_on(bits, i)) continue;
                    walk_single<Closest>(bvh, ref, float(lane_value(t, i)), single_ray(r, i), i, active, tbest, leaf);
                    if (!Closest && !lane::any(active)) return;
                }
                continue;
            }
        }
        const Node8& node = bvh.nodes[std::size_t(ref)];
        const T limit = tbest;
        std::int32_t hit_ref[kWidth];
        T hit_t[kWidth];
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
            hit_t[hits] = lane::select(in, enter, T(nan));
            if (Closest && opt.order_packet_children)
                key[hits] = float(lane::lane0(lane::hmin(lane::select(in, enter, T(inf)))));
            else
                key[hits] = float(c);  // the first slot pops first
            ++hits;
        }
        // Push by key, descending (insertion sort): the nearest (or the
        // first slot) pops first.
        int order[kWidth];
        for (int i = 0; i < hits; ++i) {
            int j = i;
            for (; j > 0 && key[order[j - 1]] < key[i]; --j) order[j] = order[j - 1];
            order[j] = i;
        }
        for (int i = 0; i < hits; ++i) push(hit_ref[order[i]], hit_t[order[i]]);
    }
}

// A coherent packet's walk (float lanes, every active lane in one direction
// octant, finite reciprocals): each node's 8 children are tested once for
// the whole packet, against the interval hull of its rays (origins in
// [o_lo, o_hi], reciprocal directions in [inv_lo, inv_hi] per axis). By the
// monotonicity of rounding, the hull's entry bound is no greater, and its
// exit bound no smaller, than any lane's own float slab values, so a child
// the hull misses is one no lane enters. Children are visited nearest hull
// entry first. A leaf's lanes are found exactly (its box against each lane)
// before its leaf function runs; few of them go alone (LaneOf).
struct Hull {
    float o_lo[3], o_hi[3], inv_lo[3], inv_hi[3], tmin;
    bool neg[3];
};

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
    return true;
}

// The children the hull enters before `limit` (the greatest tbest of the
// active lanes), with the hull's entry bounds in `entry`.
inline unsigned hull_children(const Node8& node, const Hull& h, float limit, float entry[kWidth]) {
    using N = NodeBatch;
    return test_children(node, h.tmin, limit, entry, [&](int a, const float* lo, const float* hi, N& enter, N& leave) {
        const N inv_lo(h.inv_lo[a]), inv_hi(h.inv_hi[a]);
        // d > 0: t falls as o grows; d < 0: it rises (near - o and 1/d of opposite signs there).
        const N near_d = N::load_aligned(h.neg[a] ? hi : lo) - N(h.neg[a] ? h.o_lo[a] : h.o_hi[a]);
        const N far_d = N::load_aligned(h.neg[a] ? lo : hi) - N(h.neg[a] ? h.o_hi[a] : h.o_lo[a]);
        enter = lane::max(lane::min(near_d * inv_lo, near_d * inv_hi), enter);
        leave = lane::min(lane::max(far_d * inv_lo, far_d * inv_hi), leave);
    });
}

// The lanes of `on` that enter child c of `node` before their tbest (the
// packet walk's own test).
template <class T>
inline Mask<T> lanes_entering(const Node8& node, int c, const RayView<T>& r, const Mask<T>& on, const T& tbest) {
    using S = lane::Scalar<T>;
    auto axis = [&](float lo, float hi, const T& o, const T& inv, T& enter, T& leave) {
        const Mask<T> neg = inv < T(0);
        const T l = T(S(lo)), h = T(S(hi));
        enter = lane::max((lane::select(neg, h, l) - o) * inv, enter);
        leave = lane::min((lane::select(neg, l, h) - o) * inv, leave);
    };
    T enter = r.tmin, leave = tbest;
    axis(node.lo_z[c], node.hi_z[c], r.oz, r.inv_dz, enter, leave);
    axis(node.lo_y[c], node.hi_y[c], r.oy, r.inv_dy, enter, leave);
    axis(node.lo_x[c], node.hi_x[c], r.ox, r.inv_dx, enter, leave);
    return on && enter <= grow(leave);
}

template <bool Closest, class T, class LeafFn>
bool walk_hull(const Bvh8& bvh, const RayView<T>& r, const Mask<T>& active, const T& tbest, LeafFn& leaf,
               const WalkOptions& opt) {
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
                parent = ref, slot = idx[n - 1];
                ref = node.child[slot];
                continue;
            }
        } else {
            const Node8& up = bvh.nodes[std::size_t(parent)];
            const Mask<T> on = lanes_entering(up, slot, r, active, tbest);
            if (lane::any(on)) {
                const Leaf& l = bvh.leaves[std::size_t(~ref)];
                if constexpr (takes_lanes<T, LeafFn>) {
                    if (lane::count(on) <= opt.leaf_lanes_alone) {
                        for (unsigned bits = lane::bits(on); bits != 0; bits &= bits - 1) {
                            leaf(l, LaneOf{__builtin_ctz(bits)});
                            if (!Closest && !lane::any(active)) return true;
                        }
                    } else {
                        leaf(l, on);
                    }
                } else {
                    leaf(l, on);
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
            if (opt.hull && walk_hull<Closest>(bvh, r, active, tbest, leaf, opt)) return;
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

// The slab test the walks apply to a node's child, for one box and one lane
// of float or double, without the slack: whether the ray enters `b` within
// [tmin, limit], and where (max(tmin, entry)). Tests and brute-force
// references use it; a leaf function over boxes may too.
template <class S>
inline bool slab_enter(const Box& b, const S o[3], const S inv[3], S tmin, S limit, S& entry) {
    S enter = tmin, leave = limit;
    for (int a = 2; a >= 0; --a) {
        const bool neg = std::signbit(inv[a]);
        const S t_near = (S(neg ? b.hi[a] : b.lo[a]) - o[a]) * inv[a];
        const S t_far = (S(neg ? b.lo[a] : b.hi[a]) - o[a]) * inv[a];
        enter = lane::max(t_near, enter);
        leave = lane::min(t_far, leave);
    }
    entry = enter;
    return enter <= leave;
}

}  // namespace OCTRAY_BVH_ISA
}  // namespace octray::bvh
