// dispatch/dispatch.cpp — run-time choice of ISA and feature variant.
#include "dispatch/cpu_support.hpp"
#include "dispatch/isa_kernels.hpp"

#include <octray/kernels.hpp>

#include <string_view>

namespace octray {

bool simd_supported() { return cpu::runs_avx2_fma(); }

bool avx512_supported() { return cpu::runs_avx512(); }

bool precision_supported(Precision precision) { return !needs_avx512(precision) || avx512_supported(); }

namespace kernels {
namespace {
bool always() { return true; }
}  // namespace

// The table, from the same list as the units themselves (CMakeLists.txt).
const Unit kUnits[] = {
#define OCTRAY_UNIT(name, path, isa, cpu_check, modes) {Path::path, isa, &cpu_check, &name##_kernel, modes},
#include "dispatch/isa_units.inc"
#undef OCTRAY_UNIT
};
const int kUnitCount = int(sizeof kUnits / sizeof kUnits[0]);

}  // namespace kernels

namespace {

Kernel make(Path path, Precision precision, unsigned primitive_bits, unsigned light_bits, Isa isa) {
    // Without AVX-512 the 14-bit-estimate modes become `fast` (Kernel::precision
    // says so): within approx14's stated bounds, and fast14's to a factor 2.
    if (!precision_supported(precision)) precision = Precision::fast;
    // Without AVX2 the SIMD path becomes the baseline scalar one (Kernel::isa "generic").
    if (!simd_supported()) path = Path::scalar;
    // The asked ISA if this CPU runs it and it compiles the mode (generic:
    // the scalar path only); else the best. A build with this CPU's units
    // left out (OCTRAY_ISAS=host, run on another machine) gets the scalar path.
    for (const Path p : {path, Path::scalar}) {
        for (const bool pinned : {isa != Isa::best, false}) {
            for (int i = 0; i < kernels::kUnitCount; ++i) {
                const kernels::Unit& u = kernels::kUnits[i];
                if (u.path == p && (u.modes & kernels::mode_bit(precision)) != 0 && u.supported() &&
                    (!pinned || std::string_view(u.isa) == isa_name(isa)))
                    return u.kernel(precision, primitive_bits, light_bits);
            }
        }
    }
    return kernels::generic_scalar_kernel(Precision::exact, kAllFeatures, kAllFeatures);  // not reached
}

}  // namespace

Kernel select_kernel(const PacketScene& scene, Path path, Precision precision, Isa isa) {
    const unsigned bits = scene.features().bits;
    return make(path, precision, bits & kAllPrimitives, bits & ~kAllPrimitives, isa);
}

Kernel general_kernel(Path path, Precision precision, Isa isa) {
    return make(path, precision, kAllFeatures, kAllFeatures, isa);
}

std::string Kernel::name() const {
    return std::string(path_name(path)) + "/" + isa + "/" + precision_name(precision) + " [" +
           feature_string(primitive_bits | light_bits) + "]";
}

}  // namespace octray
