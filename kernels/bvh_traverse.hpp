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
//     batch (two 4-float ones without AVX), children sorted by entry t.
//   a packet: each child is tested against every lane (the child's bounds
//     broadcast), its per-lane entry t kept on the stack; children are
//     visited in the order of their nearest lane's entry t. A subtree that
//     at most WalkOptions::single_ray_lanes lanes reach is walked lane by
//     lane as single rays (fewer node tests where a packet diverges), and
//     the lanes of each direction octant walk as a packet of their own; both
//     for float lanes only (double lanes always walk as one packet: f64 is a
//     checking mode, its node tests stay in double).
//     The thresholds and orders were chosen by bench/bench_bvh.cpp
//     (docs/performance.md has the measurements).
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

// The bits of the children a single ray enters before `limit` (its tbest),
// with their entry t in `entry`.
inline unsigned enter_children(const Node8& node, const SingleRay& r, float limit, float entry[kWidth]) {
    using N = NodeBatch;
    constexpr int w = int(N::size);
    const float* lo[3] = {node.lo_x, node.lo_y, node.lo_z};
    const float* hi[3] = {node.hi_x, node.hi_y, node.hi_z};
    unsigned bits = 0;
    for (int i = 0; i < kWidth; i += w) {
        N enter = N(r.tmin), leave = N(limit);
        for (int a = 2; a >= 0; --a) {  // max(t, acc): a NaN t is dropped
            const N o(r.o[a]), inv(r.inv[a]);
            const N t_near = (N::load_aligned((r.neg[a] ? hi[a] : lo[a]) + i) - o) * inv;
            const N t_far = (N::load_aligned((r.neg[a] ? lo[a] : hi[a]) + i) - o) * inv;
            enter = lane::max(t_near, enter);
            leave = lane::min(t_far, leave);
        }
        enter.store_aligned(entry + i);
        bits |= lane::bits(enter <= grow(leave)) << i;
    }
    // Unused slots have empty bounds, which no slab test enters, except a ray
    // whose every slab term is NaN and dropped (a NaN origin: a shadow ray
    // from a hit point that overflowed): never hand out their kEmptySlot.
    return bits & ((1u << node.child_count()) - 1u);
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

// Pushes the entered children `bits` of `node`, farthest first when
// `nearest_first` (so the nearest pops first), else the last slot first.
inline void push_children(const Node8& node, unsigned bits, const float entry[kWidth], bool nearest_first,
                          std::int32_t* stack_ref, float* stack_t, int& top) {
    int idx[kWidth], n = 0;
    for (; bits != 0; bits &= bits - 1) idx[n++] = __builtin_ctz(bits);
    if (nearest_first) {  // insertion sort, farthest first
        for (int i = 1; i < n; ++i) {
            const int v = idx[i];
            int j = i;
            for (; j > 0 && entry[idx[j - 1]] < entry[v]; --j) idx[j] = idx[j - 1];
            idx[j] = v;
        }
    } else {
        for (int i = 0, j = n - 1; i < j; ++i, --j) std::swap(idx[i], idx[j]);
    }
    for (int i = 0; i < n; ++i) {
        stack_ref[top] = node.child[idx[i]];
        stack_t[top++] = entry[idx[i]];
    }
}

// The subtree `start` walked by lane i of the packet alone, as a single ray.
template <bool Closest, class T, class LeafFn>
void walk_single(const Bvh8& bvh, std::int32_t start, float start_t, const SingleRay& r, int i,
                 const Mask<T>& active, const T& tbest, LeafFn& leaf) {
    std::int32_t stack_ref[kStackSize];
    float stack_t[kStackSize];
    int top = 0;
    stack_ref[top] = start;
    stack_t[top++] = start_t;
    const Mask<T> alone = lane_alone<T>(i);
    float limit = float(lane_value(tbest, i));
    alignas(32) float entry[kWidth];
    while (top > 0) {
        --top;
        const std::int32_t ref = stack_ref[top];
        if (stack_t[top] > grow(limit)) continue;  // tbest has come nearer since the push
        if (ref < 0) {
            leaf(bvh.leaves[std::size_t(~ref)], alone);
            if constexpr (Closest) limit = float(lane_value(tbest, i));
            else if (!lane_on(lane::bits(active), i)) return;
            continue;
        }
        const Node8& node = bvh.nodes[std::size_t(ref)];
        const unsigned bits = enter_children(node, r, limit, entry);
        push_children(node, bits, entry, Closest, stack_ref, stack_t, top);
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
        if (ref < 0) {  // a leaf: one call for all its lanes, however few (a single-ray walk would call it per lane)
            leaf(bvh.leaves[std::size_t(~ref)], on);
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
