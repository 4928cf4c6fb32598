#include "drone/core/camera_calibration.hpp"
#include "drone/core/json_text.hpp"

#include "drone/core/file_io.hpp"

#include <nlohmann/json.hpp>

#include <cmath>

namespace gs::inline core {
namespace fs = std::filesystem;
using nlohmann::json;

std::string to_string(CameraId c) {
    return c == CameraId::Front ? "front" : "bottom";
}

namespace {

CalibrationIssue issue(FileErrorCode code, std::string key, std::string message) {
    return CalibrationIssue{code, std::move(key), std::move(message)};
}

Expected<double, CalibrationIssue> number(const json& obj, const char* key) {
    auto it = obj.find(key);
    if (it == obj.end())
        return Unexpected(issue(FileErrorCode::Missing, key, "missing required key"));
    if (!it->is_number())
        return Unexpected(
            issue(FileErrorCode::Malformed, key, "expected a number, got " + it->dump()));
    const double d = it->get<double>();
    if (!std::isfinite(d))
        return Unexpected(issue(FileErrorCode::OutOfRange, key, "not a finite number"));
    return d;
}

Expected<int, CalibrationIssue> size_value(const json& obj, const char* key) {
    auto it = obj.find(key);
    if (it == obj.end())
        return Unexpected(issue(FileErrorCode::Missing, key,
                                "missing required key (width and height go together)"));
    if (!it->is_number_integer())
        return Unexpected(
            issue(FileErrorCode::Malformed, key, "expected an integer, got " + it->dump()));
    const auto v = it->get<std::int64_t>();
    if (v < 1 || v > 65535)
        return Unexpected(issue(FileErrorCode::OutOfRange, key,
                                std::to_string(v) + " is out of range [1, 65535]"));
    return static_cast<int>(v);
}

}  // namespace

Expected<CameraCalibration, CalibrationIssue> calibration_from_json(const json& obj) {
    if (!obj.is_object())
        return Unexpected(issue(FileErrorCode::Malformed, "", "expected a JSON object"));
    CameraCalibration c;
    for (auto [key, dst] : {std::pair<const char*, double*>{"fx", &c.fx},
                            {"fy", &c.fy},
                            {"cx", &c.cx},
                            {"cy", &c.cy}}) {
        GS_TRY_ASSIGN(auto v, number(obj, key));
        *dst = v;
    }
    if (!(c.fx > 0) || !(c.fy > 0))
        return Unexpected(issue(FileErrorCode::OutOfRange, "fx", "focal lengths must be positive"));
    if (auto d = obj.find("dist"); d != obj.end()) {
        if (!d->is_array() || (d->size() != 4 && d->size() != 5))
            return Unexpected(issue(FileErrorCode::Malformed, "dist",
                                    "expected an array of 4 or 5 numbers (k1, k2, p1, p2, k3)"));
        for (std::size_t i = 0; i < d->size(); ++i) {
            if (!(*d)[i].is_number() || !std::isfinite((*d)[i].get<double>()))
                return Unexpected(issue(FileErrorCode::Malformed, "dist",
                                        "element " + std::to_string(i) + " is not a number"));
            c.dist[i] = (*d)[i].get<double>();
        }
    }
    if (obj.contains("width") || obj.contains("height")) {
        GS_TRY_ASSIGN(auto w, size_value(obj, "width"));
        GS_TRY_ASSIGN(auto h, size_value(obj, "height"));
        c.width = w;
        c.height = h;
    }
    if (obj.contains("readout_ms")) {
        GS_TRY_ASSIGN(auto r, number(obj, "readout_ms"));
        if (!(r >= 0 && r <= 1000))
            return Unexpected(issue(FileErrorCode::OutOfRange, "readout_ms",
                                    "a rolling shutter's readout time must be 0-1000 ms"));
        c.readout_ms = r;
    }
    if (auto s = obj.find("source"); s != obj.end() && s->is_string())
        c.source = s->get<std::string>();
    return c;
}

json calibration_to_json(const CameraCalibration& c, bool with_extras,
                         const CalibrationInfo& info) {
    nlohmann::ordered_json j;
    j["fx"] = c.fx;
    j["fy"] = c.fy;
    j["cx"] = c.cx;
    j["cy"] = c.cy;
    j["dist"] = {c.dist[0], c.dist[1], c.dist[2], c.dist[3], c.dist[4]};
    // Part of the camera model: with or without the extras, when known.
    if (std::isfinite(c.readout_ms)) j["readout_ms"] = c.readout_ms;
    if (!with_extras) return json(j);
    if (c.width > 0 && c.height > 0) {
        j["width"] = c.width;
        j["height"] = c.height;
    }
    if (!info.camera.empty()) j["camera"] = info.camera;
    // NaN and infinities are not JSON: unknown numbers are left out.
    if (std::isfinite(info.rms_px)) j["rms_px"] = info.rms_px;
    bool any_sd = false;
    for (double s : info.std_dev) any_sd = any_sd || std::isfinite(s);
    if (any_sd) {
        nlohmann::ordered_json sd = nlohmann::ordered_json::object();
        const char* keys[] = {"fx", "fy", "cx", "cy"};
        for (std::size_t i = 0; i < 4; ++i)
            if (std::isfinite(info.std_dev[i])) sd[keys[i]] = info.std_dev[i];
        nlohmann::ordered_json d = nlohmann::ordered_json::array();
        for (std::size_t i = 4; i < 9; ++i) {
            d.push_back(std::isfinite(info.std_dev[i]) ? nlohmann::ordered_json(info.std_dev[i])
                                                       : nlohmann::ordered_json(nullptr));
        }
        sd["dist"] = d;
        j["std_dev"] = sd;
    }
    if (info.views > 0) j["views"] = info.views;
    if (!c.source.empty()) j["source"] = c.source;
    return json(j);
}

namespace {

// The notes of a calibration object (`obj`), the camera name also from the enclosing flight.json
// (`root`) when nested. Notes are optional: a malformed note is ignored.
CalibrationInfo notes_from_json(const json& obj, const json* root) {
    CalibrationInfo info;
    auto finite = [](const json& v) { return v.is_number() && std::isfinite(v.get<double>()); };
    if (auto it = obj.find("camera"); it != obj.end() && it->is_string()) {
        info.camera = it->get<std::string>();
    } else if (root != nullptr) {
        if (auto jt = root->find("camera"); jt != root->end() && jt->is_string())
            info.camera = jt->get<std::string>();
    }
    if (auto it = obj.find("rms_px"); it != obj.end() && finite(*it))
        info.rms_px = it->get<double>();
    if (auto it = obj.find("views"); it != obj.end() && it->is_number_integer()) {
        const auto v = it->get<std::int64_t>();
        if (v > 0 && v < 1'000'000) info.views = static_cast<int>(v);
    }
    if (auto it = obj.find("std_dev"); it != obj.end() && it->is_object()) {
        const char* keys[] = {"fx", "fy", "cx", "cy"};
        for (std::size_t i = 0; i < 4; ++i)
            if (auto k = it->find(keys[i]); k != it->end() && finite(*k))
                info.std_dev[i] = k->get<double>();
        if (auto sd = it->find("dist"); sd != it->end() && sd->is_array()) {
            for (std::size_t i = 0; i < sd->size() && i < 5; ++i)
                if (finite((*sd)[i])) info.std_dev[4 + i] = (*sd)[i].get<double>();
        }
    }
    return info;
}

}  // namespace

namespace {
Expected<CalibrationDocument, FileError> read_calibration_document(std::string_view text,
                                                                   const std::string& name,
                                                                   const json& root);
}  // namespace

Expected<CalibrationDocument, FileError> parse_calibration(std::string_view text,
                                                           const std::string& name) {
    // Every nlohmann exception stops at this boundary (a number overflowing a double is
    // out_of_range, not parse_error): the error names the file, the key and its position.
    GS_TRY_ASSIGN(const json root, parse_json_text(std::string(text), name));
    return json_boundary(name, [&] { return read_calibration_document(text, name, root); });
}

namespace {

Expected<CalibrationDocument, FileError> read_calibration_document(std::string_view text,
                                                                   const std::string& name,
                                                                   const json& root) {
    // A flight.json: the calibration object sits under "calibration", the size at the top.
    const bool nested = root.is_object() && root.contains("calibration");
    const json& obj = nested ? root["calibration"] : root;
    const std::string prefix = nested ? "calibration." : "";
    auto c = calibration_from_json(obj);
    if (!c) {
        const CalibrationIssue& i = c.error();
        const std::string key = i.key.empty() ? std::string() : prefix + i.key;
        if (i.code == FileErrorCode::Missing)
            return Unexpected(FileError{i.code, name, 0, 0, "missing required key '" + key + "'"});
        const std::string text_copy(text);
        auto [line, col] =
            locate_json_key(text_copy, i.key.empty() && nested ? "calibration" : i.key);
        return Unexpected(FileError{i.code, name, line, col,
                                    key.empty() ? i.message : "'" + key + "': " + i.message});
    }
    CalibrationDocument doc{std::move(*c), notes_from_json(obj, nested ? &root : nullptr)};
    if (nested && doc.camera.width == 0) {
        auto w = root.find("width"), h = root.find("height");
        if (w != root.end() && h != root.end() && w->is_number_integer() &&
            h->is_number_integer()) {
            const auto wv = w->get<std::int64_t>(), hv = h->get<std::int64_t>();
            if (wv >= 1 && wv <= 65535 && hv >= 1 && hv <= 65535) {
                doc.camera.width = static_cast<int>(wv);
                doc.camera.height = static_cast<int>(hv);
            }
        }
    }
    return doc;
}

}  // namespace

Expected<CalibrationDocument, FileError> load_calibration_document(const fs::path& file) {
    const std::string name = file.string();
    GS_TRY_ASSIGN(const std::string text, read_text_file(file, name, 1u << 20));
    return parse_calibration(text, name);
}

Expected<CameraCalibration, FileError> load_calibration_file(const fs::path& file) {
    GS_TRY_ASSIGN(CalibrationDocument doc, load_calibration_document(file));
    return std::move(doc.camera);
}

Expected<void, FileError> save_calibration_file(const fs::path& file, const CameraCalibration& c,
                                                const CalibrationInfo& info) {
    if (!c.valid())
        return Unexpected(FileError{FileErrorCode::OutOfRange, file.string(), 0, 0,
                                    "refusing to save an invalid calibration (size, fx and fy "
                                    "must be positive)"});
    if (auto e = write_file_atomic(file, calibration_to_json(c, true, info).dump(2) + "\n",
                                   file.string()))
        return Unexpected(std::move(*e));
    return {};
}

Expected<CameraCalibration, FileError> default_calibration(CameraId camera,
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

}  // namespace gs::inline core
