// cmake/isa_probe.cpp — prints the best ISA of octray's unit list that the
// configuring machine runs (OCTRAY_ISAS=host in CMakeLists.txt).
#include "dispatch/cpu_support.hpp"

#include <cstdio>

int main() {
    __builtin_cpu_init();
    std::puts(octray::cpu::best_isa());
    return 0;
}
