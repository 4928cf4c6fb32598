// The camera-model operations of CameraCalibration (camera_calibration.hpp).
#include "drone/core/camera_calibration.hpp"

#include <opencv2/calib3d.hpp>

#include <cmath>

namespace gs::inline core {

bool CameraCalibration::has_distortion() const {
    for (double d : dist)
        if (d != 0.0) return true;
    return false;
}

CameraCalibration CameraCalibration::scaled_to(int w, int h) const {
    CameraCalibration c = *this;
    c.width = w;
    c.height = h;
    if (width <= 0 || height <= 0 || (width == w && height == h)) return c;
    const double sx = static_cast<double>(w) / width;
    const double sy = static_cast<double>(h) / height;
    c.fx *= sx;
    c.cx = (cx + 0.5) * sx - 0.5;
    c.fy *= sy;
    c.cy = (cy + 0.5) * sy - 0.5;
    return c;
}

CameraCalibration CameraCalibration::with_size_if_unknown(int w, int h) const {
    CameraCalibration c = *this;
    if (c.width <= 0 || c.height <= 0) {
        c.width = w;
        c.height = h;
    }
    return c;
}

CameraCalibration CameraCalibration::ideal(int w, int h, double hfov_deg) {
    CameraCalibration c;
    c.width = w;
    c.height = h;
    c.fx = c.fy = (w / 2.0) / std::tan(hfov_deg * CV_PI / 360.0);
    c.cx = (w - 1) / 2.0;
    c.cy = (h - 1) / 2.0;
    return c;
}

void CameraCalibration::undistort_points(std::span<const cv::Point2f> in,
                                         std::span<cv::Point2f> out) const {
    CV_Assert(in.size() == out.size());
    if (in.empty()) return;
    if (!has_distortion()) {
        if (in.data() != out.data()) std::copy(in.begin(), in.end(), out.begin());
        return;
    }
    const cv::Mat src(static_cast<int>(in.size()), 1, CV_32FC2,
                      const_cast<cv::Point2f*>(in.data()));  // NOLINT: read-only view
    cv::Mat dst(static_cast<int>(out.size()), 1, CV_32FC2, out.data());
    const cv::Matx33d k = camera_matrix();
    const cv::Vec<double, 5> d = dist_coeffs();
    // The AR.Drone lens has k1 ~ -0.5: the default 5 iterations do not converge at the corners.
    cv::undistortPoints(
        src, dst, k, d, cv::noArray(), k,
        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 20, 1e-6));
}

cv::Point2f CameraCalibration::distort_point(cv::Point2f u) const {
    const double x = (static_cast<double>(u.x) - cx) / fx;
    const double y = (static_cast<double>(u.y) - cy) / fy;
    const double r2 = x * x + y * y;
    const double radial = 1 + dist[0] * r2 + dist[1] * r2 * r2 + dist[4] * r2 * r2 * r2;
    const double xd = x * radial + 2 * dist[2] * x * y + dist[3] * (r2 + 2 * x * x);
    const double yd = y * radial + dist[2] * (r2 + 2 * y * y) + 2 * dist[3] * x * y;
    return {static_cast<float>(xd * fx + cx), static_cast<float>(yd * fy + cy)};
}

}  // namespace gs::inline core
