#include "vision/stabilisation.hpp"
#include "drone/core/geometry.hpp"
#include "vision/common.hpp"

#include <opencv2/imgproc.hpp>

#include <array>
#include <vector>

namespace gs::vision {

namespace {

geom::Mat3 camera_matrix(const CameraCalibration& calib) {
    return geom::from_cv(calib.camera_matrix());
}

}  // namespace

cv::Matx33d rotation_homography(const CameraCalibration& calib, const Attitude& prev,
                                const Attitude& cur) {
    if (!prev.complete() || !cur.complete()) return cv::Matx33d::eye();
    // Only the yaw difference matters; taking it wrapped keeps 359 -> 1 a 2 degree turn.
    const double dyaw = std::remainder(cur.yaw_deg - prev.yaw_deg, 360.0);
    const geom::Mat3 world_from_prev =
        geom::world_from_body_matrix(prev.roll_deg, prev.pitch_deg, 0);
    const geom::Mat3 world_from_cur =
        geom::world_from_body_matrix(cur.roll_deg, cur.pitch_deg, dyaw);
    // Points of the previous camera frame in the current one (a far point moves by this alone).
    const geom::Mat3 cur_from_prev =
        geom::camera_rotation(geom::Mount::Front, world_from_cur.transpose() * world_from_prev);
    return geom::to_cv(geom::rotation_homography(camera_matrix(calib), cur_from_prev));
}

cv::Vec3d camera_velocity(double roll_deg, double pitch_deg, double v_forward, double v_right,
                          double v_down) {
    const double r = std::isnan(roll_deg) ? 0.0 : roll_deg;
    const double p = std::isnan(pitch_deg) ? 0.0 : pitch_deg;
    const geom::Vec3 v_body =
        geom::level_from_body_matrix(r, p).transpose() * geom::Vec3(v_forward, v_right, v_down);
    return geom::to_cv(geom::body_from_camera(geom::Mount::Front).transpose() * v_body);
}

cv::Matx33d level_from_camera(double roll_deg, double pitch_deg) {
    const double r = std::isnan(roll_deg) ? 0.0 : roll_deg;
    const double p = std::isnan(pitch_deg) ? 0.0 : pitch_deg;
    return geom::to_cv(geom::level_from_body_matrix(r, p) *
                       geom::body_from_camera(geom::Mount::Front));
}

cv::Point2f focus_of_expansion(const CameraCalibration& calib, double roll_deg, double pitch_deg,
                               double v_forward, double v_right, double v_down) {
    const bool known = !std::isnan(v_forward) && !std::isnan(v_right);
    const cv::Vec3d c = known ? camera_velocity(roll_deg, pitch_deg, v_forward, v_right,
                                                std::isnan(v_down) ? 0.0 : v_down)
                              : camera_velocity(roll_deg, pitch_deg, 1, 0, 0);
    if (!(c[2] > 1e-3 * cv::norm(c))) {
        const float nan = std::numeric_limits<float>::quiet_NaN();
        return {nan, nan};
    }
    const cv::Point2d foe = calib.project(c);
    return {static_cast<float>(foe.x), static_cast<float>(foe.y)};
}

cv::Matx33d small_rotation_homography(const CameraCalibration& calib, const cv::Vec3d& omega_rad) {
    return geom::to_cv(geom::rotation_homography(
        camera_matrix(calib), geom::rotation_from_vector(geom::from_cv(omega_rad))));
}

void detection_mask(const CameraCalibration& calib, const RollStabiliser& stab, double margin_px,
                    double scale, cv::Mat& mask) {
    const int w = static_cast<int>(std::lround(calib.width * scale));
    const int h = static_cast<int>(std::lround(calib.height * scale));
    mask.create(h, w, CV_8UC1);
    mask.setTo(0);
    const float m = static_cast<float>(margin_px);
    const float x1 = static_cast<float>(calib.width - 1) - m;
    const float y1 = static_cast<float>(calib.height - 1) - m;
    if (x1 <= m || y1 <= m) return;
    // Undistorted image (cropped like cv::undistort with the same K) ...
    const std::array<cv::Point2f, 4> img{cv::Point2f(m, m), cv::Point2f(x1, m), cv::Point2f(x1, y1),
                                         cv::Point2f(m, y1)};
    // ... intersected with the preimage of the stabilised image.
    std::array<cv::Point2f, 4> rot{};
    for (std::size_t i = 0; i < 4; ++i) rot[i] = stab.inverse(img[i]);
    std::vector<cv::Point2f> region;
    cv::intersectConvexConvex(img, rot, region, true);
    if (region.size() < 3) return;
    // Distort the boundary, sampled densely because distortion bends straight edges.
    std::vector<cv::Point> poly;
    poly.reserve(256);
    constexpr float kStep = 8.f;
    for (std::size_t i = 0; i < region.size(); ++i) {
        const cv::Point2f a = region[i], b = region[(i + 1) % region.size()];
        const int n = std::max(1, static_cast<int>(cv::norm(b - a) / static_cast<double>(kStep)));
        for (int k = 0; k < n; ++k) {
            const cv::Point2f u = a + (b - a) * (static_cast<float>(k) / static_cast<float>(n));
            const cv::Point2f d = calib.distort_point(u);
            poly.emplace_back(
                static_cast<int>(std::lround((static_cast<double>(d.x) + 0.5) * scale - 0.5)),
                static_cast<int>(std::lround((static_cast<double>(d.y) + 0.5) * scale - 0.5)));
        }
    }
    const cv::Point* pts = poly.data();
    const int npts = static_cast<int>(poly.size());
    cv::fillPoly(mask, &pts, &npts, 1, cv::Scalar(255));
}

}  // namespace gs::vision
