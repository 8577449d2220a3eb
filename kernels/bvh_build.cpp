// kernels/bvh_build.cpp — the 8-wide BVH builder (see bvh.hpp).
//
// Three steps:
// 1. references: each primitive's box and id in one 32-byte record (two SSE
//    registers), with the root's bounds and centroid bounds (parallel loop);
// 2. a binary tree, top down: per node, the primitives' centroids are binned
//    along each axis (BuildOptions::bins bins) and the SAH cost of every bin
//    boundary is swept; the node becomes a leaf where that is cheaper (and it
//    fits in max_leaf_size), else its references are partitioned in place.
//    Large subtrees become OpenMP tasks. Where no boundary separates the
//    centroids (all at one point), or deep down (binary depth
//    kForceMedianDepth), the node is split at its middle reference instead,
//    which bounds the depth;
// 3. a collapse, sequential and depth first: each wide node takes its binary
//    node's two children and opens the child of largest area that is not a
//    leaf (replacing it by its two children, in place) until it has 8
//    children or only leaves; leaves are numbered left to right, and each
//    kind's permutation is written leaf by leaf.
//
// Determinism: a node's split depends only on its references, in an order
// fixed by its ancestors' in-place partitions (each run by one thread), and
// on bins whose bounds are min/max (exact in any order) and whose counts are
// integers. Tasks only decide which thread builds a subtree; binary node
// indices depend on the schedule but the collapse follows child links, so the
// wide tree never sees them. Nothing in the parallel region allocates or
// throws: every array is made before it.
#include "bvh.hpp"

#include <octray/threads.hpp>

#include <algorithm>
#include <cmath>
#include <atomic>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>

#include <immintrin.h>
#ifdef _OPENMP
#include <omp.h>
#endif

namespace octray::bvh {
namespace {

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

Bounds bounds_of(const Ref* refs, std::uint32_t begin, std::uint32_t end) {
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

// A binary node: inner (count == 0, children first and first + 1) or leaf
// (refs[first, first + count)).
struct BNode {
    Box box;
    std::uint32_t first, count;
};

struct Context {
    Ref* refs;
    Ref* scratch;  // as many as refs: a node's partition uses the same range of it
    BNode* nodes;
    std::atomic<std::uint32_t>* next;  // next free binary node (children come in pairs)
    int bins;
    int max_leaf;
    float traversal_cost, intersection_cost;
    int leaf_block;
};

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

// Partitions refs[begin, end): the references for which goes_left holds
// first (in order), then the others (in reverse order); returns where those
// start. Branch free (a data-dependent branch mispredicts about every other
// reference): each reference is written to its place in scratch[begin, end),
// then copied back, which pass also gathers each side's bounds.
template <class GoesLeft>
std::uint32_t partition(Ref* refs, Ref* scratch, std::uint32_t begin, std::uint32_t end, Bounds& left_out,
                        Bounds& right_out, GoesLeft goes_left) {
    std::uint32_t l = begin, r = end - 1;
    for (std::uint32_t i = begin; i < end; ++i) {
        const bool left = goes_left(refs[i]);
        scratch[left ? l : r] = refs[i];
        l += left;
        r -= !left;
    }
    Bounds left, right;  // locals: no aliasing with refs, so they stay in registers
    for (std::uint32_t i = begin; i < l; ++i) left.extend(refs[i] = scratch[i]);
    for (std::uint32_t i = l; i < end; ++i) right.extend(refs[i] = scratch[i]);
    left_out = left;
    right_out = right;
    return l;
}

// Small nodes: the exact SAH sweep over the references sorted by centroid on
// each axis (cheaper than filling and sweeping bins for a few references,
// and better). Ties sort by input index, so the order is total and the
// result deterministic; a NaN centroid sorts first.
constexpr std::uint32_t kSweepSize = 16;

struct SweepSplit {
    int axis = -1;
    std::uint32_t left_count = 0;
    float cost = kInf;
    std::uint8_t order[3][kSweepSize];  // per axis, the references' positions in sorted order
};

void sweep_split(const Ref* refs, std::uint32_t n, SweepSplit& best) {
    for (int a = 0; a < 3; ++a) {
        float key[kSweepSize];
        for (std::uint32_t i = 0; i < n; ++i) {
            const float c = refs[i].lo[a] + refs[i].hi[a];
            key[i] = c == c ? c : -kInf;
        }
        auto before = [&](std::uint32_t i, std::uint32_t j) {
            return key[i] < key[j] || (key[i] == key[j] && refs[i].id < refs[j].id);
        };
        std::uint8_t* order = best.order[a];
        for (std::uint32_t i = 0; i < n; ++i) {  // insertion sort
            std::uint32_t j = i;
            for (; j > 0 && before(i, order[j - 1]); --j) order[j] = order[j - 1];
            order[j] = std::uint8_t(i);
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

void build_node(const Context& ctx, std::uint32_t node, std::uint32_t begin, std::uint32_t end, Bounds bounds,
                int depth) {
    for (;;) {  // the right child continues in this loop; the left one recurses (or is a task)
        BNode& bn = ctx.nodes[node];
        bn.box = bounds.box.box();
        const std::uint32_t n = end - begin;
        Split split;
        SweepSplit sweep;
        const bool small = n <= kSweepSize;
        const Binner binner(bounds.cbox, small ? 2 : ctx.bins);
        if (n > 1 && depth < kForceMedianDepth) {
            if (small) sweep_split(ctx.refs + begin, n, sweep);
            else split = find_split(ctx, begin, end, binner);
        }
        const float split_cost = small ? sweep.cost : split.cost;
        const float area = bounds.box.area();
        const bool leaf_ok = n <= std::uint32_t(ctx.max_leaf);
        // SAH, scaled by the node's area, in leaf blocks of b: leaf ceil(n / b) Ci A
        // vs split Ct A + Ci (sum A_side n_side) / b.
        const float block = float(ctx.leaf_block);
        const float leaf_cost = ctx.intersection_cost * std::ceil(float(n) / block) * area;
        if (n == 1 || (leaf_ok && !(leaf_cost > ctx.traversal_cost * area + ctx.intersection_cost * split_cost / block))) {
            bn.first = begin;
            bn.count = n;
            return;
        }
        std::uint32_t mid;
        Bounds left, right;
        if (small && sweep.axis >= 0) {
            Ref sorted[kSweepSize];
            for (std::uint32_t i = 0; i < n; ++i) sorted[i] = ctx.refs[begin + sweep.order[sweep.axis][i]];
            std::copy(sorted, sorted + n, ctx.refs + begin);
            mid = begin + sweep.left_count;
            left = bounds_of(ctx.refs, begin, mid);
            right = bounds_of(ctx.refs, mid, end);
        } else if (split.axis >= 0) {
            const int axis = split.axis, bin = split.bin;
            const __m128i split_bin = _mm_set1_epi32(bin);
            const int axis_bit = 1 << axis;
            mid = partition(ctx.refs, ctx.scratch, begin, end, left, right, [&](const Ref& r) {
                const __m128i below = _mm_cmplt_epi32(binner.bin(r), split_bin);
                return (_mm_movemask_ps(_mm_castsi128_ps(below)) & axis_bit) != 0;
            });
        } else {
            // No bin boundary separates the centroids (or too deep): split at the middle.
            mid = begin + n / 2;
            left = bounds_of(ctx.refs, begin, mid);
            right = bounds_of(ctx.refs, mid, end);
        }
        const std::uint32_t children = ctx.next->fetch_add(2, std::memory_order_relaxed);
        bn.first = children;
        bn.count = 0;
        if (mid - begin > kTaskSize) {
#pragma omp task firstprivate(children, begin, mid, left, depth) default(none) shared(ctx)
            build_node(ctx, children, begin, mid, left, depth + 1);
        } else {
            build_node(ctx, children, begin, mid, left, depth + 1);
        }
        node = children + 1;
        begin = mid;
        bounds = right;
        ++depth;
    }
}

// The wide tree from the binary one (step 3 above).
struct Collapser {
    const BNode* bnodes;
    const Ref* refs;
    const std::uint8_t* kind;                  // null: all kind 0
    const std::vector<std::uint32_t>& index;  // index_in_kind per input primitive
    Bvh8& out;

    std::int32_t leaf(const BNode& b) {
        Leaf l{};
        for (int k = 0; k < kMaxKinds; ++k)
            l.begin[k] = k < out.kind_count ? std::uint32_t(out.order[std::size_t(k)].size()) : 0;
        for (std::uint32_t i = b.first; i < b.first + b.count; ++i) {
            const std::uint32_t id = refs[i].id;
            const int k = kind ? kind[id] : 0;
            out.order[std::size_t(k)].push_back(index[id]);
            ++l.count[k];
        }
        out.leaves.push_back(l);
        return ~std::int32_t(out.leaves.size() - 1);
    }

    // The binary nodes that become the children of the wide node for
    // binary node b (inner, or the root even as a leaf): its two children,
    // then the largest (by area) inner one opened until there are 8 or only
    // leaves. Left-to-right order is kept.
    int open_children(std::uint32_t b, std::uint32_t kids[kWidth]) const {
        int k = 0;
        if (bnodes[b].count > 0) {
            kids[k++] = b;  // a root leaf: one child
        } else {
            kids[k++] = bnodes[b].first;
            kids[k++] = bnodes[b].first + 1;
        }
        while (k < kWidth) {
            int open = -1;
            float open_area = -1.0f;
            for (int j = 0; j < k; ++j) {
                const BNode& c = bnodes[kids[j]];
                if (c.count == 0 && c.box.area() > open_area) open = j, open_area = c.box.area();
            }
            if (open < 0) break;
            const std::uint32_t first = bnodes[kids[open]].first;
            for (int j = k; j > open + 1; --j) kids[j] = kids[j - 1];
            kids[open] = first;
            kids[open + 1] = first + 1;
            ++k;
        }
        return k;
    }

    // How many wide nodes node(b) makes (to reserve them: no regrowth).
    std::size_t count(std::uint32_t b) const {
        std::uint32_t kids[kWidth];
        const int k = open_children(b, kids);
        std::size_t n = 1;
        for (int j = 0; j < k; ++j)
            if (bnodes[kids[j]].count == 0) n += count(kids[j]);
        return n;
    }

    // The wide node for binary node b; its index.
    std::int32_t node(std::uint32_t b, int depth) {
        out.depth = std::max(out.depth, depth);
        const std::int32_t index_here = std::int32_t(out.nodes.size());
        out.nodes.emplace_back();
        std::uint32_t kids[kWidth];
        const int k = open_children(b, kids);
        std::int32_t child[kWidth];
        for (int j = 0; j < k; ++j) {
            const BNode& c = bnodes[kids[j]];
            child[j] = c.count > 0 ? leaf(c) : node(kids[j], depth + 1);
        }
        Node8& n = out.nodes[std::size_t(index_here)];  // after the recursion: the vector may have grown
        for (int j = 0; j < kWidth; ++j) {
            const Box box = j < k ? bnodes[kids[j]].box : Box::empty();
            n.lo_x[j] = box.lo[0], n.lo_y[j] = box.lo[1], n.lo_z[j] = box.lo[2];
            n.hi_x[j] = box.hi[0], n.hi_y[j] = box.hi[1], n.hi_z[j] = box.hi[2];
            n.child[j] = j < k ? child[j] : kEmptySlot;
        }
        return index_here;
    }
};

void check(bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("build_bvh8: " + what);
}

}  // namespace

Bvh8 build_bvh8(const BuildInput& in, const BuildOptions& opt) {
    const std::size_t n = in.boxes.size();
    check(in.kind_count >= 1 && in.kind_count <= kMaxKinds, "kind_count must be 1..8");
    check(in.kind.empty() || in.kind.size() == n, "kind must be empty or one per box");
    check(in.index_in_kind.empty() || in.index_in_kind.size() == n, "index_in_kind must be empty or one per box");
    check(opt.max_leaf_size >= 1 && opt.max_leaf_size <= 255, "max_leaf_size must be 1..255");
    check(opt.bins >= 2 && opt.bins <= kMaxBins, "bins must be 2..64");
    check(opt.traversal_cost >= 0 && opt.intersection_cost > 0 && opt.traversal_cost < kInf &&
              opt.intersection_cost < kInf,
          "costs must be finite, intersection_cost > 0");
    check(opt.threads >= 0, "threads must be >= 0");
    check(opt.leaf_block >= 1 && opt.leaf_block <= 255, "leaf_block must be 1..255");
    if (n > kMaxPrimitives) throw std::length_error("build_bvh8: more than 2^30 primitives");
    std::vector<std::uint32_t> per_kind(std::size_t(in.kind_count), 0);
    for (std::uint8_t k : in.kind) check(k < in.kind_count, "a kind is >= kind_count");

    // index_in_kind, given or numbered in order.
    std::vector<std::uint32_t> numbered;
    if (in.index_in_kind.empty()) {
        numbered.resize(n);
        for (std::size_t i = 0; i < n; ++i) numbered[i] = per_kind[in.kind.empty() ? 0 : in.kind[i]]++;
    } else {
        for (std::size_t i = 0; i < n; ++i) ++per_kind[in.kind.empty() ? 0 : in.kind[i]];
    }
    const std::vector<std::uint32_t>& index = in.index_in_kind.empty() ? numbered : in.index_in_kind;

    Bvh8 out;
    out.kind_count = in.kind_count;
    out.order.resize(std::size_t(in.kind_count));
    if (n == 0) return out;
    for (int k = 0; k < in.kind_count; ++k) out.order[std::size_t(k)].reserve(per_kind[std::size_t(k)]);

    // Every array the parallel region touches, made here (default-initialized:
    // only the pages the build writes are ever touched).
    std::unique_ptr<Ref[]> refs(new Ref[n]), scratch(new Ref[n]);
    std::unique_ptr<BNode[]> bnodes(new BNode[2 * n - 1]);
    std::atomic<std::uint32_t> next{1};
    const Context ctx{refs.get(),        scratch.get(),         bnodes.get(),         &next,
                      opt.bins,          opt.max_leaf_size,     opt.traversal_cost,   opt.intersection_cost,
                      opt.leaf_block};
    Bounds root;
    const Box* boxes = in.boxes.data();
#ifdef _OPENMP
    const int threads = resolve_threads(opt.threads);
#endif
#pragma omp parallel num_threads(threads) default(none) shared(ctx, root, boxes, n)
    {
        Bounds local;
#pragma omp for schedule(static)
        for (std::size_t i = 0; i < n; ++i) {
            Ref& r = ctx.refs[i];
            std::memcpy(r.lo, boxes[i].lo, sizeof r.lo);
            std::memcpy(r.hi, boxes[i].hi, sizeof r.hi);
            r.id = std::uint32_t(i);
            r.pad = 0;
            local.extend(r);
        }
#pragma omp critical(octray_bvh_root_bounds)
        root.extend(local);  // min/max: the same in any order
#pragma omp barrier
#pragma omp single
        build_node(ctx, 0, 0, std::uint32_t(n), root, 0);
    }

    out.bounds = root.box.box();
    Collapser c{bnodes.get(), refs.get(), in.kind.empty() ? nullptr : in.kind.data(), index, out};
    out.leaves.reserve((next.load() + 1) / 2);  // a binary tree of m nodes has (m + 1) / 2 leaves
    out.nodes.reserve(c.count(0));
    c.node(0, 1);
    return out;
}

double sah_cost(const Bvh8& bvh, const BuildOptions& opt) {
    if (bvh.empty()) return 0.0;
    const double root_area = bvh.bounds.area();
    if (!(root_area > 0.0)) return 0.0;
    double cost = opt.traversal_cost;  // the root is always entered
    for (const Node8& node : bvh.nodes) {
        for (int j = 0; j < node.child_count(); ++j) {
            const double a = node.bounds(j).area() / root_area;
            const std::int32_t c = node.child[j];
            cost += c >= 0 ? opt.traversal_cost * a
                           : opt.intersection_cost * a *
                                 std::ceil(double(bvh.leaves[std::size_t(~c)].size()) / opt.leaf_block);
        }
    }
    return cost;
}

}  // namespace octray::bvh
