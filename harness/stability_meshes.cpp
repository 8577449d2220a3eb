// harness/stability_meshes.cpp — the triangle cases of the stability catalogue:
// watertightness (rays through the shared edges and vertices of random terrains,
// a fan and a closed octahedron must not leak) and rays lying in a triangle's plane.
#include "stability_check.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <random>
#include <string>
#include <vector>

namespace octray::stability::detail {

namespace {

// A jittered height field over ~[0, n]^2 with random float heights, quads
// split along alternating diagonals: shared edges and vertices in general
// position (no dyadic coincidences that would make a formulation exact).
std::vector<std::array<Vec3d, 3>> height_field(int n, unsigned seed, std::vector<Vec3d>& interior_vertices,
                                               std::vector<std::array<Vec3d, 2>>& interior_edges) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> jitter(-0.3, 0.3), height(-0.7, 0.7);
    std::vector<Vec3d> v;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) v.push_back(fl(Vec3d{i + jitter(rng), j + jitter(rng), height(rng)}));
    auto at = [&](int i, int j) { return v[std::size_t(j * (n + 1) + i)]; };
    std::vector<std::array<Vec3d, 3>> tris;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const Vec3d a = at(i, j), b = at(i + 1, j), c = at(i, j + 1), d = at(i + 1, j + 1);
            if ((i + j) % 2 == 0) tris.push_back({a, b, d}), tris.push_back({a, d, c}), interior_edges.push_back({a, d});
            else tris.push_back({a, b, c}), tris.push_back({b, d, c}), interior_edges.push_back({b, c});
            if (j > 0) interior_edges.push_back({a, b});
            if (i > 0) interior_edges.push_back({a, c});
        }
    for (int j = 1; j < n; ++j)
        for (int i = 1; i < n; ++i) interior_vertices.push_back(at(i, j));
    return tris;
}

Scene triangles_scene(const std::vector<std::array<Vec3d, 3>>& tris) {
    Scene s;
    s.materials.push_back(matte());
    for (const auto& t : tris) s.objects.push_back(Object{Triangle{t[0], t[1], t[2]}, 0});
    return s;
}


// Rays from random origins (from `origin`) at each target: half with the
// direction target - o rounded to float, half normalized: the float ray
// passes within a rounding of the edge or vertex.
template <class Origin>
std::vector<Lane> rays_at(const std::vector<Vec3d>& targets, int rounds, unsigned seed, Origin origin) {
    std::mt19937 rng(seed);
    std::vector<Lane> lanes;
    for (int round = 0; round < rounds; ++round)
        for (const Vec3d& p : targets) {
            const Vec3d o = fl(origin(rng, round));
            const Vec3d v = p - o;
            lanes.push_back({o, round % 4 < 2 ? fl(v) : dir(v.x, v.y, v.z)});
        }
    return lanes;
}

// True when the reference hits something, and still does with the origin
// moved by 4 u S or the direction by 4 u |d| along any axis: the ray crosses
// the mesh well inside its coverage (not at its border, not at a silhouette).
bool surely_hits(const Scene& scene, const Lane& l) {
    const reference::Hit h = ref_trace(scene, l);
    return h.object >= 0 && !any_perturbation(scene, l, lane_scale(scene, l, h, -1),
                                              [](const reference::Hit& p) { return p.object < 0; });
}

// A leak is a kernel miss where the reference surely hits. The t of a hit is
// checked against the reference's (the primitive may differ on an edge).
Measure must_hit(const Tracer& tr, const Scene& s, const std::vector<Lane>& lanes) {
    const Traced t = run(tr, s, lanes);
    Measure m;
    int leaks = 0;
    double terr = 0;
    for (std::size_t i = 0; i < lanes.size(); ++i) {
        if (!t.lanes[i].hit) {
            if (debug() && surely_hits(s, lanes[i]))
                std::fprintf(stderr, "  leak lane %zu of %zu, %zu triangles: o=(%a, %a, %a) d=(%a, %a, %a)\n", i, lanes.size(),
                             s.objects.size(), lanes[i].o.x, lanes[i].o.y, lanes[i].o.z, lanes[i].d.x, lanes[i].d.y, lanes[i].d.z);
            if (surely_hits(s, lanes[i]) && leaks++ == 0)
                m.note = "leak: o=" + fmt("(%.9g, %.9g, %.9g)", lanes[i].o.x, lanes[i].o.y, lanes[i].o.z) +
                         fmt(" d=(%.9g, %.9g, %.9g)", lanes[i].d.x, lanes[i].d.y, lanes[i].d.z);
            continue;
        }
        // t against the reference's t for the triangle the kernel hit (on an
        // edge either neighbour is right; one the reference misses must be
        // within rounding of its border).
        const Lane& l = lanes[i];
        const reference::Hit h = ref_trace(s, l);
        const int obj = t.lanes[i].object;
        if (obj < 0 || obj >= int(s.objects.size())) continue;
        const auto tk = reference::intersect(s.objects[std::size_t(obj)].shape, ref_ray(l), l.tmin, ref_tmax(l));
        if (!tk) {
            if (!ambiguous(s, l, lane_scale(s, l, h, obj)) && m.pass) m.note = "a hit on a triangle the reference misses";
            if (!ambiguous(s, l, lane_scale(s, l, h, obj))) m.pass = false;
            continue;
        }
        const Vec3d nr = reference::geometric_normal(s.objects[std::size_t(obj)].shape, l.o + l.d * *tk);
        const double cosine = std::fabs(dot(nr, l.d)) / norm(l.d);
        const double tau = t.eps * *tk + kUnitRoundoff * lane_scale(s, l, h, obj) / std::max(cosine, std::sqrt(kUnitRoundoff));
        terr = std::max(terr, std::fabs(t.lanes[i].t - *tk) / tau);
    }
    m.error = leaks;
    m.pass = leaks == 0;
    if (terr > 8) {
        if (m.pass) m.note = fmt("t error %.3g > 8", terr);
        m.pass = false;
    }
    add_note(m, t);
    return m;
}

// Sums the leaks of several meshes.
void add_leaks(Measure& m, const Measure& more) {
    const double leaks = m.error + more.error;
    merge(m, more);
    m.error = leaks;
}

Vec3d above_or_below(std::mt19937& rng, int round) {
    return {uniform(rng, -3, 7), uniform(rng, -3, 7), (round % 2 == 0 ? 1 : -1) * uniform(rng, 2, 9)};
}

// A random terrain, rays at dyadic fractions along its interior edges or at
// its interior vertices.
Measure terrain_leaks(const Tracer& tr, unsigned seed, bool at_vertices) {
    std::vector<Vec3d> vertices;
    std::vector<std::array<Vec3d, 2>> edges;
    const Scene s = triangles_scene(height_field(4, seed, vertices, edges));
    if (at_vertices) return must_hit(tr, s, rays_at(vertices, 32, seed, above_or_below));
    std::vector<Vec3d> targets;
    for (const auto& e : edges)
        for (double f : {0.5, 0.25, 0.8125, 0.0625}) targets.push_back(e[0] + (e[1] - e[0]) * f);
    return must_hit(tr, s, rays_at(targets, 8, seed, above_or_below));
}

}  // namespace

Measure mesh_edges(const Tracer& tr) {
    Measure m;
    for (unsigned seed : {21u, 22u}) add_leaks(m, terrain_leaks(tr, seed, false));
    return m;
}

Measure mesh_vertices(const Tracer& tr) {
    Measure m;
    for (unsigned seed : {31u, 32u}) add_leaks(m, terrain_leaks(tr, seed, true));
    {
        // A fan of 9 uneven triangles around a vertex, from above and below.
        const Vec3d c = fl(Vec3d{1.3, 1.7, 0.45});
        std::vector<std::array<Vec3d, 3>> fan;
        const int k = 9;
        for (int i = 0; i < k; ++i) {
            const double a0 = 2 * kPi * (i + 0.3 * (i % 3)) / k, a1 = 2 * kPi * (i + 1 + 0.3 * ((i + 1) % 3)) / k;
            fan.push_back({c, fl(c + Vec3d{std::cos(a0), std::sin(a0), 0.1 * (i % 4) - 0.15}),
                           fl(c + Vec3d{std::cos(a1), std::sin(a1), 0.1 * ((i + 1) % 4) - 0.15})});
        }
        add_leaks(m, must_hit(tr, triangles_scene(fan), rays_at({c}, 256, 33, above_or_below)));
    }
    {
        // A closed octahedron with rotated float vertices, from inside through
        // its vertices and edge midpoints.
        const Vec3d ax = dir(0.9, 0.3, 0.1), ay0 = dir(-0.3, 0.9, 0.2);
        const Vec3d az = dir(cross(ax, ay0).x, cross(ax, ay0).y, cross(ax, ay0).z), ay = cross(az, ax);
        const Vec3d v[6] = {fl(ax * 2.0), fl(ax * -2.0), fl(ay * 2.0), fl(ay * -2.0), fl(az * 2.0), fl(az * -2.0)};
        std::vector<std::array<Vec3d, 3>> tris;
        for (int a : {0, 1})
            for (int b : {2, 3})
                for (int c : {4, 5}) tris.push_back({v[a], v[b], v[c]});
        std::vector<Vec3d> targets(std::begin(v), std::end(v));
        for (int a = 0; a < 6; ++a)
            for (int b = a + 1; b < 6; ++b)
                if (a / 2 != b / 2) targets.push_back((v[a] + v[b]) * 0.5);
        auto inside = [](std::mt19937& rng, int) { return Vec3d{uniform(rng, -0.5, 0.5), uniform(rng, -0.5, 0.5), uniform(rng, -0.5, 0.5)}; };
        add_leaks(m, must_hit(tr, triangles_scene(tris), rays_at(targets, 16, 34, inside)));
    }
    return m;
}

Measure triangle_in_plane(const Tracer& tr) {
    Measure m;
    const Scene a = scene_of({Triangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}});
    const std::vector<Lane> la = {{{-1, 0.25, 0}, {1, 0, 0}}, {{0.25, 0.25, 0}, {1, 1, 0}}, {{2, 2, 0}, {-1, -1, 0}}};
    merge(m, measure_hits(tr, a, la, {false, true}));
    // In the tilted plane x + y = 0 (collinear triangles never get here: validate() rejects them).
    const Scene b = scene_of({Triangle{{1, -1, 0}, {-1, 1, 0}, {0, 0, 1}}});
    const std::vector<Lane> lb = {{{2, -2, 0.25}, {-1, 1, 0}}, {{-3, 3, 0.5}, {1, -1, 0}}, {{0, 0, -2}, {0, 0, 1}}};
    merge(m, measure_hits(tr, b, lb, {false, true}));
    return m;
}

}  // namespace octray::stability::detail
