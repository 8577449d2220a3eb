// tests/test_model_collect.cpp — collect_model (io/model_collect.cpp), the common tail of
// every model reader: instances transformed in double, vertices shared by exact position
// in first-use order, and an instance's cost bounded by its mesh's triangles.
#include "model_fixtures.hpp"
#include "model_formats.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

using namespace octray;
using namespace octray::model_formats;

TEST_CASE("collect_model: instances share vertices by position, in first-use order") {
    RawModel model;
    RawMesh quad;
    quad.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    quad.triangles = {0, 1, 2, 0, 2, 3};
    model.meshes.push_back(quad);
    RawInstance moved;
    moved.transform[3] = 1;  // x + 1: shares the quad's right edge
    model.instances = {RawInstance{}, moved, RawInstance{}};
    const MeshData m = collect_model(model, RawInstance{}.transform, "test");
    // 4 + 2 new vertices; the third instance repeats the first one's.
    const std::vector<Vec3d> want = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {2, 1, 0}};
    model_fixtures::check_positions(m.vertices, want);
    CHECK(m.indices == std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3, 1, 4, 5, 1, 5, 2, 0, 1, 2, 0, 2, 3});
}

TEST_CASE("collect_model: -0 and +0 are one position") {
    RawModel model;
    RawMesh a;
    a.positions = {{-0.0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.0, 0, 0}};
    a.triangles = {0, 1, 2, 3, 2, 1};
    model.meshes.push_back(a);
    model.instance_each_mesh();
    const MeshData m = collect_model(model, RawInstance{}.transform, "test");
    REQUIRE(m.vertices.size() == 3);
    CHECK(m.indices == std::vector<std::uint32_t>{0, 1, 2, 0, 2, 1});
}

// A mesh of many vertices and one triangle, used by many nodes (a glTF file can say
// this in a few kilobytes): each instance costs its triangle, not the mesh's vertex
// count. Per-instance arrays of the mesh's size would make this 10^10 steps.
TEST_CASE("collect_model: many instances of a mesh with many unused vertices") {
    constexpr std::uint32_t kPositions = 1000000, kInstances = 10000;
    RawModel model;
    RawMesh mesh;
    mesh.positions.assign(kPositions, Vec3d{5, 5, 5});
    mesh.positions[10] = {0, 0, 0};
    mesh.positions[20] = {1, 0, 0};
    mesh.positions[30] = {0, 1, 0};
    mesh.triangles = {10, 20, 30};
    model.meshes.push_back(mesh);
    for (std::uint32_t i = 0; i < kInstances; ++i) {
        RawInstance use;
        use.transform[11] = double(i);  // z = i
        model.instances.push_back(use);
    }
    const MeshData m = collect_model(model, RawInstance{}.transform, "test");
    REQUIRE(m.triangle_count() == kInstances);
    REQUIRE(m.vertices.size() == 3 * kInstances);
    for (std::uint32_t i = 0; i < kInstances; i += 997) {
        CAPTURE(i);
        const Vec3d& p = m.vertices[m.indices[3 * i + 1]];
        CHECK(p.x == 1);
        CHECK(p.y == 0);
        CHECK(p.z == double(i));
    }
}
