// kernels/cluster_tree.cpp — builds the per-type bounding-sphere trees
// (cluster_tree.hpp) that the kernels' culling walks (culling.hpp).
#include "cluster_tree.hpp"

#include <cmath>

namespace octray {
namespace {

// Appends the bounding sphere of members [first, last) to (x, y, z, radius):
// centred on their bounding box, radius rounded up to a float that contains
// them all.
void enclose(const std::vector<Bound>& members, std::size_t first, std::size_t last, Floats& x, Floats& y, Floats& z,
             Floats& radius) {
    Vec3d lo = members[first].center, hi = lo;
    for (std::size_t i = first; i < last; ++i) {
        const Bound& b = members[i];
        lo = {std::min(lo.x, b.center.x - b.radius), std::min(lo.y, b.center.y - b.radius), std::min(lo.z, b.center.z - b.radius)};
        hi = {std::max(hi.x, b.center.x + b.radius), std::max(hi.y, b.center.y + b.radius), std::max(hi.z, b.center.z + b.radius)};
    }
    const Vec3f c{float((lo.x + hi.x) / 2), float((lo.y + hi.y) / 2), float((lo.z + hi.z) / 2)};
    double r = 0;
    for (std::size_t i = first; i < last; ++i)
        r = std::max(r, std::sqrt(length_squared(members[i].center - Vec3d(c))) + members[i].radius);
    x.push_back(c.x), y.push_back(c.y), z.push_back(c.z);
    radius.push_back(std::nextafter(float(r * (1 + 1e-6)), std::numeric_limits<float>::infinity()));
}

// Appends a node (a leaf until build_node says otherwise) around members [first, last).
void append_node(const std::vector<Bound>& members, std::size_t first, std::size_t last, ClusterTree& out) {
    enclose(members, first, last, out.cx, out.cy, out.cz, out.radius);
    out.first_child.push_back(-1), out.child_count.push_back(0), out.cluster.push_back(-1);
}

// Node `node` (already appended) spans clusters [first, last): a leaf for one
// cluster, else the parent of up to kTreeWidth runs of g clusters, g the
// smallest power of kTreeWidth that needs no more runs; the runs' nodes are
// appended together, then each is built. A node's bound encloses its
// primitives directly (tighter than a sphere around its children's spheres).
void build_node(const std::vector<Bound>& members, std::size_t node, int first, int last, ClusterTree& out) {
    const int n = last - first;
    if (n == 1) {
        out.cluster[node] = first;
        return;
    }
    int g = 1;
    while (g * kTreeWidth < n) g *= kTreeWidth;
    const int children = (n + g - 1) / g;
    const std::size_t first_child = out.first_child.size();
    out.first_child[node] = std::int32_t(first_child);
    out.child_count[node] = children;
    for (int c = 0; c < children; ++c)
        append_node(members, std::size_t(first + c * g) * kClusterSize,
                    std::min(members.size(), std::size_t(std::min(first + (c + 1) * g, last)) * kClusterSize), out);
    for (int c = 0; c < children; ++c)
        build_node(members, first_child + std::size_t(c), first + c * g, std::min(first + (c + 1) * g, last), out);
}

}  // namespace

ClusterTree build_cluster_tree(const std::vector<Bound>& members) {
    ClusterTree out;
    const int clusters = int((members.size() + kClusterSize - 1) / kClusterSize);
    if (clusters == 0) return out;
    append_node(members, 0, members.size(), out);
    build_node(members, 0, 0, clusters, out);
    for (std::size_t i = 0; i < members.size(); ++i) enclose(members, i, i + 1, out.px, out.py, out.pz, out.pradius);
    // Padding: a block of kTreeWidth children (or primitives) loads whole.
    for (Floats* a : {&out.cx, &out.cy, &out.cz, &out.radius, &out.px, &out.py, &out.pz, &out.pradius})
        a->insert(a->end(), kTreeWidth, 0.0f);
    return out;
}

}  // namespace octray
