// kernels/isa_avx512_simd.cpp — the SIMD path on AVX-512 F + VL: the same 8
// float lanes in one ymm register as the AVX2 unit, with the EVEX encoding's
// 32 registers and mask compares, and the modes that need AVX-512: fast14 and
// approx14 (vrcp14ps/vrsqrt14ps estimates, with and without a Newton step).
// Precision::f64: 8 double lanes, one zmm register per packet. Built with
// -mavx512f -mavx512vl -mfma; only reached after a run-time CPU check, and
// preferred to the AVX2 unit where the CPU has both. With 16 registers the
// AVX2 unit's sphere loop keeps ray fields and centres on the stack (24 of
// its 90 instructions a test are stack loads, stores and register copies);
// timed, the end-to-end SIMD render ran at 0.84-1.13x of the AVX2 unit's
// speed in three bench-report runs, within this VM's noise (README).
#define OCTRAY_ISA avx512_simd
#include "packet_kernels.hpp"
#include "isa_instantiate.hpp"

namespace octray::kernels {

// 8 float lanes: an AVX2-sized batch; the AVX-512VL flags give it EVEX code and the estimates.
using Avx512Floats = xsimd::batch<float, xsimd::fma3<xsimd::avx2>>;
static_assert(Avx512Floats::size == kPacketWidth, "one batch is one packet");

// Precision::f64: 8 double lanes, one zmm register per packet.
using Avx512Doubles = xsimd::batch<double, xsimd::avx512f>;
static_assert(Avx512Doubles::size == kPacketWidth, "one batch is one packet");

Kernel simd_avx512_kernel(Precision precision, unsigned primitive_bits, unsigned light_bits) {
    return avx512_simd::make_kernel<Avx512Floats, Avx512Doubles, kAvx512UnitModes, true>(
        Path::simd, "avx512", precision, primitive_bits, light_bits);
}
Blocks simd_avx512_blocks(Precision precision) {
    return avx512_simd::make_blocks<Avx512Floats, Avx512Doubles, kAvx512UnitModes>(precision);
}

}  // namespace octray::kernels
