// tests/test_mesh_transform.cpp — MeshTransform as the model loader applies it:
// translate, rotate and scale against analytic bounds, the matrix form against
// that form, and the validation of both.
#include "model_fixtures.hpp"
#include "model_loader.hpp"

#include <octray/constants.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <string>

namespace fs = std::filesystem;
using namespace octray;
using namespace model_fixtures;

TEST_CASE("MeshTransform: translate, rotate and scale of a unit cube give the analytic bounds") {
    TempDir dir;
    // The unit cube [0,1]^3 written here as 12 triangles (assimp-testmodels' PLY/cube.ply is
    // the same cube; this one does not need the package).
    const std::string cube = dir.write("cube.obj",
                                       "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                                       "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n");
    SUBCASE("identity") {
        const MeshData m = load_model(cube);
        CHECK(m.triangle_count() == 12);
        CHECK(m.vertices.size() == 8);
        Bounds want;
        want.lo = {0, 0, 0};
        want.hi = {1, 1, 1};
        check_bounds(bounds_of(m), want, 0);
    }
    SUBCASE("scale 2, 90 degrees about y, translate (1,2,3): exact") {
        // Scaled: [0,2]^3. About y by +90: (x, y, z) -> (z, y, -x): x in [0,2], z in [-2,0].
        const MeshData m = load_model(cube, MeshTransform::from_trs({1, 2, 3}, {0, 90, 0}, 2));
        Bounds want;
        want.lo = {1, 2, 1};
        want.hi = {3, 4, 3};
        check_bounds(bounds_of(m), want, 0);
    }
    SUBCASE("scale 1.5, 30 degrees about z, translate (-1, 0.5, 4)") {
        // (x, y) -> (x cos - y sin, x sin + y cos): x from -s sin to s cos, y from 0 to s (sin + cos).
        const double s = 1.5, sn = 0.5, cs = std::sqrt(3.0) / 2;
        const MeshData m = load_model(cube, MeshTransform::from_trs({-1, 0.5, 4}, {0, 0, 30}, s));
        Bounds want;
        want.lo = {-1 - s * sn, 0.5, 4};
        want.hi = {-1 + s * cs, 0.5 + s * (sn + cs), 4 + s};
        check_bounds(bounds_of(m), want, 1e-12);
    }
    SUBCASE("scale 0.75, (10, 20, 30) degrees: x first, then y, then z") {
        // Each corner turned one axis at a time, written out here without matrices.
        const double s = 0.75, d = kPi / 180;
        const Vec3d t{0.25, -3, 7};
        Bounds want;
        for (int c = 0; c < 8; ++c) {
            double x = s * (c & 1), y = s * ((c >> 1) & 1), z = s * ((c >> 2) & 1), u;
            u = y * std::cos(10 * d) - z * std::sin(10 * d); z = y * std::sin(10 * d) + z * std::cos(10 * d); y = u;
            u = z * std::cos(20 * d) - x * std::sin(20 * d); x = z * std::sin(20 * d) + x * std::cos(20 * d); z = u;
            u = x * std::cos(30 * d) - y * std::sin(30 * d); y = x * std::sin(30 * d) + y * std::cos(30 * d); x = u;
            want.add({x + t.x, y + t.y, z + t.z});
        }
        const MeshData m = load_model(cube, MeshTransform::from_trs(t, {10, 20, 30}, s));
        check_bounds(bounds_of(m), want, 1e-12);
    }
}

TEST_CASE("MeshTransform: the matrix form equals the translate/rotate/scale form") {
    TempDir dir;
    const std::string file = dir.write("tet.obj", "v 0.1 0.2 0.3\nv 1.7 -0.4 0.9\nv -0.6 1.3 0.5\nv 0.3 0.2 -1.1\n"
                                                  "f 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n");
    // Scale 2, +90 degrees about y, translate (1, 2, 3), written by hand:
    // (x, y, z) -> (2z + 1, 2y + 2, -2x + 3).
    const Matrix4d hand{0, 0, 2, 1, 0, 2, 0, 2, -2, 0, 0, 3, 0, 0, 0, 1};
    const MeshTransform trs = MeshTransform::from_trs({1, 2, 3}, {0, 90, 0}, 2);
    CHECK(trs.to_matrix() == hand);
    const MeshData a = load_model(file, trs);
    const MeshData b = load_model(file, MeshTransform::from_matrix(hand));
    REQUIRE(a.vertices.size() == b.vertices.size());
    CHECK(a.indices == b.indices);
    for (std::size_t i = 0; i < a.vertices.size(); ++i) {
        CHECK(a.vertices[i].x == b.vertices[i].x);
        CHECK(a.vertices[i].y == b.vertices[i].y);
        CHECK(a.vertices[i].z == b.vertices[i].z);
    }
    // Vertex 0 (0.1, 0.2, 0.3) as read in double (tinyobjloader's parser is within an ulp
    // of the nearest double), then mapped.
    CHECK(a.vertices[0].x == doctest::Approx(2 * 0.3 + 1.0).epsilon(1e-15));
    CHECK(a.vertices[0].y == doctest::Approx(2 * 0.2 + 2.0).epsilon(1e-15));
    CHECK(a.vertices[0].z == doctest::Approx(-2 * 0.1 + 3.0).epsilon(1e-15));

    // A general one: the matrix of the TRS form, given as a matrix, maps every vertex alike.
    const MeshTransform general = MeshTransform::from_trs({-4, 0.5, 2}, {12.5, -70, 200}, 0.3);
    const MeshData c = load_model(file, general);
    const MeshData d = load_model(file, MeshTransform::from_matrix(general.to_matrix()));
    CHECK(c.indices == d.indices);
    for (std::size_t i = 0; i < c.vertices.size(); ++i) CHECK(c.vertices[i].x == d.vertices[i].x);
}

TEST_CASE("MeshTransform: validation") {
    CHECK(MeshTransform{}.problem().empty());
    CHECK(MeshTransform{}.to_matrix() == Matrix4d{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1});
    CHECK(scale_problem(1e-300).empty());
    CHECK(scale_problem(0) == "must be finite and > 0, got 0");
    CHECK(scale_problem(-1) == "must be finite and > 0, got -1");
    CHECK(scale_problem(std::nan("")) == "must be finite and > 0, got nan");
    CHECK(translate_problem({0, INFINITY, 0}) == "must be finite, got (0, inf, 0)");
    CHECK(rotate_deg_problem({0, 0, NAN}).rfind("must be finite", 0) == 0);
    CHECK(MeshTransform::from_trs({0, 0, 0}, {0, 0, 0}, -2).problem() == "scale: must be finite and > 0, got -2");

    CHECK(matrix_problem({1e-6, 0, 0, 5, 0, 1e-6, 0, 0, 0, 0, 1e-6, 0, 0, 0, 0, 1}).empty());  // tiny, fine
    CHECK(matrix_problem({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 1}) ==
          "must be affine (last row 0 0 0 1), got 0 0 1 1");
    CHECK(matrix_problem({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1}) ==
          "must be invertible (row 2 of the 3x3 part is zero)");
    CHECK(matrix_problem({1, 0, 0, 0, 0, 1, 0, 0, 1, 1, 1e-14, 0, 0, 0, 0, 1}).rfind("must be invertible", 0) == 0);
    CHECK(matrix_problem({1, 2, 3, 0, 4, 5, 6, 0, 7, 8, 9, 0, 0, 0, 0, 1}).rfind("must be invertible", 0) == 0);
    CHECK(matrix_problem({1, 0, 0, NAN, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}) == "must be finite, got nan");
    CHECK(MeshTransform::from_matrix({2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2}).problem() ==
          "matrix: must be affine (last row 0 0 0 1), got 0 0 0 2");

    TempDir dir;
    const std::string tri = dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    CHECK(load_error(tri, MeshTransform::from_trs({0, 0, 0}, {0, 0, 0}, 0)) ==
          "transform: scale: must be finite and > 0, got 0");
    CHECK(load_error(tri, MeshTransform::from_trs({0, 0, 0}, {0, 0, 0}, 1e308)).empty());
    // Valid, but it sends a vertex past the largest double.
    CHECK(load_error(tri, MeshTransform::from_trs({1e308, 0, 0}, {0, 0, 0}, 1e308)) ==
          "vertex 1 is not finite after the transform: (inf, 0, 0)");
}
