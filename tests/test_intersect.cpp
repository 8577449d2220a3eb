// intersect_packet against the reference lane by lane: every primitive type on
// random rays, partial packets, and the lanes masked off for bad input.
#include <doctest/doctest.h>

#include "support.hpp"

#include "kernels/scene_data.hpp"
#include "scene_loader.hpp"
#include "verify.hpp"

#include <octray/kernels.hpp>
#include <octray/reference.hpp>
#include "reference/reference_parts.hpp"

#include <algorithm>
#include <cstring>
#include <utility>
#include <cmath>
#include <string>
#include <vector>

using namespace octray;
using namespace octray::test;

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
                        set_ray(rp, i, o, d);
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
    const Scene scene = load_repo_scene("default");
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
    const Scene scene = load_repo_scene("default");
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

// A hit's material and mesh come from its primitive id (PrimitiveOwners), not
// from per-primitive arrays: objects of many materials or of one, and few or
// many meshes (the kernel counts for a few, searches for many) of different
// sizes. Rays straight down onto a grid of spheres and mesh quads, and
// between them, against the reference's primitive and material.
// The id maps (SceneData::object_of, compiled_of) are 16 bits wide up to
// 65536 primitives and floats beyond: both widths, read by intersect (the
// primitive id) and by shade (a sphere hit's centre, through its compiled
// id), against the reference.
TEST_CASE("primitive ids and sphere shading agree with the reference below and above 65536 primitives") {
    for (const int side : {20, 265}) {  // 400 and 70225 spheres
        CAPTURE(side);
        Scene scene;
        scene.materials.push_back(Material{"m", 0.2, 0.7, {1, 0.5, 0.25}});
        for (int j = 0; j < side; ++j)
            for (int i = 0; i < side; ++i) scene.objects.push_back(Object{Sphere{{3.0 * i, 3.0 * j, 0}, 1}, 0});
        scene.point_lights.push_back(PointLight{{10, 20, 50}, {1, 1, 1}, 2000.0});
        const PacketScene ps = compile(scene);
        CHECK(scene_data(ps).object_of.narrow_ids.empty() == (side * side > 65536));
        CHECK(scene_data(ps).compiled_of.narrow_ids.empty() == (side * side > 65536));
        std::vector<int> targets;
        for (int k = 0; k < side * side; k += side * side / 61) targets.push_back(k);
        for (int k = side * side - 8; k < side * side; ++k) targets.push_back(k);
        auto ray_at = [&](int k) {
            return reference::Ray{{f(3.0 * (k % side) + 0.3), f(3.0 * (k / side) - 0.2), 5.0}, {0, 0, -1}};
        };
        std::vector<Vec3d> want;
        for (const int k : targets) {
            const reference::Hit hit = reference::trace(scene, ray_at(k));
            REQUIRE(hit.object == k);
            want.push_back(reference::shade(scene, ray_at(k), hit));
        }
        for (Isa isa : simd_isas())
            for (Path path : {Path::scalar, Path::simd}) {
                const Kernel kernel = select_kernel(ps, path, Precision::exact, isa);
                for (std::size_t first = 0; first < targets.size(); first += kPacketWidth) {
                    RayPacket8 rp;
                    HitPacket8 hp;
                    ColorPacket8 color;
                    for (int i = 0; i < kPacketWidth; ++i) {
                        const reference::Ray ray = ray_at(targets[std::min(first + std::size_t(i), targets.size() - 1)]);
                        set_ray(rp, i, ray.origin, {0, 0, -1});
                    }
                    REQUIRE(kernel.intersect(ps, rp, hp) == 0);
                    kernel.shade(ps, rp, hp, color);
                    for (int i = 0; i < kPacketWidth; ++i) {
                        const std::size_t t = std::min(first + std::size_t(i), targets.size() - 1);
                        CHECK(hp.primitive[i] == targets[t]);
                        CHECK(std::fabs(color.r[i] - want[t].x) <= 1e-4 * want[t].x);
                        CHECK(std::fabs(color.b[i] - want[t].z) <= 1e-4 * want[t].z);
                    }
                }
            }
    }
}

TEST_CASE("hits report the material and mesh of their primitive, for any number of meshes") {
    for (const int mesh_count : {0, 1, 3, 17, 40})
        for (const bool common_material : {false, true}) {
            CAPTURE(mesh_count);
            CAPTURE(common_material);
            Scene scene;
            for (int m = 0; m < 5; ++m) scene.materials.push_back(Material{"m" + std::to_string(m), 0.2, 0.7, {1, 1, 1}});
            std::vector<Vec3d> targets;  // above each primitive's middle, then between them
            const int spheres = 11;
            for (int i = 0; i < spheres; ++i) {
                scene.objects.push_back(Object{Sphere{{3.0 * i, 0, 0}, 1}, common_material ? 2 : (i * 3) % 5});
                targets.push_back({3.0 * i, 0, 5});
            }
            std::vector<int> mesh_of_primitive(std::size_t(spheres), -1);
            for (int m = 0; m < mesh_count; ++m) {
                Mesh mesh;
                mesh.material = (m * 2 + 1) % 5;
                // A quad at y = 5; every fifth mesh (from the second) a second one at y = 9.
                for (const double y : {5.0, 9.0}) {
                    if (y == 9.0 && m % 5 != 1) break;
                    const double x = 3.0 * m;
                    const auto v = std::uint32_t(mesh.vertices.size());
                    mesh.vertices.insert(mesh.vertices.end(),
                                         {{x - 1, y - 1, 0}, {x + 1, y - 1, 0}, {x + 1, y + 1, 0}, {x - 1, y + 1, 0}});
                    mesh.indices.insert(mesh.indices.end(), {v, v + 1, v + 2, v, v + 2, v + 3});
                    targets.push_back({x + 0.4, y - 0.3, 5});  // the first triangle
                    targets.push_back({x - 0.4, y + 0.3, 5});  // the second
                    mesh_of_primitive.insert(mesh_of_primitive.end(), 2, m);
                }
                scene.meshes.push_back(std::move(mesh));
            }
            for (std::size_t k = 0, n = targets.size(); k < n; k += 3) targets.push_back(targets[k] + Vec3d{1.5, 2.5, 0});
            const PacketScene ps = compile(scene);
            for (Isa isa : simd_isas())
                for (Path path : {Path::scalar, Path::simd}) {
                    const Kernel kernel = select_kernel(ps, path, Precision::exact, isa);
                    int hits = 0;
                    for (std::size_t first = 0; first < targets.size(); first += kPacketWidth) {
                        RayPacket8 rp;
                        HitPacket8 hp;
                        for (int i = 0; i < kPacketWidth; ++i) {
                            const Vec3d o = targets[std::min(first + std::size_t(i), targets.size() - 1)];
                            set_ray(rp, i, o, {0, 0, -1});
                        }
                        REQUIRE(kernel.intersect(ps, rp, hp) == 0);
                        for (int i = 0; i < kPacketWidth; ++i) {
                            const Vec3d o{rp.ox[i], rp.oy[i], rp.oz[i]};
                            const int id = reference::trace(scene, {o, {0, 0, -1}}).object;
                            CHECK(hp.primitive[i] == id);
                            if (id < 0) {
                                CHECK(hp.material[i] == -1);
                                CHECK(hp.mesh[i] == -1);
                                continue;
                            }
                            ++hits;
                            CHECK(hp.material[i] == reference::primitive_material(scene, id));
                            CHECK(hp.mesh[i] == mesh_of_primitive[std::size_t(id)]);
                        }
                    }
                    CHECK(hits >= spheres + 2 * mesh_count);
                }
        }
}

TEST_CASE("intersect_fields: intersect's hits bit for bit, with barycentrics and geometric normals that match the reference") {
    // Every primitive type, one object at a time, every SIMD ISA and the scalar
    // path, every precision mode the unit has.
    std::vector<std::pair<Path, Isa>> kernels{{Path::scalar, Isa::best}};
    for (const Isa isa : simd_isas()) kernels.emplace_back(Path::simd, isa);
    int checked_uv = 0, checked_n = 0;
    for (int type_index = 0; type_index < kPrimitiveTypeCount; ++type_index) {
        const PrimitiveType type = PrimitiveType(type_index);
        CAPTURE(primitive_type_name(type));
        RandomRays r(77u + unsigned(type_index));
        for (int shape_index = 0; shape_index < 40; ++shape_index) {
            const Scene scene = one_object_scene(random_shape(type, r));
            const Shape& shape = scene.objects[0].shape;
            const PacketScene ps = compile(scene);
            RayPacket8 rp;
            reference::Ray refs[8];
            for (int i = 0; i < 8; ++i) {
                const Vec3d o = fl(r.in_cube(8));
                const Vec3d aim = r.in_cube(1.5) - o;
                refs[i] = {o, fl(aim * (1 / std::sqrt(dot(aim, aim))))};
                set_ray(rp, i, refs[i].origin, refs[i].direction);
            }
            for (const auto& [path, isa] : kernels)
                for (const Precision mode : kPrecisions) {
                    if (!precision_supported(mode)) continue;
                    const Kernel k = select_kernel(ps, path, mode, isa);
                    HitPacket8 plain, hp;
                    HitFields8 fields;
                    k.intersect(ps, rp, plain);
                    REQUIRE(bool(k.intersect_fields));
                    k.intersect_fields(ps, rp, hp, fields);
                    CHECK(std::memcmp(&plain, &hp, sizeof hp) == 0);
                    for (int i = 0; i < 8; ++i) {
                        if (hp.hit[i] == 0) {
                            CHECK(fields.u[i] == 0.0f);
                            CHECK(fields.ngx[i] == 0.0f);
                            continue;
                        }
                        const Vec3d p = refs[i].origin + refs[i].direction * double(hp.t[i]);
                        const Vec3d ng{fields.ngx[i], fields.ngy[i], fields.ngz[i]};
                        const Vec3d n{hp.nx[i], hp.ny[i], hp.nz[i]};
                        // The geometric normal: unit, the shading normal up to its turn toward the ray.
                        CHECK(std::fabs(length_squared(ng) - 1) <= 1e-5);
                        CHECK(std::min(length_squared(ng - n), length_squared(ng + n)) <= 1e-10);
                        const Vec3d ref_n = reference::geometric_normal(shape, p);
                        if (type != PrimitiveType::box) {  // a box edge may take either face
                            CHECK(length_squared(ng - ref_n) <= 1e-6);
                            ++checked_n;
                        }
                        // Where on the primitive: (u, v) rebuild the hit point.
                        if (const auto* tri = std::get_if<Triangle>(&shape)) {
                            const double u = fields.u[i], v = fields.v[i];
                            const Vec3d q = tri->v0 * (1 - u - v) + tri->v1 * u + tri->v2 * v;
                            const double size = std::sqrt(std::max({length_squared(tri->v1 - tri->v0),
                                                                    length_squared(tri->v2 - tri->v0), 1e-30}));
                            CHECK(std::sqrt(length_squared(q - p)) <= 1e-5 * (size + std::sqrt(length_squared(p))));
                            CHECK(u >= -1e-6);
                            CHECK(v >= -1e-6);
                            CHECK(u + v <= 1 + 1e-6);
                            ++checked_uv;
                        } else if (const auto* rect = std::get_if<Rectangle>(&shape)) {
                            const Vec3d q = rect->corner + rect->a * double(fields.u[i]) + rect->b * double(fields.v[i]);
                            CHECK(std::sqrt(length_squared(q - p)) <= 1e-5 * (1 + std::sqrt(length_squared(p))));
                            ++checked_uv;
                        } else {
                            CHECK(fields.u[i] == 0.0f);
                            CHECK(fields.v[i] == 0.0f);
                        }
                    }
                }
        }
    }
    MESSAGE(checked_uv << " lanes' (u, v) and " << checked_n << " geometric normals checked");
    CHECK(checked_uv > 1000);
    CHECK(checked_n > 2000);
}
