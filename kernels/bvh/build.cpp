// kernels/bvh/build.cpp — the 8-wide BVH builder (see kernels/bvh/node.hpp): the
// top-down recursion, build_bvh8 and sah_cost. How a node splits is
// kernels/bvh/split.cpp, the collapse kernels/bvh/collapse.cpp, the shared types
// kernels/bvh/build_types.hpp.
//
// Three steps:
// 1. references: each primitive's box and id in one 32-byte record (two SSE
//    registers), with the root's bounds and centroid bounds (parallel loop);
// 2. a binary tree, top down: per node, the primitives' centroids are binned
//    along each axis (BuildOptions::bins bins) and the SAH cost of every bin
//    boundary is swept (kernels/bvh/split.cpp; nodes of at most 16 references take
//    the exact sweep instead); the node becomes a leaf where that is cheaper
//    (and it fits in max_leaf_size), else its references are partitioned in
//    place. Large subtrees become OpenMP tasks. Where no boundary separates
//    the centroids (all at one point), or deep down (binary depth
//    kForceMedianDepth), the node is split at its middle reference instead,
//    which bounds the depth;
// 3. a collapse, sequential and depth first (kernels/bvh/collapse.cpp): which
//    binary nodes become wide nodes is chosen for the least SAH cost by a
//    table over the binary tree (Ylitie et al. 2017; BuildOptions::
//    sah_collapse, else greedily: each wide node opens its largest child
//    until it has 8); leaves are numbered left to right, and each kind's
//    permutation is written leaf by leaf.
//
// Determinism: a node's split depends only on its references, in an order
// fixed by its ancestors' in-place partitions (each run by one thread), and
// on bins whose bounds are min/max (exact in any order) and whose counts are
// integers. Tasks only decide which thread builds a subtree; binary node
// indices depend on the schedule but the collapse follows child links, so the
// wide tree never sees them. Nothing in the parallel region allocates or
// throws: every array is made before it.
#include "kernels/bvh/build_types.hpp"

#include <octray/threads.hpp>

#include <cmath>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace octray::bvh {
namespace detail {

void build_node(const Context& ctx, std::uint32_t node, std::uint32_t begin, std::uint32_t end, Bounds bounds,
                int depth) {
    for (;;) {  // the right child continues in this loop; the left one recurses (or is a task)
        BNode& bn = ctx.nodes[node];
        bn.box = bounds.box.box();
        const std::uint32_t n = end - begin;
        const float area = bounds.box.area();
        const bool leaf_ok = n <= std::uint32_t(ctx.max_leaf);
        // SAH, scaled by the node's area, in leaf blocks of b: leaf ceil(n / b) Ci A
        // vs split Ct A + Ci (sum A_side n_side) / b.
        const float block = float(ctx.leaf_block);
        const float leaf_cost = ctx.intersection_cost * std::ceil(float(n) / block) * area;
        // A split costs at least Ct A (its sum is >= 0, and rounding is
        // monotone): a leaf costing no more wins without a search, the same
        // decision the comparison below makes.
        const bool leaf_now = n == 1 || (leaf_ok && !(leaf_cost > ctx.traversal_cost * area));
        const NodeSplit split = leaf_now ? NodeSplit{} : choose_split(ctx, begin, end, bounds, depth);
        if (leaf_now ||
            (leaf_ok && !(leaf_cost > ctx.traversal_cost * area + ctx.intersection_cost * split.cost() / block))) {
            bn.first = begin;
            bn.count = n;
            return;
        }
        Bounds left, right;
        const std::uint32_t mid = apply_split(ctx, begin, end, bounds, split, left, right);
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

void check(bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("build_bvh8: ") + what);
}

}  // namespace detail

using namespace detail;

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
    out.primitives = n;
    out.order.resize(std::size_t(in.kind_count));
    if (n == 0) return out;
    for (int k = 0; k < in.kind_count; ++k) out.order[std::size_t(k)].reserve(per_kind[std::size_t(k)]);

    // Every array the parallel region touches, made here (default-initialized:
    // only the pages the build writes are ever touched).
    const RawArray<Ref> refs(n);
    const RawArray<BNode> bnodes(2 * n - 1);
    std::atomic<std::uint32_t> next{1};
    const Context ctx{refs.get(),          bnodes.get(),          &next,           opt.bins, opt.max_leaf_size,
                      opt.traversal_cost, opt.intersection_cost, opt.leaf_block};
    Bounds root;
    const Box* boxes = in.boxes.data();
#ifdef _OPENMP
    const int threads = resolve_threads(opt.threads);
#endif
    // Reference i, written and added to `bounds`.
    auto write_ref = [&ctx, boxes](std::size_t i, Bounds& bounds) {
        Ref& r = ctx.refs[i];
        std::memcpy(r.lo, boxes[i].lo, sizeof r.lo);
        std::memcpy(r.hi, boxes[i].hi, sizeof r.hi);
        r.id = std::uint32_t(i);
        r.pad = 0;
        bounds.extend(r);
    };
    if (n <= kTaskSize) {
        // Too small for a task: the team would cost more than it saves, and
        // one thread builds the same tree.
        for (std::size_t i = 0; i < n; ++i) write_ref(i, root);
        build_node(ctx, 0, 0, std::uint32_t(n), root, 0);
    } else {
#pragma omp parallel num_threads(threads) default(none) shared(ctx, root, write_ref, n)
        {
            Bounds local;
#pragma omp for schedule(static)
            for (std::size_t i = 0; i < n; ++i) write_ref(i, local);
#pragma omp critical(octray_bvh_root_bounds)
            root.extend(local);  // min/max: the same in any order
#pragma omp barrier
#pragma omp single
            build_node(ctx, 0, 0, std::uint32_t(n), root, 0);
        }
    }

    out.bounds = root.box.box();
    collapse(bnodes.get(), next.load(), refs.get(), in.kind.empty() ? nullptr : in.kind.data(), index, opt, out);
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
