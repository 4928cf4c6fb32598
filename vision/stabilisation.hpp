#pragma once
// The classifiers' attitude step for the AR.Drone front camera: derotation (the image motion a
// pure attitude change causes, infinite homography K R K^-1), roll stabilisation of point
// coordinates and the detection mask that keeps corners out of what it would crop, and the focus
// of expansion the stabilised motion is measured against.
//
// Conventions and frames: drone/core/geometry.hpp (the front camera, geom::Mount::Front). The
// functions here turn its rotations into the classifiers' OpenCV types.

#include "drone/core/camera_calibration.hpp"
#include "drone/core/unknown.hpp"

#include <opencv2/core.hpp>

#include <cmath>
#include <limits>
#include <vector>

namespace gs::vision {

struct Attitude {
    double roll_deg = kUnknown;
    double pitch_deg = kUnknown;
    double yaw_deg = kUnknown;
    bool complete() const {
        return !std::isnan(roll_deg) && !std::isnan(pitch_deg) && !std::isnan(yaw_deg);
    }
};

// Maps an undistorted pixel of the frame taken at `prev` to where the same (infinitely far) point
// appears at `cur`: K M R_cur^T R_prev M^T K^-1. Identity when either attitude is incomplete.
cv::Matx33d rotation_homography(const CameraCalibration& calib, const Attitude& prev,
                                const Attitude& cur);

inline cv::Point2f apply_homography(const cv::Matx33d& h, cv::Point2f p) {
    const auto x = static_cast<double>(p.x), y = static_cast<double>(p.y);
    const double w = h(2, 0) * x + h(2, 1) * y + h(2, 2);
    return {static_cast<float>((h(0, 0) * x + h(0, 1) * y + h(0, 2)) / w),
            static_cast<float>((h(1, 0) * x + h(1, 1) * y + h(1, 2)) / w)};
}

// Velocity in camera axes (x right, y down, z forward) from a velocity in the heading-aligned level
// frame (forward, right, down, m/s) at the given roll and pitch (NaN = 0).
cv::Vec3d camera_velocity(double roll_deg, double pitch_deg, double v_forward, double v_right,
                          double v_down);

// Level frame (forward, right, down) from camera axes, at the given roll and pitch (NaN = 0).
cv::Matx33d level_from_camera(double roll_deg, double pitch_deg);

// Image of the direction of travel (undistorted pixels). Velocity in the heading-aligned level
// frame (forward, right, down, m/s); when unknown (NaN) pure forward flight is assumed. Returns
// NaN coordinates when the drone is not moving forward relative to the camera.
cv::Point2f focus_of_expansion(const CameraCalibration& calib, double roll_deg, double pitch_deg,
                               double v_forward, double v_right, double v_down);

// K R K^-1 for a small rotation vector (radians, camera axes), normalised to h(2,2) = 1.
cv::Matx33d small_rotation_homography(const CameraCalibration& calib, const cv::Vec3d& omega_rad);

// Rotation of undistorted points about a centre by `angle_deg` in image coordinates (y down):
// positive angles turn the image content clockwise on screen. Stabilising with +roll undoes a
// right-side-down roll (the scene appears turned counter-clockwise then).
class RollStabiliser {
public:
    void set(cv::Point2f centre, double angle_deg) {
        centre_ = centre;
        const double a = angle_deg * CV_PI / 180.0;
        c_ = static_cast<float>(std::cos(a));
        s_ = static_cast<float>(std::sin(a));
    }
    cv::Point2f apply(cv::Point2f p) const {
        const float dx = p.x - centre_.x, dy = p.y - centre_.y;
        return {centre_.x + c_ * dx - s_ * dy, centre_.y + s_ * dx + c_ * dy};
    }
    cv::Point2f inverse(cv::Point2f p) const {
        const float dx = p.x - centre_.x, dy = p.y - centre_.y;
        return {centre_.x + c_ * dx + s_ * dy, centre_.y - s_ * dx + c_ * dy};
    }

private:
    cv::Point2f centre_{0, 0};
    float c_ = 1, s_ = 0;
};

// Raw-image pixels (at `scale` x the calibration's size) whose undistorted, roll-stabilised
// position lies inside the image by at least margin_px: 255 there, 0 elsewhere. Computed from the
// region's boundary (two rectangles intersected, then distorted), not per pixel.
void detection_mask(const CameraCalibration& calib, const RollStabiliser& stab, double margin_px,
                    double scale, cv::Mat& mask);

}  // namespace gs::vision
