// kernels/bvh/leaf_blocks.cpp — leaf data beside its parent node: the 8-wide
// tree re-laid out depth first with each node followed by its leaf
// children's blocks, as Embree keeps its leaves in the BVH's own memory
// (kernels/geometry/triangle4v.h) and jbikker/tinybvh's BVH8_CPU writes each
// leaf after its parent (Fuetterling et al., "Accelerated Single Ray Tracing
// for Wide Vector Units", HPG 2017). A ray that enters a node and then one of
// its leaves reads lines that sit together: the same pages, one stream.
#include "kernels/bvh/node.hpp"

#include <stdexcept>

namespace octray::bvh {

namespace {

constexpr std::size_t kSlotFloats = sizeof(Node8) / sizeof(float);

struct Placer {
    const Bvh8& in;
    const std::vector<std::uint32_t>& block_floats;
    AlignedVector<Node8>& out;
    std::vector<std::uint32_t>& leaf_block;  // per leaf number

    // Node `ref` of `in` and what lies below it, from slot out.size() on; its new index.
    std::int32_t place(std::int32_t ref) {
        const Node8& node = in.nodes[std::size_t(ref)];
        const std::size_t here = out.size();
        out.emplace_back(node);
        // The node's leaf children's blocks, packed, in whole slots after it.
        std::size_t floats = 0;
        for (int c = 0; c < kWidth; ++c) {
            const std::int32_t child = node.child[c];
            if (child >= 0 || child == kEmptySlot) continue;
            const std::uint32_t n = block_floats[std::size_t(~child)];
            if (n == 0) continue;
            const std::size_t at = (here + 1) * kSlotFloats + floats;
            if (at > std::size_t(INT32_MAX)) throw std::length_error("place_leaf_blocks: the tree exceeds 8 GiB");
            leaf_block[std::size_t(~child)] = std::uint32_t(at);
            floats += n;
        }
        out.resize(out.size() + (floats + kSlotFloats - 1) / kSlotFloats);
        std::int32_t moved[kWidth];
        for (int c = 0; c < kWidth; ++c) {
            const std::int32_t child = node.child[c];
            moved[c] = child;
            if (child >= 0) moved[c] = place(child);
            else if (child != kEmptySlot && node.run[c] != 0 && leaf_block[std::size_t(~child)] != 0)
                moved[c] = ~std::int32_t(leaf_block[std::size_t(~child)]);
        }
        Node8& placed = out[here];  // after the recursion: the vector may have grown
        for (int c = 0; c < kWidth; ++c) placed.child[c] = moved[c];
        return std::int32_t(here);
    }
};

// Slots a subtree takes once placed, so out[] is sized once.
std::size_t slots_of(const Bvh8& in, const std::vector<std::uint32_t>& block_floats, std::int32_t ref) {
    const Node8& node = in.nodes[std::size_t(ref)];
    std::size_t floats = 0, slots = 1;
    for (int c = 0; c < kWidth; ++c) {
        const std::int32_t child = node.child[c];
        if (child >= 0) slots += slots_of(in, block_floats, child);
        else if (child != kEmptySlot) floats += block_floats[std::size_t(~child)];
    }
    return slots + (floats + kSlotFloats - 1) / kSlotFloats;
}

}  // namespace

void place_leaf_blocks(Bvh8& tree, const std::vector<std::uint32_t>& block_floats) {
    if (block_floats.size() != tree.leaves.size())
        throw std::invalid_argument("place_leaf_blocks: one block size per leaf record");
    if (tree.empty()) return;
    AlignedVector<Node8> out;
    out.reserve(slots_of(tree, block_floats, 0) + 1);
    std::vector<std::uint32_t> leaf_block(tree.leaves.size(), 0);
    Placer{tree, block_floats, out, leaf_block}.place(0);
    out.emplace_back();  // spare room: whole-width loads past the last block stay inside
    for (std::size_t l = 0; l < tree.leaves.size(); ++l) tree.leaves[l].block = leaf_block[l];
    tree.nodes.swap(out);
}

}  // namespace octray::bvh
