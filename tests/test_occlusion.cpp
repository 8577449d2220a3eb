// tests/test_occlusion.cpp — ambient occlusion (docs/shading-model.md, "Ambient
// occlusion"): the sample generator, the visible fraction against closed
// forms on the reference and both packet paths, the paths' agreement on
// whole renders, and determinism across thread counts.
#include <doctest/doctest.h>

#include "support.hpp"

#include "kernels/shading/sampling.hpp"
#include "scene_loader.hpp"
#include "verify.hpp"

#include <octray/kernels.hpp>
#include <octray/reference.hpp>
#include "reference/reference_parts.hpp"

#include <cmath>
#include <random>
#include <string>
#include <vector>

using namespace octray;
using namespace octray::test;

namespace {

// One matte material with ka = 1, cd = 1 and an ambient light of ls = 1: the
// radiance of a hit is its occlusion factor.
Scene occlusion_scene(int samples, double distance, double min_amount = 0) {
    Scene s;
    s.camera.width = 8;
    s.camera.height = 8;
    s.materials.push_back(Material{"white", 1.0, 0.0, {1, 1, 1}});
    s.ambient = AmbientLight{{1, 1, 1}, 1.0};
    s.ambient_occlusion = AmbientOcclusion{samples, distance, min_amount};
    return s;
}

// The occlusion factor at the point the ray `from` -> `from + dir` first
// hits, for pixel keys 0 .. count-1, on every path: the reference's
// occlusion_factor on its hit, and each kernel's radiance for engine-made
// packets (every lane the same ray, its own pixel key).
struct Factors {
    std::vector<double> reference;
    std::vector<std::vector<float>> kernels;  // per path and ISA
};
Factors factors_at(const Scene& scene, const Vec3d& from, const Vec3d& dir, int count) {
    Factors out;
    const reference::Hit hit = reference::trace(scene, {from, dir});
    REQUIRE(hit.object >= 0);
    for (int p = 0; p < count; ++p) out.reference.push_back(reference::occlusion_factor(scene, hit, std::uint32_t(p)));
    const PacketScene ps = compile(scene);
    for (Isa isa : simd_isas())
        for (Path path : {Path::scalar, Path::simd}) {
            const Kernel k = select_kernel(ps, path, Precision::exact, isa);
            std::vector<float>& got = out.kernels.emplace_back();
            for (int p0 = 0; p0 < count; p0 += kPacketWidth) {
                RayPacket8 rays;
                HitPacket8 hits;
                ColorPacket8 radiance;
                for (int i = 0; i < kPacketWidth; ++i) {
                    rays.ox[i] = float(from.x), rays.oy[i] = float(from.y), rays.oz[i] = float(from.z);
                    rays.dx[i] = float(dir.x), rays.dy[i] = float(dir.y), rays.dz[i] = float(dir.z);
                    rays.tmin[i] = 0, rays.tmax[i] = INFINITY;
                    rays.active[i] = p0 + i < count ? -1 : 0;
                    rays.pixel[i] = p0 + i;
                }
                k.intersect(ps, rays, hits);
                k.shade(ps, rays, hits, radiance);
                for (int i = 0; i < kPacketWidth && p0 + i < count; ++i) {
                    CHECK(hits.hit[i] != 0);
                    CHECK(radiance.r[i] == radiance.g[i]);
                    got.push_back(radiance.r[i]);
                }
            }
        }
    return out;
}

double mean(const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x;
    return s / double(v.size());
}
double mean(const std::vector<float>& v) {
    double s = 0;
    for (float x : v) s += x;
    return s / double(v.size());
}

}  // namespace

TEST_CASE("occlusion samples: keyed by (pixel, sample) alone, uniform, cosine-distributed about the normal") {
    double u1, u2, again1, again2;
    sampling::occlusion_uniforms(1234, 7, u1, u2);
    sampling::occlusion_uniforms(1234, 7, again1, again2);
    CHECK(u1 == again1);
    CHECK(u2 == again2);
    sampling::occlusion_uniforms(1234, 8, again1, again2);
    CHECK(u1 != again1);
    // Moments over many keys: E[u] = 1/2, E[u^2] = 1/3, E[u1 u2] = 1/4; for
    // cosine-weighted directions E[cos theta] = 2/3 and E[cos^2 theta] = 1/2,
    // and the tangent components average 0. n = 2^16 keys: sampling error
    // ~ 0.3 / 256 ~ 1e-3; 5e-3 is five of those.
    const Vec3d n = Vec3d{0.3, -0.5, 0.8} * (1 / std::sqrt(0.98));
    double s1 = 0, s11 = 0, s12 = 0, c1 = 0, c2 = 0;
    Vec3d tangent_sum;
    const int count = 1 << 16;
    for (int i = 0; i < count; ++i) {
        const std::uint32_t pixel = std::uint32_t(i) >> 6, sample = std::uint32_t(i) & 63;
        sampling::occlusion_uniforms(pixel, sample, u1, u2);
        REQUIRE(u1 >= 0);
        REQUIRE(u1 < 1);
        REQUIRE(u2 >= 0);
        REQUIRE(u2 < 1);
        s1 += u1, s11 += u1 * u1, s12 += u1 * u2;
        const Vec3d d = reference::occlusion_direction(n, pixel, int(sample));
        CHECK(std::sqrt(dot(d, d)) == doctest::Approx(1).epsilon(1e-12));
        const double c = dot(d, n);
        REQUIRE(c > 0);
        c1 += c, c2 += c * c;
        tangent_sum += d - n * c;
    }
    CHECK(s1 / count == doctest::Approx(0.5).epsilon(5e-3));
    CHECK(s11 / count == doctest::Approx(1.0 / 3).epsilon(5e-3));
    CHECK(s12 / count == doctest::Approx(0.25).epsilon(5e-3));
    CHECK(c1 / count == doctest::Approx(2.0 / 3).epsilon(5e-3));
    CHECK(c2 / count == doctest::Approx(0.5).epsilon(5e-3));
    CHECK(std::sqrt(dot(tangent_sum, tangent_sum)) / count < 5e-3);
}

TEST_CASE("occlusion: a point on a plane with nothing above it sees the whole hemisphere") {
    Scene s = occlusion_scene(64, 1e30);
    s.objects.push_back(Object{Plane{{0, 0, 0}, {0, 1, 0}}, 0});
    const Factors f = factors_at(s, {0.3, 2, -0.7}, {0, -1, 0}, 32);
    for (double x : f.reference) CHECK(x == 1.0);
    for (const auto& k : f.kernels)
        for (float x : k) CHECK(x == 1.0f);
}

TEST_CASE("occlusion: the centre of the floor inside a closed box sees nothing; min_amount is the floor of the factor") {
    for (double min_amount : {0.0, 0.25}) {
        CAPTURE(min_amount);
        Scene s = occlusion_scene(64, 1e30, min_amount);
        s.objects.push_back(Object{Box{{-1, 0, -1}, {1, 2, 1}}, 0});
        const Factors f = factors_at(s, {0, 1, 0}, {0, -1, 0}, 16);  // from inside, down to the floor's centre
        for (double x : f.reference) CHECK(x == min_amount);
        for (const auto& k : f.kernels)
            for (float x : k) CHECK(x == float(min_amount));
    }
}

TEST_CASE("occlusion: inside a closed box of mesh triangles (the BVH's any-hit walk) the floor sees nothing") {
    // The box [-1, 1] x [0, 2] x [-1, 1] as one indexed mesh, wound outward.
    Mesh box;
    for (int i = 0; i < 8; ++i) box.vertices.push_back({i & 1 ? 1.0 : -1.0, i & 2 ? 2.0 : 0.0, i & 4 ? 1.0 : -1.0});
    box.indices = {0, 1, 5, 0, 5, 4, 2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2,
                   1, 3, 7, 1, 7, 5, 0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6};
    for (double min_amount : {0.0, 0.25}) {
        CAPTURE(min_amount);
        Scene s = occlusion_scene(64, 1e30, min_amount);
        s.meshes.push_back(box);
        const Factors f = factors_at(s, {0.3, 1, 0.1}, {0, -1, 0}, 16);  // down to the floor, off its diagonal
        for (double x : f.reference) CHECK(x == min_amount);
        for (const auto& k : f.kernels)
            for (float x : k) CHECK(x == float(min_amount));
    }
}

TEST_CASE("occlusion among 2000 spheres with a shadowing light (the general shade, the BVH walk) agrees with the reference") {
    std::mt19937 rng(20);
    std::uniform_real_distribution<double> u(-1, 1);
    Scene scene = occlusion_scene(8, 1.5, 0.05);
    scene.camera.eye = {0, 3, 4};
    scene.camera.look_at = {0, 0, 0};
    scene.camera.width = scene.camera.height = 32;
    scene.materials[0].kd = 0.6;
    scene.directional_lights.push_back({{0.3, 1, 0.2}, {1, 1, 1}, 1.0, true});
    scene.objects.push_back(Object{Plane{{0, 0, 0}, {0, 1, 0}}, 0});
    for (int i = 0; i < 2000; ++i)
        scene.objects.push_back(Object{Sphere{{2 * u(rng), 0.3 + 0.25 * u(rng), 2 * u(rng)}, 0.06}, 0});
    const PacketScene ps = compile(scene);
    const ReferenceRender ref = render_reference(scene);
    for (Isa isa : simd_isas())
        for (Path path : {Path::scalar, Path::simd}) {
            const Kernel k = select_kernel(ps, path, Precision::exact, isa);
            CAPTURE(k.name());
            const PacketRender out = render_packet(k, ps);
            const Agreement a = compare(ref, out.radiance, out.primitive);
            CHECK(a.within(Tolerance{}));
            CHECK(double(a.occlusion_grazing) <= 0.05 * double(a.lanes));
        }
}

TEST_CASE("occlusion: beside an infinite wall, the visible fraction is the closed form for cosine sampling") {
    // Floor y = 0, wall x = 0, the point (a, 0, 0), rays up to distance D. A
    // sample is blocked when it meets the wall before D: d.x < -a/D. Cosine
    // sampling makes (d.x, d.z) uniform on the unit disk, so the blocked
    // fraction is the area of the disk's segment x < -c, c = a/D, over pi:
    // visible = 1 - (acos c - c sqrt(1 - c^2)) / pi (1/2 at D = infinity).
    // 64 pixels x 256 samples: sampling error sqrt(p (1 - p) / 16384) < 0.004;
    // the check allows four of it.
    const int pixels = 64, samples = 256;
    for (const double c : {0.0, 0.3, 0.7}) {
        CAPTURE(c);
        const double a = 0.5, distance = c == 0 ? 1e30 : a / c;
        const double expected = 1 - (std::acos(c) - c * std::sqrt(1 - c * c)) / kPi;
        Scene s = occlusion_scene(samples, distance);
        s.objects.push_back(Object{Plane{{0, 0, 0}, {0, 1, 0}}, 0});
        s.objects.push_back(Object{Plane{{0, 0, 0}, {1, 0, 0}}, 0});
        const Factors f = factors_at(s, {a, 1, 0}, {0, -1, 0}, pixels);
        CHECK(std::fabs(mean(f.reference) - expected) < 0.016);
        for (const auto& k : f.kernels) {
            // The kernels count the reference's samples: equal but for a sample within rounding of t = D.
            CHECK(std::fabs(mean(k) - mean(f.reference)) <= 1.0 / samples);
            CHECK(std::fabs(mean(k) - expected) < 0.016);
        }
    }
}

TEST_CASE("occlusion: scenes/aobench.json at 64x64 on the scalar and SIMD paths agrees with the reference and to the bit") {
    Scene scene = load_repo_scene("aobench");
    scene.camera.width = scene.camera.height = 64;
    scene.ambient_occlusion->samples = 16;
    const PacketScene ps = compile(scene);
    const ReferenceRender ref = render_reference(scene);
    const Tolerance tol;
    std::vector<PacketRender> renders;
    for (Isa isa : simd_isas())
        for (Path path : {Path::scalar, Path::simd}) {
            const Kernel k = select_kernel(ps, path, Precision::exact, isa);
            CAPTURE(k.name());
            CHECK((k.light_bits & kOcclusion) != 0);
            const PacketRender& out = renders.emplace_back(render_packet(k, ps));
            const Agreement a = compare(ref, out.radiance, out.primitive);
            CHECK(a.within(tol));
            // Few lanes graze: at most 2% here (the spheres' contacts with the floor).
            CHECK(double(a.occlusion_grazing) <= 0.02 * double(a.lanes));
        }
    for (std::size_t i = 1; i < renders.size(); ++i) CHECK(renders[0].radiance.rgb == renders[i].radiance.rgb);
    // The general kernel (every feature, occlusion checked at run time) gives the same image.
    const PacketRender general = render_packet(general_kernel(Path::simd), ps);
    CHECK(general.radiance.rgb == renders[0].radiance.rgb);
}

TEST_CASE("occlusion: the image does not depend on the number of threads") {
    Scene scene = load_repo_scene("aobench");
    scene.camera.width = scene.camera.height = 96;
    scene.ambient_occlusion->samples = 8;
    const PacketScene ps = compile(scene);
    for (Path path : {Path::scalar, Path::simd}) {
        const Kernel k = select_kernel(ps, path);
        const PacketRender one = render_packet(k, ps, 1), three = render_packet(k, ps, 3);
        CHECK(one.radiance.rgb == three.radiance.rgb);
    }
}

TEST_CASE("occlusion: the loader reads ambient.occlusion with its defaults and rejects bad values by path") {
    const std::string head = R"({"camera": {"type": "pinhole", "eye": [0,0,5], "look_at": [0,0,0], "up": [0,1,0],
        "fov_y": 45, "width": 8, "height": 8}, "materials": {}, "objects": [], "ambient": )";
    const Scene plain = parse_scene(head + R"({"ls": 0.5}})", "t.json");
    CHECK(!plain.ambient_occlusion);
    const Scene defaults = parse_scene(head + R"({"occlusion": {}}})", "t.json");
    REQUIRE(defaults.ambient_occlusion);
    CHECK(defaults.ambient_occlusion->samples == 16);
    CHECK(defaults.ambient_occlusion->distance == 1e30);
    CHECK(defaults.ambient_occlusion->min_amount == 0);
    const Scene set = parse_scene(head + R"({"occlusion": {"samples": 64, "distance": 2.5, "min_amount": 0.1}}})", "t.json");
    CHECK(set.ambient_occlusion->samples == 64);
    CHECK(set.ambient_occlusion->distance == 2.5);
    CHECK(set.ambient_occlusion->min_amount == 0.1);
    auto error = [&](const std::string& occlusion) {
        try {
            parse_scene(head + R"({"occlusion": )" + occlusion + "}}", "t.json");
        } catch (const SceneError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    CHECK(error(R"({"samples": 0})") == "t.json: ambient.occlusion.samples: must be in [1, 65536], got 0");
    CHECK(error(R"({"samples": 2.5})") == "t.json: ambient.occlusion.samples: must be an integer, got 2.5");
    CHECK(error(R"({"distance": 0})") == "t.json: ambient.occlusion.distance: must be > 0, got 0");
    CHECK(error(R"({"min_amount": 1.5})") == "t.json: ambient.occlusion.min_amount: must be in [0, 1], got 1.5");
    CHECK(error(R"({"sample": 4})").find("ambient.occlusion.sample: unknown field") != std::string::npos);
    // validate(): occlusion needs an ambient light.
    Scene bad = defaults;
    bad.ambient.reset();
    CHECK_THROWS_WITH_AS(validate(bad), "ambient_occlusion: needs an ambient light (Scene::ambient) to occlude",
                         std::invalid_argument);
}
