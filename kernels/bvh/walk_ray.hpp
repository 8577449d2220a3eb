// kernels/bvh/walk_ray.hpp — a ray as the BVH walks see it (kernels/bvh/traverse.hpp):
// the view (origin, IEEE reciprocal direction, tmin) and its lanes one at a
// time, the slack, and the tests of a node's children for one ray
// (SingleRay) a batch of children at a time, with their visiting order; and
// slab_enter, the same test for one box without the slack.
//
// Defines OCTRAY_BVH_ISA, the inline namespace every bvh walk header puts its
// templates in (see kernels/bvh/traverse.hpp).
#pragma once

#include "kernels/bvh/node.hpp"

#include "kernels/lanes/lane.hpp"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <utility>

#ifndef OCTRAY_BVH_ISA
#ifdef OCTRAY_ISA
#define OCTRAY_BVH_ISA OCTRAY_ISA
#else
#define OCTRAY_BVH_ISA native
#endif
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

namespace detail {

// The slack: t + |t| 2^-20 (+inf stays +inf).
template <class T>
inline T grow(const T& t) {
    return t + lane::abs(t) * T(0x1p-20f);
}

// Eight float lanes in one AVX2 register: lane moves by permutes and integer
// compares (a trip through memory costs a store-to-load forward each).
template <class T>
inline constexpr bool kFloat8Register =
#if defined(__AVX2__)
    lane::width<T> == 8 && std::is_same_v<lane::Scalar<T>, float> && sizeof(T) == 32;
#else
    false;
#endif

// Lane i of v in every lane.
template <class T>
inline T lane_broadcast(const T& v, int i) {
#if defined(__AVX2__)
    if constexpr (kFloat8Register<T>) return T(_mm256_permutevar8x32_ps(v, _mm256_set1_epi32(i)));
#endif
    if constexpr (lane::width<T> == 1) {
        (void)i;
        return v;
    } else {
        alignas(64) lane::Scalar<T> tmp[lane::width<T>];
        v.store_aligned(tmp);
        return T(tmp[i]);
    }
}

template <class T>
inline lane::Scalar<T> lane_value(const T& v, int i) {
    return lane::lane0(lane_broadcast(v, i));
}

// The mask of the lanes whose bits are set.
template <class T>
inline Mask<T> lanes_of(unsigned bits) {
#if defined(__AVX2__)
    if constexpr (kFloat8Register<T>) {
        const __m256i bit = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
        const __m256i on = _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(int(bits)), bit), bit);
        return Mask<T>(_mm256_castsi256_ps(on));
    }
#endif
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
// kernels/packet_kernels.hpp's NodeLanes (not included here: that file is being
// split); one definition should serve both once this walk is integrated.
#if defined(__AVX__)
using NodeBatch = xsimd::batch<float, xsimd::avx>;
#else
using NodeBatch = xsimd::batch<float, xsimd::sse2>;
#endif
static_assert(kWidth % NodeBatch::size == 0, "a node's children fill whole batches");

// One ray in float, broadcast once for every node it tests; each axis' near
// and far bounds chosen by its sign, as byte offsets into a Node8.
struct SingleRay {
    NodeBatch o[3], inv[3], tmin;
    std::uint32_t near[3], far[3];
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

// Byte offsets into a Node8 of each axis' lower and upper child bounds.
inline constexpr std::uint32_t kLowerBounds[3] = {offsetof(Node8, lo_x), offsetof(Node8, lo_y), offsetof(Node8, lo_z)};
inline constexpr std::uint32_t kUpperBounds[3] = {offsetof(Node8, hi_x), offsetof(Node8, hi_y), offsetof(Node8, hi_z)};

// Children i .. i + NodeBatch::size - 1 of the bound array at byte `offset`
// (kLowerBounds, kUpperBounds) of `node`.
inline NodeBatch child_bounds(const Node8& node, std::uint32_t offset, int i) {
    return NodeBatch::load_aligned(reinterpret_cast<const float*>(reinterpret_cast<const char*>(&node) + offset) + i);
}

// The bits of the used children whose slab interval, clipped to [tmin,
// limit], is non-empty (with the slack), and their entry t in `entry`:
// axis(a, i, enter, leave) narrows the interval of children i .. i +
// NodeBatch::size - 1 by axis a (child_bounds reads their bounds).
// Always inlined: every walk's inner loop (GCC otherwise keeps it out of
// line once the walk around it grows).
template <class Axis>
[[gnu::always_inline]] inline unsigned test_children(const NodeBatch& tmin, float limit, float entry[kWidth],
                                                     const Node8& node, Axis&& axis) {
    using N = NodeBatch;
    constexpr int w = int(N::size);
    unsigned bits = 0;
    for (int i = 0; i < kWidth; i += w) {
        N enter = tmin, leave = N(limit);
        for (int a = 2; a >= 0; --a) axis(a, i, enter, leave);
        enter.store_aligned(entry + i);
        bits |= lane::bits(enter <= grow(leave)) << i;
    }
    // Unused slots have empty bounds, which no slab test enters, except a ray
    // whose every slab term is NaN and dropped (a NaN origin: a shadow ray
    // from a hit point that overflowed): never hand out their kEmptySlot.
    return bits & used_children(node);
}

// The children a single ray enters before `limit` (its tbest); its operands
// are broadcast once a walk and its near bounds picked by offset (no
// per-node broadcasts or sign tests).
[[gnu::always_inline]] inline unsigned enter_children(const Node8& node, const SingleRay& r, float limit,
                                                      float entry[kWidth]) {
    using N = NodeBatch;
    return test_children(r.tmin, limit, entry, node, [&](int a, int i, N& enter, N& leave) {
        // max(t, acc): a NaN t is dropped
        enter = lane::max((child_bounds(node, r.near[a], i) - r.o[a]) * r.inv[a], enter);
        leave = lane::min((child_bounds(node, r.far[a], i) - r.o[a]) * r.inv[a], leave);
    });
}

// Asks for the lines of the child a walk visits after the one it takes next
// (the top of its stack once a node's entered children are pushed): a node's
// four lines, or the first two of a leaf's block (place_leaf_blocks). Its
// loads then overlap the walk of the nearer child instead of following it.
// In a tree without blocks a leaf's ~ref is its number, and the prefetch
// asks for some line of the node array: harmless (a prefetch never faults).
inline void prefetch_child(const Bvh8& bvh, std::int32_t ref) {
    const char* at = ref >= 0 ? reinterpret_cast<const char*>(bvh.nodes.data() + ref)
                              : reinterpret_cast<const char*>(bvh.nodes.data()) + std::size_t(~ref) * sizeof(float);
    __builtin_prefetch(at);
    __builtin_prefetch(at + 64);
    if (ref >= 0) {
        __builtin_prefetch(at + 128);
        __builtin_prefetch(at + 192);
    }
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
    using N = NodeBatch;
    SingleRay s;
    const T* o[3] = {&r.ox, &r.oy, &r.oz};
    const T* inv[3] = {&r.inv_dx, &r.inv_dy, &r.inv_dz};
    for (int a = 0; a < 3; ++a) {
        const float v = float(lane_value(*inv[a], i));
        s.o[a] = N(float(lane_value(*o[a], i)));
        s.inv[a] = N(v);
        s.near[a] = std::signbit(v) ? kUpperBounds[a] : kLowerBounds[a];
        s.far[a] = std::signbit(v) ? kLowerBounds[a] : kUpperBounds[a];
    }
    s.tmin = N(float(lane_value(r.tmin, i)));
    return s;
}

}  // namespace detail

}  // namespace OCTRAY_BVH_ISA
}  // namespace octray::bvh
