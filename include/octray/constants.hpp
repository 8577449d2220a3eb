// octray/constants.hpp — the mathematical constants every path shares.
//
// Defined once here so the reference, the compiled scene, the tools, the
// tests and the examples all divide by the same pi (the Lambertian BRDF's kd cd / pi,
// and the camera's degrees-to-radians). The unit roundoff of float lives with
// the error bounds it states: precision.hpp, kUnitRoundoff.
#pragma once

namespace octray {

// pi, rounded to the nearest double.
inline constexpr double kPi = 3.14159265358979323846;

}  // namespace octray
