#pragma once
// Small things every part of vision/ uses: the "unknown" value (the base's) and a stopwatch for
// the per-stage timings the classifiers and odometry report.

#include "drone/core/geometry_fwd.hpp"
#include "drone/core/unknown.hpp"

#include <chrono>
#include <limits>
#include <numbers>

namespace gs::vision {

using geom::kRadPerDeg;

using StageClock = std::chrono::steady_clock;

// Milliseconds from t0 to now.
inline double ms_since(StageClock::time_point t0) {
    return std::chrono::duration<double, std::milli>(StageClock::now() - t0).count();
}

}  // namespace gs::vision
