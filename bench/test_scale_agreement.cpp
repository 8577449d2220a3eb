// bench/test_scale_agreement.cpp — octray and Embree 3 give the same answers on
// the cost curve's scenes and rays (bench/scale_common.hpp), at small sizes:
// random spheres (N = 16, 256, 4096; Embree native and user spheres) and a
// height field (~1k and ~4k triangles); camera and incoherent rays; closest
// hit and any hit; rtcIntersect8/rtcOccluded8 and rtcIntersect1/rtcOccluded1.
//
// The rule (docs/performance.md, the cost curve): on >= 99.99% of the rays not near an edge, the same
// hit or miss and the same primitive, and where both hit it, t within 1e-5
// relative (to max(t, |origin| / |d|): a float t is rounded at the scale of
// the coordinates, so a bounce ray's short t, 1e-3 from its origin 4 units
// out, can only be within ~1e-7 * 4 / 1e-3; the worst plain t relative error is
// printed too). Near an edge, in double: a sphere the ray's line passes within
// 1e-4 r of its silhouette, a triangle hit whose smallest barycentric is
// below 1e-5, or two different primitives hit at t within 1e-4 of each other
// (the curve where two spheres meet). An any-hit ray is near an edge when the
// closest-hit answers of either side involve such a primitive.
#include "scale_common.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <utility>
#include <vector>

using namespace octray;
using namespace octray::scale;

namespace {

constexpr int kImage = 128;
constexpr double kRequired = 0.9999;

struct Line {
    double o[3], d[3];
};
Line line_of(const Rays& r, std::size_t l) {
    const RayPacket8& p = r.packets[l / 8];
    const int i = int(l % 8);
    return {{p.ox[i], p.oy[i], p.oz[i]}, {p.dx[i], p.dy[i], p.dz[i]}};
}

// Whether primitive `prim` (or -1) of w is near an edge for the ray.
bool near_edge(const World& w, const Line& L, int prim) {
    if (prim < 0) return false;
    if (!is_mesh(w)) {
        const float* s = &w.xyzr[4 * std::size_t(prim)];
        double f[3], dd = 0, fd = 0, ff = 0;
        for (int a = 0; a < 3; ++a) f[a] = L.o[a] - s[a], dd += L.d[a] * L.d[a], fd += f[a] * L.d[a], ff += f[a] * f[a];
        const double dist = std::sqrt(std::max(0.0, ff - fd * fd / dd));
        return std::fabs(dist - s[3]) < 1e-4 * s[3];
    }
    const unsigned* t = &w.tris[3 * std::size_t(prim)];
    double v[3][3];
    for (int k = 0; k < 3; ++k)
        for (int a = 0; a < 3; ++a) v[k][a] = w.verts[3 * std::size_t(t[k]) + std::size_t(a)];
    // Möller-Trumbore barycentrics in double.
    double e1[3], e2[3], s[3], p[3], q[3];
    for (int a = 0; a < 3; ++a) e1[a] = v[1][a] - v[0][a], e2[a] = v[2][a] - v[0][a], s[a] = L.o[a] - v[0][a];
    auto cross = [](const double* x, const double* y, double* z) {
        z[0] = x[1] * y[2] - x[2] * y[1], z[1] = x[2] * y[0] - x[0] * y[2], z[2] = x[0] * y[1] - x[1] * y[0];
    };
    auto dot = [](const double* x, const double* y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; };
    cross(L.d, e2, p);
    const double det = dot(e1, p);
    if (det == 0) return true;
    const double u = dot(s, p) / det;
    cross(s, e1, q);
    const double vv = dot(L.d, q) / det;
    return std::min({u, vv, 1 - u - vv}) < 1e-5;
}

struct Tally {
    std::int64_t rays = 0, edge = 0, agree = 0, t_bad = 0;
    double worst_t = 0;
};

Tally compare_closest(World& w, const Rays& r, Engine e, bool user) {
    const Answers a = closest(w, r, Engine::octray_simd, false), b = closest(w, r, e, user);
    Tally t;
    for (std::size_t l = 0; l < a.prim.size(); ++l) {
        if (r.pixel[l] < 0) continue;
        const Line L = line_of(r, l);
        const bool both_hit_apart = a.prim[l] >= 0 && b.prim[l] >= 0 && a.prim[l] != b.prim[l] &&
                                    std::fabs(a.t[l] - b.t[l]) <= 1e-4 * std::max(a.t[l], b.t[l]);
        if (near_edge(w, L, a.prim[l]) || near_edge(w, L, b.prim[l]) || both_hit_apart) {
            ++t.edge;
            continue;
        }
        ++t.rays;
        if (a.prim[l] != b.prim[l]) continue;
        ++t.agree;
        if (a.prim[l] >= 0) {
            const double dt = std::fabs(double(a.t[l]) - double(b.t[l])), tt = std::max(double(a.t[l]), double(b.t[l]));
            const double o = std::sqrt(L.o[0] * L.o[0] + L.o[1] * L.o[1] + L.o[2] * L.o[2]);
            const double len = std::sqrt(L.d[0] * L.d[0] + L.d[1] * L.d[1] + L.d[2] * L.d[2]);
            t.worst_t = std::max(t.worst_t, dt / tt);
            t.t_bad += dt > 1e-5 * std::max(tt, o / len);
        }
    }
    return t;
}

Tally compare_any(World& w, const Rays& r, Engine e, bool user) {
    const std::vector<int> a = occluded(w, r, Engine::octray_simd, false), b = occluded(w, r, e, user);
    const Answers ca = closest(w, r, Engine::octray_simd, false), cb = closest(w, r, e, user);
    Tally t;
    for (std::size_t l = 0; l < a.size(); ++l) {
        if (r.pixel[l] < 0) continue;
        const Line L = line_of(r, l);
        if (near_edge(w, L, ca.prim[l]) || near_edge(w, L, cb.prim[l])) {
            ++t.edge;
            continue;
        }
        ++t.rays;
        t.agree += a[l] == b[l];
    }
    return t;
}

void check_world(Family f, int n) {
    World& w = world(f, n, kImage);
    const bool spheres = !is_mesh(w);
    for (const bool incoherent : {false, true}) {
        const Rays& r = incoherent ? w.incoherent : w.camera;
        REQUIRE(r.active > 0);
        for (const Engine e : {Engine::embree8, Engine::embree1})
            for (const bool user : spheres ? std::vector<bool>{false, true} : std::vector<bool>{false})
                for (const bool any : {false, true}) {
                    const Tally t = any ? compare_any(w, r, e, user) : compare_closest(w, r, e, user);
                    const double match = t.rays ? double(t.agree) / double(t.rays) : 0.0;
                    char what[200];
                    std::snprintf(what, sizeof what, "%s %s %s %s%s: %lld rays off edges (%lld near), match %.5f%%, t worst %.2e (relative to t)",
                                  w.name.c_str(), incoherent ? "incoherent" : "camera", any ? "any" : "closest",
                                  e == Engine::embree8 ? "embree8" : "embree1", spheres ? (user ? "_user" : "_native") : "",
                                  static_cast<long long>(t.rays), static_cast<long long>(t.edge), 100 * match, t.worst_t);
                    INFO(what);
                    MESSAGE(what);
                    CHECK(t.rays > 0);
                    CHECK(match >= kRequired);
                    CHECK(t.t_bad == 0);
                }
    }
}

}  // namespace

TEST_CASE("scale agreement: random spheres, Embree native and user spheres") {
    for (const int n : {16, 256, 4096}) check_world(Family::spheres, n);
}

TEST_CASE("scale agreement: height field triangles") {
    for (const int n : {1024, 4096}) check_world(Family::heightfield, n);
}

// The SIMD path (hull walks of coherent packets, single-ray walks where a
// packet diverges, one ray against a leaf's run in the lanes) and the scalar
// path (one ray, one primitive at a time) compute each (ray, primitive) pair
// with the same arithmetic: every answer is the same, bit for bit.
TEST_CASE("scale agreement: octray SIMD and scalar give the same answers, bit for bit") {
    for (const auto& [family, n] : {std::pair{Family::heightfield, 1 << 12}, std::pair{Family::spheres, 4096}}) {
        World& w = world(family, n, kImage);
        for (const bool incoherent : {false, true}) {
            const Rays& r = incoherent ? w.incoherent : w.camera;
            CAPTURE(w.name);
            CAPTURE(incoherent);
            const Answers a = closest(w, r, Engine::octray_simd, false), b = closest(w, r, Engine::octray_scalar, false);
            const std::vector<int> oa = occluded(w, r, Engine::octray_simd, false);
            const std::vector<int> ob = occluded(w, r, Engine::octray_scalar, false);
            std::int64_t prim_differ = 0, t_differ = 0, any_differ = 0, hits = 0;
            for (std::size_t l = 0; l < a.prim.size(); ++l) {
                if (r.pixel[l] < 0) continue;
                hits += a.prim[l] >= 0;
                prim_differ += a.prim[l] != b.prim[l];
                t_differ += std::memcmp(&a.t[l], &b.t[l], sizeof a.t[l]) != 0;
                any_differ += oa[l] != ob[l];
            }
            CHECK(hits > 0);
            CHECK(prim_differ == 0);
            CHECK(t_differ == 0);
            CHECK(any_differ == 0);
        }
    }
}
