#pragma once
// Angle conversions shared by the virtual drone's code (one name per direction: no file can
// mistake one for the other): the geometry vocabulary's (drone/core/geometry.hpp).

#include "drone/core/geometry_fwd.hpp"

namespace gs::sim {

using geom::kDegPerRad;
using geom::kRadPerDeg;

}  // namespace gs::sim
