#pragma once
// Pinhole camera with OpenCV's 5-coefficient distortion (k1, k2, p1, p2, k3), in pixels of the
// images it describes. Vision moves points, not images: the undistortion and its inverse work on
// point coordinates, with the camera matrix itself as the "new" camera matrix (what cv::undistort
// does for an image, as the thesis used it).

#include <opencv2/core.hpp>

#include <array>
#include <span>

namespace gs::vision {

struct CameraCalibration {
    int width = 640;
    int height = 360;
    double fx = 0, fy = 0, cx = 0, cy = 0;
    std::array<double, 5> dist{};  // k1, k2, p1, p2, k3

    cv::Matx33d camera_matrix() const { return {fx, 0, cx, 0, fy, cy, 0, 0, 1}; }
    cv::Vec<double, 5> dist_coeffs() const { return {dist[0], dist[1], dist[2], dist[3], dist[4]}; }
    bool valid() const { return width > 0 && height > 0 && fx > 0 && fy > 0; }
    bool has_distortion() const;

    // The same camera for images resized to (w, h): intrinsics scale, distortion does not.
    CameraCalibration scaled_to(int w, int h) const;

    // A distortion-free camera with the given horizontal field of view, principal point at the
    // image centre (for synthetic scenes and for tests).
    static CameraCalibration ideal(int w, int h, double hfov_deg);

    // Raw (distorted) pixel -> undistorted pixel, iteratively (cv::undistortPoints with P = K).
    // `out` must have in.size() elements; in and out may alias.
    void undistort_points(std::span<const cv::Point2f> in, std::span<cv::Point2f> out) const;
    // Undistorted pixel -> raw (distorted) pixel, closed form.
    cv::Point2f distort_point(cv::Point2f undistorted) const;
};

}  // namespace gs::vision
