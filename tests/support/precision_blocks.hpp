// tests/support/precision_blocks.hpp — the precision building blocks as the kernels
// compute them (same lane type, same lane functions, same ISA flags), per ISA
// unit, for tests/test_precision_blocks.cpp. Test-only: tests/CMakeLists.txt
// generates one unit per line of the library's ISA list (octray_isa_sources
// with tests/support/precision_unit.cpp.in); the library carries none of it.
#pragma once

#include "dispatch/isa_kernels.hpp"

namespace octray::kernels {

// Over float arrays whose length is a multiple of kPacketWidth; nullptr
// members where a unit does not compile the mode.
struct Blocks {
    void (*rcp)(const float* x, float* out, int n) noexcept = nullptr;
    void (*rsqrt)(const float* x, float* out, int n) noexcept = nullptr;
    void (*div)(const float* a, const float* b, float* out, int n) noexcept = nullptr;
    void (*normalize)(const float* const v[3], float* const out[3], int n) noexcept = nullptr;  // v * rsqrt(v.v)
    void (*ndotl)(const float* const n[3], const float* const v[3], float* out, int count) noexcept = nullptr;  // (n.v) * rsqrt(v.v)
    void (*pow)(const float* x, const float* y, float* out, int n) noexcept = nullptr;  // x^y, x > 0: the tone map's gamma
};

// Each generated test unit provides name_blocks.
#define OCTRAY_UNIT(name, path, isa, cpu_check, modes) Blocks name##_blocks(Precision precision);
#include "dispatch/isa_units.inc"
#undef OCTRAY_UNIT

// The blocks of library unit `u` (one of kUnits) in mode `precision`.
Blocks blocks_of(const Unit& u, Precision precision);

}  // namespace octray::kernels
