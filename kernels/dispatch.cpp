// kernels/dispatch.cpp — run-time choice of ISA and feature variant; the
// packet render loop that strings the stages together.
#include "isa_kernels.hpp"

#include <octray/kernels.hpp>

#include <algorithm>
#include <cmath>

namespace octray {

bool simd_supported() {
    // The AVX2 units also use FMA; both must be there.
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
}

namespace {

Kernel make(Path path, Precision precision, unsigned primitive_bits, unsigned light_bits) {
    if (!simd_supported()) return kernels::scalar_generic_kernel(precision, primitive_bits, light_bits);
    return path == Path::simd ? kernels::simd_avx2_kernel(precision, primitive_bits, light_bits)
                              : kernels::scalar_avx2_kernel(precision, primitive_bits, light_bits);
}

}  // namespace

Kernel select_kernel(const PacketScene& scene, Path path, Precision precision) {
    const unsigned bits = scene.features.bits;
    return make(path, precision, bits & kAllPrimitives, bits & ~kAllPrimitives);
}

Kernel general_kernel(Path path, Precision precision) { return make(path, precision, kAllFeatures, kAllFeatures); }

std::string Kernel::name() const {
    return std::string(path_name(path)) + "/" + isa + "/" + precision_name(precision) + " [" +
           feature_string(primitive_bits | light_bits) + "]";
}

void render_rows(const Kernel& k, const PacketScene& scene, int y0, int y1, Image<float>& hdr, Image<float>* display,
                 RenderCounters* counters, std::int32_t* primitive_ids) noexcept {
    RayPacket8 rays;
    HitPacket8 hits;
    ColorPacket8 radiance, shown;
    RenderCounters local;
    const int width = scene.camera.width;
    for (int y = y0; y < y1; ++y) {
        for (int x0 = 0; x0 < width; x0 += kPacketWidth) {
            k.camera(scene, x0, y, rays);
            local.masked += std::uint64_t(k.intersect(scene, rays, hits));
            k.shade(scene, rays, hits, radiance);
            const int n = std::min(kPacketWidth, width - x0);
            local.rays += std::uint64_t(n);
            for (int i = 0; i < n; ++i) {
                float* px = hdr.pixel(x0 + i, y);
                px[0] = radiance.r[i], px[1] = radiance.g[i], px[2] = radiance.b[i];
                if (primitive_ids) primitive_ids[std::size_t(y) * std::size_t(width) + std::size_t(x0 + i)] = hits.primitive[i];
            }
            if (display) {
                k.tonemap(scene, radiance, shown);
                for (int i = 0; i < n; ++i) {
                    float* px = display->pixel(x0 + i, y);
                    px[0] = shown.r[i], px[1] = shown.g[i], px[2] = shown.b[i];
                }
            }
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
