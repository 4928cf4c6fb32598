#include "drone/calibration.hpp"

#include "drone/dataset/dataset.hpp"
#include "drone/dataset/json_text.hpp"
#include "drone/dataset/writer.hpp"

#include <nlohmann/json.hpp>

#include <cmath>

namespace gs {
namespace fs = std::filesystem;
using nlohmann::json;

std::string to_string(CameraId c) {
    return c == CameraId::Front ? "front" : "bottom";
}

namespace {

CalibrationIssue issue(DatasetErrorCode code, std::string key, std::string message) {
    return CalibrationIssue{code, std::move(key), std::move(message)};
}

Expected<double, CalibrationIssue> number(const json& obj, const char* key) {
    auto it = obj.find(key);
    if (it == obj.end())
        return Unexpected(issue(DatasetErrorCode::Missing, key, "missing required key"));
    if (!it->is_number())
        return Unexpected(
            issue(DatasetErrorCode::Malformed, key, "expected a number, got " + it->dump()));
    const double d = it->get<double>();
    if (!std::isfinite(d))
        return Unexpected(issue(DatasetErrorCode::OutOfRange, key, "not a finite number"));
    return d;
}

Expected<int, CalibrationIssue> size_value(const json& obj, const char* key) {
    auto it = obj.find(key);
    if (it == obj.end())
        return Unexpected(issue(DatasetErrorCode::Missing, key,
                                "missing required key (width and height go together)"));
    if (!it->is_number_integer())
        return Unexpected(
            issue(DatasetErrorCode::Malformed, key, "expected an integer, got " + it->dump()));
    const auto v = it->get<std::int64_t>();
    if (v < 1 || v > 65535)
        return Unexpected(issue(DatasetErrorCode::OutOfRange, key,
                                std::to_string(v) + " is out of range [1, 65535]"));
    return static_cast<int>(v);
}

}  // namespace

Expected<CameraCalibration, CalibrationIssue> calibration_from_json(const json& obj) {
    if (!obj.is_object())
        return Unexpected(issue(DatasetErrorCode::Malformed, "", "expected a JSON object"));
    CameraCalibration c;
    for (auto [key, dst] : {std::pair<const char*, double*>{"fx", &c.fx},
                            {"fy", &c.fy},
                            {"cx", &c.cx},
                            {"cy", &c.cy}}) {
        auto v = number(obj, key);
        if (!v) return Unexpected(v.error());
        *dst = *v;
    }
    if (!(c.fx > 0) || !(c.fy > 0))
        return Unexpected(
            issue(DatasetErrorCode::OutOfRange, "fx", "focal lengths must be positive"));
    if (auto d = obj.find("dist"); d != obj.end()) {
        if (!d->is_array() || (d->size() != 4 && d->size() != 5))
            return Unexpected(issue(DatasetErrorCode::Malformed, "dist",
                                    "expected an array of 4 or 5 numbers (k1, k2, p1, p2, k3)"));
        for (std::size_t i = 0; i < d->size(); ++i) {
            if (!(*d)[i].is_number() || !std::isfinite((*d)[i].get<double>()))
                return Unexpected(issue(DatasetErrorCode::Malformed, "dist",
                                        "element " + std::to_string(i) + " is not a number"));
            c.dist[i] = (*d)[i].get<double>();
        }
    }
    if (obj.contains("width") || obj.contains("height")) {
        auto w = size_value(obj, "width");
        if (!w) return Unexpected(w.error());
        auto h = size_value(obj, "height");
        if (!h) return Unexpected(h.error());
        c.width = *w;
        c.height = *h;
    }
    if (auto s = obj.find("source"); s != obj.end() && s->is_string())
        c.source = s->get<std::string>();
    return c;
}

json calibration_to_json(const CameraCalibration& c, bool with_extras) {
    nlohmann::ordered_json j;
    j["fx"] = c.fx;
    j["fy"] = c.fy;
    j["cx"] = c.cx;
    j["cy"] = c.cy;
    j["dist"] = {c.dist[0], c.dist[1], c.dist[2], c.dist[3], c.dist[4]};
    if (with_extras && c.width > 0 && c.height > 0) {
        j["width"] = c.width;
        j["height"] = c.height;
    }
    if (with_extras && !c.source.empty()) j["source"] = c.source;
    return json(j);
}

Expected<CameraCalibration, DatasetError> load_calibration_file(const fs::path& file) {
    const std::string name = file.string();
    auto text = read_text_file(file, name, 1u << 20);
    if (!text) return Unexpected(text.error());
    auto j = parse_json_text(*text, name);
    if (!j) return Unexpected(j.error());
    auto c = calibration_from_json(*j);  // checks every type before reading: nothing throws
    if (!c) {
        const CalibrationIssue& i = c.error();
        if (i.code == DatasetErrorCode::Missing)
            return Unexpected(
                DatasetError{i.code, name, 0, 0, "missing required key '" + i.key + "'"});
        auto [line, col] = locate_json_key(*text, i.key);
        return Unexpected(DatasetError{
            i.code, name, line, col, i.key.empty() ? i.message : "'" + i.key + "': " + i.message});
    }
    return *c;
}

std::optional<DatasetError> save_calibration_file(const fs::path& file,
                                                  const CameraCalibration& c) {
    return write_file_atomic(file, calibration_to_json(c).dump(2) + "\n", file.string());
}

Expected<CameraCalibration, DatasetError> default_calibration(CameraId camera,
                                                              const fs::path& assets_dir) {
    return load_calibration_file(assets_dir / "calibration" /
                                 ("ardrone2_" + to_string(camera) + ".json"));
}

CameraCalibration builtin_calibration(CameraId camera) {
    CameraCalibration c;
    c.width = 640;
    c.height = 360;
    if (camera == CameraId::Front) {
        c.fx = 569.883158;
        c.fy = 568.007065;
        c.cx = 331.403348;
        c.cy = 135.879365;
        c.dist = {-0.526629, 0.274357, 0.021143, -0.006394, 0.0};
        c.source = "AutonomyLab/ardrone_autonomy data/camera_info/ardrone_front.yaml";
    } else {
        c.fx = 700.490829;
        c.fy = 701.654117;
        c.cx = 319.508832;
        c.cy = 218.740254;
        c.dist = {0.018239, 0.052028, 0.006511, 0.000183, 0.0};
        c.source = "AutonomyLab/ardrone_autonomy data/camera_info/ardrone_bottom.yaml";
    }
    return c;
}

CameraCalibration scaled_to(const CameraCalibration& c, int width, int height) {
    CameraCalibration r = c;
    r.width = width;
    r.height = height;
    if (c.width <= 0 || c.height <= 0 || (c.width == width && c.height == height)) return r;
    const double sx = static_cast<double>(width) / c.width;
    const double sy = static_cast<double>(height) / c.height;
    r.fx *= sx;
    r.cx = (c.cx + 0.5) * sx - 0.5;
    r.fy *= sy;
    r.cy = (c.cy + 0.5) * sy - 0.5;
    return r;
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
    CameraCalibration unit;
    unit.fx = unit.fy = 1;
    unit.dist = c.dist;
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

}  // namespace gs
