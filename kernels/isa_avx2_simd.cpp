// kernels/isa_avx2_simd.cpp — the SIMD path: 8 float lanes, AVX2 + FMA.
// Built with -mavx2 -mfma; only reached after a run-time CPU check.
#define OCTRAY_ISA avx2_simd
#include "packet_kernels.hpp"
#include "isa_instantiate.hpp"

namespace octray::kernels {

Kernel simd_avx2_kernel(Precision precision, unsigned primitive_bits, unsigned light_bits) {
    using Lanes = xsimd::batch<float, xsimd::fma3<xsimd::avx2>>;
    static_assert(Lanes::size == kPacketWidth, "one AVX2 batch is one packet");
    return avx2_simd::make_kernel<Lanes, true>(Path::simd, "avx2", precision, primitive_bits, light_bits);
}

}  // namespace octray::kernels
