// octray/precision.hpp — precision modes of the packet kernels.
//
// A mode decides how a kernel divides and takes (reciprocal) square roots.
// It is a template parameter of every kernel: the mode costs nothing at run
// time and each mode is a separate, separately tested instantiation.
#pragma once

namespace octray {

enum class Precision {
    exact,   // IEEE-754 division and sqrt (correctly rounded)
    fast,    // hardware rcp/rsqrt estimates refined by one Newton-Raphson step
    approx,  // raw hardware estimates (rcpps/rsqrtps: rel. error <= 1.5 * 2^-12)
};

inline constexpr const char* precision_name(Precision p) {
    return p == Precision::exact ? "exact" : p == Precision::fast ? "fast" : "approx";
}

}  // namespace octray
