#pragma once
// Angle conversions shared by the virtual drone's code (one name per direction: no file can
// mistake one for the other).

#include <numbers>

namespace gs::sim {

inline constexpr double kRadPerDeg = std::numbers::pi / 180.0;
inline constexpr double kDegPerRad = 180.0 / std::numbers::pi;

}  // namespace gs::sim
