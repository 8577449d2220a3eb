// bench/bench_scale.cpp — the cost curve against Embree 3 (docs/performance.md): octray's
// SIMD and scalar paths and Embree's rtcIntersect8/rtcOccluded8 and
// rtcIntersect1/rtcOccluded1 on the same geometry and exactly the same rays,
// from 16 to a million primitives. Scenes and rays: scale_common.hpp.
//
// Names:
//   scale/SCENE/RAYS/QUERY/VARIANT
//     SCENE    spheres:16 .. spheres:1M, heightfield:1k .. heightfield:1M, model
//     RAYS     camera (coherent, 8 pixels of a row a packet, 256 x 256) or
//              incoherent (cosine-weighted bounces off the camera hits, 8 a
//              packet in pixel order, tmax = scene size)
//     QUERY    closest (intersect) or any (occluded)
//     VARIANT  octray_simd, octray_scalar; embree8, embree1 (meshes);
//              embree8_native, embree8_user, embree1_native, embree1_user (spheres)
//     counters: items_per_second (rays/s), primitives, xcheck_match (fraction
//     of active rays whose answer equals octray_simd's: primitive id for
//     closest, blocked or not for any; the agreement test holds the rule)
//   scale_build/SCENE/VARIANT    VARIANT octray (compile(): validation, SoA,
//     BVH build), embree_high, embree_medium (rtcCommitScene alone, native
//     spheres); manual time; counters bytes_per_primitive (octray: BVH + every
//     per-primitive array; Embree: its device memory monitor's net bytes after
//     the commit, geometry buffers included), primitives.
// One thread: Embree device threads=1; run pinned (taskset -c 1: OpenMP then
// builds octray's BVH on one thread too). Each scene, its rays and Embree's
// scenes are made once, on the first benchmark that needs them.
#include "bench_common.hpp"
#include "scale_common.hpp"

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace octray::bench {
namespace {

using namespace octray::scale;
constexpr int kImage = 256;

struct SceneCase {
    const char* name;
    Family family;
    int n;
};
constexpr SceneCase kScenes[] = {
    {"spheres:16", Family::spheres, 16},           {"spheres:256", Family::spheres, 256},
    {"spheres:4k", Family::spheres, 4096},         {"spheres:64k", Family::spheres, 65536},
    {"spheres:1M", Family::spheres, 1 << 20},      {"heightfield:1k", Family::heightfield, 1 << 10},
    {"heightfield:16k", Family::heightfield, 1 << 14}, {"heightfield:256k", Family::heightfield, 1 << 18},
    {"heightfield:1M", Family::heightfield, 1 << 20},  {"model", Family::model, 0},
};

struct Variant {
    const char* name;
    Engine engine;
    bool user;
};
constexpr Variant kMeshVariants[] = {{"octray_simd", Engine::octray_simd, false},
                                     {"octray_scalar", Engine::octray_scalar, false},
                                     {"embree8", Engine::embree8, false},
                                     {"embree1", Engine::embree1, false}};
constexpr Variant kSphereVariants[] = {{"octray_simd", Engine::octray_simd, false},
                                       {"octray_scalar", Engine::octray_scalar, false},
                                       {"embree8_native", Engine::embree8, false},
                                       {"embree8_user", Engine::embree8, true},
                                       {"embree1_native", Engine::embree1, false},
                                       {"embree1_user", Engine::embree1, true}};

double match_fraction(World& w, const Rays& r, const Variant& v, bool any) {
    std::int64_t same = 0;
    if (any) {
        const std::vector<int> ref = occluded(w, r, Engine::octray_simd, false), got = occluded(w, r, v.engine, v.user);
        for (std::size_t l = 0; l < ref.size(); ++l) same += ref[l] >= 0 && ref[l] == got[l];
    } else {
        const Answers ref = closest(w, r, Engine::octray_simd, false), got = closest(w, r, v.engine, v.user);
        for (std::size_t l = 0; l < ref.prim.size(); ++l) same += r.pixel[l] >= 0 && ref.prim[l] == got.prim[l];
    }
    return r.active ? double(same) / double(r.active) : 0.0;
}

void bm_trace(benchmark::State& st, SceneCase c, bool incoherent, bool any, Variant v) {
    World& w = world(c.family, c.n, kImage);
    const Rays& r = incoherent ? w.incoherent : w.camera;
    Work work = make_work(r);
    st.counters["primitives"] = w.primitives;
    st.counters["xcheck_match"] = match_fraction(w, r, v, any);
    if (v.engine == Engine::octray_simd || v.engine == Engine::octray_scalar) {
        const Kernel k = select_kernel(w.scene, v.engine == Engine::octray_simd ? Path::simd : Path::scalar);
        for (auto _ : st) {
            pass_octray(k, w.scene, r, work, any);
            benchmark::ClobberMemory();
        }
        st.SetLabel(k.name());
    } else {
        RTCScene s = embree_scene(w, v.user);
        if (!s) {
            st.SkipWithError("Embree scene could not be created");
            return;
        }
        for (auto _ : st) {
            if (v.engine == Engine::embree8) pass_embree8(s, r, work, any, !incoherent);
            else pass_embree1(s, r, work, any, !incoherent);
            benchmark::ClobberMemory();
        }
        st.SetLabel(std::string("embree ") + RTC_VERSION_STRING);
    }
    set_ray_counters(st, r.active, 0);
    for (const char* k : {"GFLOPS", "frac_peak", "flops_per_ray"}) st.counters.erase(k);
}

void bm_build(benchmark::State& st, SceneCase c, int which) {
    using clock = std::chrono::steady_clock;
    World& w = world(c.family, c.n, kImage);
    double bytes = 0;
    for (auto _ : st) {
        if (which == 0) {
            const auto t0 = clock::now();
            PacketScene s = compile(w.authored, compile_options());
            st.SetIterationTime(std::chrono::duration<double>(clock::now() - t0).count());
            bytes = double(octray_bytes(s));
        } else {
            const std::int64_t before = embree_bytes_now();
            double commit = 0;
            RTCScene s = build_embree(w, false, which == 1 ? RTC_BUILD_QUALITY_HIGH : RTC_BUILD_QUALITY_MEDIUM, &commit);
            if (!s) {
                st.SkipWithError("Embree scene could not be created");
                return;
            }
            st.SetIterationTime(commit);
            bytes = double(embree_bytes_now() - before);
            rtcReleaseScene(s);
        }
    }
    st.counters["primitives"] = w.primitives;
    st.counters["bytes_per_primitive"] = bytes / w.primitives;
}

void register_all() {
    for (const SceneCase& c : kScenes) {
        const bool big = c.n >= (1 << 18);
        const char* builds[] = {"octray", "embree_high", "embree_medium"};
        for (int b = 0; b < 3; ++b) {
            auto* bm = benchmark::RegisterBenchmark((std::string("scale_build/") + c.name + "/" + builds[b]).c_str(),
                                                    [c, b](benchmark::State& st) { bm_build(st, c, b); });
            bm->UseManualTime()->Unit(benchmark::kMillisecond);
            if (big) bm->Iterations(1);
        }
    }
    for (const SceneCase& c : kScenes)
        for (const char* rays : {"camera", "incoherent"})
            for (const char* query : {"closest", "any"}) {
                const bool incoherent = std::strcmp(rays, "incoherent") == 0, any = std::strcmp(query, "any") == 0;
                auto add = [&](const Variant& v) {
                    const std::string name = std::string("scale/") + c.name + "/" + rays + "/" + query + "/" + v.name;
                    auto* bm = benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& st) { bm_trace(st, c, incoherent, any, v); });
                    bm->Unit(benchmark::kMillisecond);
                };
                if (c.family == Family::spheres)
                    for (const Variant& v : kSphereVariants) add(v);
                else
                    for (const Variant& v : kMeshVariants) add(v);
            }
    benchmark::AddCustomContext("embree_version", RTC_VERSION_STRING);
    benchmark::AddCustomContext("scale_model", model_path());
}

}  // namespace
}  // namespace octray::bench

// OCTRAY_SCALE_LEAF, OCTRAY_SCALE_ICOST, OCTRAY_SCALE_TCOST, OCTRAY_SCALE_BLOCK:
// compile()'s BVH max_leaf_size, intersection_cost, traversal_cost and leaf_block for this run (the
// sweep of docs/history/performance-2026.md; scale_common.hpp, compile_options); unset: the
// library's own. (The walk's single_ray_lanes and octant split were swept the
// same way while the walk was tuned: docs/history/performance-2026.md, tuning the traversal.)
int main(int argc, char** argv) {
    const octray::CompileOptions o = octray::scale::compile_options();
    benchmark::AddCustomContext("bvh_options", "leaf " + std::to_string(o.sah.max_leaf_size) + ", intersection cost " +
                                                   std::to_string(o.sah.intersection_cost) + ", traversal cost " +
                                                   std::to_string(o.sah.traversal_cost) + ", leaf block " +
                                                   std::to_string(o.sah.leaf_block));
    return octray::bench::run_main(argc, argv, octray::bench::register_all);
}
