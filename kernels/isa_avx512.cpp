// kernels/isa_avx512.cpp — the modes that need AVX-512 F + VL: fast14 and
// approx14 (rcp14/rsqrt14 estimates, with and without a Newton step), on the
// scalar path (one float lane, vrcp14ss) and the SIMD path (8 float lanes in
// one ymm register, vrcp14ps). Built with -mavx512f -mavx512vl -mfma; only
// reached after a run-time CPU check. General variant only.
#define OCTRAY_ISA avx512
#include "packet_kernels.hpp"
#include "isa_instantiate.hpp"

namespace octray::kernels {

// 8 float lanes: an AVX2-sized batch; the AVX-512VL flags give it the EVEX estimates.
using Avx512Floats = xsimd::batch<float, xsimd::fma3<xsimd::avx2>>;
static_assert(Avx512Floats::size == kPacketWidth, "one batch is one packet");

// Precision::f64: 8 double lanes, one zmm register per packet.
using Avx512Doubles = xsimd::batch<double, xsimd::avx512f>;
static_assert(Avx512Doubles::size == kPacketWidth, "one batch is one packet");
inline constexpr unsigned kSimdModes = kAvx512Modes | mode_bit(Precision::f64);

Kernel simd_avx512_kernel(Precision precision, unsigned primitive_bits, unsigned light_bits) {
    return avx512::make_kernel<Avx512Floats, Avx512Doubles, kSimdModes, false>(Path::simd, "avx512", precision,
                                                                               primitive_bits, light_bits);
}
Kernel scalar_avx512_kernel(Precision precision, unsigned primitive_bits, unsigned light_bits) {
    return avx512::make_kernel<float, void, kAvx512Modes, false>(Path::scalar, "avx512", precision, primitive_bits,
                                                                 light_bits);
}
Blocks simd_avx512_blocks(Precision precision) {
    return avx512::make_blocks<Avx512Floats, Avx512Doubles, kSimdModes>(precision);
}
Blocks scalar_avx512_blocks(Precision precision) { return avx512::make_blocks<float, void, kAvx512Modes>(precision); }

}  // namespace octray::kernels
