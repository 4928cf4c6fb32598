#include "vision/calibration_file.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace gs::vision {

const char* to_string(CalibrationErrorKind k) {
    switch (k) {
        case CalibrationErrorKind::NoImages:
            return "no images";
        case CalibrationErrorKind::ImageUnreadable:
            return "image unreadable";
        case CalibrationErrorKind::ImageSizeMismatch:
            return "image size mismatch";
        case CalibrationErrorKind::BoardNotFound:
            return "board not found";
        case CalibrationErrorKind::TooFewViews:
            return "too few views";
        case CalibrationErrorKind::BadBoardSpec:
            return "bad board";
        case CalibrationErrorKind::CalibrationFailed:
            return "calibration failed";
        case CalibrationErrorKind::FileRead:
            return "cannot read file";
        case CalibrationErrorKind::FileWrite:
            return "cannot write file";
        case CalibrationErrorKind::BadJson:
            return "bad calibration JSON";
        case CalibrationErrorKind::BadValue:
            return "bad calibration value";
    }
    return "unknown calibration error";
}

std::string CalibrationError::message() const {
    return detail.empty() ? std::string(to_string(kind))
                          : std::string(to_string(kind)) + ": " + detail;
}

namespace {

using nlohmann::json;

constexpr int kMaxImageSide = 16384;
constexpr std::size_t kMaxFileBytes = 1 << 20;  // a calibration or flight.json is a few KiB

// NaN and infinities are not JSON: unknown numbers are left out.
template <class J>
void put_if_finite(J& j, const char* key, double v) {
    if (std::isfinite(v)) j[key] = v;
}

bool read_number(const json& obj, const char* key, double& out) {
    const auto it = obj.find(key);
    if (it == obj.end() || !it->is_number()) return false;
    out = it->get<double>();
    return true;
}

bool read_int(const json& obj, const char* key, int& out) {
    const auto it = obj.find(key);
    if (it == obj.end() || !it->is_number()) return false;
    const double v = it->get<double>();
    if (!std::isfinite(v) || v != std::floor(v) || v < 0 || v > kMaxImageSide) return false;
    out = static_cast<int>(v);
    return true;
}

}  // namespace

std::string calibration_to_json(const CameraCalibration& cam, const CalibrationInfo& info) {
    nlohmann::ordered_json j = nlohmann::ordered_json::object();
    if (!info.camera.empty()) j["camera"] = info.camera;
    j["width"] = cam.width;
    j["height"] = cam.height;
    j["fx"] = cam.fx;
    j["fy"] = cam.fy;
    j["cx"] = cam.cx;
    j["cy"] = cam.cy;
    j["dist"] = nlohmann::ordered_json::array(
        {cam.dist[0], cam.dist[1], cam.dist[2], cam.dist[3], cam.dist[4]});
    put_if_finite(j, "rms_px", info.rms_px);
    bool any_sd = false;
    for (double s : info.std_dev) any_sd = any_sd || std::isfinite(s);
    if (any_sd) {
        nlohmann::ordered_json sd = nlohmann::ordered_json::object();
        put_if_finite(sd, "fx", info.std_dev[0]);
        put_if_finite(sd, "fy", info.std_dev[1]);
        put_if_finite(sd, "cx", info.std_dev[2]);
        put_if_finite(sd, "cy", info.std_dev[3]);
        nlohmann::ordered_json d = nlohmann::ordered_json::array();
        for (std::size_t i = 4; i < 9; ++i) {
            d.push_back(std::isfinite(info.std_dev[i]) ? nlohmann::ordered_json(info.std_dev[i])
                                                       : nlohmann::ordered_json(nullptr));
        }
        sd["dist"] = d;
        j["std_dev"] = sd;
    }
    if (info.views > 0) j["views"] = info.views;
    if (!info.source.empty()) j["source"] = info.source;
    return j.dump(2) + "\n";
}

CalibrationExpected<CalibrationDocument> parse_calibration_json(std::string_view text,
                                                                const std::string& origin) {
    const json root = json::parse(text, nullptr, /*allow_exceptions=*/false);
    if (root.is_discarded())
        return calibration_error(CalibrationErrorKind::BadJson, origin + ": not valid JSON");
    if (!root.is_object()) {
        return calibration_error(CalibrationErrorKind::BadJson,
                                 origin + ": expected a JSON object");
    }
    // A flight.json: the calibration object sits under "calibration", the size at the top.
    const bool nested = root.contains("calibration");
    const json& c = nested ? root["calibration"] : root;
    if (!c.is_object()) {
        return calibration_error(CalibrationErrorKind::BadJson,
                                 origin + ": \"calibration\" is not an object");
    }

    CalibrationDocument doc;
    CameraCalibration& cam = doc.camera;
    for (auto [key, dst] : {std::pair{"fx", &cam.fx}, std::pair{"fy", &cam.fy},
                            std::pair{"cx", &cam.cx}, std::pair{"cy", &cam.cy}}) {
        if (!read_number(c, key, *dst)) {
            return calibration_error(CalibrationErrorKind::BadJson,
                                     origin + ": missing or non-numeric \"" + key + "\"");
        }
    }
    if (!read_int(c, "width", cam.width) && !(nested && read_int(root, "width", cam.width))) {
        return calibration_error(CalibrationErrorKind::BadJson,
                                 origin + ": missing or invalid \"width\"");
    }
    if (!read_int(c, "height", cam.height) && !(nested && read_int(root, "height", cam.height))) {
        return calibration_error(CalibrationErrorKind::BadJson,
                                 origin + ": missing or invalid \"height\"");
    }
    const auto d = c.find("dist");
    if (d == c.end() || !d->is_array() || d->size() < 4 || d->size() > 5) {
        return calibration_error(
            CalibrationErrorKind::BadJson,
            origin + ": \"dist\" must be an array of 4 or 5 numbers (k1 k2 p1 p2 [k3])");
    }
    cam.dist = {};
    for (std::size_t i = 0; i < d->size(); ++i) {
        if (!(*d)[i].is_number()) {
            return calibration_error(CalibrationErrorKind::BadJson,
                                     origin + ": \"dist\" holds a non-number");
        }
        cam.dist[i] = (*d)[i].get<double>();
    }

    bool finite = std::isfinite(cam.fx) && std::isfinite(cam.fy) && std::isfinite(cam.cx) &&
                  std::isfinite(cam.cy);
    for (double v : cam.dist) finite = finite && std::isfinite(v);
    if (!finite || !cam.valid()) {
        return calibration_error(
            CalibrationErrorKind::BadValue,
            origin + ": width, height, fx and fy must be positive and all values finite");
    }

    CalibrationInfo& info = doc.info;
    const json& meta = c;
    if (auto it = meta.find("camera"); it != meta.end() && it->is_string()) {
        info.camera = it->get<std::string>();
    } else if (auto jt = root.find("camera"); nested && jt != root.end() && jt->is_string()) {
        info.camera = jt->get<std::string>();
    }
    if (auto it = meta.find("source"); it != meta.end() && it->is_string()) {
        info.source = it->get<std::string>();
    }
    double rms = 0;
    if (read_number(meta, "rms_px", rms)) info.rms_px = rms;
    int views = 0;
    if (read_int(meta, "views", views)) info.views = views;
    if (auto it = meta.find("std_dev"); it != meta.end() && it->is_object()) {
        const char* keys[] = {"fx", "fy", "cx", "cy"};
        for (std::size_t i = 0; i < 4; ++i) {
            double v = 0;
            if (read_number(*it, keys[i], v)) info.std_dev[i] = v;
        }
        if (auto sd = it->find("dist"); sd != it->end() && sd->is_array()) {
            for (std::size_t i = 0; i < sd->size() && i < 5; ++i) {
                if ((*sd)[i].is_number()) info.std_dev[4 + i] = (*sd)[i].get<double>();
            }
        }
    }
    return doc;
}

CalibrationExpected<CalibrationDocument> load_calibration_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return calibration_error(CalibrationErrorKind::FileRead, path);
    std::string text;
    text.resize(kMaxFileBytes + 1);
    in.read(text.data(), static_cast<std::streamsize>(text.size()));
    const auto n = static_cast<std::size_t>(in.gcount());
    if (n > kMaxFileBytes) {
        return calibration_error(CalibrationErrorKind::BadJson,
                                 path + ": larger than 1 MiB, not a calibration");
    }
    text.resize(n);
    return parse_calibration_json(text, path);
}

CalibrationExpected<Done> save_calibration_file(const std::string& path,
                                                const CameraCalibration& cam,
                                                const CalibrationInfo& info) {
    if (!cam.valid())
        return calibration_error(CalibrationErrorKind::BadValue,
                                 "refusing to save an invalid calibration");
    const std::string tmp = path + ".tmp";
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) return calibration_error(CalibrationErrorKind::FileWrite, tmp);
        out << calibration_to_json(cam, info);
        out.flush();
        if (!out) {
            std::remove(tmp.c_str());
            return calibration_error(CalibrationErrorKind::FileWrite, tmp);
        }
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        std::remove(tmp.c_str());
        return calibration_error(CalibrationErrorKind::FileWrite, path);
    }
    return Done{};
}

}  // namespace gs::vision
