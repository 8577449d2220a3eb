// kernels/isa_generic.cpp — the scalar path for any x86-64 (no AVX2 assumed):
// the fallback when the CPU lacks AVX2/FMA. General variant only.
#define OCTRAY_ISA generic
#include "packet_kernels.hpp"
#include "isa_instantiate.hpp"

namespace octray::kernels {

Kernel scalar_generic_kernel(Precision precision, unsigned primitive_bits, unsigned light_bits) {
    return generic::make_kernel<float, double, kBaseModes, false>(Path::scalar, "generic", precision, primitive_bits,
                                                                  light_bits);
}
Blocks scalar_generic_blocks(Precision precision) { return generic::make_blocks<float, double, kBaseModes>(precision); }

}  // namespace octray::kernels
