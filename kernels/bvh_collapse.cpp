// kernels/bvh_collapse.cpp — step 3 of the BVH builder (bvh_build.cpp
// explains the steps): the binary tree collapsed into the 8-wide one, its
// leaves numbered left to right and each kind's permutation written leaf by
// leaf. It follows child links, so the binary node indices (which depend on
// the build's task schedule) never reach the wide tree.
#include "bvh_build_types.hpp"

#include <algorithm>

namespace octray::bvh::detail {

// The wide tree from the binary one.
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
            n.run[j] = j < k && child[j] < 0 ? leaf_run(out.leaves[std::size_t(~child[j])]) : 0;
        }
        return index_here;
    }
};

void collapse(const BNode* bnodes, std::uint32_t binary_nodes, const Ref* refs, const std::uint8_t* kind,
              const std::vector<std::uint32_t>& index, Bvh8& out) {
    Collapser c{bnodes, refs, kind, index, out};
    out.leaves.reserve((binary_nodes + 1) / 2);  // a binary tree of m nodes has (m + 1) / 2 leaves
    out.nodes.reserve(c.count(0));
    c.node(0, 1);
}

}  // namespace octray::bvh::detail
