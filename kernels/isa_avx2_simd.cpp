// kernels/isa_avx2_simd.cpp — the SIMD path: 8 float lanes, AVX2 + FMA; for
// Precision::f64, 8 double lanes as two 4-lane AVX2 batches per packet.
// Built with -mavx2 -mfma; only reached after a run-time CPU check.
#define OCTRAY_ISA avx2_simd
#include "packet_kernels.hpp"
#include "isa_instantiate.hpp"

namespace octray::kernels {

using Avx2Floats = xsimd::batch<float, xsimd::fma3<xsimd::avx2>>;
using Avx2Doubles = xsimd::batch<double, xsimd::fma3<xsimd::avx2>>;
static_assert(Avx2Floats::size == kPacketWidth, "one AVX2 batch is one packet");

Kernel simd_avx2_kernel(Precision precision, unsigned primitive_bits, unsigned light_bits) {
    return avx2_simd::make_kernel<Avx2Floats, Avx2Doubles, kBaseModes, true>(Path::simd, "avx2", precision,
                                                                             primitive_bits, light_bits);
}
Blocks simd_avx2_blocks(Precision precision) {
    return avx2_simd::make_blocks<Avx2Floats, Avx2Doubles, kBaseModes>(precision);
}

}  // namespace octray::kernels
