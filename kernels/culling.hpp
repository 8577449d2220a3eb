// kernels/culling.hpp — which primitives a packet may hit: the walk of a
// type's bounding-sphere tree (cluster_tree.hpp), the root tested ray by ray,
// the levels below against the packet's beam (a cone around its rays), eight
// children or primitives per vector test.
#pragma once

#include "ray.hpp"

namespace octray::kernels::OCTRAY_ISA {

// May a valid lane of the packet hit anything inside the bounding sphere j of
// `c` before `tbest`? It answers no only when, on every valid lane, the ray's
// line passes outside the sphere, or the sphere lies behind the origin, or
// it begins beyond tbest — each by a margin of 2^-18 of the squared scale
// (t: 2^-10 relative), far above the rounding error of these few operations
// (~12u). NaN or inf (huge coordinates) answers maybe. Skipping changes no
// lane's result, so the scalar and SIMD paths still agree bit for bit.
template <class T, Precision P>
OCTRAY_HOT bool cluster_may_hit(const Ray<T, P>& r, const ClusterTree& c, int j, const T& tbest) {
    const Vec3<T> f = r.o - broadcast3<T>(c.cx, c.cy, c.cz, j);
    const T rb = broadcast<T>(c.radius, j);
    const T rb2 = rb * rb, s2 = fdot(f, f);
    const T b = fdot(f, r.d);
    // The line misses: a (rb^2 - |perp|^2) = b^2 - a (s2 - rb2) < 0, in the
    // textbook form for its short dependency chain (as sphere_roots' exit;
    // its error is below ~12u a (s2 + rb2), a sixth of the margin).
    const T outside = s2 - rb2, margin = T(0x1p-18f) * (s2 + rb2);
    const Mask<T> line_misses = b * b - r.dd * outside < T(0) - r.dd * margin;
    // Most packets pass a small type's root far off: stop before the other
    // two tests, as a single ray's short-circuit would.
    if (lane::all(line_misses || lane::not_(r.valid))) return false;
    const Mask<T> behind = b > T(0) && outside > margin;
    const T t_enter = (T(0) - b - rb * r.len_d) * r.inv_dd;  // no point of the sphere is nearer
    const Mask<T> beyond = t_enter - lane::abs(t_enter) * T(0x1p-10f) > tbest;
    return lane::any(r.valid && lane::not_(line_misses || behind || beyond));
}

// A node's children are tested against a packet's beam a vector of them at a
// time, on every path (the scalar path too, as single-ray tracers test wide
// nodes): 8 floats where the unit has AVX, else 4.
#if defined(__AVX__)
using NodeLanes = xsimd::batch<float, xsimd::avx>;
#else
using NodeLanes = xsimd::batch<float, xsimd::sse2>;
#endif
static_assert(kTreeWidth % NodeLanes::size == 0, "a node's children fill whole vectors");

// The valid rays of a packet as one beam: every ray's line passes within
// `spread` of `origin` and runs at an angle theta or less to the unit `axis`
// (cos_theta <= cos of each ray's angle, sin_theta >= its sine). Axis and
// origin are lane 0's: any ray would do, the bound holds for every choice (a
// masked-off lane 0, rare, makes it loose). sin theta is taken as
// |d x axis|, not sqrt(1 - cos^2), which cancels for the small angles of
// coherent rays. Broadcast to the node lanes; computed in float (double
// lanes round to it).
struct Beam {
    Vec3<NodeLanes> origin, axis;
    NodeLanes cos2_theta, sin_theta, spread;
};

template <class T, Precision P>
inline Beam make_beam(const Ray<T, P>& r) {
    const T inv_len = r.len_d * r.inv_dd;  // 1 / |d|
    const Vec3<T> dir = r.d * inv_len;
    // The origin in float, and the spread measured from it: double lanes'
    // rounding of it is part of the spread.
    const float ox = float(lane::lane0(r.o.x)), oy = float(lane::lane0(r.o.y)), oz = float(lane::lane0(r.o.z));
    const float ax = float(lane::lane0(dir.x)), ay = float(lane::lane0(dir.y)), az = float(lane::lane0(dir.z));
    const Vec3<T> axis{T(ax), T(ay), T(az)};
    const Vec3<T> across = cross(dir, axis);
    const Vec3<T> off = r.o - Vec3<T>{T(ox), T(oy), T(oz)};  // each component rounded once: relative error u
    const float cos_theta = float(lane::lane0(lane::hmin(lane::select(r.valid, fdot(dir, axis), T(1)))));
    const float sin2_theta = float(lane::lane0(lane::hmax(lane::keep(r.valid, fdot(across, across)))));
    const float spread2 = float(lane::lane0(lane::hmax(lane::keep(r.valid, fdot(off, off)))));
    // At 90 degrees or more (cos <= 0, or NaN) the bound says nothing: cos 0, sin 1.
    const bool narrow = cos_theta > 0.0f;
    return {{NodeLanes(ox), NodeLanes(oy), NodeLanes(oz)},
            {NodeLanes(ax), NodeLanes(ay), NodeLanes(az)},
            NodeLanes(narrow ? cos_theta * cos_theta : 0.0f),
            NodeLanes(narrow ? std::sqrt(sin2_theta) : 1.0f),
            NodeLanes(std::sqrt(spread2) * (1 + 0x1p-16f))};
}

// A packet's beam, made when a walk first needs it and shared by the types'
// walks (any_hit's later walks have fewer valid lanes: the beam still covers
// them).
template <class T, Precision P>
struct LazyBeam {
    const Ray<T, P>& r;
    bool made = false;
    Beam beam;
    explicit LazyBeam(const Ray<T, P>& ray) : r(ray) {}
    const Beam& get() {
        if (!made) beam = make_beam(r), made = true;
        return beam;
    }
};

// Which of the `count` spheres at cx[first..] (a node's children, or a
// leaf's primitives) may a ray of the beam come near? Bit i clear means every
// ray's line passes outside sphere i. With q = centre - origin, the distance
// from the centre to a ray's line is at least |q x axis| cos theta -
// |q.axis| sin theta - spread (the angle between the lines of q and of the
// ray is at least that between q's and the axis' less theta); the test
// compares squares (no sqrt on the way to the branch). The rounding error is
// a few u |q| (a few float u more for double lanes' beam); the test keeps a
// margin of 2^-14 max|q_i| (>= 2^-15 |q|). Infinite or NaN terms (huge
// coordinates, infinite radii) keep the sphere.
OCTRAY_HOT unsigned beam_near(const Beam& b, const Floats& cx, const Floats& cy, const Floats& cz, const Floats& radius,
                              int first, int count) {
    using N = NodeLanes;
    constexpr int w = int(N::size);
    unsigned near = 0;
    for (int i = 0; i < count; i += w) {
        const std::size_t at = std::size_t(first + i);
        const Vec3<N> q = Vec3<N>{N::load_unaligned(cx.data() + at), N::load_unaligned(cy.data() + at),
                                  N::load_unaligned(cz.data() + at)} - b.origin;
        const Vec3<N> x = cross(q, b.axis);
        const N q_max = lane::max(lane::abs(q.x), lane::max(lane::abs(q.y), lane::abs(q.z)));
        const N reach = N::load_unaligned(radius.data() + at) + b.spread + lane::abs(fdot(q, b.axis)) * b.sin_theta +
                        q_max * N(0x1p-14f);
        const N across2 = fdot(x, x);
        const auto outside = across2 * b.cos2_theta > reach * reach && across2 < N(INFINITY);
        near |= (lane::bits(outside) ^ ((1u << w) - 1u)) << i;
    }
    return near & ((1u << count) - 1u);
}

// for_each_candidate's walk below the root.
template <PrimitiveType Type, class T, Precision P, class Test>
OCTRAY_HOT void walk_tree(const ClusterTree& tree, int n, const Ray<T, P>& r, LazyBeam<T, P>& lazy, Test& test) {
    const Beam& beam = lazy.get();
    int stack[64];  // a pop pushes <= kTreeWidth - 1 more per level: 8 levels for 2^24 primitives
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const int j = stack[--top];
        const int first = tree.first_child[std::size_t(j)];
        if (first < 0) {
            const int k0 = tree.cluster[std::size_t(j)] * kClusterSize;
            const int k1 = k0 + kClusterSize < n ? k0 + kClusterSize : n;
            for (unsigned near = beam_near(beam, tree.px, tree.py, tree.pz, tree.pradius, k0, k1 - k0); near != 0;
                 near &= near - 1)
                test(k0 + __builtin_ctz(near));
            if (!lane::any(r.valid)) return;  // any_hit: every lane blocked
            continue;
        }
        // Pushed last to first, so they pop in order.
        for (unsigned near = beam_near(beam, tree.cx, tree.cy, tree.cz, tree.radius, first,
                                       tree.child_count[std::size_t(j)]);
             near != 0;) {
            const int i = 31 - __builtin_clz(near);
            near &= ~(1u << i);
            assert(top < 64 && "deeper than a tree of 2^24 primitives");
            stack[top++] = first + i;
        }
    }
}

// Out of line, for kernels with several bounded primitive types: inline, six
// walks crowd the small scenes' path (one node per type), where they never
// run (callgrind, scenes/default.json: +12% instructions in intersect); with
// one type the walk stays inline (the Embree peer's spheres:64: 10% fewer).
template <PrimitiveType Type, class T, Precision P, class Test>
OCTRAY_WALK void walk_tree_out_of_line(const ClusterTree& tree, int n, const Ray<T, P>& r, LazyBeam<T, P>& lazy,
                                       Test& test) {
    walk_tree<Type>(tree, n, r, lazy, test);
}

// Primitive types other than planes (those with a tree) in a feature set.
inline constexpr int bounded_types(unsigned f) {
    return __builtin_popcount(f & kAllPrimitives & ~unsigned(kPlane));
}

// Calls test(k) for every primitive k of the type that may hit before `tbest`,
// walking the type's bounding-sphere tree (planes: all of them). The root is
// tested ray by ray (cluster_may_hit, which knows tbest); below it a node's
// children, and a leaf's primitives, are tested against the packet's beam a
// vector at a time, and only those it comes near are visited. Ray by ray
// every node cost about a sphere test; the beam tests 8 for about one
// (callgrind, the Embree peer's spheres:64 scene: 1048 instructions per
// packet with the binary tree of per-ray tests, 722 so). `test` may lower
// tbest and narrow r.valid as it goes (any_hit drops blocked lanes; the walk
// ends when none is left). Children are visited in order whatever the rays'
// direction, so primitives are tested in compiled order, as without the
// tree: exact-t ties resolve the same way on every path. F, the kernel's
// features, decides where the walk is compiled (walk_tree_out_of_line).
template <PrimitiveType Type, unsigned F = (1u << unsigned(Type)), class T, Precision P, class Test>
OCTRAY_HOT void for_each_candidate(const SceneData& s, int n, const Ray<T, P>& r, const T& tbest, LazyBeam<T, P>& lazy,
                                   Test&& test) {
    if constexpr (Type == PrimitiveType::plane) {
        for (int k = 0; k < n; ++k) test(k);
    } else {
        const ClusterTree& tree = s.clusters[std::size_t(Type)];
        if (tree.size() == 0 || !cluster_may_hit(r, tree, 0, tbest)) return;
        if constexpr (Type == PrimitiveType::box) make_slabs(r);
        if constexpr (Type == PrimitiveType::triangle) make_shear(r);
        if (tree.size() == 1) {  // one cluster (a scene with few of the type): no walk
            for (int k = 0; k < n; ++k) test(k);
            return;
        }
        if constexpr (bounded_types(F) > 1) walk_tree_out_of_line<Type>(tree, n, r, lazy, test);
        else walk_tree<Type>(tree, n, r, lazy, test);
    }
}

// The same for a walk of one type alone.
template <PrimitiveType Type, class T, Precision P, class Test>
OCTRAY_HOT void for_each_candidate(const SceneData& s, int n, const Ray<T, P>& r, const T& tbest, Test&& test) {
    LazyBeam<T, P> lazy(r);
    for_each_candidate<Type>(s, n, r, tbest, lazy, test);
}

}  // namespace octray::kernels::OCTRAY_ISA
