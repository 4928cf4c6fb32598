#include "drone/sim/calibration.hpp"

#include "drone/sim/json_util.hpp"

#include <cmath>

namespace gs::sim {

CameraCalibration default_front_calibration() {
    CameraCalibration c;
    c.fx = 569.883158;
    c.fy = 568.007065;
    c.cx = 331.403348;
    c.cy = 135.879365;
    c.dist = {-0.526629, 0.274357, 0.021143, -0.006394, 0.0};
    c.source = "AutonomyLab/ardrone_autonomy data/camera_info/ardrone_front.yaml";
    return c;
}

CameraCalibration default_bottom_calibration() {
    CameraCalibration c;
    c.fx = 700.490829;
    c.fy = 701.654117;
    c.cx = 319.508832;
    c.cy = 218.740254;
    c.dist = {0.018239, 0.052028, 0.006511, 0.000183, 0.0};
    c.source = "AutonomyLab/ardrone_autonomy data/camera_info/ardrone_bottom.yaml";
    return c;
}

Expected<CameraCalibration, AssetError> load_calibration(const std::string& path) {
    auto doc = read_json_file(path);
    if (!doc) return Unexpected{doc.error()};
    JsonReader r(path);
    const nlohmann::json& j = *doc;
    CameraCalibration c;
    c.width = r.get_int(j, "", "width");
    c.height = r.get_int(j, "", "height");
    c.fx = r.get_number(j, "", "fx");
    c.fy = r.get_number(j, "", "fy");
    c.cx = r.get_number(j, "", "cx");
    c.cy = r.get_number(j, "", "cy");
    const auto d = r.get_numbers(j, "", "dist", 4, 5);
    for (std::size_t i = 0; i < d.size(); ++i) c.dist[i] = d[i];
    c.source = r.get_string(j, "", "source", "");
    if (r.failed()) return Unexpected{r.error()};
    if (!c.valid() || c.width > 8192 || c.height > 8192)
        return Unexpected{AssetError{AssetErrorKind::BadValue, path, "",
                                     "width, height, fx and fy must be positive"}};
    return c;
}

cv::Point2d distort_to_pixel(const CameraCalibration& c, cv::Point2d n) {
    const double k1 = c.dist[0], k2 = c.dist[1], p1 = c.dist[2], p2 = c.dist[3], k3 = c.dist[4];
    const double x = n.x, y = n.y;
    const double r2 = x * x + y * y;
    const double radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
    const double xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x);
    const double yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y;
    return {c.fx * xd + c.cx, c.fy * yd + c.cy};
}

std::optional<cv::Point2d> undistort_pixel(const CameraCalibration& c, cv::Point2d px) {
    const cv::Point2d target{(px.x - c.cx) / c.fx, (px.y - c.cy) / c.fy};
    const CameraCalibration unit = [&] {
        CameraCalibration u = c;
        u.fx = u.fy = 1;
        u.cx = u.cy = 0;
        return u;
    }();
    cv::Point2d x = target;
    for (int it = 0; it < 50; ++it) {
        const cv::Point2d f = distort_to_pixel(unit, x) - target;
        if (std::hypot(f.x, f.y) < 1e-12) return x;
        const double h = 1e-7;
        const cv::Point2d fx = (distort_to_pixel(unit, {x.x + h, x.y}) - target - f) / h;
        const cv::Point2d fy = (distort_to_pixel(unit, {x.x, x.y + h}) - target - f) / h;
        const double det = fx.x * fy.y - fy.x * fx.y;
        if (std::abs(det) < 1e-12) return std::nullopt;
        const double dx = (fy.y * f.x - fy.x * f.y) / det;
        const double dy = (-fx.y * f.x + fx.x * f.y) / det;
        x.x -= dx;
        x.y -= dy;
        if (!std::isfinite(x.x) || !std::isfinite(x.y) || std::hypot(x.x, x.y) > 10)
            return std::nullopt;
    }
    const cv::Point2d f = distort_to_pixel(unit, x) - target;
    if (std::hypot(f.x, f.y) < 1e-9) return x;
    return std::nullopt;
}

}  // namespace gs::sim
