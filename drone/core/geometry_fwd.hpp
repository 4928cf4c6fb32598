#pragma once
// The part of the geometry vocabulary (drone/core/geometry.hpp) that needs no Eigen: the angle
// units and the camera mounts. Headers that only name these include this one, so Eigen (about
// two seconds of parsing) reaches only the files that compute with it.

#include <numbers>

namespace gs::geom {

inline constexpr double kRadPerDeg = std::numbers::pi / 180.0;
inline constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// Where a camera is mounted: the AR.Drone's front and bottom cameras, and the upward camera of
// the thesis' rig (image up = body forward, image right = body left, the view from below).
// Axes: body_from_camera (drone/core/geometry.hpp).
enum class Mount { Front, Bottom, Top };

}  // namespace gs::geom
