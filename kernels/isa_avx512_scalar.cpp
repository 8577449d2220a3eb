// kernels/isa_avx512_scalar.cpp — the scalar path with the SIMD path's flags
// where that path is isa_avx512_simd.cpp (-mavx512f -mavx512vl -mfma): the
// same kernel at one float lane (one double lane for Precision::f64), so the
// baseline gets the same 32 registers and estimate instructions (vrcp14ss)
// as the 8 lanes it is compared with.
#define OCTRAY_ISA avx512_scalar
#include "packet_kernels.hpp"
#include "isa_instantiate.hpp"

namespace octray::kernels {

Kernel scalar_avx512_kernel(Precision precision, unsigned primitive_bits, unsigned light_bits) {
    return avx512_scalar::make_kernel<float, double, kAvx512UnitModes, true>(Path::scalar, "avx512", precision,
                                                                            primitive_bits, light_bits);
}
Blocks scalar_avx512_blocks(Precision precision) {
    return avx512_scalar::make_blocks<float, double, kAvx512UnitModes>(precision);
}

}  // namespace octray::kernels
