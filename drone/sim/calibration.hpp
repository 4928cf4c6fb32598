#pragma once
// Camera calibration for the simulator: OpenCV pinhole + (k1, k2, p1, p2, k3), in pixels of the
// delivered image. A plain struct with the same fields as gs::vision::CameraCalibration (drone/
// may not depend on vision/); the JSON shape is DATASET.md's flight.json "calibration" object plus
// width, height and a "source" note.

#include "drone/expected.hpp"
#include "drone/sim/asset_error.hpp"

#include <opencv2/core.hpp>

#include <array>
#include <optional>
#include <string>

namespace gs::sim {

struct CameraCalibration {
    int width = 640;
    int height = 360;
    double fx = 0, fy = 0, cx = 0, cy = 0;
    std::array<double, 5> dist{};  // k1, k2, p1, p2, k3
    std::string source;            // where the numbers come from

    bool valid() const { return width > 0 && height > 0 && fx > 0 && fy > 0; }
};

// ardrone_autonomy's front (data/camera_info/ardrone_front.yaml) and bottom camera files, the
// PROTOCOL.md §6 defaults; the same numbers as assets/calibration/ardrone2_{front,bottom}.json.
CameraCalibration default_front_calibration();
CameraCalibration default_bottom_calibration();

// Reads a calibration JSON: {"width", "height", "fx", "fy", "cx", "cy", "dist": [5], "source"}.
[[nodiscard]] Expected<CameraCalibration, AssetError> load_calibration(const std::string& path);

// Undistorted normalised coordinates (x/z, y/z) -> distorted pixel (OpenCV's model).
cv::Point2d distort_to_pixel(const CameraCalibration& c, cv::Point2d normalised);

// Distorted pixel -> undistorted normalised coordinates (Newton iterations on the full model);
// nullopt when it does not converge (outside the model's invertible range).
std::optional<cv::Point2d> undistort_pixel(const CameraCalibration& c, cv::Point2d pixel);

}  // namespace gs::sim
