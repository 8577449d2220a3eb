// bench/bench_variants.cpp — what leaving out absent features buys.
//
// For six feature subsets, intersect + shade on the same camera packets with:
//   dispatched  select_kernel(): the variant specialized to the scene's features;
//   hand        a kernel written here by hand for exactly that subset: explicit
//               loops over the present primitive and light types, nothing else,
//               from the same building blocks (intersect_sphere, intersect_plane, ...,
//               for_each_candidate's BVH walk);
//   general     general_kernel(): every feature compiled in, absent ones skipped
//               at run time (zero-trip loops, ambient of zero, ...).
// Target: dispatched within 2% of hand. The hand kernels keep the two-stage
// shape (intersect into a HitPacket, shade from it) so that the comparison
// measures the feature machinery, not a fused pipeline. This file is built
// with -mavx2 -mfma, so the library's kernels are pinned to its AVX2 unit
// (Isa::avx2) too: the comparison is of features, not of instruction sets.
#define OCTRAY_ISA bench_hand
#include "kernels/packet_kernels.hpp"

#include "bench_common.hpp"
#include "scene_loader.hpp"
#include "support.hpp"

#include <octray/kernels.hpp>

#include <benchmark/benchmark.h>

#include <cmath>
#include <functional>
#include <string>

namespace octray::bench::variants {
namespace {

using namespace octray::kernels::bench_hand;
using T = xsimd::batch<float, xsimd::fma3<xsimd::avx2>>;
constexpr Precision P = Precision::exact;
using M = lane::Mask<T>;

// ---- hand-written pieces ------------------------------------------------------
// Stores a closest hit whose geometric normal `n` the caller computed.
void store_hit(const SceneData& s, const Ray<T, P>& r, const Closest<T>& best, Vec3<T> n, HitPacket8& hp) {
    const T &t = best.t, &cid = best.cid;
    const M hit = r.valid && cid >= T(0);
    const T k = lane::select(hit, cid, T(0));
    n = face_forward(s, n, r, best);
    store(hp.t, 0, lane::select(hit, t, inf<T>()));
    const Lookup<T> at(k, hit);
    const T primitive = lane::select(hit, at(s.object_of), T(-1));
    store_index(hp.primitive, 0, primitive);
    T material, mesh;
    owners_of<T, 0u>(s.owners, at, primitive, hit, material, mesh);  // no meshes in these subsets
    store_index(hp.material, 0, material);
    store_index(hp.mesh, 0, mesh);
    store(hp.nx, 0, lane::select(hit, n.x, T(0)));
    store(hp.ny, 0, lane::select(hit, n.y, T(0)));
    store(hp.nz, 0, lane::select(hit, n.z, T(0)));
    store_mask<T>(hp.hit, 0, hit);
    store_mask<T>(hp.invalid, 0, r.invalid);
}

// The hit lanes' data of a single-type scene, read at compiled id = index.
Lookup<T> hit_lookup(const Closest<T>& best) {
    const M hit = best.cid >= T(0);
    return Lookup<T>(lane::select(hit, best.cid, T(0)), hit);
}

// Spheres only; compiled id k = sphere k.
int intersect_spheres(const PacketScene& scene, const RayPacket8& rp, HitPacket8& hp) noexcept {
    const SceneData& s = scene_data(scene);
    int masked = 0;
    const Ray<T, P> r = load_ray<T, P>(rp, 0, masked);
    const SphereArrays& a = s.spheres;
    Closest<T> best{r.tmax, T(-1)};
    for_each_candidate<true, kSphere>(s, r, r.valid, best.t, [&](auto, int k, const Run&) OCTRAY_HOT_LAMBDA {
        M hit;
        M near;
        const T t = intersect_sphere(r, broadcast3<T>(a.cx, a.cy, a.cz, k), SphereRadius<T>{broadcast<T>(a.radius, k)}, hit,
                                     best.t, near);
        best.take(hit, t, k, near);
    });
    const Lookup<T> at = hit_lookup(best);
    store_hit(s, r, best, compiled_sphere_normal(s, at, r, load_residual<T>(rp, 0), best.near), hp);
    return masked;
}

// Planes only.
int intersect_planes(const PacketScene& scene, const RayPacket8& rp, HitPacket8& hp) noexcept {
    const SceneData& s = scene_data(scene);
    int masked = 0;
    const Ray<T, P> r = load_ray<T, P>(rp, 0, masked);
    const PlaneArrays& a = s.planes;
    Closest<T> best{r.tmax, T(-1)};
    for (int k = 0; k < s.count[1]; ++k) {
        M hit;
        const T t = intersect_plane(r, broadcast3<T>(a.px, a.py, a.pz, k), broadcast3<T>(a.nx, a.ny, a.nz, k), hit, best.t);
        best.take(hit, t, k);
    }
    const Lookup<T> at = hit_lookup(best);
    store_hit(s, r, best, at(a.nx, a.ny, a.nz), hp);
    return masked;
}

// Spheres, then planes (compiled ids: spheres first).
int intersect_spheres_planes(const PacketScene& scene, const RayPacket8& rp, HitPacket8& hp) noexcept {
    const SceneData& s = scene_data(scene);
    int masked = 0;
    const Ray<T, P> r = load_ray<T, P>(rp, 0, masked);
    const SphereArrays& a = s.spheres;
    const PlaneArrays& b = s.planes;
    Closest<T> best{r.tmax, T(-1)};
    for_each_candidate<true, kSphere>(s, r, r.valid, best.t, [&](auto, int k, const Run&) OCTRAY_HOT_LAMBDA {
        M hit;
        M near;
        const T t = intersect_sphere(r, broadcast3<T>(a.cx, a.cy, a.cz, k), SphereRadius<T>{broadcast<T>(a.radius, k)}, hit,
                                     best.t, near);
        best.take(hit, t, k, near);
    });
    for (int k = 0; k < s.count[1]; ++k) {
        M hit;
        const T t = intersect_plane(r, broadcast3<T>(b.px, b.py, b.pz, k), broadcast3<T>(b.nx, b.ny, b.nz, k), hit, best.t);
        best.take(hit, t, s.offset[1] + k);
    }
    const T& cid = best.cid;
    const M is_sphere = cid >= T(0) && cid < T(float(s.count[0]));
    const M is_plane = cid >= T(float(s.offset[1]));
    const Lookup<T> sphere_at(lane::select(is_sphere, cid, T(0)), is_sphere);
    const Lookup<T> plane_at(lane::select(is_plane, cid - T(float(s.offset[1])), T(0)), is_plane);
    const Vec3<T> ns = compiled_sphere_normal(s, sphere_at, r, load_residual<T>(rp, 0), best.near);
    const Vec3<T> np = plane_at(b.nx, b.ny, b.nz);
    store_hit(s, r, best,
              {lane::select(is_sphere, ns.x, np.x), lane::select(is_sphere, ns.y, np.y), lane::select(is_sphere, ns.z, np.z)},
              hp);
    return masked;
}

// Triangles only.
int intersect_triangles(const PacketScene& scene, const RayPacket8& rp, HitPacket8& hp) noexcept {
    const SceneData& s = scene_data(scene);
    int masked = 0;
    const Ray<T, P> r = load_ray<T, P>(rp, 0, masked);
    Closest<T> best{r.tmax, T(-1)};
    for_each_candidate<true, kTriangle>(s, r, r.valid, best.t, [&](auto, int k, const Run& run) OCTRAY_HOT_LAMBDA {
        M hit;
        const T t = test_triangle(run.tri, k - run.k0, r, hit, best.t);
        best.take(hit, t, k);
    });
    const Lookup<T> at = hit_lookup(best);
    store_hit(s, r, best, triangle_fields3(s, at, kNormal), hp);
    return masked;
}

// Boxes only; the face normal from the hit point as in the library kernel.
int intersect_boxes(const PacketScene& scene, const RayPacket8& rp, HitPacket8& hp) noexcept {
    const SceneData& s = scene_data(scene);
    int masked = 0;
    const Ray<T, P> r = load_ray<T, P>(rp, 0, masked);
    const BoxArrays& a = s.boxes;
    Closest<T> best{r.tmax, T(-1)};
    for_each_candidate<true, kBox>(s, r, r.valid, best.t, [&](auto, int k, const Run&) OCTRAY_HOT_LAMBDA {
        M hit;
        const T t = intersect_box(r, broadcast3<T>(a.minx, a.miny, a.minz, k), broadcast3<T>(a.maxx, a.maxy, a.maxz, k), hit, best.t);
        best.take(hit, t, k);
    });
    const Lookup<T> at = hit_lookup(best);
    const Vec3<T> lo = at(a.minx, a.miny, a.minz), hi = at(a.maxx, a.maxy, a.maxz);
    const Vec3<T> q = r.o + r.d * best.t - (lo + hi) * T(0.5f), h = (hi - lo) * T(0.5f);
    const T rx = lane::abs(q.x) / h.x, ry = lane::abs(q.y) / h.y, rz = lane::abs(q.z) / h.z;
    const M ax = rx >= ry && rx >= rz, ay = lane::not_(ax) && ry >= rz, az = lane::not_(ax || ay);
    store_hit(s, r, best,
              {lane::select(ax, lane::copysign(T(1), q.x), T(0)), lane::select(ay, lane::copysign(T(1), q.y), T(0)),
               lane::select(az, lane::copysign(T(1), q.z), T(0))},
              hp);
    return masked;
}

// Shading pieces: the hit point, normal and material of a HitPacket.
struct Surface {
    M hit;
    Vec3<T> p, n;
    T m;
};
Surface surface(const RayPacket8& rp, const HitPacket8& hp) {
    Surface f;
    f.hit = load_mask<T>(hp.hit, 0) && load_mask<T>(rp.active, 0);
    const T t = lane::select(f.hit, load<T>(hp.t, 0), T(0));
    f.p = {lane::fma(load<T>(rp.dx, 0), t, load<T>(rp.ox, 0)), lane::fma(load<T>(rp.dy, 0), t, load<T>(rp.oy, 0)),
           lane::fma(load<T>(rp.dz, 0), t, load<T>(rp.oz, 0))};
    f.n = {load<T>(hp.nx, 0), load<T>(hp.ny, 0), load<T>(hp.nz, 0)};
    f.m = lane::select(f.hit, load_index<T>(hp.material, 0), T(0));
    return f;
}
void store_color(const SceneData& s, const Surface& f, const Vec3<T>& c, ColorPacket8& out) {
    store(out.r, 0, lane::select(f.hit, c.x, T(s.background[0])));
    store(out.g, 0, lane::select(f.hit, c.y, T(s.background[1])));
    store(out.b, 0, lane::select(f.hit, c.z, T(s.background[2])));
}
Vec3<T> directional_sum(const SceneData& s, const Surface& f) {
    const DirectionalArrays& a = s.directional;
    Vec3<T> e{T(0), T(0), T(0)};
    for (int k = 0; k < s.directional_count; ++k) {
        const T ndl = fdot(f.n, broadcast3<T>(a.lx, a.ly, a.lz, k));
        accumulate(e, f.hit && ndl > T(0), ndl, broadcast3<T>(a.r, a.g, a.b, k));
    }
    return e;
}

// directional lights, no ambient
void shade_directional(const PacketScene& scene, const RayPacket8& rp, const HitPacket8& hp, ColorPacket8& out) noexcept {
    const SceneData& s = scene_data(scene);
    const Surface f = surface(rp, hp);
    store_color(s, f, hadamard(Lookup<T>(f.m, f.hit)(s.diffuse_r, s.diffuse_g, s.diffuse_b), directional_sum(s, f)), out);
}
// ambient + directional lights
void shade_ambient_directional(const PacketScene& scene, const RayPacket8& rp, const HitPacket8& hp, ColorPacket8& out) noexcept {
    const SceneData& s = scene_data(scene);
    const Surface f = surface(rp, hp);
    const Lookup<T> material(f.m, f.hit);
    const Vec3<T> c = hadamard(material(s.diffuse_r, s.diffuse_g, s.diffuse_b), directional_sum(s, f)) +
                      material(s.ambient_r, s.ambient_g, s.ambient_b);
    store_color(s, f, c, out);
}
// point lights, with or without 1/r^2, no ambient
template <bool Attenuated>
void shade_point(const PacketScene& scene, const RayPacket8& rp, const HitPacket8& hp, ColorPacket8& out) noexcept {
    const SceneData& s = scene_data(scene);
    const Surface f = surface(rp, hp);
    const PointArrays& a = Attenuated ? s.point_attenuated : s.point;
    const int count = Attenuated ? s.point_attenuated_count : s.point_count;
    Vec3<T> e{T(0), T(0), T(0)};
    for (int k = 0; k < count; ++k) {
        const Vec3<T> v = broadcast3<T>(a.px, a.py, a.pz, k) - f.p;
        const T r2 = fdot(v, v);
        const M apart = r2 > T(0);
        const T inv_r = lane::rsqrt<P>(lane::select(apart, r2, T(1)));
        const T ndl = fdot(f.n, v) * inv_r;
        T w = ndl;
        if constexpr (Attenuated) w = w * (inv_r * inv_r);
        accumulate(e, f.hit && apart && ndl > T(0), w, broadcast3<T>(a.r, a.g, a.b, k));
    }
    store_color(s, f, hadamard(Lookup<T>(f.m, f.hit)(s.diffuse_r, s.diffuse_g, s.diffuse_b), e), out);
}

// ---- the subsets ------------------------------------------------------------
struct Subset {
    const char* name;
    std::function<Scene()> scene;
    IntersectFn hand_intersect;
    ShadeFn hand_shade;
};

Scene base_scene() { return test::two_material_scene({0, 6, 14}, 256, 192, {0.1, 0.1, 0.2}); }
void grid(Scene& s, int n, const std::function<Shape(double, double)>& make) {
    const int side = int(std::ceil(std::sqrt(double(n))));
    for (int i = 0; i < n; ++i) {
        const double x = (i % side - (side - 1) / 2.0) * 2.2, z = (i / side - (side - 1) / 2.0) * 2.2;
        s.objects.push_back(Object{make(x, z), i % 2});
    }
}
DirectionalLight sun(double x, double y, double z, double ls) {
    const double l = std::sqrt(x * x + y * y + z * z);
    return DirectionalLight{{x / l, y / l, z / l}, {1, 0.95, 0.9}, ls, false};
}

const Subset kSubsets[] = {
    {"sphere|directional",
     [] {
         Scene s = base_scene();
         grid(s, 16, [](double x, double z) { return Shape{Sphere{{x, 0, z}, 1}}; });
         s.directional_lights = {sun(1, 2, 1, 2)};
         return s;
     },
     &intersect_spheres, &shade_directional},
    {"plane|point_attenuated",
     [] {
         Scene s = base_scene();
         s.objects = {Object{Plane{{0, -1, 0}, {0, 1, 0}}, 0}, Object{Plane{{0, 0, -8}, {0, 0, 1}}, 1},
                      Object{Plane{{-9, 0, 0}, {1, 0, 0}}, 0}, Object{Plane{{9, 0, 0}, {-1, 0, 0}}, 1}};
         s.point_lights = {PointLight{{-2, 3, 2}, {1, 1, 1}, 20, Attenuation::inverse_square, false},
                           PointLight{{3, 2, -2}, {1, 0.8, 0.6}, 15, Attenuation::inverse_square, false}};
         return s;
     },
     &intersect_planes, &shade_point<true>},
    {"sphere+plane|ambient+directional",
     [] {
         Scene s = base_scene();
         grid(s, 16, [](double x, double z) { return Shape{Sphere{{x, 0, z}, 1}}; });
         s.objects.push_back(Object{Plane{{0, -1, 0}, {0, 1, 0}}, 0});
         s.ambient = AmbientLight{{1, 1, 1}, 0.3};
         s.directional_lights = {sun(1, 2, 1, 2), sun(-1, 1, 0.5, 0.8)};
         return s;
     },
     &intersect_spheres_planes, &shade_ambient_directional},
    {"triangle|point",
     [] {
         Scene s = base_scene();
         grid(s, 32, [](double x, double z) { return Shape{Triangle{{x - 1, -1, z + 1}, {x + 1, -1, z + 1}, {x, 1, z - 0.5}}}; });
         s.point_lights = {PointLight{{-3, 4, 3}, {1, 1, 1}, 1.5, Attenuation::none, false},
                           PointLight{{4, 3, 1}, {1, 0.9, 0.7}, 1.0, Attenuation::none, false}};
         return s;
     },
     &intersect_triangles, &shade_point<false>},
    {"box|ambient+directional",
     [] {
         Scene s = base_scene();
         grid(s, 9, [](double x, double z) { return Shape{Box{{x - 0.8, -1, z - 0.8}, {x + 0.8, 0.6, z + 0.8}}}; });
         s.ambient = AmbientLight{{1, 1, 1}, 0.3};
         s.directional_lights = {sun(1, 2, 1.5, 2)};
         return s;
     },
     &intersect_boxes, &shade_ambient_directional},
};

enum class Which { dispatched, hand, general };

void run(benchmark::State& state, const Subset& subset, Which which) {
    const Scene scene = subset.scene();
    const PacketScene ps = compile(scene);
    const Kernel dispatched = select_kernel(ps, Path::simd, Precision::exact, Isa::avx2);
    Kernel k = which == Which::general ? general_kernel(Path::simd, Precision::exact, Isa::avx2) : dispatched;
    if (which == Which::hand) k.intersect = subset.hand_intersect, k.shade = subset.hand_shade;
    const RaySet rays = camera_rays(ps);
    // The three must compute the same image before their times mean anything.
    {
        HitPacket8 h0, h1;
        ColorPacket8 c0, c1;
        for (const RayPacket8& rp : rays.packets) {
            dispatched.intersect(ps, rp, h0), dispatched.shade(ps, rp, h0, c0);
            k.intersect(ps, rp, h1), k.shade(ps, rp, h1, c1);
            for (int i = 0; i < 8; ++i)
                if (rp.active[i] && (h0.primitive[i] != h1.primitive[i] || c0.r[i] != c1.r[i] || c0.g[i] != c1.g[i] ||
                                     c0.b[i] != c1.b[i])) {
                    state.SkipWithError("kernel disagrees with the dispatched variant");
                    return;
                }
        }
    }
    HitPacket8 hits;
    ColorPacket8 color;
    for (auto _ : state) {
        for (const RayPacket8& rp : rays.packets) {
            k.intersect(ps, rp, hits);
            k.shade(ps, rp, hits, color);
            benchmark::DoNotOptimize(color);
        }
    }
    set_ray_counters(state, rays.rays(), intersect_flops_per_ray(ps) + shade_flops_per_ray(ps));
    state.SetLabel(k.name());
}

// "everything": default.json; the hand-restricted kernel for all features is the general one.
void run_everything(benchmark::State& state, Which which) {
    const PacketScene ps = compile(load_scene(default_scene_path()));
    const Kernel k = which == Which::dispatched ? select_kernel(ps, Path::simd, Precision::exact, Isa::avx2)
                                                : general_kernel(Path::simd, Precision::exact, Isa::avx2);
    const RaySet rays = camera_rays(ps);
    HitPacket8 hits;
    ColorPacket8 color;
    for (auto _ : state) {
        for (const RayPacket8& rp : rays.packets) {
            k.intersect(ps, rp, hits);
            k.shade(ps, rp, hits, color);
            benchmark::DoNotOptimize(color);
        }
    }
    set_ray_counters(state, rays.rays(), intersect_flops_per_ray(ps) + shade_flops_per_ray(ps));
    state.SetLabel(k.name());
}

void register_all() {
    for (const Subset& s : kSubsets) {
        for (auto [which, label] : {std::pair{Which::dispatched, "dispatched"}, std::pair{Which::hand, "hand"},
                                    std::pair{Which::general, "general"}})
            benchmark::RegisterBenchmark((std::string("variants/") + s.name + "/" + label).c_str(),
                                         [&s, w = which](benchmark::State& st) { run(st, s, w); });
    }
    benchmark::RegisterBenchmark("variants/everything(default.json)/dispatched",
                                 [](benchmark::State& st) { run_everything(st, Which::dispatched); });
    benchmark::RegisterBenchmark("variants/everything(default.json)/general",
                                 [](benchmark::State& st) { run_everything(st, Which::general); });
}

}  // namespace
}  // namespace octray::bench::variants

int main(int argc, char** argv) { return octray::bench::run_main(argc, argv, octray::bench::variants::register_all); }
