// dispatch/isa_kernels.hpp — what each per-ISA translation unit provides.
#pragma once

#include <octray/kernels.hpp>

namespace octray::kernels {

// Exact precision is specialized on the scene's features: intersect on the
// primitive bits (64 variants), shade on the light bits (32 variants). The
// other precision modes are compiled once, with every feature.
inline constexpr int kPrimitiveVariants = 64;
inline constexpr int kLightVariants = 32;
inline constexpr unsigned kLightShift = 6;

// A set of precision modes, one bit each.
inline constexpr unsigned mode_bit(Precision p) { return 1u << unsigned(p); }
// What the AVX2 and baseline units compile; the AVX-512 units compile these
// and the 14-bit-estimate modes.
inline constexpr unsigned kBaseModes =
    mode_bit(Precision::exact) | mode_bit(Precision::fast) | mode_bit(Precision::approx) | mode_bit(Precision::f64);
inline constexpr unsigned kAvx512Modes = mode_bit(Precision::fast14) | mode_bit(Precision::approx14);
inline constexpr unsigned kAvx512UnitModes = kBaseModes | kAvx512Modes;

// Each unit (one per line of octray_isa_unit in CMakeLists.txt, listed in
// the generated isa_units.inc as OCTRAY_UNIT(name, path, isa, cpu_check,
// modes)) provides name_kernel. `primitive_bits` /
// `light_bits` are FeatureBit sets; pass kAllFeatures for the general kernel.
// A mode the unit does not compile gives an empty Kernel.
#define OCTRAY_UNIT(name, path, isa, cpu_check, modes)                                  \
    Kernel name##_kernel(Precision precision, unsigned primitive_bits, unsigned light_bits);
#include "dispatch/isa_units.inc"
#undef OCTRAY_UNIT


// One translation unit's kernels: what it runs, where, and how to get them.
struct Unit {
    Path path;
    const char* isa;
    bool (*supported)();  // this CPU runs the unit's code
    Kernel (*kernel)(Precision precision, unsigned primitive_bits, unsigned light_bits);
    unsigned modes;  // mode_bit set the unit compiles
};
// Every unit built into the library; within a path the preferred one first.
// Dispatch takes the first supported unit that compiles the asked mode.
extern const Unit kUnits[];
extern const int kUnitCount;

}  // namespace octray::kernels
