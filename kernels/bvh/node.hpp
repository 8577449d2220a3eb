// kernels/bvh/node.hpp — one acceleration structure for every bounded primitive:
// an 8-wide BVH (axis-aligned boxes, structure-of-arrays nodes whose 8
// children are slab-tested at once), built by binned SAH (Wald 2007, "On fast
// construction of SAH-based bounding volume hierarchies") into a binary tree
// which is then collapsed into 8-wide nodes (SAH-optimally, as Ylitie et
// al. 2017 do; madmann91/bvh and Embree's BVH8 collapse greedily).
// Internal header: the builder is kernels/bvh/build.cpp, the walks are
// kernels/bvh/traverse.hpp.
//
// The tree is one structure for primitives of several kinds (sphere, disk,
// rectangle, box, triangle, mesh triangle, ...: up to kMaxKinds, numbered by
// the caller). A leaf holds primitives of any kinds; after the build each
// kind's primitives are in leaf order, so the caller reorders each kind's SoA
// arrays by Bvh8::order[kind] and a leaf names, per kind, one contiguous run.
#pragma once

#include "kernels/lanes/aligned.hpp"

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace octray::bvh {

inline constexpr int kWidth = 8;     // children per node
inline constexpr int kMaxKinds = 8;  // primitive kinds one tree holds
// Depth bound of the 8-wide tree (root = depth 1): the builder guarantees it
// (it forces median splits deep down), so a walk's stack of
// (kWidth - 1) * kMaxDepth + 1 entries never overflows.
inline constexpr int kMaxDepth = 72;
inline constexpr int kStackSize = (kWidth - 1) * kMaxDepth + 1;
// The child reference of an unused slot: neither an inner node (>= 0) nor a
// leaf number any tree has (~kEmptySlot = INT32_MAX). Its bounds are empty,
// so no slab test enters it.
inline constexpr std::int32_t kEmptySlot = std::numeric_limits<std::int32_t>::min();

// An axis-aligned box. Empty: lo = +inf, hi = -inf (any lo > hi is empty).
struct Box {
    float lo[3], hi[3];

    static Box empty() {
        constexpr float inf = std::numeric_limits<float>::infinity();
        return {{inf, inf, inf}, {-inf, -inf, -inf}};
    }
    bool is_empty() const { return !(lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2]); }
    // Union with b. A NaN coordinate of b is ignored (the comparison fails).
    void extend(const Box& b) {
        for (int a = 0; a < 3; ++a) {
            if (b.lo[a] < lo[a]) lo[a] = b.lo[a];
            if (b.hi[a] > hi[a]) hi[a] = b.hi[a];
        }
    }
    void extend(const float p[3]) { extend(Box{{p[0], p[1], p[2]}, {p[0], p[1], p[2]}}); }
    bool contains(const Box& b) const {
        for (int a = 0; a < 3; ++a)
            if (!(lo[a] <= b.lo[a] && b.hi[a] <= hi[a])) return false;
        return true;
    }
    // Surface area; 0 for an empty box.
    float area() const {
        if (is_empty()) return 0.0f;
        const float x = hi[0] - lo[0], y = hi[1] - lo[1], z = hi[2] - lo[2];
        return 2.0f * (x * y + y * z + z * x);
    }
};

// An inner node: up to 8 children, their boxes as structure of arrays (so
// one 8-float load per bound and axis serves all children). child[i] >= 0:
// the index of an inner node in Bvh8::nodes; child[i] < 0 (but not
// kEmptySlot): the leaf number ~child[i] in Bvh8::leaves. Used slots come
// first; then unused ones (kEmptySlot, empty bounds) up to 8.
// Children are in the binary tree's left-to-right order (the order of their
// primitives in each kind's array), not sorted by anything else: walks order
// them per ray. run[i]: a leaf child's primitives inline (leaf_run), so a
// walk reaches them without a read of Bvh8::leaves (a cache miss per leaf
// on a large tree); 0 for an inner node, an empty slot, or a leaf that does
// not fit in the word.
struct alignas(64) Node8 {
    float lo_x[kWidth], lo_y[kWidth], lo_z[kWidth];
    float hi_x[kWidth], hi_y[kWidth], hi_z[kWidth];
    std::int32_t child[kWidth];
    std::uint32_t run[kWidth];

    int child_count() const {
        int n = 0;
        while (n < kWidth && child[n] != kEmptySlot) ++n;
        return n;
    }
    Box bounds(int i) const { return {{lo_x[i], lo_y[i], lo_z[i]}, {hi_x[i], hi_y[i], hi_z[i]}}; }
};
// A node is four whole cache lines; child[] and run[] share the last.
static_assert(sizeof(Node8) == 256, "Node8 is four cache lines");

// A leaf: for each kind k, its primitives of kind k are positions
// begin[k] .. begin[k] + count[k] - 1 of kind k's (reordered) arrays.
// count[k] = 0 for a kind the leaf has none of (begin[k] is then where the
// next leaf's run of kind k starts). 8 runs of up to 255 primitives (leaves
// hold at most BuildOptions::max_leaf_size <= 255). block: where the leaf's
// own data sits beside its parent (place_leaf_blocks), as a float offset
// into the node array; 0 where it has none.
struct Leaf {
    std::uint32_t begin[kMaxKinds];
    std::uint8_t count[kMaxKinds];
    std::uint32_t block = 0;

    int size() const {
        int n = 0;
        for (std::uint8_t c : count) n += c;
        return n;
    }
};
static_assert(sizeof(Leaf) == 44, "Leaf: 8 begins, 8 counts, the block");

// A leaf's one run inline, for its parent's Node8::run: begin | kind << 24 |
// count << 27, where the leaf holds primitives of one kind only, at most 31
// of them, beginning below 2^24 (every leaf of a scene's tree with the
// default leaf size); else 0.
inline std::uint32_t leaf_run(const Leaf& l) {
    int kind = -1;
    for (int k = 0; k < kMaxKinds; ++k) {
        if (l.count[k] == 0) continue;
        if (kind >= 0) return 0;  // two kinds
        kind = k;
    }
    if (kind < 0 || l.count[kind] > 31 || l.begin[kind] >= (1u << 24)) return 0;
    return l.begin[kind] | std::uint32_t(kind) << 24 | std::uint32_t(l.count[kind]) << 27;
}

// The leaf a walk reaches by child reference `ref` (< 0) whose parent's run
// word is `run`: decoded into `scratch` when inline (its block is ~ref once
// place_leaf_blocks has run), else read from leaves.
inline const Leaf& leaf_of(const AlignedVector<Leaf>& leaves, std::int32_t ref, std::uint32_t run, Leaf& scratch) {
    if (run == 0) return leaves[std::size_t(~ref)];
    scratch = Leaf{};
    const unsigned kind = (run >> 24) & 7u;
    scratch.begin[kind] = run & 0xffffffu;
    scratch.count[kind] = std::uint8_t(run >> 27);
    scratch.block = std::uint32_t(~ref);
    return scratch;
}

// The tree. nodes[0] is the root whenever there is a primitive (even one: a
// root with a single leaf child); no primitive: no node, no leaf. The build
// makes nodes[] of nodes alone, depth first; place_leaf_blocks may then
// interleave leaf data with them, so code that visits every node follows
// the child references from the root (for_each_node), not the array.
// Nodes and leaves in aligned arrays (kernels/lanes/aligned.hpp): every Node8 starts a
// cache line, and a large tree sits in huge pages.
struct Bvh8 {
    AlignedVector<Node8> nodes;
    // Leaf number l's record. A caller may release it where
    // every_leaf_inline(tree) (compile() does, for a tree it walks): the walks
    // then decode each leaf from its run word; sah_cost needs the records.
    AlignedVector<Leaf> leaves;
    // order[k][position] = the caller's index (BuildInput::index_in_kind) of
    // the primitive of kind k now at `position`; one vector per kind used.
    // Only the caller's reordering reads it: the caller may release it
    // (compile() does), the walks never read it.
    std::vector<std::vector<std::uint32_t>> order;
    Box bounds = Box::empty();  // of every primitive
    int depth = 0;              // levels of inner nodes (root alone: 1); 0 when empty
    int kind_count = 0;
    std::size_t primitives = 0;

    bool empty() const { return nodes.empty(); }
    std::size_t primitive_count() const { return primitives; }
    // Memory held (nodes, leaves and the permutations).
    std::size_t bytes() const {
        std::size_t b = nodes.size() * sizeof(Node8) + leaves.size() * sizeof(Leaf);
        for (const auto& o : order) b += o.size() * sizeof(std::uint32_t);
        return b;
    }
};

// What to build over: primitive i has box boxes[i], kind kind[i] (< kind_count)
// and index index_in_kind[i] within its kind. kind empty: every primitive is
// kind 0. index_in_kind empty: primitive i's index is the number of
// primitives of its kind before it (the natural numbering of primitives given
// kind by kind, or interleaved, in the caller's order). Boxes should be
// finite and conservative for the caller's own intersection tests (a walk
// enters a child when the ray's slab test hits its box, with a relative slack
// of 2^-20 of t); an empty or NaN box is kept in a leaf but no ray reaches it.
struct BuildInput {
    std::vector<Box> boxes;
    std::vector<std::uint8_t> kind;
    std::vector<std::uint32_t> index_in_kind;
    int kind_count = 1;
};

// Defaults measured with bench/bench_bvh.cpp (closest hit on a tessellated
// sphere's 262k triangle boxes, 8-float packets and single rays): over
// max_leaf_size 1/2/4/8 x traversal_cost 1/2/4, larger leaves and costlier
// nodes were faster and smaller (docs/history/performance-2026.md has the sweep);
// cost 2 is kept because the benchmark's leaf test (a slab test a box) is
// much cheaper than the kernels' primitive tests.
struct BuildOptions {
    // At most this many primitives a leaf (1..255). A larger node is always
    // split; a smaller one becomes a leaf where SAH prefers it.
    int max_leaf_size = 8;
    int bins = 16;  // SAH bins per axis (2..64); 8 and 32 gave about the same SAH cost (docs/history/performance-2026.md)
    // SAH costs, per binary node visited and per primitive tested. A wide
    // node is 8 child slab tests standing for ~3 binary levels.
    float traversal_cost = 2.0f;
    float intersection_cost = 1.0f;
    // Primitives one leaf test takes at once (a single ray against a leaf's
    // run, side by side in the lanes): a leaf costs intersection_cost per
    // block of this many, and the primitives below a split count as packed
    // in blocks too, so the SAH fills leaves up to the block.
    int leaf_block = 8;
    // How the binary tree becomes 8-wide: true, the SAH-optimal choice of
    // the binary nodes that become wide nodes (kernels/bvh/collapse.cpp's Plan:
    // fuller nodes, fewer of them); false, greedy (each node opens its
    // largest child until it has 8).
    bool sah_collapse = true;
    // OpenMP threads for the build; 0: OpenMP's default. The tree is the
    // same whatever the count.
    int threads = 0;
};

// Calls fn(node) for every inner node, depth first from the root (parent
// before children, children in slot order).
template <class Fn>
void for_each_node(const Bvh8& tree, Fn&& fn) {
    if (tree.empty()) return;
    std::int32_t stack[kStackSize];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node8& node = tree.nodes[std::size_t(stack[--top])];
        fn(node);
        for (int c = kWidth - 1; c >= 0; --c)
            if (node.child[c] >= 0) stack[top++] = node.child[c];
    }
}

// Whether every leaf of the tree is inline in its parent's run word (so no
// walk reads Bvh8::leaves, and a caller that needs no leaf records may
// release them).
inline bool every_leaf_inline(const Bvh8& tree) {
    bool inline_only = true;
    for_each_node(tree, [&](const Node8& node) {
        for (int c = 0; c < kWidth; ++c)
            if (node.child[c] < 0 && node.child[c] != kEmptySlot && node.run[c] == 0) inline_only = false;
    });
    return inline_only;
}

// Room for each leaf's own data beside its parent (Embree's leaves in the
// BVH's memory; tinybvh's BVH8_CPU writes them after their parent): the
// nodes re-laid out depth first, each followed by the blocks of its leaf
// children in slot order, block_floats[l] floats for leaf number l (0: no
// block), packed, in whole Node8 slots. Each leaf's Leaf::block is set to
// its block's float offset into nodes[], and the reference to a leaf inline
// in its parent (a run word) becomes ~block (leaf_of decodes it). Needs the
// leaf records; leaves a packet width of floats of spare room at the end,
// for whole-width loads past the last block. The walks read the same tree.
void place_leaf_blocks(Bvh8& tree, const std::vector<std::uint32_t>& block_floats);

// Builds the tree. Deterministic: the same input and options give the same
// tree, bit for bit, on any number of threads. Throws std::invalid_argument
// for inconsistent input (sizes differ, a kind >= kind_count, kind_count
// outside 1..kMaxKinds, options out of range) and std::length_error beyond
// 2^30 primitives; never from inside its parallel region.
Bvh8 build_bvh8(const BuildInput& input, const BuildOptions& options = {});

// The SAH cost of a built tree (traversal_cost per node entered and
// intersection_cost per primitive tested, each weighted by the area of the
// box that gates it, relative to the root's bounds): a quality measure for
// comparing options.
double sah_cost(const Bvh8& bvh, const BuildOptions& options = {});

}  // namespace octray::bvh
