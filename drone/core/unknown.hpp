#pragma once
// "Unknown" has one spelling: a quiet NaN, never 0 (an indicator says only what is known).
// known(v) is the test; NaN compares false with everything, so never write v == kUnknown.

#include <cmath>
#include <limits>

namespace gs::inline core {

inline constexpr double kUnknown = std::numeric_limits<double>::quiet_NaN();

inline bool known(double v) {
    return !std::isnan(v);
}

}  // namespace gs::inline core
