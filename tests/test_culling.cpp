// Culling (kernels/bvh/culling.hpp): what the scene's BVH lets a walk skip changes no
// result, bit for bit.
#include <doctest/doctest.h>

#include "support.hpp"

#include "dispatch/isa_kernels.hpp"
#include "kernels/scene_data.hpp"
#include "scene_loader.hpp"
#include "verify.hpp"

#include <octray/kernels.hpp>
#include <octray/reference.hpp>

#include <cmath>
#include <random>
#include <cstring>
#include <string>
#include <vector>

using namespace octray;
using namespace octray::test;

TEST_CASE("BVH culling: scenes of hundreds of primitives agree with the reference, and the paths bit for bit") {
    // Many primitives of every type, scattered, so packets skip most of the
    // BVH and test a few leaves: culling must change no lane.
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
    // Every bounded primitive is in exactly one leaf, as a run of its type's
    // compiled arrays, inside every box on its way down; planes are not.
    const SceneData& data = scene_data(ps);
    REQUIRE(!data.bvh.empty());
    std::vector<int> seen(std::size_t(ps.primitive_count()), 0);
    bvh::for_each_node(data.bvh, [&](const bvh::Node8& node) {  // each leaf as the walks find it (its record may be released)
        for (int c = 0; c < bvh::kWidth; ++c) {
            if (node.child[c] >= 0 || node.child[c] == bvh::kEmptySlot) continue;
            bvh::Leaf scratch;
            const bvh::Leaf& leaf = bvh::leaf_of(data.bvh.leaves, node.child[c], node.run[c], scratch);
            for (int type = 0; type < kPrimitiveTypeCount; ++type)
                for (std::uint32_t k = leaf.begin[type]; k < leaf.begin[type] + leaf.count[type]; ++k)
                    ++seen[std::size_t(data.offset[std::size_t(type)]) + k];
        }
    });
    for (int type = 0; type < kPrimitiveTypeCount; ++type)
        for (int k = 0; k < data.count[std::size_t(type)]; ++k) {
            CAPTURE(type);
            CHECK(seen[std::size_t(data.offset[std::size_t(type)] + k)] == (type == int(PrimitiveType::plane) ? 0 : 1));
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
    // The tree only skips work: with every box infinite (nothing culled,
    // every primitive tested) the image is the same, bit for bit.
    CompileOptions flat;
    flat.acceleration = CompileOptions::Acceleration::none;
    const PacketScene unculled = compile(s, flat);
    for (Path path : {Path::scalar, Path::simd}) {
        const PacketRender all = render_packet(select_kernel(unculled, path), unculled);
        CHECK(all.radiance.rgb == out[int(path)].radiance.rgb);
        CHECK(all.primitive == out[int(path)].primitive);
    }

    // Any-hit (shadow) queries skip leaves the same way: against the
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

TEST_CASE("the BVH walk skips only what no ray of the packet could hit: bundles of every coherence, bit for bit") {
    // 1200 small primitives (spheres, boxes, triangles) in a 40-unit cube: a
    // tree several levels deep. Packets: bundles around a random ray whose lanes
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
    REQUIRE(scene_data(culled).bvh.depth >= 3);
    CompileOptions flat;
    flat.acceleration = CompileOptions::Acceleration::none;
    const PacketScene unculled = compile(s, flat);
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
            // The general kernel: every type compiled into the leaf tests.
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
