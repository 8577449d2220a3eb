// bench/bench_stages.cpp — octray per stage and end to end, scalar path against
// SIMD path on the same data, plus this core's FMA peak.
//
// Names are STAGE/CASE/PATH (PATH = scalar | simd), so a SIMD/scalar ratio is
// the ratio of two rows of one run:
//   camera/{pinhole,orthographic}/PATH           128x128 image per iteration
//   intersect/TYPE:N/PATH                        one type, N = 1, 16, 256
//   intersect/sphere:256_all_tests/PATH          256 spheres, cluster culling off
//   intersect/sphere:256_full_tests/PATH         256 nested spheres, culling off,
//                                                every test runs in full (no exit)
//   intersect/mixed:N/PATH                       six types cycled, N = 1..256
//   shade/LIGHTS/PATH                            per light type, 1..64 lights
//   shade/default/PATH                           scenes/default.json's lights and hits
//   tonemap/MODE/PATH                            per tone-map mode (+ gamma 2.2)
//   e2e/default/render_rows/PATH                 render_rows(): camera, intersect,
//                                                shade, tone map, image writes
//   e2e/default/pipeline/PATH                    the four kernels per packet, no image
//   e2e/default/render_rows_{fast,approx}/PATH   other precision modes
//   {e2e/default/render_rows,shade/default,intersect/sphere:256_full_tests}_avx2/PATH
//                                                the same on the AVX2 unit, where the
//                                                CPU also runs the (preferred) AVX-512 one
//   fma_peak/8lanes/chains:C                     sustained FP32 FMA throughput
//   divider/{div,sqrt}/{8lanes,1lane}            divide / sqrt unit throughput, lane
//                                                results per second (vdivps ymm vs divss)
// Every benchmark (except fma_peak) reports items_per_second = rays/s,
// ns_per_ray, flops_per_ray, GFLOPS and frac_peak (bench_common.hpp).
#include "bench_common.hpp"

#include "kernels/scene_data.hpp"

#include <scene_loader.hpp>

#include <octray/render.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>

namespace octray::bench {
namespace {

constexpr int kImage = 128;  // stage benchmarks: 128 x 128 = 16384 rays, 2048 packets
constexpr Path kPaths[] = {Path::scalar, Path::simd};

// ---- fixtures (built on first use, outside the timed loop, then cached) -------
struct Fixture {
    Scene authored;                    // what `scene` was compiled from
    PacketScene scene;
    RaySet rays;
    AlignedVec<HitPacket8> hits;       // SIMD path's hits (bit-identical to scalar's)
    AlignedVec<ColorPacket8> radiance; // tone-map input
    std::string error;                 // set when the fixture could not be built
};

const Fixture& cached(const std::string& key, const std::function<void(Fixture&)>& build) {
    static std::map<std::string, std::unique_ptr<Fixture>> cache;
    auto it = cache.find(key);
    if (it == cache.end()) {
        auto f = std::make_unique<Fixture>();
        try {
            build(*f);
        } catch (const std::exception& e) {
            f->error = e.what();
        }
        it = cache.emplace(key, std::move(f)).first;
    }
    return *it->second;
}

void prepare(Fixture& f, const Scene& scene) {
    f.authored = scene;
    f.scene = compile(scene);
    f.rays = camera_rays(f.scene);
    f.hits = trace(select_kernel(f.scene, Path::simd), f.scene, f.rays);
}

const Fixture& default_fixture() {
    return cached("default", [](Fixture& f) {
        f.authored = load_scene(default_scene_path());
        f.scene = compile(f.authored);
    });
}

bool check(benchmark::State& st, const Fixture& f) {
    if (f.error.empty()) return true;
    st.SkipWithError(f.error.c_str());
    return false;
}

// ---- camera -----------------------------------------------------------------
void bm_camera(benchmark::State& st, bool ortho, Path path) {
    const Fixture& f = cached(ortho ? "camera/ortho" : "camera/pinhole", [&](Fixture& fx) {
        Scene s = grid_scene(Layout::sphere, 1, false, kImage, kImage);
        if (ortho) s.camera.type = CameraType::orthographic, s.camera.height_world = 4;
        fx.scene = compile(s);
    });
    if (!check(st, f)) return;
    const Kernel k = select_kernel(f.scene, path);
    RayPacket8 rays;
    for (auto _ : st) {
        for (int y = 0; y < kImage; ++y)
            for (int x0 = 0; x0 < kImage; x0 += kPacketWidth) {
                k.camera(f.scene, x0, y, rays);
                benchmark::DoNotOptimize(rays);
            }
    }
    st.SetLabel(k.name());
    set_ray_counters(st, std::int64_t(kImage) * kImage, camera_flops_per_ray(ortho));
}

// ---- intersect --------------------------------------------------------------
void bm_intersect(benchmark::State& st, Layout layout, int n, Path path) {
    const std::string key = std::string("intersect/") + layout_name(layout) + ":" + std::to_string(n);
    const Fixture& f = cached(key, [&](Fixture& fx) { prepare(fx, grid_scene(layout, n, false, kImage, kImage)); });
    if (!check(st, f)) return;
    time_intersect(st, select_kernel(f.scene, path), f.scene, f.rays);
    st.counters["hit_frac"] = hit_fraction(f.rays, f.hits);
}

// Intersect with culling switched off (CompileOptions::Acceleration::none:
// every packet tests every primitive): the kernel's raw test throughput.
void time_unculled(benchmark::State& st, const Fixture& f, Path path, Isa isa = Isa::best) {
    if (!check(st, f)) return;
    CompileOptions flat;
    flat.acceleration = CompileOptions::Acceleration::none;
    const PacketScene all = compile(f.authored, flat);
    time_intersect(st, select_kernel(all, path, Precision::exact, isa), all, f.rays);
    st.counters["hit_frac"] = hit_fraction(f.rays, f.hits);
}

// The grid scene unculled. Most packets leave most sphere tests at the miss
// exit, so the FLOP count per ray (every test in full) is an upper bound here.
void bm_intersect_all_tests(benchmark::State& st, Layout layout, int n, Path path) {
    const std::string key = std::string("intersect/") + layout_name(layout) + ":" + std::to_string(n);
    time_unculled(st, cached(key, [&](Fixture& fx) { prepare(fx, grid_scene(layout, n, false, kImage, kImage)); }), path);
}

// Nested spheres unculled: every test runs in full, so the FLOP count per ray
// is the work done (intersect_fraction_of_peak is measured here).
void bm_intersect_full_tests(benchmark::State& st, int n, Path path, Isa isa) {
    time_unculled(st, cached("intersect/nested_spheres:" + std::to_string(n),
                             [&](Fixture& fx) { prepare(fx, nested_spheres_scene(n, kImage, kImage)); }),
                  path, isa);
}

// ---- shade ------------------------------------------------------------------
// The geometry: 16 spheres on a floor plane, every ray hits something.
struct LightSpec {
    std::string name;
    bool ambient = false;
    int directional = 0, point = 0;
    Attenuation attenuation = Attenuation::none;
    bool shadows = false;
};

Scene shade_scene(const LightSpec& spec) {
    Scene s = grid_scene(Layout::sphere, 16, true, kImage, kImage);
    if (!spec.ambient) s.ambient.reset();
    s.directional_lights.clear();
    constexpr double kTwoPi = 6.283185307179586;
    for (int i = 0; i < spec.directional; ++i) {
        const double a = kTwoPi * (i + 0.5) / spec.directional;
        const Vec3d d{std::cos(a), 1.5, std::sin(a)};
        s.directional_lights.push_back(
            DirectionalLight{d * (1.0 / std::sqrt(dot(d, d))), {1, 0.95, 0.9}, 2.0 / spec.directional, spec.shadows});
    }
    for (int i = 0; i < spec.point; ++i) {
        const double a = kTwoPi * (i + 0.25) / spec.point;
        const double ls = spec.attenuation == Attenuation::none ? 2.0 / spec.point : 80.0 / spec.point;
        s.point_lights.push_back(PointLight{{8 * std::cos(a), 6, 8 * std::sin(a)}, {0.9, 0.95, 1}, ls, spec.attenuation, spec.shadows});
    }
    return s;
}

void bm_shade(benchmark::State& st, const LightSpec& spec, Path path, Isa isa = Isa::best) {
    const Fixture& f = spec.name == "default"
                           ? cached("shade/default",
                                    [](Fixture& fx) {
                                        Scene s = load_scene(default_scene_path());
                                        fx.scene = compile(s);
                                        fx.rays = camera_rays(fx.scene);
                                        fx.hits = trace(select_kernel(fx.scene, Path::simd), fx.scene, fx.rays);
                                    })
                           : cached("shade/" + spec.name, [&](Fixture& fx) { prepare(fx, shade_scene(spec)); });
    if (!check(st, f)) return;
    const Kernel k = select_kernel(f.scene, path, Precision::exact, isa);
    ColorPacket8 out;
    const std::size_t n = f.rays.packets.size();
    for (auto _ : st) {
        for (std::size_t p = 0; p < n; ++p) {
            k.shade(f.scene, f.rays.packets[p], f.hits[p], out);
            benchmark::DoNotOptimize(out);
        }
    }
    st.SetLabel(k.name());
    st.counters["hit_frac"] = hit_fraction(f.rays, f.hits);
    set_ray_counters(st, f.rays.rays(), shade_flops_per_ray(f.scene));
}

// ---- tone map ---------------------------------------------------------------
// Input: the HDR radiance of shade/directional:4 times 3 (a third of the
// pixels exceed 1 in some channel), so every branch of every mode runs.
void bm_tonemap(benchmark::State& st, ToneMap mode, float gamma, Path path) {
    const Fixture& f = cached("tonemap", [](Fixture& fx) {
        LightSpec spec{"directional:4", true, 4};
        prepare(fx, shade_scene(spec));
        const Kernel k = select_kernel(fx.scene, Path::simd);
        fx.radiance.resize(fx.rays.packets.size());
        for (std::size_t p = 0; p < fx.rays.packets.size(); ++p) {
            k.shade(fx.scene, fx.rays.packets[p], fx.hits[p], fx.radiance[p]);
            for (int i = 0; i < kPacketWidth; ++i) {
                fx.radiance[p].r[i] *= 3, fx.radiance[p].g[i] *= 3, fx.radiance[p].b[i] *= 3;
            }
        }
    });
    if (!check(st, f)) return;
    Scene authored = f.authored;  // the same scene; only the tone-map settings differ
    authored.render.tonemap = mode;
    authored.render.gamma = gamma;
    const PacketScene scene = compile(authored);
    const Kernel k = select_kernel(scene, path);
    ColorPacket8 out;
    for (auto _ : st) {
        for (const ColorPacket8& c : f.radiance) {
            k.tonemap(scene, c, out);
            benchmark::DoNotOptimize(out);
        }
    }
    st.SetLabel(k.name());
    set_ray_counters(st, std::int64_t(f.radiance.size()) * kPacketWidth, tonemap_flops_per_ray(mode, gamma != 1.0f));
}

// ---- end to end on scenes/default.json -----------------------------------------
double e2e_flops(const PacketScene& scene) {
    const SceneData& s = scene_data(scene);
    return camera_flops_per_ray(s.camera.orthographic) + intersect_flops_per_ray(scene) + shade_flops_per_ray(scene) +
           tonemap_flops_per_ray(s.tonemap, s.inv_gamma != 1.0f);
}

void bm_render_rows(benchmark::State& st, Precision precision, Path path, Isa isa = Isa::best) {
    const Fixture& f = default_fixture();
    if (!check(st, f)) return;
    const Kernel k = select_kernel(f.scene, path, precision, isa);
    const int w = f.scene.width(), h = f.scene.height();
    Image<float> hdr(w, h), display(w, h);
    for (auto _ : st) {
        render_rows(k, f.scene, 0, h, hdr, &display);
        benchmark::DoNotOptimize(display.rgb.data());
        benchmark::ClobberMemory();
    }
    st.SetLabel(k.name());
    set_ray_counters(st, std::int64_t(w) * h, e2e_flops(f.scene));
}

void bm_pipeline(benchmark::State& st, Path path) {
    const Fixture& f = default_fixture();
    if (!check(st, f)) return;
    const Kernel k = select_kernel(f.scene, path);
    const int w = f.scene.width(), h = f.scene.height();
    RayPacket8 rays;
    HitPacket8 hits;
    ColorPacket8 radiance, shown;
    for (auto _ : st) {
        for (int y = 0; y < h; ++y)
            for (int x0 = 0; x0 < w; x0 += kPacketWidth) {
                k.camera(f.scene, x0, y, rays);
                k.intersect(f.scene, rays, hits);
                k.shade(f.scene, rays, hits, radiance);
                k.tonemap(f.scene, radiance, shown);
                benchmark::DoNotOptimize(shown);
            }
    }
    st.SetLabel(k.name());
    set_ray_counters(st, std::int64_t(w) * h, e2e_flops(f.scene));
}

// ---- peak -------------------------------------------------------------------
void bm_fma_peak(benchmark::State& st, int chains) {
    if (!simd_supported()) {
        st.SkipWithError("this CPU lacks AVX2+FMA");
        return;
    }
    constexpr std::int64_t kReps = 1 << 16;
    for (auto _ : st) benchmark::DoNotOptimize(fma_chains(chains, kReps));
    const double flops = double(st.iterations()) * chains * kFmaChainFlops * double(kReps);
    st.counters["GFLOPS"] = benchmark::Counter(flops * 1e-9, benchmark::Counter::kIsRate);
    st.counters["chains"] = chains;
}

// Lane results per second of the divide/sqrt unit (8 independent chains).
void bm_divider(benchmark::State& st, DividerOp op, int lanes) {
    if (!simd_supported()) {
        st.SkipWithError("this CPU lacks AVX2+FMA");
        return;
    }
    constexpr std::int64_t kReps = 1 << 14;
    for (auto _ : st) benchmark::DoNotOptimize(divider_chains(op, lanes, kReps));
    st.counters["Glane_results_per_s"] =
        benchmark::Counter(double(st.iterations()) * 8.0 * lanes * double(kReps) * 1e-9, benchmark::Counter::kIsRate);
}

std::string path_suffix(Path p) { return std::string("/") + path_name(p); }

void register_all() {
    for (int chains : {1, 4, 8, 12})
        benchmark::RegisterBenchmark(("fma_peak/8lanes/chains:" + std::to_string(chains)).c_str(),
                                     [chains](benchmark::State& st) { bm_fma_peak(st, chains); });
    for (DividerOp op : {DividerOp::div, DividerOp::sqrt})
        for (int lanes : {1, 8})
            benchmark::RegisterBenchmark((std::string("divider/") + (op == DividerOp::div ? "div" : "sqrt") +
                                          (lanes == 8 ? "/8lanes" : "/1lane")).c_str(),
                                         [op, lanes](benchmark::State& st) { bm_divider(st, op, lanes); });
    for (Path p : kPaths) {
        for (CameraType c : {CameraType::pinhole, CameraType::orthographic})
            benchmark::RegisterBenchmark((std::string("camera/") + camera_type_name(c) + path_suffix(p)).c_str(),
                                         [p, c](benchmark::State& st) { bm_camera(st, c == CameraType::orthographic, p); });
    }
    for (Layout l : {Layout::sphere, Layout::plane, Layout::disk, Layout::rectangle, Layout::box, Layout::triangle})
        for (int n : {1, 16, 256})
            for (Path p : kPaths)
                benchmark::RegisterBenchmark((std::string("intersect/") + layout_name(l) + ":" + std::to_string(n) + path_suffix(p)).c_str(),
                                             [l, n, p](benchmark::State& st) { bm_intersect(st, l, n, p); });
 for (Path p : kPaths)
        benchmark::RegisterBenchmark(("intersect/sphere:256_all_tests" + path_suffix(p)).c_str(),
                                     [p](benchmark::State& st) { bm_intersect_all_tests(st, Layout::sphere, 256, p); });
    for (Path p : kPaths)
        benchmark::RegisterBenchmark(("intersect/sphere:256_full_tests" + path_suffix(p)).c_str(),
                                     [p](benchmark::State& st) { bm_intersect_full_tests(st, 256, p, Isa::best); });
    for (int n : {1, 4, 16, 64, 256})
        for (Path p : kPaths)
            benchmark::RegisterBenchmark(("intersect/mixed:" + std::to_string(n) + path_suffix(p)).c_str(),
                                         [n, p](benchmark::State& st) { bm_intersect(st, Layout::mixed, n, p); });

    std::vector<LightSpec> specs = {
        {"ambient", true, 0, 0},
        {"point_inverse_square:1", false, 0, 1, Attenuation::inverse_square},
        {"directional_shadows:1", false, 1, 0, Attenuation::none, true},
        {"point_shadows:1", false, 0, 1, Attenuation::none, true},
    };
    for (int n : {1, 4, 16, 64}) {
        specs.push_back({"directional:" + std::to_string(n), false, n, 0});
        specs.push_back({"point:" + std::to_string(n), false, 0, n});
    }
    specs.push_back({"default"});
    for (const LightSpec& spec : specs)
        for (Path p : kPaths)
            benchmark::RegisterBenchmark(("shade/" + spec.name + path_suffix(p)).c_str(),
                                         [spec, p](benchmark::State& st) { bm_shade(st, spec, p); });

    struct Mode { ToneMap mode; float gamma; const char* suffix; };
    for (const Mode& m : {Mode{ToneMap::max_to_one, 1, ""}, Mode{ToneMap::clamp_to_color, 1, ""},
                          Mode{ToneMap::saturate, 1, ""}, Mode{ToneMap::max_to_one, 2.2f, "_gamma2.2"}})
        for (Path p : kPaths)
            benchmark::RegisterBenchmark((std::string("tonemap/") + tonemap_name(m.mode) + m.suffix + path_suffix(p)).c_str(),
                                         [m, p](benchmark::State& st) { bm_tonemap(st, m.mode, m.gamma, p); });

    for (Path p : kPaths) {
        benchmark::RegisterBenchmark(("e2e/default/render_rows" + path_suffix(p)).c_str(),
                                     [p](benchmark::State& st) { bm_render_rows(st, Precision::exact, p); });
        benchmark::RegisterBenchmark(("e2e/default/pipeline" + path_suffix(p)).c_str(), [p](benchmark::State& st) { bm_pipeline(st, p); });
        benchmark::RegisterBenchmark(("e2e/default/render_rows_fast" + path_suffix(p)).c_str(),
                                     [p](benchmark::State& st) { bm_render_rows(st, Precision::fast, p); });
        benchmark::RegisterBenchmark(("e2e/default/render_rows_approx" + path_suffix(p)).c_str(),
                                     [p](benchmark::State& st) { bm_render_rows(st, Precision::approx, p); });
    }

    // The AVX-512 unit is preferred where the CPU runs it; these rows time the
    // AVX2 unit on the same data in the same run, so the two compare directly.
    if (avx512_supported()) {
        for (Path p : kPaths) {
            benchmark::RegisterBenchmark(("e2e/default/render_rows_avx2" + path_suffix(p)).c_str(),
                                         [p](benchmark::State& st) { bm_render_rows(st, Precision::exact, p, Isa::avx2); });
            benchmark::RegisterBenchmark(("shade/default_avx2" + path_suffix(p)).c_str(), [p](benchmark::State& st) {
                bm_shade(st, LightSpec{"default"}, p, Isa::avx2);
            });
            benchmark::RegisterBenchmark(("intersect/sphere:256_full_tests_avx2" + path_suffix(p)).c_str(),
                                         [p](benchmark::State& st) { bm_intersect_full_tests(st, 256, p, Isa::avx2); });
        }
    }
}

}  // namespace
}  // namespace octray::bench

int main(int argc, char** argv) { return octray::bench::run_main(argc, argv, octray::bench::register_all); }
