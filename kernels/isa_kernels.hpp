// kernels/isa_kernels.hpp — what each per-ISA translation unit provides.
#pragma once

#include <octray/kernels.hpp>

namespace octray::kernels {

// Exact precision is specialized on the scene's features: intersect on the
// primitive bits (64 variants), shade on the light bits (32 variants). The
// other precision modes are compiled once, with every feature.
inline constexpr int kPrimitiveVariants = 64;
inline constexpr int kLightVariants = 32;
inline constexpr unsigned kLightShift = 6;

// `primitive_bits` / `light_bits` are FeatureBit sets; pass kAllFeatures for the general kernel.
Kernel simd_avx2_kernel(Precision precision, unsigned primitive_bits, unsigned light_bits);
Kernel scalar_avx2_kernel(Precision precision, unsigned primitive_bits, unsigned light_bits);
// Baseline x86-64 (no AVX2): the scalar path, general variant only.
Kernel scalar_generic_kernel(Precision precision, unsigned primitive_bits, unsigned light_bits);

}  // namespace octray::kernels
