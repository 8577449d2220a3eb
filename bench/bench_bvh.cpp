// bench/bench_bvh.cpp — the 8-wide BVH (kernels/bvh/node.hpp): build time and
// size, and closest-hit walks (kernels/bvh/traverse.hpp) for choosing the
// builder's leaf size and costs and the walk's packet options.
//
//   bvh_build/<input>/<n>/threads:<t>  build_bvh8 on n random boxes or on the
//       n triangles of a tessellated sphere; counters: bytes_per_prim
//       (Bvh8::bytes() / n), nodes, leaves, depth, sah (sah_cost, default
//       costs), items_per_second = primitives built per second (wall time).
//   bvh_walk/<rays>/<lanes>/...  closest hit over the sphere's 262k
//       triangle boxes (each leaf primitive slab-tested on every lane, as a
//       stand-in for a primitive test), 256x256 camera rays (coherent: 4x2
//       pixel packets) or random chords (incoherent); items_per_second = rays/s.
//
// Compiled with -mavx2 -mfma (8-float node batches and packets), like
// octray_bench_variants: it runs only on such CPUs.
#include "kernels/bvh/node.hpp"
#include "kernels/bvh/traverse.hpp"

#include <octray/constants.hpp>

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <tuple>
#include <vector>

namespace {

using namespace octray;
using bvh::Box;

// ---- inputs --------------------------------------------------------------------
std::uint32_t lcg(std::uint32_t& s) { return (s = s * 1664525u + 1013904223u) >> 8; }
float uniform(std::uint32_t& s) { return float(lcg(s)) * 0x1p-24f; }

// n boxes in the unit cube, edges up to 0.01 (about 1M of them fill it sparsely).
bvh::BuildInput random_boxes(std::size_t n) {
    std::uint32_t s = 12345u;
    bvh::BuildInput in;
    in.boxes.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        Box b;
        for (int a = 0; a < 3; ++a) {
            b.lo[a] = uniform(s);
            b.hi[a] = b.lo[a] + 0.01f * uniform(s);
        }
        in.boxes.push_back(b);
    }
    return in;
}

// The triangles of a UV sphere of radius 1 with `rings` x 2 rings segments:
// 4 rings^2 - 4 rings... about 4 rings^2 triangles (the poles' fans have one
// a quad), as boxes.
bvh::BuildInput sphere_triangles(int rings) {
    const int segments = 2 * rings;
    auto vertex = [&](int ring, int seg, float v[3]) {
        const double theta = kPi * ring / rings, phi = 2 * kPi * seg / segments;
        v[0] = float(std::sin(theta) * std::cos(phi));
        v[1] = float(std::cos(theta));
        v[2] = float(std::sin(theta) * std::sin(phi));
    };
    bvh::BuildInput in;
    auto add = [&](const float* a, const float* b, const float* c) {
        Box box = Box::empty();
        box.extend(a), box.extend(b), box.extend(c);
        in.boxes.push_back(box);
    };
    for (int r = 0; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            float p00[3], p01[3], p10[3], p11[3];
            vertex(r, s, p00), vertex(r, s + 1, p01), vertex(r + 1, s, p10), vertex(r + 1, s + 1, p11);
            if (r > 0) add(p00, p01, p11);
            if (r + 1 < rings) add(p00, p11, p10);
        }
    return in;
}

// Rings for about n triangles.
int rings_for(std::size_t n) { return int(std::lround(std::sqrt(double(n) / 4.0))); }

const bvh::BuildInput& input(int kind, std::size_t n) {
    static std::map<std::pair<int, std::size_t>, std::unique_ptr<bvh::BuildInput>> cache;
    auto& slot = cache[{kind, n}];
    if (!slot) slot = std::make_unique<bvh::BuildInput>(kind == 0 ? random_boxes(n) : sphere_triangles(rings_for(n)));
    return *slot;
}

// ---- build ---------------------------------------------------------------------
void bvh_build(benchmark::State& state) {
    const int kind = int(state.range(0));
    const bvh::BuildInput& in = input(kind, std::size_t(state.range(1)));
    bvh::BuildOptions opt;
    opt.threads = int(state.range(2));
    bvh::Bvh8 tree;
    for (auto _ : state) {
        tree = bvh::build_bvh8(in, opt);
        benchmark::DoNotOptimize(tree.nodes.data());
    }
    const double n = double(in.boxes.size());
    state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(n));
    state.counters["prims"] = n;
    state.counters["bytes_per_prim"] = double(tree.bytes()) / n;
    state.counters["nodes"] = double(tree.nodes.size());
    state.counters["leaves"] = double(tree.leaves.size());
    state.counters["depth"] = tree.depth;
    state.counters["sah"] = bvh::sah_cost(tree, opt);
}

// ---- walks ---------------------------------------------------------------------
using Floats8 = xsimd::batch<float, xsimd::fma3<xsimd::avx2>>;

// The sphere's triangle boxes built with given options, reordered by the
// tree's permutation into SoA arrays (as a caller's primitive arrays).
struct WalkScene {
    bvh::Bvh8 tree;
    std::vector<float> lo[3], hi[3];
};

const WalkScene& walk_scene(int max_leaf, int traversal_cost) {
    static std::map<std::pair<int, int>, std::unique_ptr<WalkScene>> cache;
    auto& slot = cache[{max_leaf, traversal_cost}];
    if (!slot) {
        const bvh::BuildInput& in = input(1, std::size_t(1) << 18);
        bvh::BuildOptions opt;
        opt.max_leaf_size = max_leaf;
        opt.traversal_cost = float(traversal_cost);
        slot = std::make_unique<WalkScene>();
        slot->tree = bvh::build_bvh8(in, opt);
        for (std::uint32_t i : slot->tree.order[0])
            for (int a = 0; a < 3; ++a) {
                slot->lo[a].push_back(in.boxes[i].lo[a]);
                slot->hi[a].push_back(in.boxes[i].hi[a]);
            }
    }
    return *slot;
}

// Rays in packets of 8: origin, direction, by lane.
struct Rays {
    std::vector<float> o[3], d[3];
    std::size_t count() const { return o[0].size(); }
};

// coherent: a pinhole camera at (0, 0.3, 3) looking at the origin, fov 40,
// 256 x 256, each packet a 4 x 2 pixel tile; incoherent: chords between two
// random points of the sphere of radius 1.2.
const Rays& rays(bool coherent) {
    static std::unique_ptr<Rays> cache[2];
    auto& slot = cache[coherent ? 1 : 0];
    if (slot) return *slot;
    slot = std::make_unique<Rays>();
    Rays& r = *slot;
    auto add = [&](const float o[3], const float d[3]) {
        for (int a = 0; a < 3; ++a) r.o[a].push_back(o[a]), r.d[a].push_back(d[a]);
    };
    const int size = 256;
    if (coherent) {
        const float eye[3] = {0.0f, 0.3f, 3.0f};
        const float t = std::tan(20.0f * float(kPi) / 180.0f);
        for (int ty = 0; ty < size; ty += 2)
            for (int tx = 0; tx < size; tx += 4)
                for (int k = 0; k < 8; ++k) {
                    const int x = tx + k % 4, y = ty + k / 4;
                    const float sx = (2.0f * (float(x) + 0.5f) / size - 1.0f) * t;
                    const float sy = (1.0f - 2.0f * (float(y) + 0.5f) / size) * t;
                    const float d[3] = {sx, sy - 0.1f, -1.0f};
                    add(eye, d);
                }
    } else {
        std::uint32_t s = 777u;
        auto point = [&](float p[3]) {
            float len2;
            do {
                for (int a = 0; a < 3; ++a) p[a] = 2.0f * uniform(s) - 1.0f;
                len2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
            } while (len2 > 1.0f || len2 < 0.01f);
            const float k = 1.2f / std::sqrt(len2);
            for (int a = 0; a < 3; ++a) p[a] *= k;
        };
        for (int i = 0; i < size * size; ++i) {
            float a[3], b[3];
            point(a), point(b);
            const float d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
            add(a, d);
        }
    }
    return r;
}

template <class T>
T load(const std::vector<float>& v, std::size_t i) {
    if constexpr (std::is_same_v<T, float>) return v[i];
    else return T::load_unaligned(v.data() + i);
}

// Closest hit of every ray; the leaf function slab-tests its boxes on every lane.
template <class T>
void bvh_walk(benchmark::State& state, bool coherent, int max_leaf, int traversal_cost, bvh::WalkOptions opt) {
    const WalkScene& scene = walk_scene(max_leaf, traversal_cost);
    const Rays& r = rays(coherent);
    constexpr std::size_t W = std::size_t(lane::width<T>);
    const float inf = INFINITY;
    std::int64_t hits = 0;
    for (auto _ : state) {
        hits = 0;
        for (std::size_t i = 0; i < r.count(); i += W) {
            const T ox = load<T>(r.o[0], i), oy = load<T>(r.o[1], i), oz = load<T>(r.o[2], i);
            const auto view = bvh::make_ray_view(ox, oy, oz, load<T>(r.d[0], i), load<T>(r.d[1], i),
                                                 load<T>(r.d[2], i), T(0.0f));
            T tbest(inf);
            const lane::Mask<T> active = T(0.0f) == T(0.0f);
            bvh::traverse_closest(
                scene.tree, view, active, tbest,
                [&](const bvh::Leaf& leaf, const lane::Mask<T>&) {
                    for (std::uint32_t k = leaf.begin[0]; k < leaf.begin[0] + leaf.count[0]; ++k) {
                        T enter = view.tmin, leave = tbest;
                        auto slab = [&](int a, const T& o, const T& inv) {
                            const T t1 = (T(scene.lo[a][k]) - o) * inv, t2 = (T(scene.hi[a][k]) - o) * inv;
                            enter = lane::max(lane::min(t1, t2), enter);
                            leave = lane::min(lane::max(t1, t2), leave);
                        };
                        slab(0, ox, view.inv_dx), slab(1, oy, view.inv_dy), slab(2, oz, view.inv_dz);
                        tbest = lane::select(enter <= leave && enter < tbest, enter, tbest);
                    }
                },
                opt);
            hits += lane::count(tbest < T(inf));
        }
        benchmark::DoNotOptimize(hits);
    }
    state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(r.count()));
    state.counters["hit_frac"] = double(hits) / double(r.count());
    state.counters["bytes_per_prim"] = double(scene.tree.bytes()) / double(scene.lo[0].size());
}

void register_all() {
    for (const int kind : {0, 1})
        for (const std::int64_t n : {std::int64_t(1) << 16, std::int64_t(1) << 18, std::int64_t(1) << 20})
            for (const int threads : {1, 2})
                benchmark::RegisterBenchmark(
                    (std::string("bvh_build/") + (kind == 0 ? "random_boxes" : "sphere_triangles")).c_str(), bvh_build)
                    ->Args({kind, n, threads})
                    ->ArgNames({"", "n", "threads"})
                    ->Unit(benchmark::kMillisecond)
                    ->UseRealTime();
    for (const bool coherent : {true, false}) {
        const std::string rays_name = coherent ? "camera" : "random";
        // Leaf size and SAH traversal cost: single rays and packets.
        for (const int max_leaf : {1, 2, 4, 8})
            for (const int tc : {1, 2, 4}) {
                const std::string suffix = "/leaf:" + std::to_string(max_leaf) + "/tcost:" + std::to_string(tc);
                benchmark::RegisterBenchmark(("bvh_walk/" + rays_name + "/1lane" + suffix).c_str(),
                                             [=](benchmark::State& s) { bvh_walk<float>(s, coherent, max_leaf, tc, {}); })
                    ->Unit(benchmark::kMillisecond);
                benchmark::RegisterBenchmark(("bvh_walk/" + rays_name + "/8lanes" + suffix).c_str(),
                                             [=](benchmark::State& s) { bvh_walk<Floats8>(s, coherent, max_leaf, tc, {}); })
                    ->Unit(benchmark::kMillisecond);
            }
        // Packet options at the default build.
        struct Variant {
            int single;
            bool order, split;
        };
        for (const Variant v : {Variant{0, true, true}, Variant{1, true, true}, Variant{2, true, true},
                                Variant{3, true, true}, Variant{4, true, true}, Variant{8, true, true},
                                Variant{0, true, false}, Variant{2, true, false}, Variant{4, true, false},
                                Variant{2, false, true}}) {
            bvh::WalkOptions opt;
            opt.single_ray_lanes = v.single;
            opt.order_packet_children = v.order;
            opt.split_octants = v.split;
            const std::string name = "bvh_walk/" + rays_name + "/8lanes/single_ray_lanes:" + std::to_string(v.single) +
                                     (v.order ? "/ordered" : "/slot_order") + (v.split ? "/octants" : "/whole");
            benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& s) {
                const bvh::BuildOptions defaults;
                bvh_walk<Floats8>(s, coherent, defaults.max_leaf_size, int(defaults.traversal_cost), opt);
            })->Unit(benchmark::kMillisecond);
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    register_all();
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
