// kernels/bvh/culling.hpp — which bounded primitives a packet may hit: the walk
// of the scene's 8-wide BVH (kernels/bvh/node.hpp; walks in kernels/bvh/traverse.hpp, nearest
// child first, a diverged packet's few lanes as single rays). Planes are
// unbounded and stay outside the tree. Each leaf lists its primitives by
// type (a run of each type's compiled arrays), and only the types of the
// kernel's feature set F are compiled into the leaf's tests.
#pragma once

#include "kernels/bvh/traverse.hpp"
#include "kernels/trace/ray.hpp"

namespace octray::kernels::OCTRAY_ISA {

// A function object with the call operators of several lambdas.
template <class... F>
struct Overloaded : F... {
    using F::operator()...;
};
template <class... F>
Overloaded(F...) -> Overloaded<F...>;

template <PrimitiveType Type>
using TypeTag = std::integral_constant<PrimitiveType, Type>;

// Primitive types other than planes (those in the tree) in a feature set.
inline constexpr unsigned bounded_bits(unsigned f) { return f & kAllPrimitives & ~unsigned(kPlane); }

// Calls body(TypeTag<type>) for each bounded type in F, in type order.
template <unsigned F, class Body>
OCTRAY_HOT void for_each_bounded_type(Body&& body) {
    if constexpr ((F & kSphere) != 0) body(TypeTag<PrimitiveType::sphere>{});
    if constexpr ((F & kDisk) != 0) body(TypeTag<PrimitiveType::disk>{});
    if constexpr ((F & kRectangle) != 0) body(TypeTag<PrimitiveType::rectangle>{});
    if constexpr ((F & kBox) != 0) body(TypeTag<PrimitiveType::box>{});
    if constexpr ((F & kTriangle) != 0) body(TypeTag<PrimitiveType::triangle>{});
}

// The walk's view of a ray: origin and exact reciprocal direction (the node
// tests' slack assumes IEEE reciprocals, whatever the precision mode).
template <class T, Precision P>
inline bvh::RayView<T> ray_view(const Ray<T, P>& r) {
    return bvh::make_ray_view(r.o.x, r.o.y, r.o.z, r.d.x, r.d.y, r.d.z, r.tmin);
}


// Types whose tests take one ray against a leaf's run side by side in the
// lanes (test_run): the leaf kinds that are most of a large scene.
template <PrimitiveType Type>
inline constexpr bool kRunTested = Type == PrimitiveType::sphere || Type == PrimitiveType::triangle;

// No run tests: every leaf's primitives are tested against the packet.
struct NoRunTest {};

// Where a run test's lanes stand: lane j tests primitive k0 + j; lanes past
// the run's n primitives are off.
template <class T>
inline Mask<T> run_lanes(int n) {
    alignas(64) static constexpr float kIota[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
    return load<T>(kIota, 0) < T(float(n));
}

// A leaf's primitives of one type: indices k0 .. k0 + n - 1 within the
// type; a triangle run also has its block (TriangleRun), beside the leaf's
// parent node.
struct Run {
    int k0, n;
    TriangleRun tri;
};

// Three fields (f, f + 1, f + 2) of a triangle run's triangles j .. j +
// width - 1, in the lanes.
template <class T>
inline Vec3<T> load_run3(const TriangleRun& tri, int f, int j) {
    const float* at = tri.data + std::size_t(f) * std::size_t(tri.n) + std::size_t(j);
    return {load<T>(at, 0), load<T>(at + tri.n, 0), load<T>(at + 2 * tri.n, 0)};
}

// The boxes of a run's primitives j .. j + width - 1 (a kRunTested type), in
// the lanes, each at least the tree's box of that primitive (box_of in
// compile/primitive_bounds.cpp: the float data's box widened by 2^-20 of its
// size and position). These are widened by 2^-18 of the same, which covers
// that and the rounding of this float arithmetic (a few 2^-24).
template <PrimitiveType Type, class T>
OCTRAY_HOT void run_boxes(const SceneData& s, const Run& run, int j, T lo[3], T hi[3]) {
    if constexpr (Type == PrimitiveType::sphere) {
        const SphereArrays& a = s.spheres;
        const int k = run.k0 + j;
        const T c[3] = {load<T>(a.cx.data(), k), load<T>(a.cy.data(), k), load<T>(a.cz.data(), k)};
        const T r = load<T>(a.radius.data(), k);
        const T far = lane::max(lane::max(lane::abs(c[0]), lane::abs(c[1])), lane::abs(c[2]));
        const T half = r + (far + T(3) * r) * T(0x1p-18f);
        for (int i = 0; i < 3; ++i) lo[i] = c[i] - half, hi[i] = c[i] + half;
    } else {
        static_assert(Type == PrimitiveType::triangle, "run tests: spheres and triangles");
        (void)s;
        const Vec3<T> p = load_run3<T>(run.tri, kV0, j), q = load_run3<T>(run.tri, kV1, j),
                      w = load_run3<T>(run.tri, kV2, j);
        const T* v[3][3] = {{&p.x, &q.x, &w.x}, {&p.y, &q.y, &w.y}, {&p.z, &q.z, &w.z}};
        T size(0), far(0);
        for (int i = 0; i < 3; ++i) {
            lo[i] = lane::min(lane::min(*v[i][0], *v[i][1]), *v[i][2]), hi[i] = lane::max(lane::max(*v[i][0], *v[i][1]), *v[i][2]);
            size = lane::max(size, hi[i] - lo[i]);
            far = lane::max(far, lane::max(lane::abs(lo[i]), lane::abs(hi[i])));
        }
        const T e = (size + far) * T(0x1p-18f);
        for (int i = 0; i < 3; ++i) lo[i] = lo[i] - e, hi[i] = hi[i] + e;
    }
}

// A run of at least this many primitives reached by a hull walk's packet is
// culled against the hull first (run_boxes, bvh::hull_boxes).
inline constexpr int kHullCullRun = 2;

// Calls test(TypeTag<type>{}, k, run) for every primitive k (index within
// its type) of every leaf some valid lane of r may reach before its `limit`,
// run being the leaf's primitives of that type (Run): `closest` walks nearest
// first and re-reads limit (the caller's best t) after each leaf; otherwise
// (any hit) the walk re-reads `active` and ends when no lane is left. The box
// and triangle tests' per-ray setup is made the first time a leaf holds such
// a primitive: most packets of most scenes reach none.
// Where a packet's leaf is visited by one lane alone (bvh::LaneOf) and the
// type is kRunTested, test_run(TypeTag<type>{}, run, lane) tests that lane's
// ray against the run's primitives instead (SIMD lanes only).
template <bool Closest, unsigned F, class T, Precision P, class Test, class TestRun = NoRunTest>
OCTRAY_HOT void for_each_candidate(const SceneData& s, const Ray<T, P>& r, const Mask<T>& active, const T& limit,
                                   Test&& test, TestRun&& test_run = {}) {
    if constexpr (bounded_bits(F) != 0) {
        if (s.bvh.empty()) return;
        constexpr bool kRuns = lane::width<T> > 1 && std::is_same_v<lane::Scalar<T>, float> &&
                               !std::is_same_v<std::decay_t<TestRun>, NoRunTest>;
        bool slabs = false, shear = false;
        auto setup = [&](auto tag) OCTRAY_HOT_LAMBDA {
            constexpr PrimitiveType type = decltype(tag)::value;
            if constexpr (type == PrimitiveType::box)
                if (!slabs) make_slabs(r), slabs = true;
            if constexpr (type == PrimitiveType::triangle)
                if (!shear) make_shear(r), shear = true;
        };
        // body(tag, run) for each type's run of leaf l, after its setup.
        auto each_run = [&](const bvh::Leaf& l, auto&& body) OCTRAY_HOT_LAMBDA {
            for_each_bounded_type<F>([&](auto tag) OCTRAY_HOT_LAMBDA {
                constexpr PrimitiveType type = decltype(tag)::value;
                const int n = l.count[int(type)];
                if (n == 0) return;
                setup(tag);
                Run run{int(l.begin[int(type)]), n, {nullptr, 0}};
                if constexpr (type == PrimitiveType::triangle) run.tri = triangle_run(s, l.block);
                body(tag, run);
            });
        };
        auto test_each = [&](auto tag, const Run& run) OCTRAY_HOT_LAMBDA {
            for (int k = run.k0; k < run.k0 + run.n; ++k) test(tag, k, run);
        };
        auto packet_leaf = [&](const bvh::Leaf& l, const Mask<T>&) OCTRAY_HOT_LAMBDA { each_run(l, test_each); };
        auto lane_leaf = [&](const bvh::Leaf& l, bvh::LaneOf one) OCTRAY_HOT_LAMBDA {
            each_run(l, [&](auto tag, const Run& run) OCTRAY_HOT_LAMBDA {
                if constexpr (kRuns && kRunTested<decltype(tag)::value>) test_run(tag, run, one.lane);
                else test_each(tag, run);
            });
        };
        // A hull walk's packet: the primitives of a run whose boxes the
        // packet's hull misses are not tested (most of a leaf, for a packet
        // of neighbouring camera rays), the rest in the same order as
        // packet_leaf's.
        auto hull_leaf = [&](const bvh::Leaf& l, const Mask<T>&, const bvh::InHull& in) OCTRAY_HOT_LAMBDA {
            each_run(l, [&](auto tag, const Run& run) OCTRAY_HOT_LAMBDA {
                constexpr PrimitiveType type = decltype(tag)::value;
                if constexpr (kRuns && kRunTested<type>) {
                    if (run.n >= kHullCullRun) {
                        for (int j = 0; j < run.n; j += lane::width<T>) {
                            T lo[3], hi[3];
                            run_boxes<type>(s, run, j, lo, hi);
                            unsigned bits = bvh::hull_boxes(in.hull, in.limit, lo, hi) & lane::bits(run_lanes<T>(run.n - j));
                            for (; bits != 0; bits &= bits - 1) test(tag, run.k0 + j + __builtin_ctz(bits), run);
                        }
                        return;
                    }
                }
                test_each(tag, run);
            });
        };
        auto walk = [&](auto&& leaf) OCTRAY_HOT_LAMBDA {
            if (s.bvh.primitive_count() <= kTestAllPrimitives) {
                // A leaf's worth of primitives (aobench's three spheres, a
                // small scene): every leaf, no walk. Testing them all costs
                // about the root's node test, and needs no ray view (three
                // divides).
                for (const bvh::Leaf& l : s.bvh.leaves) {
                    packet_leaf(l, active);
                    if (!Closest && !lane::any(active)) return;
                }
            } else if constexpr (Closest) {
                bvh::traverse_closest(s.bvh, ray_view(r), active, limit, leaf);
            } else {
                bvh::traverse_any(s.bvh, ray_view(r), active, limit, leaf);
            }
        };
        if constexpr (kRuns) walk(Overloaded{packet_leaf, lane_leaf, hull_leaf});
        else walk(packet_leaf);
    }
}

}  // namespace octray::kernels::OCTRAY_ISA
