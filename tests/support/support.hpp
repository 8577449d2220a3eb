// tests/support/support.hpp — what the test suites and the benchmarks share: float
// rounding as the kernels see it, seeded random geometry, small scene builders,
// the ISAs this CPU runs.
#pragma once

#include <octray/kernels.hpp>
#include <octray/reference.hpp>
#include <octray/scene.hpp>

#include <random>
#include <string>
#include <vector>

namespace octray::test {

// x rounded to float, opaquely: GCC 12 -O3 otherwise vectorises away the
// (double)(float) round trip, and the reference must see floats.
float f(double x);
// Rounds to float so the reference sees exactly the geometry the kernels see.
Vec3d fl(const Vec3d& v);

// Seeded points and unit directions (rounded to float).
struct RandomRays {
    std::mt19937 rng;
    explicit RandomRays(unsigned seed) : rng(seed) {}
    double uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
    Vec3d in_cube(double h) { return {uniform(-h, h), uniform(-h, h), uniform(-h, h)}; }
    Vec3d direction();
};

// A primitive of `type` about the origin, a few units across, float-exact.
Shape random_shape(PrimitiveType type, RandomRays& r);

// True when the reference's hit/miss answer for `ray` changes under a
// perturbation of the origin or direction of relative size `rel`: the ray is
// within float rounding of the primitive's boundary, where either answer is right.
bool near_boundary(const Shape& shape, const reference::Ray& ray, double rel);

// Lane `lane` of `rp`: the ray o + t d, t in (0, inf), active; o and d rounded to float.
void set_ray(RayPacket8& rp, int lane, const Vec3d& o, const Vec3d& d);

// One object, one material (ka 0.25, kd 0.65, white), no lights.
Scene one_object_scene(const Shape& shape);

// A camera looking at the origin from `eye`, a background, and two materials
// ("a" orange, "b" blue); no objects, no lights.
Scene two_material_scene(const Vec3d& eye, int width, int height, const Vec3d& background);

// A small scene that uses exactly the features in `bits` (features.hpp).
Scene scene_with_features(unsigned bits, std::mt19937& rng);

// The instruction sets this CPU runs the SIMD path with (each pinned with select_kernel's Isa).
std::vector<Isa> simd_isas();

// scenes/NAME.json, loaded.
Scene load_repo_scene(const std::string& name);

}  // namespace octray::test
