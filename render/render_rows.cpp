// render/render_rows.cpp — the packet render loop that strings the kernels'
// stages together, and the 8-bit conversion of its display image.
#include <octray/render.hpp>

#include <algorithm>
#include <cmath>
#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace octray {

namespace {

// The first n pixels of a packet, SoA, to interleaved RGB at dst. A full
// packet goes through SSE shuffles (this runs once per packet on every path,
// and element by element it was a large share of the SIMD path's work).
void interleave_rgb(const ColorPacket8& c, int n, float* dst) {
#if defined(__SSE2__)
    if (n == kPacketWidth) {
        for (int h = 0; h < kPacketWidth; h += 4, dst += 12) {
            const __m128 r = _mm_load_ps(c.r + h), g = _mm_load_ps(c.g + h), b = _mm_load_ps(c.b + h);
            const __m128 rg_lo = _mm_unpacklo_ps(r, g), rg_hi = _mm_unpackhi_ps(r, g);  // r0 g0 r1 g1 | r2 g2 r3 g3
            const __m128 b0r1 = _mm_shuffle_ps(b, r, _MM_SHUFFLE(1, 1, 0, 0));          // b0 b0 r1 r1
            const __m128 g1b1 = _mm_shuffle_ps(rg_lo, b, _MM_SHUFFLE(1, 1, 3, 3));      // g1 g1 b1 b1
            const __m128 b2r3 = _mm_shuffle_ps(b, rg_hi, _MM_SHUFFLE(2, 2, 2, 2));      // b2 b2 r3 r3
            const __m128 g3b3 = _mm_shuffle_ps(rg_hi, b, _MM_SHUFFLE(3, 3, 3, 3));      // g3 g3 b3 b3
            _mm_storeu_ps(dst, _mm_shuffle_ps(rg_lo, b0r1, _MM_SHUFFLE(2, 0, 1, 0)));    // r0 g0 b0 r1
            _mm_storeu_ps(dst + 4, _mm_shuffle_ps(g1b1, rg_hi, _MM_SHUFFLE(1, 0, 2, 0)));  // g1 b1 r2 g2
            _mm_storeu_ps(dst + 8, _mm_shuffle_ps(b2r3, g3b3, _MM_SHUFFLE(2, 0, 2, 0)));   // b2 r3 g3 b3
        }
        return;
    }
#endif
    for (int i = 0; i < n; ++i, dst += 3) dst[0] = c.r[i], dst[1] = c.g[i], dst[2] = c.b[i];
}

}  // namespace

// Packets shaded before their tone maps run, back to back. A tone map is a
// few chains of dependent polynomial steps; run between one packet's shading
// and the next packet's camera rays it leaves the core idle on their
// latency; over a group (Kernel::tonemap_group, two packets in lockstep) the
// chains of neighbouring packets overlap.
constexpr int kToneGroup = 8;

void render_rows(const Kernel& k, const PacketScene& scene, int y0, int y1, Image<float>& hdr, Image<float>* display,
                 RenderCounters* counters, std::int32_t* primitive_ids) noexcept {
    RayPacket8 rays;
    HitPacket8 hits;
    ColorPacket8 radiance[kToneGroup], shown[kToneGroup];
    RenderCounters local;
    const int width = scene.width();
    const int group_width = kPacketWidth * kToneGroup;
    for (int y = y0; y < y1; ++y) {
        for (int g0 = 0; g0 < width; g0 += group_width) {
            const int g1 = std::min(width, g0 + group_width);
            for (int x0 = g0, j = 0; x0 < g1; x0 += kPacketWidth, ++j) {
                k.camera(scene, x0, y, rays);
                local.masked += std::uint64_t(k.intersect(scene, rays, hits));
                k.shade(scene, rays, hits, radiance[j]);
                const int n = std::min(kPacketWidth, width - x0);
                local.rays += std::uint64_t(n);
                interleave_rgb(radiance[j], n, hdr.pixel(x0, y));
                if (primitive_ids)
                    std::copy(hits.primitive, hits.primitive + n,
                              primitive_ids + std::size_t(y) * std::size_t(width) + std::size_t(x0));
            }
            if (!display) continue;
            const int count = (g1 - g0 + kPacketWidth - 1) / kPacketWidth;
            if (k.tonemap_group) k.tonemap_group(scene, radiance, shown, count);
            else for (int j = 0; j < count; ++j) k.tonemap(scene, radiance[j], shown[j]);
            for (int x0 = g0, j = 0; x0 < g1; x0 += kPacketWidth, ++j)
                interleave_rgb(shown[j], std::min(kPacketWidth, width - x0), display->pixel(x0, y));
        }
    }
    if (counters) {
        counters->rays += local.rays;
        counters->masked += local.masked;
    }
}

ImageRGB8 quantize(const Image<float>& display) {
    ImageRGB8 out(display.width, display.height);
    for (std::size_t i = 0; i < display.rgb.size(); ++i) {
        const float c = display.rgb[i];
        const double clamped = c > 0.0f ? std::min(double(c), 1.0) : 0.0;  // NaN -> 0
        out.rgb[i] = std::uint8_t(std::floor(255.0 * clamped + 0.5));
    }
    return out;
}

}  // namespace octray
