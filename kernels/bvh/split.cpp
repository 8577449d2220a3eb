// kernels/bvh/split.cpp — how the BVH builder splits a node (step 2 of
// kernels/bvh/build.cpp): the binned SAH split search, the exact sweep for small
// nodes and the in-place partition.
//
// Binning (Wald 2007, "On fast Construction of SAH-based Bounding Volume
// Hierarchies"): the node's centroids are binned along each axis
// (BuildOptions::bins bins, over the centroid bounds) and the SAH cost of
// every bin boundary is swept; a bin keeps only its box and count, so the
// result does not depend on the order the references come in.
#include "kernels/bvh/build_types.hpp"

#include <algorithm>
#include <cstring>

namespace octray::bvh::detail {

// Bins refs[begin, end) and sweeps the SAH cost of each bin boundary on each
// axis. Bins live in this frame only (the recursion keeps no bins).
Split find_split(const Context& ctx, std::uint32_t begin, std::uint32_t end, const Binner& binner) {
    const int nb = ctx.bins;
    Bin bins[3][kMaxBins];
    for (auto& axis : bins)
        for (int i = 0; i < nb; ++i) axis[i] = {Box4::empty(), 0};
    for (std::uint32_t i = begin; i < end; ++i) {
        const Ref& r = ctx.refs[i];
        alignas(16) std::int32_t idx[4];
        _mm_store_si128(reinterpret_cast<__m128i*>(idx), binner.bin(r));
        for (int a = 0; a < 3; ++a) {
            Bin& b = bins[a][idx[a]];
            b.box.extend(ref_lo(r), ref_hi(r));
            ++b.count;
        }
    }
    Split best;
    for (int a = 0; a < 3; ++a) {
        if (!binner.can_split(a)) continue;
        // right_cost[i]: area x count of bins i..nb-1.
        float right_cost[kMaxBins];
        std::uint32_t right_count[kMaxBins];
        Box4 acc = Box4::empty();
        std::uint32_t n = 0;
        for (int i = nb - 1; i > 0; --i) {
            acc.extend(bins[a][i].box);
            n += bins[a][i].count;
            right_cost[i] = acc.area() * float(n);
            right_count[i] = n;
        }
        acc = Box4::empty();
        n = 0;
        for (int i = 1; i < nb; ++i) {
            acc.extend(bins[a][i - 1].box);
            n += bins[a][i - 1].count;
            if (n == 0 || right_count[i] == 0) continue;
            const float cost = acc.area() * float(n) + right_cost[i];
            if (cost < best.cost) {
                best.cost = cost;
                best.axis = a;
                best.bin = i;
                best.left_count = n;
            }
        }
    }
    return best;
}

// Small nodes (at most kSweepSize references): the exact SAH sweep over the
// references sorted by centroid on each axis (cheaper than filling and
// sweeping bins for a few references, and better). Ties sort by input index,
// so the order is total and the result deterministic; a NaN centroid sorts
// first. The sort is by rank (each reference's position is the number of
// keys below its own): branch free, so its cost does not depend on the order
// the partition above left the references in.
namespace {
// The centroid on one axis and the input index as one integer whose order is
// (centroid, index): the float's bits made monotone (negatives reversed).
inline std::uint64_t sweep_key(const Ref& r, int a) {
    float c = r.lo[a] + r.hi[a];
    if (c != c) c = -kInf;
    if (c == 0.0f) c = 0.0f;  // -0 and +0 tie (and sort by index), as float comparison has them
    std::uint32_t bits;
    std::memcpy(&bits, &c, sizeof bits);
    bits = (bits & 0x80000000u) != 0 ? ~bits : bits | 0x80000000u;
    return std::uint64_t(bits) << 32 | r.id;
}
}  // namespace

void sweep_split(const Ref* refs, std::uint32_t n, SweepSplit& best) {
    for (int a = 0; a < 3; ++a) {
        std::uint64_t key[kSweepSize];
        for (std::uint32_t i = 0; i < n; ++i) key[i] = sweep_key(refs[i], a);
        std::uint8_t* order = best.order[a];
        for (std::uint32_t i = 0; i < n; ++i) {  // keys are distinct (the index): the ranks are a permutation
            std::uint32_t rank = 0;
            for (std::uint32_t j = 0; j < n; ++j) rank += key[j] < key[i];
            order[rank] = std::uint8_t(i);
        }
        float right_cost[kSweepSize];
        Box4 acc = Box4::empty();
        for (std::uint32_t i = n - 1; i > 0; --i) {
            acc.extend(ref_lo(refs[order[i]]), ref_hi(refs[order[i]]));
            right_cost[i] = acc.area() * float(n - i);
        }
        acc = Box4::empty();
        for (std::uint32_t i = 1; i < n; ++i) {
            acc.extend(ref_lo(refs[order[i - 1]]), ref_hi(refs[order[i - 1]]));
            const float cost = acc.area() * float(i) + right_cost[i];
            if (cost < best.cost) best.cost = cost, best.axis = a, best.left_count = i;
        }
    }
    if (best.axis < 0) best.axis = 0, best.left_count = n / 2;  // every cost NaN or inf
}

NodeSplit choose_split(const Context& ctx, std::uint32_t begin, std::uint32_t end, const Bounds& bounds, int depth) {
    NodeSplit s;
    const std::uint32_t n = end - begin;
    s.small = n <= kSweepSize;
    if (n > 1 && depth < kForceMedianDepth) {
        if (s.small) sweep_split(ctx.refs + begin, n, s.sweep);
        else s.split = find_split(ctx, begin, end, Binner(bounds.cbox, ctx.bins));
    }
    return s;
}

std::uint32_t apply_split(const Context& ctx, std::uint32_t begin, std::uint32_t end, const Bounds& bounds,
                          const NodeSplit& s, Bounds& left, Bounds& right) {
    const std::uint32_t n = end - begin;
    std::uint32_t mid;
    if (s.small && s.sweep.axis >= 0) {
        Ref sorted[kSweepSize];
        for (std::uint32_t i = 0; i < n; ++i) sorted[i] = ctx.refs[begin + s.sweep.order[s.sweep.axis][i]];
        std::copy(sorted, sorted + n, ctx.refs + begin);
        mid = begin + s.sweep.left_count;
        left = bounds_of(ctx.refs, begin, mid);
        right = bounds_of(ctx.refs, mid, end);
    } else if (s.split.axis >= 0) {
        // The binner find_split used (the same bounds and bins: the same bits).
        const Binner binner(bounds.cbox, ctx.bins);
        const __m128i split_bin = _mm_set1_epi32(s.split.bin);
        const int axis_bit = 1 << s.split.axis;
        mid = partition(ctx.refs, begin, end, left, right, [&](const Ref& r) {
            const __m128i below = _mm_cmplt_epi32(binner.bin(r), split_bin);
            return (_mm_movemask_ps(_mm_castsi128_ps(below)) & axis_bit) != 0;
        });
    } else {
        // No bin boundary separates the centroids (or too deep): split at the middle.
        mid = begin + n / 2;
        left = bounds_of(ctx.refs, begin, mid);
        right = bounds_of(ctx.refs, mid, end);
    }
    return mid;
}

}  // namespace octray::bvh::detail
