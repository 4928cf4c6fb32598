#include "vision/geometry.hpp"
#include "vision/common.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <array>
#include <vector>

namespace gs::vision {

namespace {
// camera <- body: x_c = y_b, y_c = z_b, z_c = x_b.
const cv::Matx33d kCamFromBody(0, 1, 0, 0, 0, 1, 1, 0, 0);
}  // namespace

const cv::Matx33d& camera_from_body() {
    return kCamFromBody;
}

cv::Matx33d body_rotation(double roll_deg, double pitch_deg, double yaw_deg) {
    const double cr = std::cos(roll_deg * kRadPerDeg), sr = std::sin(roll_deg * kRadPerDeg);
    const double cp = std::cos(pitch_deg * kRadPerDeg), sp = std::sin(pitch_deg * kRadPerDeg);
    const double cy = std::cos(yaw_deg * kRadPerDeg), sy = std::sin(yaw_deg * kRadPerDeg);
    const cv::Matx33d rz(cy, -sy, 0, sy, cy, 0, 0, 0, 1);
    const cv::Matx33d ry(cp, 0, sp, 0, 1, 0, -sp, 0, cp);
    const cv::Matx33d rx(1, 0, 0, 0, cr, -sr, 0, sr, cr);
    return rz * ry * rx;
}

cv::Matx33d rotation_homography(const CameraCalibration& calib, const Attitude& prev,
                                const Attitude& cur) {
    if (!prev.complete() || !cur.complete()) return cv::Matx33d::eye();
    // Only the yaw difference matters; taking it wrapped keeps 359 -> 1 a 2 degree turn.
    double dyaw = std::remainder(cur.yaw_deg - prev.yaw_deg, 360.0);
    const cv::Matx33d rp = body_rotation(prev.roll_deg, prev.pitch_deg, 0);
    const cv::Matx33d rc = body_rotation(cur.roll_deg, cur.pitch_deg, dyaw);
    const cv::Matx33d k = calib.camera_matrix();
    const cv::Matx33d r = kCamFromBody * rc.t() * rp * kCamFromBody.t();
    cv::Matx33d h = k * r * k.inv();
    return h * (1.0 / h(2, 2));
}

cv::Vec3d camera_velocity(double roll_deg, double pitch_deg, double v_forward, double v_right,
                          double v_down) {
    const double r = std::isnan(roll_deg) ? 0.0 : roll_deg;
    const double p = std::isnan(pitch_deg) ? 0.0 : pitch_deg;
    return kCamFromBody * (body_rotation(r, p, 0).t() * cv::Vec3d(v_forward, v_right, v_down));
}

cv::Matx33d level_from_camera(double roll_deg, double pitch_deg) {
    const double r = std::isnan(roll_deg) ? 0.0 : roll_deg;
    const double p = std::isnan(pitch_deg) ? 0.0 : pitch_deg;
    return body_rotation(r, p, 0) * kCamFromBody.t();
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
    return {static_cast<float>(calib.fx * c[0] / c[2] + calib.cx),
            static_cast<float>(calib.fy * c[1] / c[2] + calib.cy)};
}

cv::Matx33d small_rotation_homography(const CameraCalibration& calib, const cv::Vec3d& omega_rad) {
    cv::Matx33d r;
    cv::Rodrigues(omega_rad, r);
    const cv::Matx33d k = calib.camera_matrix();
    cv::Matx33d h = k * r * k.inv();
    return h * (1.0 / h(2, 2));
}

bool estimate_residual_rotation(const CameraCalibration& calib, std::span<const cv::Point2f> pred,
                                std::span<const cv::Point2f> cur, cv::Point2f foe,
                                double min_foe_px, double huber_px, int min_points,
                                RotationFitScratch& sc, cv::Vec3d& omega_rad) {
    omega_rad = {0, 0, 0};
    // Linearised: moving pred by the small rotation w adds J w, J from the exact flow of a
    // rotation about each camera axis (finite differences of K R K^-1, so no sign convention to
    // get wrong). Each point gives one equation: its flow across the FOE ray, n . (cur - pred) =
    // (n^T J) w, with n the unit normal of the ray.
    constexpr double kEps = 1e-4;
    cv::Matx33d hj[3];
    for (int j = 0; j < 3; ++j) {
        cv::Vec3d e(0, 0, 0);
        e[j] = kEps;
        hj[j] = small_rotation_homography(calib, e);
    }
    sc.a.clear();
    sc.b.clear();
    const double min_d2 = min_foe_px * min_foe_px;
    for (std::size_t i = 0; i < pred.size() && i < cur.size(); ++i) {
        const cv::Point2f d = cur[i] - foe;
        const double d2 = static_cast<double>(d.dot(d));
        if (d2 < min_d2) continue;
        const double dn = std::sqrt(d2);
        const double nx = -static_cast<double>(d.y) / dn, ny = static_cast<double>(d.x) / dn;
        for (int j = 0; j < 3; ++j) {
            const cv::Point2f m = apply_homography(hj[j], pred[i]) - pred[i];
            sc.a.push_back((nx * static_cast<double>(m.x) + ny * static_cast<double>(m.y)) / kEps);
        }
        const cv::Point2f f = cur[i] - pred[i];
        sc.b.push_back(nx * static_cast<double>(f.x) + ny * static_cast<double>(f.y));
    }
    const std::size_t n = sc.b.size();
    if (static_cast<int>(n) < std::max(3, min_points)) return false;
    sc.w.assign(n, 1.0);
    cv::Vec3d w(0, 0, 0);
    for (int iter = 0; iter < 5; ++iter) {  // IRLS with Huber weights
        cv::Matx33d ata = cv::Matx33d::zeros();
        cv::Vec3d atb(0, 0, 0);
        for (std::size_t i = 0; i < n; ++i) {
            const cv::Vec3d ai(sc.a[3 * i], sc.a[3 * i + 1], sc.a[3 * i + 2]);
            ata += sc.w[i] * (ai * ai.t());
            atb += sc.w[i] * sc.b[i] * ai;
        }
        cv::Vec3d ev;
        cv::eigen(ata, ev);
        if (!(ev[2] > 1e-6 * std::max(1.0, ev[0]))) return false;
        if (!cv::solve(ata, atb, w, cv::DECOMP_CHOLESKY)) return false;
        for (std::size_t i = 0; i < n; ++i) {
            const double r = std::abs(
                sc.b[i] - (sc.a[3 * i] * w[0] + sc.a[3 * i + 1] * w[1] + sc.a[3 * i + 2] * w[2]));
            sc.w[i] = r <= huber_px ? 1.0 : huber_px / r;
        }
    }
    omega_rad = w;
    return true;
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
