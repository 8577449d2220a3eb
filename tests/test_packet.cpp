// Packet path (scalar and SIMD instantiations) against the double reference.
#include <doctest/doctest.h>

#include "scene_files.hpp"

#include "../kernels/isa_kernels.hpp"
#include "scene_loader.hpp"
#include "verify.hpp"

#include <octray/kernels.hpp>
#include <octray/reference.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

using namespace octray;

namespace {

// The volatile keeps GCC 12 -O3 from vectorising away the (double)(float)
// round trip (seen in the stability suite); the reference must see floats.
float f(double x) {
    volatile float rounded = float(x);
    return rounded;
}
// Rounds to float so the reference sees exactly the geometry the kernels see.
Vec3d fl(const Vec3d& v) { return {double(f(v.x)), double(f(v.y)), double(f(v.z))}; }

struct RandomRays {
    std::mt19937 rng;
    explicit RandomRays(unsigned seed) : rng(seed) {}
    double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
    Vec3d in_cube(double h) { return {uniform(-h, h), uniform(-h, h), uniform(-h, h)}; }
    Vec3d direction() {
        for (;;) {
            const Vec3d d = in_cube(1);
            const double l2 = dot(d, d);
            if (l2 > 1e-4 && l2 <= 1) return fl(d * (1 / std::sqrt(l2)));
        }
    }
};

Shape random_shape(PrimitiveType type, RandomRays& r) {
    switch (type) {
    case PrimitiveType::sphere: return Sphere{fl(r.in_cube(1)), double(f(r.uniform(0.3, 2)))};
    case PrimitiveType::plane: return Plane{fl(r.in_cube(1)), r.direction()};
    case PrimitiveType::disk: return Disk{fl(r.in_cube(1)), r.direction(), double(f(r.uniform(0.3, 2)))};
    case PrimitiveType::rectangle: return Rectangle{fl(r.in_cube(1)), fl(r.in_cube(2)), fl(r.in_cube(2))};
    case PrimitiveType::box: {
        const Vec3d a = fl(r.in_cube(1.5)), e = fl(Vec3d{r.uniform(0.2, 2), r.uniform(0.2, 2), r.uniform(0.2, 2)});
        return Box{a, fl(a + e)};
    }
    case PrimitiveType::triangle: return Triangle{fl(r.in_cube(2)), fl(r.in_cube(2)), fl(r.in_cube(2))};
    }
    return Sphere{};
}

// True when the reference's hit/miss answer for `ray` changes under a
// perturbation of the origin or direction of relative size `rel`: the ray is
// within float rounding of the primitive's boundary, where either answer is right.
bool near_boundary(const Shape& shape, const reference::Ray& ray, double rel) {
    const bool base = reference::intersect(shape, ray, 0, 1e300).has_value();
    for (int axis = 0; axis < 3; ++axis)
        for (double sign : {-1.0, 1.0}) {
            Vec3d e;
            (axis == 0 ? e.x : axis == 1 ? e.y : e.z) = sign * rel;
            const double scale = 1 + std::sqrt(dot(ray.origin, ray.origin));
            const reference::Ray moved{ray.origin + e * scale, ray.direction};
            const reference::Ray turned{ray.origin, ray.direction + e};
            if (reference::intersect(shape, moved, 0, 1e300).has_value() != base) return true;
            if (reference::intersect(shape, turned, 0, 1e300).has_value() != base) return true;
        }
    return false;
}

Scene one_object_scene(const Shape& shape) {
    Scene s;
    s.materials.push_back(Material{"m", 0.25, 0.65, {1, 1, 1}});
    s.objects.push_back(Object{shape, 0});
    return s;
}

}  // namespace

namespace {

// The instruction sets this CPU runs the SIMD path with (each pinned with select_kernel's Isa).
std::vector<Isa> simd_isas() {
    std::vector<Isa> isas;
    if (avx512_supported()) isas.push_back(Isa::avx512);
    if (simd_supported()) isas.push_back(Isa::avx2);
    if (isas.empty()) isas.push_back(Isa::best);  // the generic scalar unit
    return isas;
}

}  // namespace

TEST_CASE("every scene in scenes/ agrees with the reference on the scalar and SIMD paths, on every ISA") {
    const Tolerance tol;
    for (const std::string& file : scene_files()) {
        CAPTURE(file);
        const Scene scene = load_scene(file);
        const PacketScene packet = compile(scene);
        const ReferenceRender ref = render_reference(scene);
        std::vector<PacketRender> renders;
        for (Isa isa : simd_isas()) {
            for (Path path : {Path::scalar, Path::simd}) {
                const Kernel k = select_kernel(packet, path, Precision::exact, isa);
                CAPTURE(k.name());
                if (isa != Isa::best) CHECK(std::string(k.isa) == isa_name(isa));
                const PacketRender& out = renders.emplace_back(render_packet(k, packet));
                const Agreement a = compare(ref, out.radiance, out.primitive);
                CHECK(a.nonfinite == 0);
                CHECK(a.max_scaled <= tol.scaled_error);
                CHECK(a.mismatched == a.mismatched_silhouette);
                CHECK(double(a.mismatched) <= tol.silhouette_fraction * double(a.lanes));
                CHECK(a.within(tol));
                CHECK(out.counters.masked == 0);
            }
        }
        // Same kernel, same operations, same order: both paths on every ISA agree to the bit.
        for (std::size_t i = 1; i < renders.size(); ++i) {
            CAPTURE(i);
            CHECK(renders[0].radiance.rgb == renders[i].radiance.rgb);
            CHECK(renders[0].primitive == renders[i].primitive);
        }
    }
}

TEST_CASE("select_kernel's Isa pins the instruction set this CPU runs, and falls back to the best otherwise") {
    const PacketScene ps = compile(load_scene(scene_files().front()));
    for (Path path : {Path::scalar, Path::simd}) {
        CAPTURE(path_name(path));
        const std::string best = select_kernel(ps, path).isa;
        CHECK(best == (avx512_supported() ? "avx512" : simd_supported() ? "avx2" : "generic"));
        CHECK(std::string(select_kernel(ps, path, Precision::exact, Isa::avx512).isa) ==
              (avx512_supported() ? "avx512" : best));
        CHECK(std::string(select_kernel(ps, path, Precision::exact, Isa::avx2).isa) ==
              (simd_supported() ? "avx2" : best));
        // generic is the scalar path's baseline unit; the SIMD path has none.
        CHECK(std::string(select_kernel(ps, path, Precision::exact, Isa::generic).isa) ==
              (path == Path::scalar ? "generic" : best));
        // fast14 is compiled for AVX-512 only: pinned to avx2 it runs where it is compiled.
        if (avx512_supported())
            CHECK(std::string(general_kernel(path, Precision::fast14, Isa::avx2).isa) == "avx512");
        // Pinned or not, the variant is the scene's.
        const Kernel k = select_kernel(ps, path, Precision::exact, Isa::avx2);
        CHECK((k.primitive_bits | k.light_bits) == ps.features.bits);
    }
}

TEST_CASE("randomized packets agree with the reference lane by lane, for every primitive type") {
    constexpr int kRaysPerType = 100'000;
    for (int type_index = 0; type_index < kPrimitiveTypeCount; ++type_index) {
        const PrimitiveType type = PrimitiveType(type_index);
        const std::string type_name = primitive_type_name(type);
        CAPTURE(type_name);
        RandomRays rnd(1234u + unsigned(type_index));
        int hits = 0, boundary = 0, rays = 0;
        double max_t_err = 0, max_n_err = 0;
        for (Path path : {Path::scalar, Path::simd}) {
            RandomRays r(1234u + unsigned(type_index));
            for (int batch = 0; rays < kRaysPerType * (int(path) + 1); ++batch) {
                // A new primitive every 8 packets: many shapes, many rays each.
                const Scene scene = one_object_scene(random_shape(type, r));
                const PacketScene ps = compile(scene);
                const Kernel k = select_kernel(ps, path);
                for (int p = 0; p < 8; ++p, rays += 8) {
                    RayPacket8 rp;
                    reference::Ray refs[8];
                    for (int i = 0; i < 8; ++i) {
                        // Half the origins near the primitive (often inside), half far out.
                        // Half the directions random, half aimed at the primitive's neighbourhood.
                        const Vec3d o = fl(i % 2 == 0 ? r.in_cube(1.5) : r.in_cube(8));
                        Vec3d d = r.direction();
                        if (i % 4 >= 2) {
                            const Vec3d aim = r.in_cube(1.5) - o;
                            if (dot(aim, aim) > 1e-6) d = fl(aim * (1 / std::sqrt(dot(aim, aim))));
                        }
                        refs[i] = {o, d};
                        rp.ox[i] = f(o.x), rp.oy[i] = f(o.y), rp.oz[i] = f(o.z);
                        rp.dx[i] = f(d.x), rp.dy[i] = f(d.y), rp.dz[i] = f(d.z);
                        rp.tmin[i] = 0, rp.tmax[i] = INFINITY, rp.active[i] = -1;
                    }
                    HitPacket8 hp;
                    REQUIRE(k.intersect(ps, rp, hp) == 0);
                    for (int i = 0; i < 8; ++i) {
                        const Shape& shape = scene.objects[0].shape;
                        const auto t = reference::intersect(shape, refs[i], 0, 1e300);
                        if (t.has_value() != (hp.hit[i] != 0)) {
                            // Only legal within float rounding of the boundary.
                            const bool legal = near_boundary(shape, refs[i], 1e-5);
                            CHECK_MESSAGE(legal, "lane " << i << " ref t=" << (t ? *t : -1.0) << " kernel hit=" << hp.hit[i]);
                            ++boundary;
                            continue;
                        }
                        if (!t) {
                            CHECK(hp.primitive[i] == -1);
                            continue;
                        }
                        ++hits;
                        CHECK(hp.primitive[i] == 0);
                        CHECK(hp.material[i] == 0);
                        // t: float rounding moves the hit point by a few ulps of the
                        // ray's length scale along the normal; along the ray that is
                        // that distance over |cos(incidence)|, so |dt| |cos| / scale is
                        // the well-conditioned error measure.
                        const double scale = 1 + std::sqrt(dot(refs[i].origin, refs[i].origin)) + *t;
                        Vec3d nr = reference::geometric_normal(shape, refs[i].origin + refs[i].direction * *t);
                        const double cosine = std::fabs(dot(nr, refs[i].direction));
                        const double t_err = std::fabs(double(hp.t[i]) - *t) * cosine / scale;
                        max_t_err = std::max(max_t_err, t_err);
                        // Normal: unit, facing the ray, and the reference's face-forward normal.
                        const Vec3d n{hp.nx[i], hp.ny[i], hp.nz[i]};
                        if (dot(nr, refs[i].direction) > 0) nr = -nr;
                        CHECK(dot(n, refs[i].direction) <= 0);
                        if (type != PrimitiveType::box)  // box edges: either face is right
                            max_n_err = std::max(max_n_err, std::sqrt(length_squared(n - nr)));
                    }
                }
            }
        }
        MESSAGE(type_name << ": " << rays << " rays, " << hits << " hits, " << boundary
                                          << " boundary mismatches, max t err " << max_t_err << ", max normal err "
                                          << max_n_err);
        CHECK(hits > rays / 20);  // the test exercises hits, not only misses
        CHECK(double(boundary) <= 1e-3 * rays);
        CHECK(max_t_err <= 1e-5);
        CHECK(max_n_err <= 1e-3);
    }
}

TEST_CASE("partial packets and inactive lanes leave the other lanes untouched") {
    const Scene scene = load_scene(std::string(OCTRAY_SOURCE_DIR) + "/scenes/default.json");
    const PacketScene ps = compile(scene);
    for (Path path : {Path::scalar, Path::simd}) {
        CAPTURE(path_name(path));
        const Kernel k = select_kernel(ps, path);
        std::mt19937 rng(99);
        for (int y = 0; y < scene.camera.height; y += 7) {
            for (int x0 = 0; x0 < scene.camera.width; x0 += 8) {
                RayPacket8 full;
                k.camera(ps, x0, y, full);
                HitPacket8 h_full, h_part;
                ColorPacket8 c_full, c_part;
                k.intersect(ps, full, h_full);
                k.shade(ps, full, h_full, c_full);
                RayPacket8 part = full;
                const unsigned mask = rng() & 0xffu;
                for (int i = 0; i < 8; ++i) {
                    if ((mask >> i) & 1u) continue;
                    part.active[i] = 0;
                    part.ox[i] = NAN, part.dx[i] = NAN;  // inactive lanes are never read
                }
                CHECK(k.intersect(ps, part, h_part) == 0);
                k.shade(ps, part, h_part, c_part);
                for (int i = 0; i < 8; ++i) {
                    const bool active = (mask >> i) & 1u && full.active[i];
                    if (active) {
                        CHECK(h_part.t[i] == h_full.t[i]);
                        CHECK(h_part.primitive[i] == h_full.primitive[i]);
                        CHECK(c_part.r[i] == c_full.r[i]);
                        CHECK(c_part.g[i] == c_full.g[i]);
                        CHECK(c_part.b[i] == c_full.b[i]);
                    } else {
                        CHECK(h_part.hit[i] == 0);
                        CHECK(h_part.primitive[i] == -1);
                        CHECK(c_part.r[i] == float(scene.background.x));
                        CHECK(c_part.g[i] == float(scene.background.y));
                        CHECK(c_part.b[i] == float(scene.background.z));
                    }
                }
            }
        }
    }
}

TEST_CASE("lanes with NaN, Inf, zero directions or empty intervals are masked, counted and shaded as background") {
    const Scene scene = load_scene(std::string(OCTRAY_SOURCE_DIR) + "/scenes/default.json");
    const PacketScene ps = compile(scene);
    for (Path path : {Path::scalar, Path::simd})
        for (Precision prec : {Precision::exact, Precision::fast, Precision::approx}) {
            CAPTURE(path_name(path));
            CAPTURE(precision_name(prec));
            const Kernel k = select_kernel(ps, path, prec);
            RayPacket8 rp;
            k.camera(ps, 152, 120, rp);  // the centre of the image: every lane hits something
            rp.ox[0] = NAN;
            rp.dy[1] = INFINITY;
            rp.dx[2] = rp.dy[2] = rp.dz[2] = 0;
            rp.tmin[3] = 5, rp.tmax[3] = 5;
            rp.tmax[4] = NAN;
            rp.oz[5] = -INFINITY;
            rp.dx[6] = 1e-30f, rp.dy[6] = 0, rp.dz[6] = 0;  // |d|^2 underflows
            HitPacket8 hp;
            CHECK(k.intersect(ps, rp, hp) == 7);
            ColorPacket8 c, shown;
            k.shade(ps, rp, hp, c);
            k.tonemap(ps, c, shown);
            for (int i = 0; i < 7; ++i) {
                CHECK(hp.hit[i] == 0);
                CHECK(c.r[i] == float(scene.background.x));
            }
            CHECK(hp.hit[7] != 0);
            for (int i = 0; i < 8; ++i) {
                CHECK(std::isfinite(c.r[i]));
                CHECK(std::isfinite(c.g[i]));
                CHECK(std::isfinite(c.b[i]));
                CHECK(std::isfinite(shown.r[i]));
                CHECK(std::isfinite(hp.nx[i]));
            }
        }
}

TEST_CASE("tone mapping maps NaN and infinite radiance into gamut on every path") {
    Scene scene = one_object_scene(Sphere{{0, 0, 0}, 1});
    for (ToneMap mode : {ToneMap::max_to_one, ToneMap::clamp_to_color, ToneMap::saturate})
        for (double gamma : {1.0, 2.2}) {
            scene.render.tonemap = mode;
            scene.render.gamma = gamma;
            const PacketScene ps = compile(scene);
            for (Path path : {Path::scalar, Path::simd}) {
                const Kernel k = select_kernel(ps, path);
                ColorPacket8 in{}, out{};
                const float special[8][3] = {{NAN, 0.5f, 0.25f}, {INFINITY, 2, 0.5f}, {INFINITY, INFINITY, 0},
                                             {-INFINITY, 0.5f, 0.5f}, {3e38f, 3e38f, 1}, {0.2f, 0.4f, 0.8f},
                                             {2, 4, 8}, {-1, -NAN, 0}};
                for (int i = 0; i < 8; ++i) in.r[i] = special[i][0], in.g[i] = special[i][1], in.b[i] = special[i][2];
                k.tonemap(ps, in, out);
                for (int i = 0; i < 8; ++i) {
                    CAPTURE(i);
                    for (float c : {out.r[i], out.g[i], out.b[i]}) {
                        CHECK(c >= 0.0f);
                        CHECK(c <= 1.0f);
                    }
                    // Finite input: the packet tone map is the reference's, to float rounding.
                    const Vec3d hdr{special[i][0], special[i][1], special[i][2]};
                    if (std::isfinite(hdr.x) && std::isfinite(hdr.y) && std::isfinite(hdr.z) && hdr.x >= 0 && hdr.y >= 0 && hdr.z >= 0) {
                        const Vec3d ref = reference::tonemap(hdr, scene.render);
                        CHECK(std::fabs(out.r[i] - ref.x) <= 1e-6);
                        CHECK(std::fabs(out.g[i] - ref.y) <= 1e-6);
                        CHECK(std::fabs(out.b[i] - ref.z) <= 1e-6);
                    }
                }
            }
        }
}

TEST_CASE("compile() rejects scenes built in code that break the invariants, naming the field") {
    auto message = [](const Scene& s) -> std::string {
        try {
            compile(s);
        } catch (const std::invalid_argument& e) {
            return e.what();
        }
        return "";
    };
    Scene ok = one_object_scene(Sphere{{0, 0, 0}, 1});
    CHECK(message(ok).empty());
    Scene bad = ok;
    bad.objects[0].material = 3;
    CHECK(message(bad).find("objects[0].material: index 3, but there are 1 materials") != std::string::npos);
    bad = ok;
    bad.objects[0].shape = Sphere{{0, 0, 0}, -1};
    CHECK(message(bad).find("objects[0].radius") != std::string::npos);
    bad = ok;
    bad.objects[0].shape = Box{{0, 0, 0}, {1, 0, 1}};
    CHECK(message(bad).find("objects[0]: is degenerate") != std::string::npos);
    bad = ok;
    bad.objects[0].shape = Triangle{{0, 0, 0}, {1, 1, 1}, {2, 2, 2}};
    CHECK(message(bad).find("objects[0]: is degenerate") != std::string::npos);
    bad = ok;
    bad.point_lights.push_back(PointLight{{0, NAN, 0}});
    CHECK(message(bad).find("point_lights[0].position[1]: must be finite") != std::string::npos);
    bad = ok;
    bad.camera.up = {0, 0, 1};  // parallel to eye - look_at
    CHECK(message(bad).find("camera.up") != std::string::npos);
}

TEST_CASE("HitPacket::invalid flags exactly the lanes that were masked off") {
    const PacketScene ps = compile(one_object_scene(Sphere{{0, 0, 0}, 1}));
    for (Path path : {Path::scalar, Path::simd}) {
        const Kernel k = select_kernel(ps, path);
        RayPacket8 rp;
        for (int i = 0; i < 8; ++i) {
            rp.ox[i] = 0, rp.oy[i] = 0, rp.oz[i] = 5, rp.dx[i] = 0, rp.dy[i] = 0, rp.dz[i] = -1;
            rp.tmin[i] = 0, rp.tmax[i] = INFINITY, rp.active[i] = -1;
        }
        rp.dz[2] = 0;          // zero direction: invalid
        rp.active[3] = 0;      // inactive: not invalid, just not traced
        rp.oy[5] = NAN;        // invalid
        HitPacket8 hp;
        CHECK(k.intersect(ps, rp, hp) == 2);
        for (int i = 0; i < 8; ++i) {
            CAPTURE(i);
            CHECK((hp.invalid[i] != 0) == (i == 2 || i == 5));
            CHECK((hp.hit[i] != 0) == (i != 2 && i != 3 && i != 5));
            if (hp.hit[i]) CHECK(hp.t[i] == doctest::Approx(4.0).epsilon(1e-6));
        }
    }
}

TEST_CASE("dispatch picks the variant compiled for exactly the scene's features, for every scene in scenes/") {
    for (const std::string& file : scene_files()) {
        CAPTURE(file);
        const PacketScene ps = compile(load_scene(file));
        for (Path path : {Path::scalar, Path::simd}) {
            const Kernel k = select_kernel(ps, path);
            CHECK((k.primitive_bits | k.light_bits) == ps.features.bits);
            const bool specialized = k.intersect != general_kernel(path).intersect;
            CHECK(specialized);
        }
    }
}

namespace {

// A small scene that uses exactly the features in `bits`.
Scene scene_with_features(unsigned bits, std::mt19937& rng) {
    Scene s;
    s.camera.eye = {0.3, 2.5, 7};
    s.camera.look_at = {0, 0, 0};
    s.camera.width = 48;
    s.camera.height = 36;
    s.background = {0.1, 0.2, 0.3};
    s.materials = {Material{"a", 0.3, 0.6, {0.9, 0.4, 0.2}}, Material{"b", 0.2, 0.7, {0.2, 0.5, 0.9}}};
    auto u = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
    auto add = [&](Shape shape) { s.objects.push_back(Object{shape, int(s.objects.size() % 2)}); };
    if (bits & kSphere) add(Sphere{{u(-1, 1), u(0, 1), u(-1, 1)}, u(0.5, 1)});
    if (bits & kPlane) add(Plane{{0, -1, 0}, {0, 1, 0}});
    if (bits & kDisk) add(Disk{{-2, 0.5, -1}, {0.3, 0.2, 1}, 0.8});
    if (bits & kRectangle) add(Rectangle{{-1.5, -1, -2.5}, {3, 0, 0}, {0, 2.5, 0.3}});
    if (bits & kBox) add(Box{{1.2, -1, -0.5}, {2.2, 0.3, 0.5}});
    if (bits & kTriangle) add(Triangle{{0.5, -1, 1.5}, {2, -1, 2}, {1.2, 0.5, 1.8}});
    const bool shadows = (bits & kShadows) != 0;
    if (bits & kAmbient) s.ambient = AmbientLight{{1, 1, 1}, 0.4};
    if (bits & kDirectional) s.directional_lights.push_back({{0.4, 0.8, 0.45}, {1, 0.9, 0.8}, 1.5, shadows});
    if (bits & kPoint) s.point_lights.push_back({{-3, 4, 3}, {1, 1, 1}, 1.2, Attenuation::none, shadows});
    if (bits & kPointAttenuated) s.point_lights.push_back({{2, 3, 3}, {1, 0.8, 0.6}, 25, Attenuation::inverse_square, shadows});
    for (DirectionalLight& l : s.directional_lights) l.direction = l.direction * (1 / std::sqrt(dot(l.direction, l.direction)));
    return s;
}

}  // namespace

TEST_CASE("sampled feature variants agree with the reference (each variant on a scene that exercises it)") {
    std::mt19937 rng(7);
    const Tolerance tol;
    int tested = 0;
    for (int trial = 0; trial < 48; ++trial) {
        unsigned bits = rng() & kAllFeatures;
        if ((bits & kAllPrimitives) == 0) bits |= kSphere;
        // Shadows need a light that casts them.
        if ((bits & (kDirectional | kPoint | kPointAttenuated)) == 0) bits &= ~kShadows;
        CAPTURE(feature_string(bits));
        const Scene scene = scene_with_features(bits, rng);
        const PacketScene ps = compile(scene);
        REQUIRE(ps.features.bits == bits);
        const ReferenceRender ref = render_reference(scene);
        for (Isa isa : simd_isas()) {
            for (Path path : {Path::scalar, Path::simd}) {
                const Kernel k = select_kernel(ps, path, Precision::exact, isa);
                CAPTURE(k.name());
                CHECK((k.primitive_bits | k.light_bits) == bits);
                const PacketRender out = render_packet(k, ps);
                const Agreement a = compare(ref, out.radiance, out.primitive);
                CHECK(a.within(tol));
            }
        }
        ++tested;
    }
    CHECK(tested == 48);
}

TEST_CASE("cluster culling: scenes of hundreds of primitives agree with the reference, and the paths bit for bit") {
    // Many primitives of every type, scattered, so packets skip most clusters
    // (bounding-sphere tree) and test a few: culling must change no lane.
    std::mt19937 rng(2024);
    auto u = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
    Scene s;
    s.camera.eye = {0, 4, 14};
    s.camera.look_at = {0, 0, 0};
    s.camera.width = 96;
    s.camera.height = 72;
    s.ambient = AmbientLight{{1, 1, 1}, 0.3};
    s.directional_lights.push_back({{0.48, 0.8, 0.36}, {1, 1, 1}, 1.5, true});
    s.materials = {Material{"a", 0.3, 0.6, {0.9, 0.4, 0.2}}, Material{"b", 0.2, 0.7, {0.2, 0.5, 0.9}}};
    s.objects.push_back(Object{Plane{{0, -3, 0}, {0, 1, 0}}, 0});
    for (int i = 0; i < 400; ++i) {
        const Vec3d c{u(-6, 6), u(-2.5, 2.5), u(-6, 6)};
        const double r = u(0.1, 0.5);
        Shape shape;
        switch (i % 5) {
        case 0: shape = Sphere{c, r}; break;
        case 1: shape = Disk{c, {u(-1, 1), 1, u(-1, 1)}, r}; break;
        case 2: shape = Rectangle{c, {r, 0, u(0, r)}, {0, r, u(0, r)}}; break;
        case 3: shape = Box{c, c + Vec3d{r, r, r}}; break;
        default: shape = Triangle{c, c + Vec3d{r, 0, 0}, c + Vec3d{0, r, r}}; break;
        }
        s.objects.push_back(Object{shape, i % 2});
    }
    const PacketScene ps = compile(s);
    // 80 spheres: clusters of kClusterSize under a root of runs of kTreeWidth
    // clusters (the last shorter), each node's children consecutive, leaves
    // in compiled order, every node's sphere around its primitives' spheres.
    const ClusterTree& tree = ps.clusters[0];
    const int clusters = (80 + kClusterSize - 1) / kClusterSize;
    REQUIRE(clusters > kTreeWidth);
    REQUIRE(clusters <= kTreeWidth * kTreeWidth);
    const int runs = (clusters + kTreeWidth - 1) / kTreeWidth;
    REQUIRE(tree.size() == 1 + runs + clusters);
    CHECK(tree.child_count[0] == runs);
    CHECK(tree.child_count[1] == kTreeWidth);
    CHECK(tree.child_count[std::size_t(runs)] == clusters - (runs - 1) * kTreeWidth);
    CHECK(tree.px.size() == std::size_t(80 + kTreeWidth));
    auto inside = [&](int node, int k) {
        const double dx = double(tree.px[std::size_t(k)]) - tree.cx[std::size_t(node)];
        const double dy = double(tree.py[std::size_t(k)]) - tree.cy[std::size_t(node)];
        const double dz = double(tree.pz[std::size_t(k)]) - tree.cz[std::size_t(node)];
        return std::sqrt(dx * dx + dy * dy + dz * dz) + tree.pradius[std::size_t(k)] <= tree.radius[std::size_t(node)];
    };
    for (int j = 0, leaves = 0; j < tree.size(); ++j) {
        if (tree.first_child[std::size_t(j)] >= 0) continue;
        CHECK(tree.cluster[std::size_t(j)] == leaves);
        for (int k = leaves * kClusterSize; k < std::min(80, (leaves + 1) * kClusterSize); ++k) {
            CHECK(inside(j, k));
            CHECK(inside(0, k));
        }
        ++leaves;
    }
    const ReferenceRender ref = render_reference(s);
    PacketRender out[2];
    for (Path path : {Path::scalar, Path::simd}) {
        out[int(path)] = render_packet(select_kernel(ps, path), ps);
        const Agreement a = compare(ref, out[int(path)].radiance, out[int(path)].primitive);
        INFO("max L/S " << a.max_scaled << ", mismatched " << a.mismatched << " (silhouette "
                        << a.mismatched_silhouette << "), nonfinite " << a.nonfinite);
        CHECK(a.within(Tolerance{}));
        // Shadow boundaries are left out of the error, like silhouettes. With 400
        // small casters at 96x72 they are many (~30% of lanes here); the rest
        // must still be within tolerance, and any-hit is checked ray by ray below.
        CHECK(a.shadow_edges > 0);
        CHECK(double(a.shadow_edges) <= 0.5 * double(a.lanes));
    }
    CHECK(out[0].radiance.rgb == out[1].radiance.rgb);
    CHECK(out[0].primitive == out[1].primitive);
    // The tree only skips work: with every bound infinite (nothing culled,
    // every primitive tested in compiled order) the image is the same, bit for bit.
    PacketScene unculled = ps;
    for (ClusterTree& c : unculled.clusters) c.disable_culling();
    for (Path path : {Path::scalar, Path::simd}) {
        const PacketRender all = render_packet(select_kernel(unculled, path), unculled);
        CHECK(all.radiance.rgb == out[int(path)].radiance.rgb);
        CHECK(all.primitive == out[int(path)].primitive);
    }

    // Any-hit (shadow) queries skip clusters the same way: against the
    // reference's "anything in (0, tmax)?" on random rays, disagreeing only
    // where some primitive's answer flips under a 1e-5 perturbation.
    RandomRays rays(77);
    int checked = 0, boundary = 0;
    for (Path path : {Path::scalar, Path::simd}) {
        const Kernel k = select_kernel(ps, path);
        for (int p = 0; p < 2500; ++p) {
            RayPacket8 rp;
            reference::Ray refs[8];
            for (int i = 0; i < 8; ++i) {
                const Vec3d o = fl(rays.in_cube(7)), d = rays.direction();
                refs[i] = {o, d};
                rp.ox[i] = f(o.x), rp.oy[i] = f(o.y), rp.oz[i] = f(o.z);
                rp.dx[i] = f(d.x), rp.dy[i] = f(d.y), rp.dz[i] = f(d.z);
                rp.tmin[i] = 0, rp.tmax[i] = float(rays.uniform(0.5, 20)), rp.active[i] = -1;
            }
            std::int32_t occluded[8];
            k.occluded(ps, rp, occluded);
            for (int i = 0; i < 8; ++i, ++checked) {
                const bool expected = reference::trace(s, refs[i], 0, double(rp.tmax[i])).object >= 0;
                if (expected == (occluded[i] != 0)) continue;
                bool legal = false;
                for (const Object& o : s.objects) legal = legal || near_boundary(o.shape, refs[i], 1e-5);
                CHECK(legal);
                ++boundary;
            }
        }
    }
    CHECK(checked == 40000);
    CHECK(boundary <= 40);
}

TEST_CASE("the packet beam skips only what no ray of the packet could hit: bundles of every coherence, bit for bit") {
    // 1200 small primitives (spheres, boxes, triangles) in a 40-unit cube: a
    // tree three levels deep. Packets: bundles around a random ray whose lanes
    // spread in origin (0 .. 3 units) and angle (0 .. 2 rad), far from the
    // scene's origin too; some lanes inactive or invalid. Every answer must be
    // the one of the same scene with every bound infinite (nothing skipped),
    // on every unit (ISA, path) and precision mode, closest hit and any hit.
    std::mt19937 rng(31);
    auto u = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
    const Vec3d shift{3e4, -2e4, 1e4};
    Scene s;
    s.materials = {Material{"a", 0.3, 0.6, {0.9, 0.4, 0.2}}};
    std::vector<Vec3d> centres;
    for (int i = 0; i < 1200; ++i) {
        const Vec3d c = fl(Vec3d{u(-20, 20), u(-20, 20), u(-20, 20)} + shift);
        centres.push_back(c);
        const double r = f(u(0.05, 0.6));
        Shape shape;
        switch (i % 3) {
        case 0: shape = Sphere{c, r}; break;
        case 1: shape = Box{c, fl(c + Vec3d{r, r, r})}; break;
        default: shape = Triangle{c, fl(c + Vec3d{r, 0, 0}), fl(c + Vec3d{0, r, r})}; break;
        }
        s.objects.push_back(Object{shape, 0});
    }
    const PacketScene culled = compile(s);
    REQUIRE(culled.clusters[0].size() > 1 + kTreeWidth);  // more than one level of inner nodes
    PacketScene unculled = culled;
    for (ClusterTree& c : unculled.clusters) c.disable_culling();
    RandomRays rays(5);
    const double origin_spread[] = {0, 1e-3, 0.1, 3};
    const double angle_spread[] = {0, 1e-3, 0.05, 0.5, 2};
    int packets = 0, hits = 0, units = 0;
    for (int u = 0; u < kernels::kUnitCount; ++u) {
        const kernels::Unit& unit = kernels::kUnits[u];
        if (!unit.supported()) continue;
        for (Precision precision : kPrecisions) {
            if ((unit.modes & kernels::mode_bit(precision)) == 0) continue;
            ++units;
            // The general kernel: kernels with several bounded types walk out of line.
            const Kernel kc = unit.kernel(precision, kAllFeatures, kAllFeatures), &ku = kc;
            INFO(path_name(unit.path) << "/" << unit.isa << "/" << precision_name(precision));
            for (int p = 0; p < 200; ++p, ++packets) {
                // Aimed at a primitive, so that coherent bundles hit things.
                const Vec3d o0 = rays.in_cube(30) + shift, aim = centres[std::size_t(p * 7 % 1200)] - o0;
                const Vec3d d0 = aim * (1 / std::sqrt(dot(aim, aim)));
                const double so = origin_spread[p % 4], sa = angle_spread[p / 4 % 5];
                RayPacket8 rp;
                for (int i = 0; i < 8; ++i) {
                    const Vec3d o = fl(o0 + rays.in_cube(so)), d = fl(d0 + rays.in_cube(sa));
                    rp.ox[i] = f(o.x), rp.oy[i] = f(o.y), rp.oz[i] = f(o.z);
                    rp.dx[i] = f(d.x), rp.dy[i] = f(d.y), rp.dz[i] = f(d.z);
                    rp.tmin[i] = 0, rp.tmax[i] = i == 3 ? 10.0f : INFINITY;
                    rp.active[i] = p % 7 == 0 && i == 0 ? 0 : -1;
                }
                if (p % 11 == 0) rp.dx[5] = NAN;  // an invalid lane
                HitPacket8 hc, hu;
                CHECK(kc.intersect(culled, rp, hc) == ku.intersect(unculled, rp, hu));
                for (int i = 0; i < 8; ++i) {
                    if (rp.active[i] == 0) continue;
                    INFO("packet " << p << " lane " << i << " origin spread " << so << " angle spread " << sa);
                    CHECK(hc.hit[i] == hu.hit[i]);
                    CHECK(hc.primitive[i] == hu.primitive[i]);
                    CHECK(std::memcmp(&hc.t[i], &hu.t[i], sizeof(float)) == 0);
                    hits += hc.hit[i] != 0;
                }
                for (int i = 0; i < 8; ++i) rp.tmax[i] = float(rays.uniform(1, 40));
                std::int32_t oc[8], ou[8];
                kc.occluded(culled, rp, oc);
                ku.occluded(unculled, rp, ou);
                for (int i = 0; i < 8; ++i)
                    if (rp.active[i] != 0) CHECK(oc[i] == ou[i]);
            }
        }
    }
    CHECK(units >= 8);  // avx2 scalar and simd, 4 modes each (more with AVX-512, the generic unit)
    CHECK(packets == 200 * units);
    CHECK(hits > 200 * units);  // the bundles do hit things (~2 lanes a packet): the comparison is not vacuous
}
