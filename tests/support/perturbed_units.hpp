// tests/support/perturbed_units.hpp — the test-only kernel units whose estimates sit
// at the limits of their specification (perturbed_unit.cpp.in,
// perturbed_estimates.hpp): the AVX2 units' code on both paths, every
// estimate mode, the 14-bit ones too (their estimates are software here, so
// no AVX-512 is needed).
#pragma once

#include "dispatch/isa_kernels.hpp"

namespace octray::kernels {

inline constexpr unsigned kPerturbedModes =
    mode_bit(Precision::fast) | mode_bit(Precision::approx) | mode_bit(Precision::fast14) | mode_bit(Precision::approx14);

Kernel perturbed_avx2_simd_kernel(Precision precision);
Kernel perturbed_avx2_scalar_kernel(Precision precision);

}  // namespace octray::kernels
