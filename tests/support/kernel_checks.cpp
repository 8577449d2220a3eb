// tests/support/kernel_checks.cpp — see kernel_checks.hpp. Compiled with
// -ffp-contract=off: expected_mask's d.d must round exactly as written.
#include "kernel_checks.hpp"

#include "dispatch/isa_kernels.hpp"

#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

namespace octray::test {

namespace {

template <class F>
bool lane_valid(const RayPacket8& r, int i) {
    const F ox = F(r.ox[i]), oy = F(r.oy[i]), oz = F(r.oz[i]);
    const F dx = F(r.dx[i]), dy = F(r.dy[i]), dz = F(r.dz[i]);
    const F tmin = F(r.tmin[i]), tmax = F(r.tmax[i]);
    const bool finite = std::isfinite(ox) && std::isfinite(oy) && std::isfinite(oz) && std::isfinite(dx) &&
                        std::isfinite(dy) && std::isfinite(dz);
    const F dd = std::fma(dx, dx, std::fma(dy, dy, dz * dz));
    const bool usable = dd >= F(0x1p-126f) && dd < F(0x1p126f);
    return finite && usable && tmin < tmax;
}

std::string lane_message(int i, const std::string& what) {
    return "lane " + std::to_string(i) + ": " + what;
}

std::string number(double v) {
    std::ostringstream s;
    s.precision(9);
    s << v;
    return s.str();
}

// Any NaN in n floats: the lane, else -1.
int nan_lane(const float* v, int n = kPacketWidth) {
    for (int i = 0; i < n; ++i)
        if (std::isnan(v[i])) return i;
    return -1;
}

}  // namespace

std::vector<Kernel> every_kernel(unsigned features) {
    std::vector<Kernel> ks;
    for (int u = 0; u < kernels::kUnitCount; ++u) {
        const kernels::Unit& unit = kernels::kUnits[u];
        if (!unit.supported()) continue;
        for (Precision p : kPrecisions)
            if ((unit.modes & kernels::mode_bit(p)) != 0)
                ks.push_back(unit.kernel(p, features & kAllPrimitives, features & ~kAllPrimitives));
    }
    return ks;
}

LaneMask expected_mask(const RayPacket8& rays, Precision precision) {
    LaneMask m;
    for (int i = 0; i < kPacketWidth; ++i) {
        if (rays.active[i] == 0) continue;
        m.valid[i] = precision == Precision::f64 ? lane_valid<double>(rays, i) : lane_valid<float>(rays, i);
        m.invalid[i] = !m.valid[i];
        m.masked += m.invalid[i];
    }
    return m;
}

SceneFacts scene_facts(const Scene& scene) {
    SceneFacts f;
    f.primitives = int(scene.objects.size() + scene.mesh_triangle_count());
    f.meshes = int(scene.meshes.size());
    f.materials = int(scene.materials.size());
    f.background[0] = float(scene.background.x);
    f.background[1] = float(scene.background.y);
    f.background[2] = float(scene.background.z);
    const Vec3d& c = scene.render.clamp_color;
    f.display_bounded = scene.render.tonemap != ToneMap::clamp_to_color || (c.x <= 1 && c.y <= 1 && c.z <= 1);
    return f;
}

std::string check_intersect(const SceneFacts& scene, const RayPacket8& rays, const HitPacket8& hits, int masked,
                            Precision precision) {
    const LaneMask m = expected_mask(rays, precision);
    if (masked != m.masked)
        return "intersect returned " + std::to_string(masked) + " masked lanes, expected " + std::to_string(m.masked);
    for (int i = 0; i < kPacketWidth; ++i) {
        if (hits.invalid[i] != (m.invalid[i] ? -1 : 0))
            return lane_message(i, "invalid flag " + std::to_string(hits.invalid[i]) + ", expected " +
                                       (m.invalid[i] ? "-1" : "0"));
        if (hits.hit[i] != 0 && hits.hit[i] != -1) return lane_message(i, "hit flag " + std::to_string(hits.hit[i]));
        const float n[3] = {hits.nx[i], hits.ny[i], hits.nz[i]};
        if (hits.hit[i] == 0) {
            if (!(hits.t[i] == std::numeric_limits<float>::infinity()) || hits.primitive[i] != -1 ||
                hits.material[i] != -1 || n[0] != 0 || n[1] != 0 || n[2] != 0)
                return lane_message(i, "a miss with t " + number(hits.t[i]) + ", primitive " +
                                           std::to_string(hits.primitive[i]) + ", material " +
                                           std::to_string(hits.material[i]) + " or a non-zero normal");
            continue;
        }
        if (!m.valid[i]) return lane_message(i, "hit on an inactive or masked lane");
        if (!std::isfinite(hits.t[i]) || !(hits.t[i] >= rays.tmin[i] && hits.t[i] <= rays.tmax[i]))
            return lane_message(i, "hit t " + number(hits.t[i]) + " outside [" + number(rays.tmin[i]) + ", " +
                                       number(rays.tmax[i]) + "]");
        if (hits.primitive[i] < 0 || hits.primitive[i] >= scene.primitives)
            return lane_message(i, "primitive " + std::to_string(hits.primitive[i]) + " out of range");
        if (hits.material[i] < 0 || hits.material[i] >= scene.materials)
            return lane_message(i, "material " + std::to_string(hits.material[i]) + " out of range");
        if (hits.mesh[i] < -1 || hits.mesh[i] >= scene.meshes)
            return lane_message(i, "mesh " + std::to_string(hits.mesh[i]) + " out of range");
        if (!std::isfinite(n[0]) || !std::isfinite(n[1]) || !std::isfinite(n[2]))
            return lane_message(i, "normal (" + number(n[0]) + ", " + number(n[1]) + ", " + number(n[2]) + ")");
    }
    return "";
}

std::string check_occluded(const RayPacket8& rays, const std::int32_t* occluded, Precision precision) {
    const LaneMask m = expected_mask(rays, precision);
    for (int i = 0; i < kPacketWidth; ++i) {
        if (occluded[i] != 0 && occluded[i] != -1) return lane_message(i, "occluded " + std::to_string(occluded[i]));
        if (occluded[i] != 0 && !m.valid[i]) return lane_message(i, "occluded on an inactive or masked lane");
    }
    return "";
}

std::string check_shade(const SceneFacts& scene, const RayPacket8& rays, const HitPacket8& hits,
                        const ColorPacket8& radiance) {
    const float* c[3] = {radiance.r, radiance.g, radiance.b};
    for (int k = 0; k < 3; ++k)
        if (const int i = nan_lane(c[k]); i >= 0) return lane_message(i, "NaN radiance");
    for (int i = 0; i < kPacketWidth; ++i) {
        const bool hit = rays.active[i] != 0 && hits.hit[i] != 0;
        for (int k = 0; k < 3; ++k) {
            if (c[k][i] < 0) return lane_message(i, "negative radiance " + number(c[k][i]));
            if (!hit && std::memcmp(&c[k][i], &scene.background[k], sizeof(float)) != 0)
                return lane_message(i, "no hit, radiance " + number(c[k][i]) + " is not the background " +
                                           number(scene.background[k]));
        }
    }
    return "";
}

std::string check_tonemap(const SceneFacts& scene, const ColorPacket8& display) {
    const float* c[3] = {display.r, display.g, display.b};
    for (int k = 0; k < 3; ++k) {
        if (const int i = nan_lane(c[k]); i >= 0) return lane_message(i, "NaN display colour");
        for (int i = 0; i < kPacketWidth; ++i)
            if (c[k][i] < 0 || (scene.display_bounded && c[k][i] > 1))
                return lane_message(i, "display colour " + number(c[k][i]) + " outside [0, 1]");
    }
    return "";
}

StageCounts& StageCounts::operator+=(const StageCounts& o) {
    lanes += o.lanes, active += o.active, masked += o.masked, hits += o.hits, occluded += o.occluded;
    return *this;
}

std::string run_and_check(const Kernel& k, const PacketScene& ps, const SceneFacts& facts, const RayPacket8& rays,
                          const ColorPacket8& colours, StageCounts* counts) {
    HitPacket8 hits;
    ColorPacket8 radiance, display;
    alignas(32) std::int32_t occluded[kPacketWidth];
    const int masked = k.intersect(ps, rays, hits);
    std::string e = check_intersect(facts, rays, hits, masked, k.precision);
    if (!e.empty()) return "intersect: " + e;
    k.occluded(ps, rays, occluded);
    if (!(e = check_occluded(rays, occluded, k.precision)).empty()) return "occluded: " + e;
    k.shade(ps, rays, hits, radiance);
    if (!(e = check_shade(facts, rays, hits, radiance)).empty()) return "shade: " + e;
    k.tonemap(ps, radiance, display);
    if (!(e = check_tonemap(facts, display)).empty()) return "tonemap (shaded): " + e;
    k.tonemap(ps, colours, display);
    if (!(e = check_tonemap(facts, display)).empty()) return "tonemap (raw): " + e;
    if (counts) {
        StageCounts c;
        c.lanes = kPacketWidth;
        for (int i = 0; i < kPacketWidth; ++i) {
            c.active += rays.active[i] != 0;
            c.hits += hits.hit[i] != 0;
            c.occluded += occluded[i] != 0;
        }
        c.masked = std::uint64_t(masked);
        *counts += c;
    }
    return "";
}

// ---- garbage ------------------------------------------------------------------

namespace {

float from_bits(std::uint32_t b) {
    float f;
    std::memcpy(&f, &b, sizeof f);
    return f;
}

}  // namespace

float GarbageRays::value() {
    const std::uint32_t sign = bits() & 0x80000000u;
    switch (bits() % 16) {
    case 0: return from_bits(bits());                                  // any pattern
    case 1: return from_bits(0x7f800001u | sign | (bits() & 0x7fffffu));  // NaN: signalling or quiet, any payload
    case 2: return from_bits(0x7fc00000u | sign);                      // the default quiet NaN
    case 3: return from_bits(0x7f800000u | sign);                      // +-inf
    case 4: return from_bits(sign);                                    // +-0
    case 5: return from_bits(sign | (bits() & 0x7fffffu));              // subnormal (or zero)
    case 6: return from_bits(sign | 1u);                               // +-denorm_min
    case 7: return from_bits(sign | 0x00800000u);                      // +-FLT_MIN
    case 8: return from_bits(sign | 0x7f7fffffu);                      // +-FLT_MAX
    case 9: return from_bits(sign | ((0xc0u + bits() % 0x3f) << 23) | (bits() & 0x7fffffu));  // huge: 2^65..2^127
    case 10: return from_bits(sign | ((0x01u + bits() % 0x3f) << 23) | (bits() & 0x7fffffu));  // tiny: 2^-126..2^-64
    case 11: return from_bits(sign | 0x1f000000u);                     // 2^-63: |d|^2 = 2^-126
    case 12: return from_bits(sign | 0x5f000000u);                     // 2^63: |d|^2 = 2^126
    default: return float(uniform(-1e4, 1e4));                         // ordinary
    }
}

void GarbageRays::fill(RayPacket8& rays) {
    float* fields[8] = {rays.ox, rays.oy, rays.oz, rays.dx, rays.dy, rays.dz, rays.tmin, rays.tmax};
    for (int i = 0; i < kPacketWidth; ++i) {
        // An ordinary ray: origin about the scene, direction of any length
        // 2^-60..2^60 (occasionally within a few ulps of the d.d limits), a
        // usual interval.
        const double o[3] = {uniform(-8, 8), uniform(-8, 8), uniform(-8, 8)};
        double d[3] = {uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)};
        const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        double scale = 1;
        switch (bits() % 8) {
        case 0: scale = std::ldexp(1.0, int(bits() % 121) - 60); break;
        case 1: scale = 0x1p-63 * (1 + double(int(bits() % 17) - 8) * 0x1p-23); break;  // d.d near 2^-126
        case 2: scale = 0x1p63 * (1 + double(int(bits() % 17) - 8) * 0x1p-23); break;   // d.d near 2^126
        default: break;
        }
        for (int k = 0; k < 3; ++k) fields[k][i] = float(o[k]), fields[3 + k][i] = float(d[k] / len * scale);
        rays.tmin[i] = bits() % 4 == 0 ? float(uniform(0, 2)) : 0.0f;
        rays.tmax[i] = bits() % 4 == 0 ? float(uniform(0, 20)) : std::numeric_limits<float>::infinity();
        rays.active[i] = 1;
        rays.pixel[i] = std::int32_t(bits());  // any value keys occlusion samples
        // Rounding residuals (RayPacket::ox_lo...): zero, a real one (below
        // u/2 of its component), or garbage (any float: not a rounding, but
        // the normals must stay finite).
        float* residuals[6] = {rays.ox_lo, rays.oy_lo, rays.oz_lo, rays.dx_lo, rays.dy_lo, rays.dz_lo};
        const std::uint32_t residual_kind = bits() % 4;
        for (int k = 0; k < 6; ++k)
            residuals[k][i] = residual_kind == 0   ? 0.0f
                              : residual_kind == 1 ? fields[k][i] * float(uniform(-0x1p-25, 0x1p-25))
                              : bits() % 2         ? value()
                                                   : 0.0f;
        // Then garbage: a whole lane of random bits, or some fields replaced.
        const std::uint32_t kind = bits() % 16;
        if (kind == 0) {
            for (float* f : fields) f[i] = from_bits(bits());
            for (float* f : residuals) f[i] = from_bits(bits());
            rays.active[i] = std::int32_t(bits());
            continue;
        }
        for (float* f : fields)
            if (bits() % 16 == 0) f[i] = value();
        if (kind == 1) std::swap(rays.tmin[i], rays.tmax[i]);  // tmin > tmax (or a NaN stays NaN)
        if (kind == 2) rays.tmax[i] = rays.tmin[i];             // empty interval
        if (kind == 3) rays.active[i] = 0;
        if (kind == 4) rays.active[i] = std::int32_t(bits());  // any non-zero int is active
    }
}

void GarbageRays::fill(ColorPacket8& colours) {
    float* c[3] = {colours.r, colours.g, colours.b};
    for (float* channel : c)
        for (int i = 0; i < kPacketWidth; ++i) channel[i] = bits() % 2 ? value() : float(uniform(0, 4));
}

std::string trace_camera_tiles(const Scene& scene) {
    const PacketScene ps = compile(scene);
    const SceneFacts facts = scene_facts(scene);
    const int w = ps.width(), h = ps.height();
    const int last_tile = (w - 1) / kPacketWidth * kPacketWidth;
    for (Path path : {Path::simd, Path::scalar}) {
        const Kernel k = select_kernel(ps, path);
        for (const int y : {0, h / 2, h - 1})
            for (const int x0 : {0, last_tile}) {
                RayPacket8 rays;
                k.camera(ps, x0, y, rays);
                ColorPacket8 colours;  // raw radiance for tonemap: whatever the rays hold
                for (int i = 0; i < kPacketWidth; ++i) colours.r[i] = rays.ox[i], colours.g[i] = rays.dy[i], colours.b[i] = rays.dz[i];
                const std::string e = run_and_check(k, ps, facts, rays, colours);
                if (!e.empty()) return k.name() + " tile (" + std::to_string(x0) + ", " + std::to_string(y) + "): " + e;
            }
    }
    return "";
}

}  // namespace octray::test
