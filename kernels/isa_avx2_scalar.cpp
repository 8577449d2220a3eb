// kernels/isa_avx2_scalar.cpp — the scalar path: the same kernel at one float
// lane, compiled with the same flags as the SIMD path (-mavx2 -mfma) so the
// baseline is honest: scalar FMAs and the same operation order, one lane at a time.
#define OCTRAY_ISA avx2_scalar
#include "packet_kernels.hpp"
#include "isa_instantiate.hpp"

namespace octray::kernels {

Kernel scalar_avx2_kernel(Precision precision, unsigned primitive_bits, unsigned light_bits) {
    return avx2_scalar::make_kernel<float, true>(Path::scalar, "avx2", precision, primitive_bits, light_bits);
}

}  // namespace octray::kernels
