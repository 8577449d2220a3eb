// kernels/bvh/collapse.cpp — step 3 of the BVH builder (kernels/bvh/build.cpp
// explains the steps): the binary tree collapsed into the 8-wide one, its
// leaves numbered left to right and each kind's permutation written leaf by
// leaf. It follows child links, so the binary node indices (which depend on
// the build's task schedule) never reach the wide tree.
#include "kernels/bvh/build_types.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace octray::bvh::detail {

// Which binary nodes become wide nodes: the SAH-optimal choice for the
// binary tree as built (Ylitie, Karras and Laine 2017, "Efficient
// incoherent ray traversal on GPUs through compressed wide BVHs", section
// 4.1, with its leaves kept as the builder made them). cost[b][i - 1] is
// the least SAH cost of binary subtree b spread over at most i child slots
// of its wide parent: one slot holds b as a leaf or as a wide node of its
// own (traversal_cost times its area, plus its subtree spread over 8
// slots); more slots may hand b's two children k and i - k of them.
// split[b][i - 1] records the choice: the left child's k (0: fewer slots
// do as well); split[b][0] is the k of b's own wide node. The greedy
// collapse leaves bottom nodes part full (a parent opens its children
// until 8, so each child subtree keeps only a few leaves); the plan pulls
// leaves up where that costs less, which fills the nodes.
struct Plan {
    std::vector<std::array<std::int8_t, kWidth>> split;

    void make(const BNode* bnodes, std::uint32_t binary_nodes, const BuildOptions& opt) {
        split.assign(binary_nodes, {});
        std::vector<std::array<float, kWidth>> cost(binary_nodes);
        solve(bnodes, 0, opt, cost);
    }

    void solve(const BNode* bnodes, std::uint32_t b, const BuildOptions& opt,
               std::vector<std::array<float, kWidth>>& cost) {
        const BNode& n = bnodes[b];
        std::array<float, kWidth>& c = cost[b];
        if (n.count > 0) {
            c.fill(opt.intersection_cost * std::ceil(float(n.count) / float(opt.leaf_block)) * n.box.area());
            return;
        }
        const std::uint32_t l = n.first, r = n.first + 1;
        solve(bnodes, l, opt, cost);
        solve(bnodes, r, opt, cost);
        // spread[j]: the two children over at most j slots (j >= 2), and the left's share.
        float spread[kWidth + 1];
        std::int8_t share[kWidth + 1];
        for (int j = 2; j <= kWidth; ++j) {
            spread[j] = kInf, share[j] = 1;
            for (int k = 1; k < j; ++k) {
                const float v = cost[l][std::size_t(k - 1)] + cost[r][std::size_t(j - k - 1)];
                if (v < spread[j]) spread[j] = v, share[j] = std::int8_t(k);
            }
        }
        c[0] = opt.traversal_cost * n.box.area() + spread[kWidth];
        split[b][0] = share[kWidth];
        for (int i = 2; i <= kWidth; ++i) {
            const bool fewer = !(spread[i] < c[std::size_t(i - 2)]);
            c[std::size_t(i - 1)] = fewer ? c[std::size_t(i - 2)] : spread[i];
            split[b][std::size_t(i - 1)] = fewer ? 0 : share[i];
        }
    }
};

// The wide tree from the binary one.
struct Collapser {
    const BNode* bnodes;
    const Ref* refs;
    const std::uint8_t* kind;                  // null: all kind 0
    const std::vector<std::uint32_t>& index;  // index_in_kind per input primitive
    Bvh8& out;
    Plan plan;  // empty: the greedy collapse

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

    // The children of the wide node for binary node b (inner, or the root
    // even as a leaf), left to right, by the plan where there is one (see
    // Plan), else greedily: b's two children, then the largest (by area)
    // inner one opened until there are 8 or only leaves.
    int open_children(std::uint32_t b, std::uint32_t kids[kWidth]) const {
        int k = 0;
        if (bnodes[b].count > 0) {
            kids[k++] = b;  // a root leaf: one child
            return k;
        }
        if (!plan.split.empty()) {
            const std::uint32_t first = bnodes[b].first;
            const int left = plan.split[b][0];
            take(first, left, kids, k);
            take(first + 1, kWidth - left, kids, k);
            return k;
        }
        kids[k++] = bnodes[b].first;
        kids[k++] = bnodes[b].first + 1;
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

    // The children subtree b gives in at most `slots` slots, by the plan.
    void take(std::uint32_t b, int slots, std::uint32_t kids[kWidth], int& k) const {
        for (;;) {
            const BNode& n = bnodes[b];
            if (slots == 1 || n.count > 0) {
                kids[k++] = b;
                return;
            }
            const int left = plan.split[b][std::size_t(slots - 1)];
            if (left == 0) {
                --slots;
                continue;
            }
            take(n.first, left, kids, k);
            b = n.first + 1, slots -= left;
        }
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
            n.run[j] = j < k && child[j] < 0 ? leaf_run(out.leaves[std::size_t(~child[j])]) : 0;
        }
        return index_here;
    }
};

void collapse(const BNode* bnodes, std::uint32_t binary_nodes, const Ref* refs, const std::uint8_t* kind,
              const std::vector<std::uint32_t>& index, const BuildOptions& opt, Bvh8& out) {
    Collapser c{bnodes, refs, kind, index, out, {}};
    if (opt.sah_collapse) c.plan.make(bnodes, binary_nodes, opt);
    out.leaves.reserve((binary_nodes + 1) / 2);  // a binary tree of m nodes has (m + 1) / 2 leaves
    out.nodes.reserve(c.count(0));
    c.node(0, 1);
}

}  // namespace octray::bvh::detail
