// tests/test_mesh_generators.cpp — io/mesh_generators (uv_sphere,
// height_field) and save_ply, whose binary PLY the model loader reads back.
#include "mesh_generators.hpp"
#include "model_fixtures.hpp"
#include "model_loader.hpp"

#include <doctest/doctest.h>

#include <string>

namespace fs = std::filesystem;
using namespace octray;
using namespace model_fixtures;

TEST_CASE("mesh_generators: uv_sphere and height_field") {
    const MeshData s = uv_sphere(6, 10);
    CHECK(s.vertices.size() == 5 * 10 + 2);
    CHECK(s.triangle_count() == 2 * 10 * 5);
    for (const Vec3d& v : s.vertices) CHECK(std::fabs(length_squared(v) - 1) < 1e-15);
    for (std::size_t t = 0; t < s.triangle_count(); ++t) {
        const Vec3d a = s.vertices[s.indices[3 * t]], b = s.vertices[s.indices[3 * t + 1]],
                    c = s.vertices[s.indices[3 * t + 2]];
        CAPTURE(t);
        CHECK(dot(cross(b - a, c - a), a + b + c) > 0);  // outward
    }
    const MeshData h = height_field(7);
    CHECK(h.vertices.size() == 64);
    CHECK(h.triangle_count() == 2 * 49);
    for (std::size_t t = 0; t < h.triangle_count(); ++t) {
        const Vec3d a = h.vertices[h.indices[3 * t]], b = h.vertices[h.indices[3 * t + 1]],
                    c = h.vertices[h.indices[3 * t + 2]];
        CHECK(cross(b - a, c - a).y > 0);  // facing +y
    }
    CHECK(h.vertices.front().x == -1);
    CHECK(h.vertices.back().z == 1);
    CHECK_THROWS_AS(uv_sphere(1, 10), std::invalid_argument);
    CHECK_THROWS_AS(uv_sphere(4, 2), std::invalid_argument);
    CHECK_THROWS_AS(height_field(0), std::invalid_argument);
}

TEST_CASE("save_ply: a generated mesh, written as binary PLY and loaded back, gives the same triangles") {
    TempDir dir;
    for (const MeshData& src : {uv_sphere(12, 24), height_field(9)}) {
        const std::string path = (dir.path / "mesh.ply").string();
        save_ply(src, path);
        CHECK(read_bytes(path).find("format binary_little_endian 1.0") != std::string::npos);
        const MeshData back = load_model(path);
        CHECK(back.format == "PLY");
        CHECK(back.dropped_degenerate == 0);
        REQUIRE(back.triangle_count() == src.triangle_count());
        CHECK(back.vertices.size() == src.vertices.size());
        auto as_float = [](const Vec3d& v) { return round_to_float(v); };
        for (std::size_t i = 0; i < src.indices.size(); ++i) {
            const Vec3d want = as_float(src.vertices[src.indices[i]]);
            const Vec3d got = back.vertices[back.indices[i]];
            CAPTURE(i);
            REQUIRE((got.x == want.x && got.y == want.y && got.z == want.z));
        }
    }
    MeshData bad = height_field(1);
    bad.vertices[0].x = 1e300;
    CHECK_THROWS_WITH_AS(save_ply(bad, (dir.path / "bad.ply").string()),
                         doctest::Contains("does not fit in float"), ModelError);
    bad = height_field(1);
    bad.indices[4] = 99;
    CHECK_THROWS_WITH_AS(save_ply(bad, (dir.path / "bad.ply").string()),
                         doctest::Contains("index 99 out of range (4 vertices)"), ModelError);
    CHECK_THROWS_AS(save_ply(MeshData{}, (dir.path / "empty.ply").string()), ModelError);
    CHECK_THROWS_AS(save_ply(height_field(1), (dir.path / "no" / "such" / "dir.ply").string()), ModelError);
}
