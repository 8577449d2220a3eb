// kernels/isa_avx2_scalar.cpp — the scalar path: the same kernel at one float
// lane, compiled with the same flags as the SIMD path (-mavx2 -mfma) so the
// baseline is honest: scalar FMAs and the same operation order, one lane at a time.
// Precision::f64 runs it at one double lane.
#define OCTRAY_ISA avx2_scalar
#include "packet_kernels.hpp"
#include "isa_instantiate.hpp"

namespace octray::kernels {

Kernel scalar_avx2_kernel(Precision precision, unsigned primitive_bits, unsigned light_bits) {
    return avx2_scalar::make_kernel<float, double, kBaseModes, true>(Path::scalar, "avx2", precision, primitive_bits,
                                                                     light_bits);
}
Blocks scalar_avx2_blocks(Precision precision) { return avx2_scalar::make_blocks<float, double, kBaseModes>(precision); }

}  // namespace octray::kernels
