// bench/bench_aobench.cpp — aobench (scenes/aobench.json: three spheres and a
// plane, 64 cosine-weighted occlusion rays per hit): ambient occlusion's
// incoherent rays in 8-lane packets, against the scalar path and Embree.
//
//   ao/render/{simd,scalar}   render_rows over the whole 512x512 image, the
//                             kernels select_kernel picks (the CLI's).
//   ao/render/spheres+plane:64/{simd,scalar}
//                             the same on 64 spheres over a plane: how the
//                             spheres' culling holds up with incoherent rays.
//   ao/shade/{pixels,samples}/simd, ao/shade/pixels/scalar
//                             the shade stage alone on the image's camera hits,
//                             per packet layout of the occlusion rays
//                             (kernels/shading/occlusion.hpp), compiled here for AVX2.
//   ao/occluded/VARIANT       the same occlusion rays through an any-hit query:
//                             those of aobench's own 256x256 image, generated
//                             once as the kernel makes them (8 pixels' k-th
//                             samples a packet, lanes that missed inactive).
//       octray_simd, octray_scalar    Kernel::occluded (select_kernel's);
//       embree8_native, embree8_user  rtcOccluded8, spheres as Embree's
//                                     RTC_GEOMETRY_TYPE_SPHERE_POINT or as user
//                                     geometry (embree_spheres.hpp: octray's
//                                     quadratic, 8 lanes when Embree passes 8);
//       embree1_native, embree1_user  rtcOccluded1, ray by ray.
//     Embree's plane is one quad (its native geometry, the fast path; an
//     infinite plane has no bounds for its BVH), 2e4 across: larger, its float
//     test misses ordinary rays (embree_set). The cross-check counts the rays
//     that meet the plane farther out. Context flag INCOHERENT,
//     build quality HIGH, device threads=1, FTZ/DAZ on for both (bench_common).
//     Embree's tfar is reset before each call (rtcOccluded writes -inf on a
//     hit), in the timed loop as an application must.
//
// Counters: items_per_second is occlusion rays per second everywhere (the
// render's camera rays are not counted: 1 per 64 occlusion rays). Before any
// ao/occluded timing counts, every variant's blocked/unblocked answer per ray
// is compared with octray's SIMD kernel; below 99.99% agreement the benchmark
// stops with SkipWithError. `--crosscheck` prints the table and exits 1 on a
// failure (a CTest test).
#define OCTRAY_ISA bench_ao
#include "kernels/packet_kernels.hpp"

#include "bench_common.hpp"
#include "scene_loader.hpp"

#if OCTRAY_HAVE_EMBREE
#include "embree_spheres.hpp"
#include <embree3/rtcore.h>
#endif

#include <octray/kernels.hpp>
#include <octray/render.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace octray::bench::aobench {
namespace {

using namespace octray::kernels::bench_ao;
using T8 = xsimd::batch<float, xsimd::fma3<xsimd::avx2>>;
constexpr Precision P = Precision::exact;
constexpr double kRequiredMatch = 0.9999;

// scenes/aobench.json, at its own size (0) or another square size.
struct Setup {
    Scene scene;
    PacketScene ps;
    RaySet camera;
    AlignedVec<HitPacket8> hits;
    std::int64_t occlusion_rays = 0;  // hit pixels x samples
};

Setup& setup(int size) {
    static std::map<int, std::unique_ptr<Setup>> cache;
    auto& slot = cache[size];
    if (slot) return *slot;
    slot = std::make_unique<Setup>();
    Setup& s = *slot;
    s.scene = load_scene(std::string(OCTRAY_SOURCE_DIR) + "/scenes/aobench.json");
    if (size > 0) s.scene.camera.width = s.scene.camera.height = size;
    s.ps = compile(s.scene);
    s.camera = camera_rays(s.ps);
    s.hits = trace(select_kernel(s.ps, Path::simd), s.ps, s.camera);
    for (const HitPacket8& h : s.hits)
        for (int i = 0; i < kPacketWidth; ++i) s.occlusion_rays += h.hit[i] != 0;
    s.occlusion_rays *= s.scene.ambient_occlusion->samples;
    return s;
}

void rays_per_second(benchmark::State& st, std::int64_t rays, const std::string& label) {
    st.SetLabel(label);
    set_ray_counters(st, rays, 0);
    for (const char* c : {"GFLOPS", "frac_peak", "flops_per_ray"}) st.counters.erase(c);
}

// ---- the whole render ---------------------------------------------------------------
void bm_render(benchmark::State& st, Path path) {
    Setup& s = setup(0);
    const Kernel k = select_kernel(s.ps, path);
    Image<float> hdr(s.ps.width(), s.ps.height()), display(s.ps.width(), s.ps.height());
    for (auto _ : st) {
        render_rows(k, s.ps, 0, s.ps.height(), hdr, &display);
        benchmark::ClobberMemory();
    }
    rays_per_second(st, s.occlusion_rays, k.name() + ", occlusion rays");
}

// The same on 64 spheres over a plane (bench_common's grid, 256x256, ambient
// only, 16 samples): the acceleration structure over the spheres decides
// what a packet of incoherent rays tests.
void bm_render_grid(benchmark::State& st, Path path) {
    static const PacketScene ps = [] {
        Scene s = grid_scene(Layout::sphere, 64, true, 256, 256);
        s.directional_lights.clear();
        s.ambient_occlusion = AmbientOcclusion{16, 1e30, 0};
        return compile(s);
    }();
    const Kernel k = select_kernel(ps, path);
    Image<float> hdr(ps.width(), ps.height());
    RenderCounters counters;
    for (auto _ : st) {
        counters = {};
        render_rows(k, ps, 0, ps.height(), hdr, nullptr, &counters);
        benchmark::ClobberMemory();
    }
    std::int64_t hits = 0;
    {
        const RaySet rays = camera_rays(ps);
        for (const HitPacket8& h : trace(k, ps, rays))
            for (int i = 0; i < kPacketWidth; ++i) hits += h.hit[i] != 0;
    }
    rays_per_second(st, hits * 16, k.name() + ", occlusion rays");
}

// ---- the shade stage, per layout --------------------------------------------------------
constexpr unsigned kAoLights = kAmbient | kOcclusion;
template <class T, unsigned F, OcclusionLayout L = kOcclusionLayout>
void bm_shade(benchmark::State& st, const char* what) {
    Setup& s = setup(0);
    ColorPacket8 out;
    for (auto _ : st) {
        for (std::size_t k = 0; k < s.hits.size(); ++k) {
            shade_packet<T, P, F, L>(s.ps, s.camera.packets[k], s.hits[k], out);
            benchmark::DoNotOptimize(out);
        }
    }
    rays_per_second(st, s.occlusion_rays, what);
}

// ---- the occlusion ray set ----------------------------------------------------------------
// Sample k of every hit lane of camera packet j, as the kernel builds it
// (OcclusionSamples at one float lane: the SIMD kernel's bits too).
struct OcclusionRays {
    AlignedVec<RayPacket8> packets;
    std::int64_t rays = 0;
    std::vector<std::int32_t> reference;  // octray SIMD's answer per lane of every packet (-1 blocked)
};

OcclusionRays& occlusion_rays() {
    static std::unique_ptr<OcclusionRays> cached;
    if (cached) return *cached;
    cached = std::make_unique<OcclusionRays>();
    OcclusionRays& o = *cached;
    Setup& s = setup(256);
    const SceneData& sd = scene_data(s.ps);
    const int samples = sd.occlusion.samples;
    for (std::size_t j = 0; j < s.hits.size(); ++j) {
        const RayPacket8& cam = s.camera.packets[j];
        const HitPacket8& hit = s.hits[j];
        const std::size_t first = o.packets.size();
        o.packets.resize(first + std::size_t(samples));
        for (int k = 0; k < samples; ++k) {
            RayPacket8& r = o.packets[first + std::size_t(k)];
            r = RayPacket8{};
            std::copy(cam.pixel, cam.pixel + kPacketWidth, r.pixel);
        }
        for (int i = 0; i < kPacketWidth; ++i) {
            if (!hit.hit[i]) continue;
            const Vec3<float> d{cam.dx[i], cam.dy[i], cam.dz[i]};
            const float t = hit.t[i];
            const Vec3<float> p{std::fma(d.x, t, cam.ox[i]), std::fma(d.y, t, cam.oy[i]), std::fma(d.z, t, cam.oz[i])};
            const Vec3<float> n{hit.nx[i], hit.ny[i], hit.nz[i]};
            const float reach = t * std::max({std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)});
            OcclusionSamples<float, P> from(sd, std::uint32_t(cam.pixel[i]), true, p, n, reach);
            for (int k = 0; k < samples; ++k) {
                const Ray<float, P>& ray = from.at(k);
                RayPacket8& r = o.packets[first + std::size_t(k)];
                r.ox[i] = ray.o.x, r.oy[i] = ray.o.y, r.oz[i] = ray.o.z;
                r.dx[i] = ray.d.x, r.dy[i] = ray.d.y, r.dz[i] = ray.d.z;
                r.tmin[i] = ray.tmin, r.tmax[i] = ray.tmax, r.active[i] = -1;
                ++o.rays;
            }
        }
    }
    const Kernel k = select_kernel(s.ps, Path::simd);
    o.reference.resize(o.packets.size() * kPacketWidth);
    for (std::size_t j = 0; j < o.packets.size(); ++j) k.occluded(s.ps, o.packets[j], &o.reference[j * kPacketWidth]);
    return o;
}

// Fraction of active lanes on which `answers` (-1 blocked, 0 not) agrees with octray SIMD.
double agreement(const OcclusionRays& o, const std::vector<std::int32_t>& answers) {
    std::int64_t same = 0;
    for (std::size_t j = 0; j < o.packets.size(); ++j)
        for (int i = 0; i < kPacketWidth; ++i) {
            const std::size_t at = j * kPacketWidth + std::size_t(i);
            same += o.packets[j].active[i] && (answers[at] != 0) == (o.reference[at] != 0);
        }
    return double(same) / double(o.rays);
}

std::vector<std::int32_t> octray_answers(const OcclusionRays& o, Path path) {
    Setup& s = setup(256);
    const Kernel k = select_kernel(s.ps, path);
    std::vector<std::int32_t> out(o.packets.size() * kPacketWidth);
    for (std::size_t j = 0; j < o.packets.size(); ++j) k.occluded(s.ps, o.packets[j], &out[j * kPacketWidth]);
    return out;
}

void bm_octray_occluded(benchmark::State& st, Path path) {
    OcclusionRays& o = occlusion_rays();
    Setup& s = setup(256);
    const double match = path == Path::simd ? 1.0 : agreement(o, octray_answers(o, path));
    st.counters["xcheck_match"] = match;
    if (match < kRequiredMatch) {
        st.SkipWithError("cross-check failed: scalar and SIMD disagree");
        return;
    }
    const Kernel k = select_kernel(s.ps, path);
    std::vector<std::int32_t> flags(o.packets.size() * kPacketWidth);
    for (auto _ : st) {
        for (std::size_t j = 0; j < o.packets.size(); ++j) k.occluded(s.ps, o.packets[j], &flags[j * kPacketWidth]);
        benchmark::ClobberMemory();
    }
    rays_per_second(st, o.rays, k.name());
}

#if OCTRAY_HAVE_EMBREE
// ---- Embree -------------------------------------------------------------------------------
void on_embree_error(void*, RTCError code, const char* message) {
    std::fprintf(stderr, "embree: error %d: %s\n", int(code), message ? message : "");
}

RTCDevice device() {
    static RTCDevice d = [] {
        RTCDevice dev = rtcNewDevice("threads=1");
        if (dev) rtcSetDeviceErrorFunction(dev, on_embree_error, nullptr);
        return dev;
    }();
    return d;
}

struct EmbreeSet {
    UserSpheres spheres;
    float quad_half = 0;
    std::map<bool, RTCScene> scenes;  // by user geometry
    AlignedVec<RTCRay8> rays8;
    AlignedVec<std::array<int, 8>> valid8;
    std::vector<RTCRay> rays1;
    std::vector<float> tfar1;
};

EmbreeSet& embree_set() {
    static std::unique_ptr<EmbreeSet> cached;
    if (cached) return *cached;
    cached = std::make_unique<EmbreeSet>();
    EmbreeSet& e = *cached;
    const OcclusionRays& o = occlusion_rays();
    const Scene& scene = setup(256).scene;
    for (const Object& obj : scene.objects)
        if (const Sphere* sp = std::get_if<Sphere>(&obj.shape))
            e.spheres.xyzr.insert(e.spheres.xyzr.end(), {float(sp->center.x), float(sp->center.y), float(sp->center.z),
                                                         float(sp->radius)});
    // Every plane hit of the set (the plane y = -0.5 within each ray's tmax), for the quad's size.
    double far = 10;
    e.rays8.resize(o.packets.size());
    e.valid8.resize(o.packets.size());
    for (std::size_t j = 0; j < o.packets.size(); ++j) {
        const RayPacket8& r = o.packets[j];
        RTCRay8& q = e.rays8[j];
        std::memset(&q, 0, sizeof q);
        for (int i = 0; i < kPacketWidth; ++i) {
            q.org_x[i] = r.ox[i], q.org_y[i] = r.oy[i], q.org_z[i] = r.oz[i];
            q.dir_x[i] = r.dx[i], q.dir_y[i] = r.dy[i], q.dir_z[i] = r.dz[i];
            q.tnear[i] = r.tmin[i], q.tfar[i] = r.tmax[i], q.mask[i] = ~0u;
            q.id[i] = unsigned(j * kPacketWidth + std::size_t(i));
            e.valid8[j][std::size_t(i)] = r.active[i] ? -1 : 0;
            if (!r.active[i]) continue;
            RTCRay one{};
            one.org_x = r.ox[i], one.org_y = r.oy[i], one.org_z = r.oz[i];
            one.dir_x = r.dx[i], one.dir_y = r.dy[i], one.dir_z = r.dz[i];
            one.tnear = r.tmin[i], one.tfar = r.tmax[i], one.mask = ~0u, one.id = q.id[i];
            e.rays1.push_back(one);
            e.tfar1.push_back(r.tmax[i]);
            if (r.dy[i] < 0) {
                const double t = (-0.5 - double(r.oy[i])) / double(r.dy[i]);
                if (t > 0 && t < double(r.tmax[i]))
                    far = std::max({far, std::fabs(r.ox[i] + r.dx[i] * t), std::fabs(r.oz[i] + r.dz[i] * t)});
            }
        }
    }
    // Near-horizontal rays meet the plane up to ~1e6 away, but Embree's float
    // quad test misses ordinary rays once the quad is ~1e6 across (the
    // cross-check: 586 of 2.28M rays at 1e6, 39 at 1e5, 19 at 1e4, 90 at
    // 1e3): a quad of half side 1e4 leaves out only the rays beyond it.
    e.quad_half = float(std::min(2 * far, 1e4));
    return e;
}

RTCScene embree_scene(bool user) {
    EmbreeSet& e = embree_set();
    if (auto it = e.scenes.find(user); it != e.scenes.end()) return it->second;
    RTCScene scene = sphere_scene(device(), e.spheres, user, nullptr, user_occluded, -0.5f, e.quad_half);
    e.scenes[user] = scene;
    return scene;
}

RTCIntersectContext incoherent_context() { return intersect_context(RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT); }

// One pass over the set, tfar reset per call; the rays' own tmax restored from the octray packets.
void pass8(RTCScene scene, EmbreeSet& e, const OcclusionRays& o) {
    RTCIntersectContext ctx = incoherent_context();
    for (std::size_t j = 0; j < e.rays8.size(); ++j) {
        RTCRay8& r = e.rays8[j];
        std::memcpy(r.tfar, o.packets[j].tmax, sizeof r.tfar);
        rtcOccluded8(e.valid8[j].data(), scene, &ctx, &r);
    }
}
void pass1(RTCScene scene, EmbreeSet& e) {
    RTCIntersectContext ctx = incoherent_context();
    for (std::size_t i = 0; i < e.rays1.size(); ++i) {
        RTCRay& r = e.rays1[i];
        r.tfar = e.tfar1[i];
        rtcOccluded1(scene, &ctx, &r);
    }
}

std::vector<std::int32_t> embree_answers(bool user, bool packet) {
    EmbreeSet& e = embree_set();
    const OcclusionRays& o = occlusion_rays();
    RTCScene scene = embree_scene(user);
    std::vector<std::int32_t> out(o.packets.size() * kPacketWidth, 0);
    if (!scene) return out;
    if (packet) {
        pass8(scene, e, o);
        for (std::size_t j = 0; j < e.rays8.size(); ++j)
            for (int i = 0; i < kPacketWidth; ++i) out[j * kPacketWidth + std::size_t(i)] = e.rays8[j].tfar[i] < 0 ? -1 : 0;
    } else {
        pass1(scene, e);
        for (const RTCRay& r : e.rays1) out[r.id] = r.tfar < 0 ? -1 : 0;
    }
    return out;
}

void bm_embree(benchmark::State& st, bool user, bool packet) {
    const OcclusionRays& o = occlusion_rays();
    RTCScene scene = embree_scene(user);
    if (!scene) {
        st.SkipWithError("Embree device or scene could not be created");
        return;
    }
    const double match = agreement(o, embree_answers(user, packet));
    st.counters["xcheck_match"] = match;
    if (match < kRequiredMatch) {
        const std::string msg = "cross-check failed: same answer on " + std::to_string(100 * match) + "% of rays (< 99.99%)";
        st.SkipWithError(msg.c_str());
        return;
    }
    EmbreeSet& e = embree_set();
    for (auto _ : st) {
        if (packet) pass8(scene, e, o);
        else pass1(scene, e);
        benchmark::ClobberMemory();
    }
    rays_per_second(st, o.rays, std::string("embree ") + RTC_VERSION_STRING + (packet ? " rtcOccluded8" : " rtcOccluded1") +
                                    (user ? " user spheres" : " native spheres"));
}
#endif

struct Variant {
    const char* name;
    bool user, packet;
};
#if OCTRAY_HAVE_EMBREE
constexpr Variant kEmbree[] = {{"embree8_native", false, true}, {"embree8_user", true, true},
                               {"embree1_native", false, false}, {"embree1_user", true, false}};
#endif

void register_all() {
    benchmark::RegisterBenchmark("ao/render/simd", [](benchmark::State& st) { bm_render(st, Path::simd); });
    benchmark::RegisterBenchmark("ao/render/scalar", [](benchmark::State& st) { bm_render(st, Path::scalar); });
    for (Path path : {Path::simd, Path::scalar})
        benchmark::RegisterBenchmark((std::string("ao/render/spheres+plane:64/") + path_name(path)).c_str(),
                                     [path](benchmark::State& st) { bm_render_grid(st, path); });
    benchmark::RegisterBenchmark("ao/shade/pixels/simd",
                                 [](benchmark::State& st) { bm_shade<T8, kAoLights>(st, "avx2, 8 pixels' k-th samples a packet"); });
    benchmark::RegisterBenchmark("ao/shade/samples/simd", [](benchmark::State& st) {
        bm_shade<T8, kAoLights, OcclusionLayout::samples>(st, "avx2, one pixel's 8 samples a packet");
    });
    benchmark::RegisterBenchmark("ao/shade/pixels/scalar", [](benchmark::State& st) { bm_shade<float, kAoLights>(st, "avx2, one lane"); });
    benchmark::RegisterBenchmark("ao/occluded/octray_simd", [](benchmark::State& st) { bm_octray_occluded(st, Path::simd); });
    benchmark::RegisterBenchmark("ao/occluded/octray_scalar", [](benchmark::State& st) { bm_octray_occluded(st, Path::scalar); });
#if OCTRAY_HAVE_EMBREE
    for (const Variant& v : kEmbree)
        benchmark::RegisterBenchmark((std::string("ao/occluded/") + v.name).c_str(),
                                     [v](benchmark::State& st) { bm_embree(st, v.user, v.packet); });
    benchmark::AddCustomContext("embree_version", RTC_VERSION_STRING);
#endif
}

int run_crosscheck() {
    const OcclusionRays& o = occlusion_rays();
    int failures = 0;
    auto row = [&](const char* name, double match) {
        const bool ok = match >= kRequiredMatch;
        failures += !ok;
        std::printf("%-16s %10.4f %10lld %s\n", name, 100 * match,
                    static_cast<long long>(double(o.rays) * (1 - match) + 0.5), ok ? "ok" : "FAIL");
    };
    std::printf("%-16s %10s %10s %s\n", "variant", "match %", "mismatch", "verdict");
    row("octray_scalar", agreement(o, octray_answers(o, Path::scalar)));
#if OCTRAY_HAVE_EMBREE
    for (const Variant& v : kEmbree) {
        if (!embree_scene(v.user)) {
            row(v.name, 0.0);
            continue;
        }
        const std::vector<std::int32_t> answers = embree_answers(v.user, v.packet);
        row(v.name, agreement(o, answers));
        // The first few rays it answers otherwise, to see why.
        int shown = 0;
        for (std::size_t j = 0; j < o.packets.size() && shown < 3; ++j)
            for (int i = 0; i < kPacketWidth && shown < 3; ++i) {
                const std::size_t at = j * kPacketWidth + std::size_t(i);
                const RayPacket8& r = o.packets[j];
                if (!r.active[i] || (answers[at] != 0) == (o.reference[at] != 0)) continue;
                ++shown;
                std::printf("    %s: octray %s, o (%.9g %.9g %.9g) d (%.9g %.9g %.9g) tmax %g\n", v.name,
                            o.reference[at] ? "blocked" : "open", r.ox[i], r.oy[i], r.oz[i], r.dx[i], r.dy[i], r.dz[i],
                            double(r.tmax[i]));
            }
    }
#endif
    std::printf("%s: every variant must agree with octray simd on >= 99.99%% of %lld occlusion rays (aobench, 256x256)\n",
                failures ? "FAILED" : "passed", static_cast<long long>(o.rays));
    return failures ? 1 : 0;
}

}  // namespace
}  // namespace octray::bench::aobench

int main(int argc, char** argv) {
    for (int i = 1; i < argc; ++i)
        if (std::strcmp(argv[i], "--crosscheck") == 0) {
            octray::bench::set_ftz_daz();
            return octray::bench::aobench::run_crosscheck();
        }
    return octray::bench::run_main(argc, argv, octray::bench::aobench::register_all);
}
