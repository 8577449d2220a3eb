// compile(): what it rejects in scenes built in code, and its options.
#include <doctest/doctest.h>

#include "support.hpp"

#include "kernels/scene_data.hpp"
#include "scene_loader.hpp"
#include "verify.hpp"

#include <octray/kernels.hpp>
#include <octray/reference.hpp>
#include <octray/threads.hpp>

#include <string>
#include <vector>

using namespace octray;
using namespace octray::test;

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

// SphereArrays: centres' residuals in 16 bits where each decodes to within
// 2^-27 of its radius of the exact one, as floats where one would not.
TEST_CASE("compile: sphere centre residuals in 16 bits near the origin, as floats far from it") {
    RandomRays rays(23);
    Scene near = one_object_scene(Sphere{{0.1, 0.2, 0.3}, 0.5});
    for (int i = 0; i < 200; ++i)
        near.objects.push_back(Object{Sphere{rays.in_cube(50), rays.uniform(0.02, 0.5)}, 0});
    const PacketScene a = compile(near);
    const SphereArrays& sa = scene_data(a).spheres;
    REQUIRE(!sa.cx_q.empty());
    CHECK(sa.cx_lo.empty());
    for (std::size_t k = 0; k < near.objects.size(); ++k) {
        // compiled position k's sphere: its primitive id through object_of
        const Sphere& s = std::get<Sphere>(near.objects[std::size_t(scene_data(a).object_of[k])].shape);
        CHECK(double(sa.cx[k]) == double(f(s.center.x)));
        CHECK(std::fabs(double(residual16(sa.cx[k], sa.cx_q[k])) - (s.center.x - double(sa.cx[k]))) <=
              std::ldexp(s.radius, -27));
        CHECK(std::fabs(double(residual16(sa.cz[k], sa.cz_q[k])) - (s.center.z - double(sa.cz[k]))) <=
              std::ldexp(s.radius, -27));
    }
    Scene far = near;
    far.objects.push_back(Object{Sphere{{1e7 + 0.1, 0.3, 0.7}, 0.01}, 0});  // |c| / r = 1e9
    const PacketScene b = compile(far);
    const SphereArrays& sf = scene_data(b).spheres;
    CHECK(sf.cx_q.empty());
    CHECK(!sf.cx_lo.empty());

    // A centre half a float ulp from two floats rounds to the even one: the
    // residual is then exactly 2^15 units of 2^(e - 39). 1 + 3 * 2^-24 rounds
    // up to 1 + 2^-22, k = -32768, which int16 holds; 1 + 2^-24 rounds down
    // to 1, k = +32768, stored as 32767: one unit (2^-39) off, within the
    // tolerance 2^-27 r for r = 1, beyond it for r = 2^-13 (floats are kept).
    Scene tie_low = one_object_scene(Sphere{{1.0 + 3 * std::ldexp(1.0, -24), 0.25, 0.5}, 1.0});
    const PacketScene c = compile(tie_low);
    REQUIRE(!scene_data(c).spheres.cx_q.empty());
    CHECK(scene_data(c).spheres.cx_q[0] == -32768);
    CHECK(double(residual16(scene_data(c).spheres.cx[0], scene_data(c).spheres.cx_q[0])) == -std::ldexp(1.0, -24));
    Scene tie_high = one_object_scene(Sphere{{1.0 + std::ldexp(1.0, -24), 0.25, 0.5}, 1.0});
    const PacketScene d = compile(tie_high);
    REQUIRE(!scene_data(d).spheres.cx_q.empty());
    CHECK(scene_data(d).spheres.cx_q[0] == 32767);
    CHECK(double(residual16(scene_data(d).spheres.cx[0], scene_data(d).spheres.cx_q[0])) ==
          std::ldexp(1.0, -24) - std::ldexp(1.0, -39));
    Scene tie_high_small = one_object_scene(Sphere{{1.0 + std::ldexp(1.0, -24), 0.25, 0.5}, std::ldexp(1.0, -13)});
    const PacketScene e = compile(tie_high_small);
    CHECK(scene_data(e).spheres.cx_q.empty());
    CHECK(double(scene_data(e).spheres.cx_lo[0]) == std::ldexp(1.0, -24));
}

TEST_CASE("CompileOptions: the thread count never changes the tree; bad options are refused") {
    Scene s = one_object_scene(Sphere{{0, 0, 0}, 1});
    RandomRays rays(11);
    for (int i = 0; i < 300; ++i) s.objects.push_back(Object{Sphere{fl(rays.in_cube(5)), f(rays.uniform(0.05, 0.3))}, 0});
    CompileOptions one, three;
    one.threads = 1, three.threads = 3;
    const PacketScene a = compile(s, one), b = compile(s, three), every = compile(s);
    CHECK(scene_data(a).bvh.nodes.size() > 1);
    for (const PacketScene* p : {&b, &every}) {
        CHECK(scene_data(*p).object_of == scene_data(a).object_of);  // the leaf order
        CHECK(scene_data(*p).bvh.nodes.size() == scene_data(a).bvh.nodes.size());
        CHECK(scene_data(*p).spheres.cx == scene_data(a).spheres.cx);
    }
    CHECK(resolve_threads(5) == 5);  // the one rule: n > 0 is n, 0 every core
    CHECK(resolve_threads(0) >= 1);
    for (auto broken : {+[](CompileOptions& o) { o.threads = -1; }, +[](CompileOptions& o) { o.sah.max_leaf_size = 0; },
                        +[](CompileOptions& o) { o.sah.bins = 1; }, +[](CompileOptions& o) { o.sah.intersection_cost = 0; },
                        +[](CompileOptions& o) { o.sah.leaf_block = 0; }}) {
        CompileOptions o;
        broken(o);
        CHECK_THROWS_AS(compile(s, o), std::invalid_argument);
    }
}

TEST_CASE("CompileOptions: the SAH presets build what compile() accepts; the deprecated fields still count") {
    Scene s = one_object_scene(Sphere{{0, 0, 0}, 1});
    RandomRays rays(12);
    for (int i = 0; i < 300; ++i) s.objects.push_back(Object{Sphere{fl(rays.in_cube(5)), f(rays.uniform(0.05, 0.3))}, 0});
    const PacketScene balanced = compile(s);
    for (const SahOptions& preset : {SahOptions::fast_build(), SahOptions::high_quality()}) {
        CompileOptions o;
        o.sah = preset;
        const PacketScene p = compile(s, o);
        CHECK(scene_data(p).bvh.primitive_count() == scene_data(balanced).bvh.primitive_count());
    }
    // A deprecated field that differs from its default stands in for sah's:
    // an out-of-range one is refused, an in-range one builds sah's tree.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
    CompileOptions old_bad, old_leaf, new_leaf;
    old_bad.bins = 1;
    CHECK_THROWS_AS(compile(s, old_bad), std::invalid_argument);
    old_leaf.max_leaf_size = 2;
#pragma GCC diagnostic pop
    new_leaf.sah.max_leaf_size = 2;
    const PacketScene a = compile(s, old_leaf), b = compile(s, new_leaf);
    CHECK(scene_data(a).object_of == scene_data(b).object_of);
    CHECK(scene_data(a).bvh.nodes.size() == scene_data(b).bvh.nodes.size());
    CHECK(scene_data(a).bvh.nodes.size() != scene_data(balanced).bvh.nodes.size());
}
