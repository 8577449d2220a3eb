// kernels/cluster_tree.hpp — the bounding-sphere tree over one primitive type.
//
// A tree of bounding spheres over one type's primitives (in compiled, i.e.
// Morton, order), so a packet skips every region none of its rays comes near.
// Leaves are clusters of kClusterSize consecutive primitives; an inner node
// splits its run of clusters into up to kTreeWidth runs of equal length (a
// power of kTreeWidth clusters each, the last shorter), whose nodes are
// consecutive: node j's children are first_child[j] .. first_child[j] +
// child_count[j] - 1 (first_child -1 for a leaf, whose cluster is cluster[j]:
// primitives from cluster[j] * kClusterSize on). Node 0 is the root. Radii are
// rounded up: every primitive lies inside each node above it. The node arrays
// are padded by kTreeWidth entries, so the bounds of a node's children load as
// one block of kTreeWidth floats.
// kTreeWidth and kClusterSize 8: one AVX register of children, or of a
// leaf's primitives, per beam test (culling.hpp, for_each_candidate); leaves
// of 8 beat leaves of 4 in callgrind counts (docs/performance.md).
#pragma once

#include "aligned.hpp"

#include <octray/vec3.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

namespace octray {

inline constexpr int kClusterSize = 8;
inline constexpr int kTreeWidth = 8;

struct ClusterTree {
    Floats cx, cy, cz, radius;              // per node (then kTreeWidth of padding)
    std::vector<std::int32_t> first_child;  // -1 for a leaf
    std::vector<std::int32_t> child_count;  // 0 for a leaf
    std::vector<std::int32_t> cluster;      // a leaf's cluster (-1 for an inner node)
    Floats px, py, pz, pradius;             // per primitive, its bounding sphere (then padding)
    int size() const { return int(first_child.size()); }
    // Test hook: every bound infinite, so the walk skips nothing and tests
    // every primitive in compiled order (tests and benchmarks compare against it).
    void disable_culling() {
        for (Floats* r : {&radius, &pradius}) std::fill(r->begin(), r->end(), std::numeric_limits<float>::infinity());
    }
};

// A sphere that contains a primitive.
struct Bound {
    Vec3d center;
    double radius = 0;
};

// The tree over `members` (bounding spheres in compiled order).
ClusterTree build_cluster_tree(const std::vector<Bound>& members);

}  // namespace octray
