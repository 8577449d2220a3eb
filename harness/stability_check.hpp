// harness/stability_check.hpp — how a stability case measures a Tracer: the rays
// as authored (Lane), running them through the tracer (run), the double
// reference on the same float inputs, the checks against it and the small scene
// builders the cases share. The error model is in stability_cases.hpp.
//
// The cases themselves live one family per file (stability_spheres.cpp,
// stability_planar.cpp, stability_meshes.cpp, stability_lighting.cpp,
// stability_inputs.cpp); stability_cases.cpp lists them in table order.
#pragma once

#include "stability_cases.hpp"

#include <octray/reference.hpp>

#include <cstddef>
#include <initializer_list>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace octray::stability::detail {

constexpr double kInf = std::numeric_limits<double>::infinity();

// ---- float inputs ----------------------------------------------------------------

// x rounded to float (see stability_check.cpp for why through a volatile).
double fl(double x);
Vec3d fl(const Vec3d& v);
double norm(const Vec3d& v);
// A unit vector as the kernels see it: normalized in double, rounded to float.
Vec3d dir(double x, double y, double z);
// snprintf into a string: at most four doubles.
std::string fmt(const char* f, double a, double b = 0, double c = 0, double d = 0);
double uniform(std::mt19937& rng, double lo, double hi);

// ---- running a tracer ---------------------------------------------------------------

// One ray as authored: every number already a float (as a double), and
// optionally the rounding residuals of a double ray (RayPacket::ox_lo...):
// the ray is then o + o_lo, d + d_lo, and the reference traces that.
struct Lane {
    Vec3d o, d;
    double tmin = 0, tmax = kInf;
    bool active = true;
    Vec3d o_lo{}, d_lo{};
};

// What the tracer returned for one lane.
struct Out {
    bool hit = false;
    int object = -1;
    double t = 0;
    Vec3d n, L, shown;
};

struct Traced {
    std::vector<Out> lanes;
    int masked = 0;
    double eps = kUnitRoundoff;  // the mode's bound for 1/x and 1/sqrt(x)
    bool flush = false;
    std::string note;  // e.g. "ran as fast" when the CPU lacks a mode
};

// OCTRAY_STABILITY_DEBUG=1 in the environment: every lane's error on stderr.
bool debug();

// Compiles the scene and runs the lanes through the tracer, 8 to a packet,
// with flush-to-zero and denormals-are-zero set (flush) or cleared.
Traced run(const Tracer& tr, const Scene& scene, const std::vector<Lane>& lanes, bool flush = false);

// ---- the reference side ---------------------------------------------------------------

reference::Ray ref_ray(const Lane& l);
double ref_tmax(const Lane& l);
reference::Hit ref_trace(const Scene& scene, const Lane& l);

// S of the error model for a lane: origin, hit point and the primitives involved.
double lane_scale(const Scene& scene, const Lane& l, const reference::Hit& h, int other_object);

// True when `pred` holds for the reference's hit of the ray with the origin
// moved by 4 u S or the direction by 4 u |d| along some axis (12 rays).
template <class Pred>
bool any_perturbation(const Scene& scene, const Lane& l, double scale, Pred pred) {
    for (int axis = 0; axis < 3; ++axis)
        for (double sign : {-1.0, 1.0}) {
            Vec3d e;
            (axis == 0 ? e.x : axis == 1 ? e.y : e.z) = sign * 4 * kUnitRoundoff;
            Lane moved = l, turned = l;
            moved.o = l.o + e * scale;
            turned.d = l.d + e * norm(l.d);
            if (pred(ref_trace(scene, moved)) || pred(ref_trace(scene, turned))) return true;
        }
    return false;
}

// True when the reference's answer (which object) changes under such a
// perturbation: the ray is within its own rounding of a boundary, where
// either answer is right.
bool ambiguous(const Scene& scene, const Lane& l, double scale);

// ---- checks ------------------------------------------------------------------------

struct HitOptions {
    bool exact_inputs = false;  // |dt| <= K eps |t| only (no u S term)
    bool strict = false;        // a boundary rule decides: no ambiguity allowed
};

struct RadianceOptions {
    bool exact_inputs = false;  // the scene's floats are exact: only the modes' errors count
};

// Hit/miss, primitive and t of every active lane against the reference.
Measure check_hits(const Scene& scene, const std::vector<Lane>& lanes, const Traced& tr, HitOptions opt = {});
// Lanes that must come out masked (counted, missed, background, finite).
Measure check_masked(const Scene& scene, const std::vector<Lane>& lanes, const Traced& tr, const std::vector<bool>& masked);
// check_hits and the radiance check (stability_check.cpp); the worse error.
Measure check_all(const Scene& scene, const std::vector<Lane>& lanes, const Traced& tr, HitOptions ho = {},
                  RadianceOptions ro = {});

// Merges the measure of one more scene of a case into `m`.
void merge(Measure& m, const Measure& more);
// The tracer's note (e.g. a mode's fallback) when nothing failed.
void add_note(Measure& m, const Traced& tr);

// Runs `lanes` through the tracer and checks the hits (measure_hits) or hits
// and radiance (measure_all) against the reference.
Measure measure_hits(const Tracer& tr, const Scene& s, const std::vector<Lane>& lanes, HitOptions opt = {});
Measure measure_all(const Tracer& tr, const Scene& s, const std::vector<Lane>& lanes, HitOptions ho = {},
                    RadianceOptions ro = {});

// ---- scene building ------------------------------------------------------------------

Material matte(const char* name = "m", Vec3d cd = {1, 1, 1}, double ka = 0.0, double kd = 0.65);
// The shapes with one matte material.
Scene scene_of(std::vector<Shape> shapes);
// A ray from o toward `target` with the float-rounded unit direction.
Lane toward(const Vec3d& o, const Vec3d& target);
// The same ray in double (o as given, the unit direction unrounded), carried
// as float + residual: the camera kernel's kind of ray.
Lane toward_exact(const Vec3d& o, const Vec3d& target);
// Rays straight down (-z) from height h onto points (x, y, 0): t = h exactly.
std::vector<Lane> down_onto(std::initializer_list<std::pair<double, double>> xy, double h = 1);

// ---- the cases, one family per file ----------------------------------------------------

// stability_spheres.cpp: spheres near and far, tiny and huge, tangents, the
// camera inside, the origin on the surface; normals in the sphere's frame.
Measure planet(const Tracer& tr);
Measure planet_exact(const Tracer& tr);
Measure tiny_sphere(const Tracer& tr);
Measure far_sphere(const Tracer& tr, double distance);
Measure small_far_outline(const Tracer& tr);
// Shared with stability_pinhole.cpp: rays from o at c + (f r) e (three
// directions e across c - o per fraction f), and the hit and normal checks
// (the normals against the reference's on the same float rays; the naive
// column the kernels' earlier n = (o + t d - c) / r).
std::vector<Lane> sphere_probe(const Vec3d& o, const Vec3d& c, double r, std::initializer_list<double> fractions,
                               Lane (*ray)(const Vec3d&, const Vec3d&) = toward);
Measure measure_frame(const Tracer& tr, const Scene& s, const std::vector<Lane>& lanes);
Measure small_sphere_field(const Tracer& tr);
Measure large_far_sphere(const Tracer& tr);
Measure tangent_rays(const Tracer& tr);
Measure camera_inside(const Tracer& tr);
Measure origin_on_surface(const Tracer& tr);

// stability_pinhole.cpp: small spheres through a pinhole camera's rays:
// a wide angle near the outline, a far telephoto field; each with float
// inputs, and with a double eye, centres and rays (float + residual).
Measure pinhole_wide_outline(const Tracer& tr);
Measure pinhole_far_field(const Tracer& tr);
Measure pinhole_wide_outline_double(const Tracer& tr);
Measure pinhole_far_field_double(const Tracer& tr);
// stability_shadows.cpp: shadow rays on meshes, a blocker 0.02 above the surface.
Measure mesh_shadows(const Tracer& tr);
// stability_planar.cpp: planes, disks, rectangles and boxes: parallel and
// grazing rays, rims, edges and corners.
Measure plane_parallel(const Tracer& tr);
Measure plane_in_plane(const Tracer& tr);
Measure plane_grazing(const Tracer& tr);
Measure disk_rim(const Tracer& tr);
Measure rectangle_edges(const Tracer& tr);
Measure box_origin_on_face(const Tracer& tr);
Measure box_zero_components(const Tracer& tr);
Measure box_edges_corners(const Tracer& tr);

// stability_meshes.cpp: watertight triangle meshes, a ray in a triangle's plane.
Measure mesh_edges(const Tracer& tr);
Measure mesh_vertices(const Tracer& tr);
Measure triangle_in_plane(const Tracer& tr);

// stability_lighting.cpp: grazing light, dynamic range, point lights near
// and at the hit point, radiance past FLT_MAX.
Measure grazing_light(const Tracer& tr);
Measure lights_dynamic_range(const Tracer& tr);
Measure lights_64_decades(const Tracer& tr);
Measure point_light_near(const Tracer& tr);
Measure point_light_zero(const Tracer& tr);
Measure radiance_overflow(const Tracer& tr);

// stability_inputs.cpp: zero, NaN and infinite directions, subnormal inputs,
// coordinates near 1e19.
Measure zero_direction(const Tracer& tr);
Measure nan_direction(const Tracer& tr);
Measure inf_direction(const Tracer& tr);
Measure subnormals(const Tracer& tr, bool ftz_daz);
Measure huge_coordinates(const Tracer& tr);

}  // namespace octray::stability::detail
