// harness/stability_cases.cpp — the catalogue of stiff and extreme cases in table
// order, and the tracers that run it (see stability_cases.hpp for the error
// model). The cases are defined one family per file (stability_check.hpp lists
// them); this file names each, states its expectation and bound, and enforces
// the bound.
#include "stability_check.hpp"

#include <string>
#include <utility>
#include <vector>

namespace octray::stability {

std::string Tracer::name() const {
    if (naive) return "naive";
    return std::string(path_name(path)) + "/" + precision_name(precision) + (label.empty() ? "" : " " + label);
}

std::vector<Tracer> kernel_tracers() {
    std::vector<Tracer> out;
    for (Path path : {Path::scalar, Path::simd})
        for (Precision p : kPrecisions) out.push_back(Tracer{path, p, false});
    return out;
}

Tracer naive_tracer() { return Tracer{Path::scalar, Precision::exact, true}; }

using namespace detail;

namespace {

const char* kTBound = "dt/(eps t + u S/cos)";
const char* kTExact = "dt/(eps t)";
const char* kLBound = "dL/(eps L + u sum F g)";
const char* kLExact = "dL/(eps L)";

Case make(std::string name, std::string expectation, std::string bound_text, double bound, Measure (*fn)(const Tracer&)) {
    return Case{std::move(name), std::move(expectation), std::move(bound_text), bound, [fn, bound](const Tracer& tr) {
                    Measure m = fn(tr);
                    if (!(m.error <= bound)) {
                        if (m.pass) m.note = "error over the bound";
                        m.pass = false;
                    }
                    return m;
                }};
}

}  // namespace

const std::vector<Case>& catalogue() {
    static const std::vector<Case> cases = [] {
        std::vector<Case> c;
        const std::string t8 = std::string(kTBound) + " <= 8", te = std::string(kTExact) + " <= 16";
        const std::string l16 = std::string(kLBound) + " <= 16", le = std::string(kLExact) + " <= 16";
        const std::string zero = "wrong lanes = 0", leaks = "leaks = 0, t err <= 8";
        c.push_back(make("planet_1e6_from_1_above", "hits down to the horizon; t to input precision", t8, 8, planet));
        c.push_back(make("planet_exact_inputs", "exact o, c: t ~1 to a few eps (cancel-free c)", te, 16, planet_exact));
        c.push_back(make("sphere_r1e-4_at_1", "hit/miss and t of a tiny sphere", t8, 8, tiny_sphere));
        c.push_back(make("sphere_r1_at_1e4", "far sphere: no lost discriminant", t8, 8,
                         [](const Tracer& tr) { return far_sphere(tr, 1e4); }));
        c.push_back(make("sphere_r1_at_t1e7", "t ~ 1e7 to input precision", t8, 8,
                         [](const Tracer& tr) { return far_sphere(tr, 1e7); }));
        const std::string nb = "dn/(u(1+1/cos)) <= 8, t8";
        c.push_back(make("sphere_r1e-2_at_1e3_outline", "normal to a few u near the outline, t/r = 1e5", nb, 8,
                         small_far_outline));
        c.push_back(make("small_sphere_field", "400 spheres r <= 0.05 at 10-40: normals few u", nb, 8, small_sphere_field));
        c.push_back(make("pinhole_120deg_r0.04_outline", "wide-angle pinhole rays near the outline: normals few u", nb, 8,
                         pinhole_wide_outline));
        c.push_back(make("pinhole_3deg_far_field", "400 spheres r = 1e-3 at 100 through a pinhole: few u", nb, 8,
                         pinhole_far_field));
        c.push_back(make("pinhole_120deg_double", "the same from double eye, centre, rays (float + residual)",
                         nb, 8, pinhole_wide_outline_double));
        c.push_back(make("pinhole_3deg_far_double", "the same from double eye, centres, rays (float + residual)",
                         nb, 8, pinhole_far_field_double));
        c.push_back(make("sphere_r1e3_at_1e6", "large sphere seen from far: normals few u", nb, 8, large_far_sphere));
        c.push_back(make("sphere_tangent_rays", "exact tangent hits (disc = 0); 1 ulp out misses", t8, 8, tangent_rays));
        c.push_back(make("camera_inside_sphere", "the far root (exit) is the hit", t8, 8, camera_inside));
        c.push_back(make("origin_on_sphere", "no self-hit at t = 0; chords hit", t8, 8, origin_on_surface));
        c.push_back(make("plane_ray_parallel", "d.n = 0 exactly: miss, no NaN", zero + " (t8)", 8, plane_parallel));
        c.push_back(make("plane_ray_in_plane", "ray lying in the plane: miss", zero + " (t8)", 8, plane_in_plane));
        c.push_back(make("plane_grazing_1e-7", "d.n = 1e-7: hit at t = 1e7", te, 16, plane_grazing));
        c.push_back(make("disk_rim_hits", "points on the rim hit; 1 ulp outside misses", t8, 8, disk_rim));
        c.push_back(make("rectangle_edge_hits", "edges and corners hit (closed)", t8, 8, rectangle_edges));
        c.push_back(make("box_origin_on_face", "closed box: exit face from the face", t8, 8, box_origin_on_face));
        c.push_back(make("box_zero_dir_components", "0 * inf slabs: inside iff origin in slab", t8, 8, box_zero_components));
        c.push_back(make("box_edges_corners", "edge/corner grazes hit (enter = exit)", t8, 8, box_edges_corners));
        c.push_back(make("mesh_shared_edges", "watertight: rays through edges hit", leaks, 0, mesh_edges));
        c.push_back(make("mesh_shared_vertices", "watertight: rays through vertices hit", leaks, 0, mesh_vertices));
        c.push_back(make("triangle_ray_in_plane", "ray in the triangle's plane: miss", zero + " (t8)", 8, triangle_in_plane));
        c.push_back(make("mesh_shadows_each_mode", "a sheet 0.02 above shadows a mesh, no flip in any mode", l16, 16,
                         mesh_shadows));
        c.push_back(make("grazing_light_1e-7", "n.l = 1e-7 lights to eps relative", le, 16, grazing_light));
        c.push_back(make("lights_1e30_and_1e-30", "tiny term absorbed; alone it is exact", l16, 16, lights_dynamic_range));
        c.push_back(make("lights_64_over_12_decades", "sum of >= 0 terms: (n-1)u + terms", std::string(kLBound) + " <= 80", 80,
                         lights_64_decades));
        c.push_back(make("point_light_1e-6_inv_square", "1/r^2 = 1e12 to a few eps", le, 16, point_light_near));
        c.push_back(make("point_light_at_distance_0", "r=0: nothing; r->0: +inf, never NaN", l16, 16, point_light_zero));
        c.push_back(make("radiance_overflow_to_inf", "E > FLT_MAX: +inf; 0*inf = 0; no NaN", l16, 16, radiance_overflow));
        c.push_back(make("zero_direction", "masked, counted, background", zero, 0, zero_direction));
        c.push_back(make("nan_direction", "masked, counted, background", zero, 0, nan_direction));
        c.push_back(make("inf_direction", "masked, counted, background", zero, 0, inf_direction));
        c.push_back(make("subnormals_ftz_daz_off", "subnormal inputs as given", "dL/(eps L+u sum F g), dt <= 16", 16,
                         [](const Tracer& tr) { return subnormals(tr, false); }));
        c.push_back(make("subnormals_ftz_daz_on", "as given or as zero, never NaN", "dL/(eps L+u sum F g), dt <= 16", 16,
                         [](const Tracer& tr) { return subnormals(tr, true); }));
        c.push_back(make("coordinates_near_1e19", "squares overflow: correct hits (scaled)", "dL/(eps L+u sum F g), dt <= 16", 16, huge_coordinates));
        return c;
    }();
    return cases;
}

}  // namespace octray::stability
