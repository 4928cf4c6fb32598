#pragma once
// Renders textured planes seen by a pinhole camera under a known pose: ground truth image motion
// for tests and benchmarks (forward flight past a wall, approach to a wall, pure roll / yaw).
// Not a hot path.

#include "drone/core/camera_calibration.hpp"

#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

namespace gs::vision {

// World axes are the camera's at zero attitude: x right, y down, z forward.
struct TexturedPlane {
    cv::Mat texture;   // 8-bit grey
    cv::Vec3d origin;  // world position of texel (0, 0)
    cv::Vec3d axis_u;  // world step per texel along a row (texture x)
    cv::Vec3d axis_v;  // world step per texel down a column (texture y)
};

// A plane from its centre, in-plane unit directions and size in metres, with texels of texel_m.
TexturedPlane make_plane(cv::Vec3d centre, cv::Vec3d dir_u, cv::Vec3d dir_v, double width_m,
                         double height_m, double texel_m, std::uint64_t seed);

// Multi-scale blob texture (deterministic for a seed), light blur against aliasing.
cv::Mat make_texture(int width, int height, std::uint64_t seed);

struct CameraPose {
    cv::Vec3d position{0, 0, 0};                      // world
    double roll_deg = 0, pitch_deg = 0, yaw_deg = 0;  // drone attitude (drone/sample.hpp signs)
};

// Draws planes in order (later ones over earlier) into a grey image of the calibration's size.
// Every plane must lie entirely in front of the camera. Background is mid grey.
void render_scene(const std::vector<TexturedPlane>& planes, const CameraCalibration& calib,
                  const CameraPose& pose, cv::Mat& out);

}  // namespace gs::vision
