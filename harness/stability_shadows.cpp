// harness/stability_shadows.cpp — shadow rays on meshes in every precision
// mode: a sheet of triangles 0.02 above a triangle floor, lit by a low
// directional light, so that floor points beside the sheet lie in its shadow
// with the blocker 0.02 above them. Every mode must decide those lanes as the
// reference does: the estimate modes shade from exact's hit point (every
// primitive test's t is IEEE) with exact's shadow offset (precision.hpp).
#include "stability_check.hpp"

#include "reference/reference_parts.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace octray::stability::detail {

namespace {

// A square of two triangles at height y over [x0, x1] x [z0, z1]. (Triangle
// objects: the catalogue's checks index Scene::objects; the kernels compile
// them into the same triangle arrays as a mesh's.)
void add_square(Scene& s, double y, double x0, double x1, double z0, double z1) {
    const Vec3d a = fl(Vec3d{x0, y, z0}), b = fl(Vec3d{x1, y, z0}), c = fl(Vec3d{x1, y, z1}), d = fl(Vec3d{x0, y, z1});
    s.objects.push_back(Object{Triangle{a, b, c}, 0});
    s.objects.push_back(Object{Triangle{a, c, d}, 0});
}

}  // namespace

// The floor's lanes beside the sheet, under its shadow (x 9.03 to 9.17: the
// shadow ray climbs 0.1 per unit toward -x and meets the sheet, 0.02 up, after
// 0.2) and past it (x 9.25 to 9.5: lit), seen from 7 to 8 units away. The naive
// column is approx's earlier rule: the point o + t d with approx's t, lifted
// by 8 * 1.5 * 2^-12 (|p| + t) (0.05 here), asked of the reference: it starts
// above the sheet and sees the light.
Measure mesh_shadows(const Tracer& tr) {
    Scene s = scene_of({});
    add_square(s, 0, -12, 12, -12, 12);
    add_square(s, 0.02, 7, 9, 7, 9);
    s.directional_lights.push_back({dir(-1, 0.1, 0), {1, 1, 1}, 1.5, true});
    const Vec3d o = fl(Vec3d{9.1, 5, 14});
    std::vector<Lane> lanes;
    for (double x : {9.03, 9.06, 9.1, 9.13, 9.17, 9.25, 9.35, 9.5})
        for (double z : {7.2, 7.6, 8.0, 8.4, 8.8}) lanes.push_back(toward(o, {x, 0, z}));
    if (!tr.naive) return measure_all(tr, s, lanes);
    const Traced k = run(Tracer{Path::simd, Precision::approx, false}, s, lanes);
    Measure m;
    int flips = 0;
    for (std::size_t i = 0; i < lanes.size(); ++i) {
        const reference::Hit h = ref_trace(s, lanes[i]);
        if (!k.lanes[i].hit || h.object < 0) continue;
        const Lane& l = lanes[i];
        const Vec3d p = l.o + l.d * k.lanes[i].t;
        const double scale = std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z), 1.0});
        const double reach = k.lanes[i].t * std::max({std::fabs(l.d.x), std::fabs(l.d.y), std::fabs(l.d.z)});
        const double eps = std::max(1e-4 * scale, (scale + reach) * 8 * (1.5 / 4096));
        reference::Hit old = h;
        old.point = p + h.normal * eps;
        if (reference::shadowed(s, old, s.directional_lights[0]) != reference::shadowed(s, h, s.directional_lights[0]))
            ++flips;
    }
    m.error = flips;
    m.pass = flips == 0;
    m.note = fmt("naive here: approx's earlier shadow origin (o + t d lifted by 8 * 1.5 * 2^-12 (|p| + t)): %g of %g lanes flip",
                 flips, double(lanes.size()));
    return m;
}

}  // namespace octray::stability::detail
