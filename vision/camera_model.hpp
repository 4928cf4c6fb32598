#pragma once
// Pinhole camera with OpenCV's 5-coefficient distortion (k1, k2, p1, p2, k3), in pixels of the
// images it describes.

#include <opencv2/core.hpp>

#include <array>

namespace gs::vision {

struct CameraCalibration {
    int width = 640;
    int height = 360;
    double fx = 0, fy = 0, cx = 0, cy = 0;
    std::array<double, 5> dist{};  // k1, k2, p1, p2, k3

    cv::Matx33d camera_matrix() const { return {fx, 0, cx, 0, fy, cy, 0, 0, 1}; }
    cv::Vec<double, 5> dist_coeffs() const { return {dist[0], dist[1], dist[2], dist[3], dist[4]}; }
    bool valid() const { return width > 0 && height > 0 && fx > 0 && fy > 0; }

    // The same camera for images resized to (w, h): intrinsics scale, distortion does not.
    CameraCalibration scaled_to(int w, int h) const;
};

}  // namespace gs::vision
