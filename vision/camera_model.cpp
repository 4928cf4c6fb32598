#include "vision/camera_model.hpp"

namespace gs::vision {

CameraCalibration CameraCalibration::scaled_to(int w, int h) const {
    CameraCalibration c = *this;
    const double sx = static_cast<double>(w) / width;
    const double sy = static_cast<double>(h) / height;
    c.width = w;
    c.height = h;
    c.fx *= sx;
    c.cx = (cx + 0.5) * sx - 0.5;
    c.fy *= sy;
    c.cy = (cy + 0.5) * sy - 0.5;
    return c;
}

}  // namespace gs::vision
