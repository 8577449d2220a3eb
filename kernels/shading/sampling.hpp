// kernels/shading/sampling.hpp — the ambient-occlusion sample generator (docs/shading-model.md,
// "Ambient occlusion"): counter-based, keyed by (pixel, sample index), no
// state. Every path (the reference in double, the scalar and SIMD kernels in
// float) gets the same two integers for a key, so the same sample rays up to
// the rounding of the direction built from them.
//
// The hash is pcg3d of Jarzynski & Olano, "Hash Functions for GPU Rendering",
// JCGT 9(3), 2020: a 3-d -> 3-d mix of 32-bit words by multiply, add, xor
// and shift (tests/test_occlusion.cpp checks the moments and the cosine
// distribution of what it gives here). It is written once over
// U = std::uint32_t or an unsigned 32-bit SIMD lane type (xsimd::batch<
// std::uint32_t, A>): integer arithmetic, so every lane type computes the
// same bits. Key (pixel, sample, stream); the top 24 bits of the first two
// outputs are the sample's two uniform numbers u = i * 2^-24 in [0, 1), exact
// in float and double.
#pragma once

#include <cstdint>

namespace octray::sampling {

// Third word of every occlusion key: a stream id, so other sampled effects
// keyed by (pixel, sample) can draw other numbers.
inline constexpr std::uint32_t kOcclusionStream = 0x414f0001u;
// 2^-24: a 24-bit integer to [0, 1).
inline constexpr float kUnit24 = 0x1p-24f;

template <class U>
inline void pcg3d(U& x, U& y, U& z) {
    x = x * U(1664525u) + U(1013904223u);
    y = y * U(1664525u) + U(1013904223u);
    z = z * U(1664525u) + U(1013904223u);
    x += y * z;
    y += z * x;
    z += x * y;
    x ^= x >> 16;
    y ^= y >> 16;
    z ^= z >> 16;
    x += y * z;
    y += z * x;
    z += x * y;
}

// The two 24-bit integers of occlusion sample `sample` at `pixel`: the
// sample's u1 = a * 2^-24 (the radius, squared, of its point on the unit disk)
// and u2 = b * 2^-24 (its angle, in turns).
template <class U>
inline void occlusion_bits(U pixel, U sample, U& a, U& b) {
    U stream(kOcclusionStream);
    pcg3d(pixel, sample, stream);
    a = pixel >> 8;
    b = sample >> 8;
}

// The same as doubles in [0, 1), for the reference and tests.
inline void occlusion_uniforms(std::uint32_t pixel, std::uint32_t sample, double& u1, double& u2) {
    std::uint32_t a, b;
    occlusion_bits(pixel, sample, a, b);
    u1 = double(a) * double(kUnit24);
    u2 = double(b) * double(kUnit24);
}

}  // namespace octray::sampling
