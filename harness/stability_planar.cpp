// harness/stability_planar.cpp — the flat-faced cases of the stability catalogue:
// planes (rays parallel to, lying in and grazing them), disk rims, rectangle and
// parallelogram edges, boxes (origin on a face, zero direction components,
// edges and corners), where a boundary rule decides hit or miss.
#include "stability_check.hpp"

#include <vector>

namespace octray::stability::detail {

namespace {

Vec3d tilted_normal() { return dir(1, 1, 0); }  // (0.70710677, 0.70710677, 0): d = (1, -1, 0) is exactly parallel

Scene unit_box() { return scene_of({Box{{-1, -1, -1}, {1, 1, 1}}}); }

}  // namespace

Measure plane_parallel(const Tracer& tr) {
    Measure m;
    const Scene a = scene_of({Plane{{0, 0, 0}, {0, 1, 0}}});
    const std::vector<Lane> la = {{{0, 1, 0}, {1, 0, 0}}, {{3, -2, 1}, {0, 0, -1}}, {{1, 5, 1}, dir(0.6, 0, 0.8)},
                                  {{0, 1e-30, 0}, {1, 0, 0}}};
    merge(m, measure_hits(tr, a, la, {false, true}));
    const Scene b = scene_of({Plane{{0, 0, 0}, tilted_normal()}});
    const std::vector<Lane> lb = {{{1, 2, 0}, {1, -1, 0}}, {{-3, 0, 2}, {-2, 2, 0}}};
    merge(m, measure_hits(tr, b, lb, {false, true}));
    return m;
}

Measure plane_in_plane(const Tracer& tr) {
    Measure m;
    const Scene a = scene_of({Plane{{0, 0, 0}, {0, 1, 0}}});
    const std::vector<Lane> la = {{{1, 0, 2}, {1, 0, 0}}, {{0, 0, 0}, dir(0.6, 0, -0.8)}, {{-7, 0, 3}, {0, 0, -1}}};
    merge(m, measure_hits(tr, a, la, {false, true}));
    const Scene b = scene_of({Plane{{0, 0, 0}, tilted_normal()}});
    const std::vector<Lane> lb = {{{1, -1, 0}, {1, -1, 0}}, {{-2, 2, 5}, {-1, 1, 0}}};
    merge(m, measure_hits(tr, b, lb, {false, true}));
    return m;
}

Measure plane_grazing(const Tracer& tr) {
    const Scene s = scene_of({Plane{{0, 0, 0}, {0, 1, 0}}});
    std::vector<Lane> lanes;
    for (double slope : {1e-7, 3e-7, 1e-6, 1e-5})
        for (const Vec3d& along : {Vec3d{1, 0, 0}, Vec3d{-0.5, 0, 0.75}})
            lanes.push_back({{0, 1, 0}, fl(Vec3d{along.x, -slope, along.z})});
    return measure_hits(tr, s, lanes, {true, false});
}

Measure disk_rim(const Tracer& tr) {
    const Scene s = scene_of({Disk{{0, 0, 0}, {0, 0, 1}, 1}});
    const double out = fl(1 + 0x1p-23), in = fl(1 - 0x1p-24);
    std::vector<Lane> lanes = down_onto({{1, 0}, {0, -1}, {-1, 0}, {0, 1}, {out, 0}, {0, -out}, {in, 0}, {0.6, 0.8}});
    lanes.push_back({{0, 0, 1}, {1, 0, -1}});   // oblique onto the rim point (1, 0, 0)
    lanes.push_back({{-1, 0, 2}, {1, 0, -1}});  // the same point, t = 2
    lanes.push_back({{0, 3, 1}, {0, -2, -1}});  // onto (0, 1, 0)
    return measure_hits(tr, s, lanes);
}

Measure rectangle_edges(const Tracer& tr) {
    Measure m;
    const Scene a = scene_of({Rectangle{{-1, -1, 0}, {2, 0, 0}, {0, 2, 0}}});
    const double out = fl(1 + 0x1p-23);
    std::vector<Lane> la = down_onto({{-1, 0}, {1, 0.5}, {0, -1}, {0.25, 1}, {-1, -1}, {1, 1}, {1, -1}, {-1, 1}, {out, 0},
                                      {0, -out}, {-out, -out}});
    la.push_back({{-2, 0.5, 1}, {1, 0, -1}});  // oblique onto the edge x = -1
    la.push_back({{3, 3, 2}, {-1, -1, -1}});   // oblique onto the corner (1, 1)
    merge(m, measure_hits(tr, a, la));
    const Scene b = scene_of({Rectangle{{0, 0, 0}, {2, 0, 0}, {1, 2, 0}}});  // a parallelogram
    const std::vector<Lane> lb = down_onto({{0, 0}, {2, 0}, {3, 2}, {1, 2}, {0.5, 1}, {2.5, 1}, {1, 0}, {2, 2}});
    merge(m, measure_hits(tr, b, lb));
    return m;
}

Measure box_origin_on_face(const Tracer& tr) {
    const Scene s = unit_box();
    std::vector<Lane> lanes;
    for (const Vec3d& o : {Vec3d{1, 0.25, 0.5}, Vec3d{1, 1, 0.5}, Vec3d{1, 1, 1}, Vec3d{-0.5, -1, 0.75}})
        for (const Vec3d& d : {Vec3d{-1, 0, 0}, Vec3d{1, 0, 0}, Vec3d{0, 1, 0}, Vec3d{0, -1, 0}, Vec3d{0, 0, -1},
                               dir(-1, -0.5, 0.25), dir(1, 1, 1)})
            lanes.push_back({o, d});
    return measure_hits(tr, s, lanes, {false, true});
}

Measure box_zero_components(const Tracer& tr) {
    const Scene s = unit_box();
    std::vector<Lane> lanes;
    const double nz = -0.0;
    for (const Vec3d& o : {Vec3d{-3, 0, 0}, Vec3d{-3, 1, 0}, Vec3d{-3, 1, -1}, Vec3d{-3, fl(1 + 0x1p-23), 0}, Vec3d{-3, -1, 1}})
        for (const Vec3d& d : {Vec3d{1, 0, 0}, Vec3d{1, nz, nz}, Vec3d{2, 0, nz}}) lanes.push_back({o, d});
    lanes.push_back({{0.5, 0.5, 5}, {nz, 0, -1}});
    lanes.push_back({{0.5, -4, 1}, {0, 1, nz}});
    return measure_hits(tr, s, lanes, {false, true});
}

Measure box_edges_corners(const Tracer& tr) {
    const Scene s = unit_box();
    const std::vector<Lane> lanes = {
        {{-3, 1, 0}, {1, 0, 0}},     // along the face y = 1: hits at t = 2
        {{-3, 1, 1}, {1, 0, 0}},     // along the edge y = z = 1
        {{-3, -3, 0}, {1, 1, 0}},    // enters through the edge x = y = -1
        {{-3, -3, -3}, {1, 1, 1}},   // enters through the corner (-1, -1, -1)
        {{-3, 1, 0}, {1, -1, 0}},    // touches only the edge x = y = -1 (enter t = exit t = 2)
        {{2, 2, 0}, {-1, -1, 1}},    // touches only the corner (1, 1, 1) at t = 1
        {{0, 3, 0}, {1, -1, 0}},     // passes the edge x = 1 at y = 2: misses
        {{3, 1, -3}, {-1, 0, 1}},    // enters at the corner (1, 1, -1), runs along the face y = 1
    };
    return measure_hits(tr, s, lanes, {false, true});
}

}  // namespace octray::stability::detail
