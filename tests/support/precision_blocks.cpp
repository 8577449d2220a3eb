// tests/support/precision_blocks.cpp — blocks_of (precision_blocks.hpp): the test
// units' blocks, in the order of the library's table (both from isa_units.inc).
#include "precision_blocks.hpp"

#include <iterator>

namespace octray::kernels {
namespace {

using BlocksFn = Blocks (*)(Precision);
const BlocksFn kBlocks[] = {
#define OCTRAY_UNIT(name, path, isa, cpu_check, modes) &name##_blocks,
#include "dispatch/isa_units.inc"
#undef OCTRAY_UNIT
};
static_assert(std::size(kBlocks) > 0);

}  // namespace

Blocks blocks_of(const Unit& u, Precision precision) {
    const std::ptrdiff_t i = &u - kUnits;
    return i >= 0 && i < kUnitCount && i < std::ptrdiff_t(std::size(kBlocks)) ? kBlocks[i](precision) : Blocks{};
}

}  // namespace octray::kernels
