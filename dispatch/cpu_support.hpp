// dispatch/cpu_support.hpp — what this CPU runs, as the per-ISA units need it:
// AVX2 with FMA (the AVX2 units use both), and AVX-512 F + VL on top. Used by
// dispatch (dispatch/dispatch.cpp) and by the configure-time probe of
// OCTRAY_ISAS=host (cmake/isa_probe.cpp), so both apply one rule.
#pragma once

namespace octray::cpu {

inline bool runs_avx2_fma() { return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"); }

inline bool runs_avx512() {
    return runs_avx2_fma() && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl");
}

// The best ISA of the unit list (CMakeLists.txt, octray_isa_unit's ISA field) this CPU runs.
inline const char* best_isa() { return runs_avx512() ? "avx512" : runs_avx2_fma() ? "avx2" : "generic"; }

}  // namespace octray::cpu
