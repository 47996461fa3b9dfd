#pragma once
// Mathematical constants shared by every layer: pi once, from C++20 <numbers>,
// in double and in float (the renderer's arithmetic is float).
#include <numbers>

namespace plumage {

inline constexpr double kPi = std::numbers::pi;
inline constexpr float kPiF = std::numbers::pi_v<float>;
// Degrees to radians.
inline constexpr double kDegToRad = kPi / 180.0;

}  // namespace plumage
