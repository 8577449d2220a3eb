// harness/stability_naive.cpp — the textbook formulation, for `octray stability`'s
// naive count only: how many catalogue cases a straightforward float
// implementation fails. Nothing else uses it. Scalar float, one lane at a
// time, over the same compiled scene the kernels read.
#include "stability_cases.hpp"

#include "kernels/scene_data.hpp"

#include <cmath>
#include <limits>

namespace octray::stability {
namespace {

constexpr float kEps = 1e-4f;  // the fixed self-intersection epsilon

struct V {
    float x, y, z;
};
V operator-(V a, V b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
V operator+(V a, V b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
V operator*(V a, float s) { return {a.x * s, a.y * s, a.z * s}; }
float dot(V a, V b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
V cross(V a, V b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
V at(const Floats& x, const Floats& y, const Floats& z, int k) {
    return {x[std::size_t(k)], y[std::size_t(k)], z[std::size_t(k)]};
}

// Nearest root above kEps of a t^2 + b t + c, or a negative number.
float sphere(V o, V d, V c, float r2) {
    const V f = o - c;
    const float a = dot(d, d), b = 2 * dot(f, d), cc = dot(f, f) - r2;
    const float disc = b * b - 4 * a * cc;
    if (disc < 0) return -1;
    const float sq = std::sqrt(disc);
    float t = (-b - sq) / (2 * a);
    if (t > kEps) return t;
    t = (-b + sq) / (2 * a);
    return t > kEps ? t : -1;
}

float plane(V o, V d, V p, V n) {
    const float den = dot(d, n);
    if (std::fabs(den) < 1e-6f) return -1;
    const float t = dot(p - o, n) / den;
    return t > kEps ? t : -1;
}

float box(V o, V d, V lo, V hi) {
    float t0 = -std::numeric_limits<float>::infinity(), t1 = std::numeric_limits<float>::infinity();
    const float os[3] = {o.x, o.y, o.z}, ds[3] = {d.x, d.y, d.z}, ls[3] = {lo.x, lo.y, lo.z}, hs[3] = {hi.x, hi.y, hi.z};
    for (int k = 0; k < 3; ++k) {
        float a = (ls[k] - os[k]) / ds[k], b = (hs[k] - os[k]) / ds[k];
        if (a > b) std::swap(a, b);
        if (a > t0) t0 = a;
        if (b < t1) t1 = b;
    }
    if (t0 > t1) return -1;
    if (t0 > kEps) return t0;
    return t1 > kEps ? t1 : -1;
}

// Moller-Trumbore.
float triangle(V o, V d, V a, V b, V c) {
    const V e1 = b - a, e2 = c - a, p = cross(d, e2);
    const float det = dot(e1, p);
    if (std::fabs(det) < 1e-8f) return -1;
    const float inv = 1 / det;
    const V s = o - a;
    const float u = dot(s, p) * inv;
    if (u < 0 || u > 1) return -1;
    const V q = cross(s, e1);
    const float v = dot(d, q) * inv;
    if (v < 0 || u + v > 1) return -1;
    const float t = dot(e2, q) * inv;
    return t > kEps ? t : -1;
}

}  // namespace

int naive_intersect(const PacketScene& scene, const RayPacket8& rp, HitPacket8& hp) noexcept {
    const SceneData& s = scene_data(scene);
    for (int i = 0; i < 8; ++i) {
        const V o{rp.ox[i], rp.oy[i], rp.oz[i]}, d{rp.dx[i], rp.dy[i], rp.dz[i]};
        float best = rp.tmax[i];
        int cid = -1;
        V n{0, 0, 1};
        auto take = [&](float t, int id, V normal) {
            if (t > 0 && t < best) best = t, cid = id, n = normal;
        };
        if (rp.active[i] != 0) {
            for (int k = 0; k < s.count[0]; ++k) {
                const V c = at(s.spheres.cx, s.spheres.cy, s.spheres.cz, k);
                const double radius = s.spheres.radius[std::size_t(k)];
                const float t = sphere(o, d, c, float(radius * radius));
                take(t, s.offset[0] + k, (o + d * t - c) * float(1.0 / radius));
            }
            for (int k = 0; k < s.count[1]; ++k) {
                const V nn = at(s.planes.nx, s.planes.ny, s.planes.nz, k);
                take(plane(o, d, at(s.planes.px, s.planes.py, s.planes.pz, k), nn), s.offset[1] + k, nn);
            }
            for (int k = 0; k < s.count[2]; ++k) {
                const V c = at(s.disks.cx, s.disks.cy, s.disks.cz, k), nn = at(s.disks.nx, s.disks.ny, s.disks.nz, k);
                const float t = plane(o, d, c, nn);
                const V q = o + d * t - c;
                if (dot(q, q) <= s.disks.radius2[std::size_t(k)]) take(t, s.offset[2] + k, nn);
            }
            const RectangleArrays& ra = s.rectangles;
            for (int k = 0; k < s.count[3]; ++k) {
                const V c = at(ra.cx, ra.cy, ra.cz, k), nn = at(ra.nx, ra.ny, ra.nz, k);
                const float t = plane(o, d, c, nn);
                const V q = o + d * t - c;
                const float a = dot(q, at(ra.dual_ax, ra.dual_ay, ra.dual_az, k));
                const float b = dot(q, at(ra.dual_bx, ra.dual_by, ra.dual_bz, k));
                if (a >= 0 && a <= 1 && b >= 0 && b <= 1) take(t, s.offset[3] + k, nn);
            }
            const BoxArrays& ba = s.boxes;
            for (int k = 0; k < s.count[4]; ++k) {
                const V lo = at(ba.minx, ba.miny, ba.minz, k), hi = at(ba.maxx, ba.maxy, ba.maxz, k);
                const float t = box(o, d, lo, hi);
                // The face nearest to the hit point.
                const V p = o + d * t;
                const float dist[6] = {std::fabs(p.x - lo.x), std::fabs(p.x - hi.x), std::fabs(p.y - lo.y),
                                       std::fabs(p.y - hi.y), std::fabs(p.z - lo.z), std::fabs(p.z - hi.z)};
                int face = 0;
                for (int j = 1; j < 6; ++j)
                    if (dist[j] < dist[face]) face = j;
                V nn{0, 0, 0};
                (face / 2 == 0 ? nn.x : face / 2 == 1 ? nn.y : nn.z) = face % 2 == 0 ? -1.0f : 1.0f;
                take(t, s.offset[4] + k, nn);
            }
            auto field3 = [&](int k, int f) {
                return V{triangle_field(s, k, f), triangle_field(s, k, f + 1), triangle_field(s, k, f + 2)};
            };
            for (int k = 0; k < s.count[5]; ++k)
                take(triangle(o, d, field3(k, kV0), field3(k, kV1), field3(k, kV2)), s.offset[5] + k, field3(k, kNormal));
        }
        if (dot(n, d) > 0) n = n * -1.0f;
        const bool hit = cid >= 0;
        hp.t[i] = hit ? best : std::numeric_limits<float>::infinity();
        hp.primitive[i] = hit ? int(s.object_of[std::size_t(cid)]) : -1;
        hp.material[i] = s.owners.material(hp.primitive[i], cid);
        hp.mesh[i] = s.owners.mesh(hp.primitive[i]);
        hp.nx[i] = hit ? n.x : 0, hp.ny[i] = hit ? n.y : 0, hp.nz[i] = hit ? n.z : 0;
        hp.hit[i] = hit ? -1 : 0;
    }
    return 0;  // the textbook checks no input
}

void naive_shade(const PacketScene& scene, const RayPacket8& rp, const HitPacket8& hp, ColorPacket8& out) noexcept {
    const SceneData& s = scene_data(scene);
    for (int i = 0; i < 8; ++i) {
        if (hp.hit[i] == 0 || rp.active[i] == 0) {
            out.r[i] = s.background[0], out.g[i] = s.background[1], out.b[i] = s.background[2];
            continue;
        }
        const V o{rp.ox[i], rp.oy[i], rp.oz[i]}, d{rp.dx[i], rp.dy[i], rp.dz[i]};
        const V p = o + d * hp.t[i], n{hp.nx[i], hp.ny[i], hp.nz[i]};
        V e{0, 0, 0};
        for (int k = 0; k < s.directional_count; ++k) {
            const float ndl = dot(n, at(s.directional.lx, s.directional.ly, s.directional.lz, k));
            if (ndl > 0) e = e + at(s.directional.r, s.directional.g, s.directional.b, k) * ndl;
        }
        auto point = [&](const PointArrays& a, int count, bool attenuated) {
            for (int k = 0; k < count; ++k) {
                const V v = at(a.px, a.py, a.pz, k) - p;
                const float r = std::sqrt(dot(v, v));
                const float ndl = dot(n, v * (1 / r));
                if (ndl > 0) e = e + at(a.r, a.g, a.b, k) * (attenuated ? ndl / (r * r) : ndl);
            }
        };
        point(s.point, s.point_count, false);
        point(s.point_attenuated, s.point_attenuated_count, true);
        const std::size_t m = std::size_t(hp.material[i]);
        out.r[i] = s.ambient_r[m] + s.diffuse_r[m] * e.x;
        out.g[i] = s.ambient_g[m] + s.diffuse_g[m] * e.y;
        out.b[i] = s.ambient_b[m] + s.diffuse_b[m] * e.z;
    }
}

}  // namespace octray::stability
