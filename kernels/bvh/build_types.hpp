// kernels/bvh/build_types.hpp — the BVH builder's shared types (internal to
// kernels/bvh/build.cpp, kernels/bvh/split.cpp and kernels/bvh/collapse.cpp; see kernels/bvh/build.cpp for
// the three steps): references and boxes in SSE registers, bounds, the
// binner, a node's split, binary nodes and the build context. The helpers run
// per reference are inline here so that every unit inlines them.
#pragma once

#include "kernels/bvh/node.hpp"

#include <atomic>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <immintrin.h>

namespace octray::bvh::detail {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr int kMaxBins = 64;
constexpr std::size_t kMaxPrimitives = std::size_t(1) << 30;
// From this binary depth on, nodes split at their middle reference: with at
// most 2^30 primitives the binary tree then has at most 40 + 30 + 1 levels,
// and a wide tree no more than its binary tree (kMaxDepth).
constexpr int kForceMedianDepth = 40;
static_assert(kForceMedianDepth + 31 <= kMaxDepth, "the depth bound holds");
// Subtrees of more references than this become tasks.
constexpr std::uint32_t kTaskSize = 4096;
// Nodes of at most this many references take the exact sweep (kernels/bvh/split.cpp).
constexpr std::uint32_t kSweepSize = 16;

// A primitive while building: its box, its input index in lo's fourth float
// (ignored by the box arithmetic, which uses lanes 0-2 only).
struct alignas(32) Ref {
    float lo[3];
    std::uint32_t id;
    float hi[3];
    std::uint32_t pad;
};
static_assert(sizeof(Ref) == 32, "two SSE registers");

// A box in two SSE registers (lanes 0-2: x, y, z; lane 3 ignored).
// extend(l, h) ignores NaN lanes of l and h: minps(a, b) is a < b ? a : b.
struct Box4 {
    __m128 lo, hi;

    static Box4 empty() { return {_mm_set1_ps(kInf), _mm_set1_ps(-kInf)}; }
    void extend(__m128 l, __m128 h) {
        lo = _mm_min_ps(l, lo);
        hi = _mm_max_ps(h, hi);
    }
    void extend(const Box4& b) { extend(b.lo, b.hi); }
    Box box() const {
        alignas(16) float l[4], h[4];
        _mm_store_ps(l, lo);
        _mm_store_ps(h, hi);
        return {{l[0], l[1], l[2]}, {h[0], h[1], h[2]}};
    }
    // Surface area (0 for an empty box: negative extents count as 0).
    float area() const {
        const __m128 d = _mm_max_ps(_mm_sub_ps(hi, lo), _mm_setzero_ps());  // max(NaN, 0) = 0
        const __m128 e = _mm_shuffle_ps(d, d, _MM_SHUFFLE(3, 0, 2, 1));     // y z x
        const __m128 p = _mm_mul_ps(d, e);                                  // xy yz zx
        alignas(16) float v[4];
        _mm_store_ps(v, p);
        return 2.0f * (v[0] + v[1] + v[2]);
    }
};

inline __m128 ref_lo(const Ref& r) { return _mm_load_ps(r.lo); }
inline __m128 ref_hi(const Ref& r) { return _mm_load_ps(r.hi); }
// Twice the centroid (lo + hi): the scale cancels in every use.
inline __m128 ref_centroid2(const Ref& r) { return _mm_add_ps(ref_lo(r), ref_hi(r)); }

// Bounds and centroid bounds of refs[begin, end).
struct Bounds {
    Box4 box = Box4::empty(), cbox = Box4::empty();
    void extend(const Ref& r) {
        box.extend(ref_lo(r), ref_hi(r));
        const __m128 c = ref_centroid2(r);
        cbox.extend(c, c);
    }
    void extend(const Bounds& b) {
        box.extend(b.box);
        cbox.extend(b.cbox);
    }
};

inline Bounds bounds_of(const Ref* refs, std::uint32_t begin, std::uint32_t end) {
    Bounds b;
    for (std::uint32_t i = begin; i < end; ++i) b.extend(refs[i]);
    return b;
}

// Maps a centroid to its bin on each axis: floor((c - cmin) * scale), clamped
// to [0, bins - 1]; NaN (a NaN or empty box) goes to bin 0. The binning and
// the partition both call this, so they agree to the bit.
struct Binner {
    __m128 cmin, scale, last;

    Binner(const Box4& cbox, int bins) {
        alignas(16) float lo[4], hi[4], s[4] = {0, 0, 0, 0};
        _mm_store_ps(lo, cbox.lo);
        _mm_store_ps(hi, cbox.hi);
        for (int a = 0; a < 3; ++a) {
            const float extent = hi[a] - lo[a];
            // A zero, infinite or NaN extent: the axis cannot be binned (scale 0).
            if (extent > 0.0f && extent < kInf) s[a] = float(bins) / extent;
        }
        cmin = cbox.lo;
        scale = _mm_load_ps(s);
        last = _mm_set1_ps(float(bins - 1));
    }
    bool can_split(int axis) const {
        alignas(16) float s[4];
        _mm_store_ps(s, scale);
        return s[axis] > 0.0f;
    }
    __m128i bin(const Ref& r) const {
        __m128 f = _mm_mul_ps(_mm_sub_ps(ref_centroid2(r), cmin), scale);
        f = _mm_min_ps(_mm_max_ps(f, _mm_setzero_ps()), last);  // max(NaN, 0) = 0
        return _mm_cvttps_epi32(f);
    }
};

// Trivial, so find_split's bins cost nothing until it fills the ones it uses.
// No centroid bounds: the partition computes the children's.
struct Bin {
    Box4 box;
    std::uint32_t count;
};

// The chosen split of a node: references whose bin on `axis` is below `bin`
// go left.
struct Split {
    int axis = -1;  // -1: none
    int bin = 0;
    float cost = kInf;  // sum of area x count over both sides
    std::uint32_t left_count = 0;
};

// The exact sweep's split of a small node (at most kSweepSize references).
struct SweepSplit {
    int axis = -1;
    std::uint32_t left_count = 0;
    float cost = kInf;
    std::uint8_t order[3][kSweepSize];  // per axis, the references' positions in sorted order
};

// How a node would split: by the sweep (small) or by bins.
struct NodeSplit {
    bool small = false;
    Split split;
    SweepSplit sweep;
    float cost() const { return small ? sweep.cost : split.cost; }
};

// A binary node: inner (count == 0, children first and first + 1) or leaf
// (refs[first, first + count)).
struct BNode {
    Box box;
    std::uint32_t first, count;
};

struct Context {
    Ref* refs;
    BNode* nodes;
    std::atomic<std::uint32_t>* next;  // next free binary node (children come in pairs)
    int bins;
    int max_leaf;
    float traversal_cost, intersection_cost;
    int leaf_block;
};

// kernels/bvh/split.cpp: how a node splits.
// Binned SAH: the best bin boundary of refs[begin, end) on any axis.
Split find_split(const Context& ctx, std::uint32_t begin, std::uint32_t end, const Binner& binner);
// The exact SAH sweep of a small node's n references into `best`.
void sweep_split(const Ref* refs, std::uint32_t n, SweepSplit& best);
// The best split of refs[begin, end) (bounds: theirs), none (axis -1) for a
// single reference or from kForceMedianDepth on.
NodeSplit choose_split(const Context& ctx, std::uint32_t begin, std::uint32_t end, const Bounds& bounds, int depth);
// Reorders refs[begin, end) by `s` (at the middle where it found none) and
// returns where the right side starts, with both sides' bounds.
std::uint32_t apply_split(const Context& ctx, std::uint32_t begin, std::uint32_t end, const Bounds& bounds,
                          const NodeSplit& s, Bounds& left, Bounds& right);

// Partitions refs[begin, end) in place: the references for which goes_left
// holds first (in order), then the others; returns where those start, with
// each side's bounds. Branch free (a data-dependent branch mispredicts about
// every other reference): each reference is swapped with the first one of
// the right side so far, which moves only when it went left (Lomuto's
// scheme; [begin, l) went left, [l, i] right). One read and one write of the
// range, then one read for the bounds; no second buffer to fault in.
template <class GoesLeft>
std::uint32_t partition(Ref* refs, std::uint32_t begin, std::uint32_t end, Bounds& left_out, Bounds& right_out,
                        GoesLeft goes_left) {
    std::uint32_t l = begin;
    for (std::uint32_t i = begin; i < end; ++i) {
        const Ref r = refs[i];
        const bool left = goes_left(r);
        refs[i] = refs[l];
        refs[l] = r;
        l += left;
    }
    left_out = bounds_of(refs, begin, l);
    right_out = bounds_of(refs, l, end);
    return l;
}

// kernels/bvh/build.cpp: the binary tree below `node`, top down (step 2); an
// invalid_argument naming `what` unless ok (the option checks).
void build_node(const Context& ctx, std::uint32_t node, std::uint32_t begin, std::uint32_t end, Bounds bounds,
                int depth);
void check(bool ok, const char* what);

// kernels/bvh/collapse.cpp: the wide tree from the binary one (step 3): out's nodes,
// leaves, per-kind order and depth. kind: null for all kind 0; index: each
// input primitive's index_in_kind; binary_nodes: how many bnodes holds;
// opt: the costs and BuildOptions::sah_collapse.
void collapse(const BNode* bnodes, std::uint32_t binary_nodes, const Ref* refs, const std::uint8_t* kind,
              const std::vector<std::uint32_t>& index, const BuildOptions& opt, Bvh8& out);

}  // namespace octray::bvh::detail
