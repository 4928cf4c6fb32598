#pragma once
// Calibration files: DATASET.md's flight.json "calibration" object ({"fx","fy","cx","cy",
// "dist":[k1,k2,p1,p2,k3]}) plus "width", "height" and optional notes ("camera", "rms_px",
// "std_dev", "views", "source"). Readers ignore keys they do not know, so the same file works for
// `--calibration FILE`, for assets/calibration/*.json and inside flight.json.

#include "vision/calibration_error.hpp"
#include "vision/camera_model.hpp"

#include <array>
#include <limits>
#include <string>
#include <string_view>

namespace gs::vision {

// What a calibration file says besides the camera model. Unknown numbers are NaN, unknown text
// empty.
struct CalibrationInfo {
    std::string camera;  // "front", "bottom" or empty
    std::string source;  // where the numbers come from, free text
    double rms_px = std::numeric_limits<double>::quiet_NaN();
    // One standard deviation of fx, fy, cx, cy, k1, k2, p1, p2, k3 (OpenCV's estimate).
    std::array<double, 9> std_dev{nan(), nan(), nan(), nan(), nan(), nan(), nan(), nan(), nan()};
    int views = 0;  // images used, 0 = unknown

    static constexpr double nan() { return std::numeric_limits<double>::quiet_NaN(); }
};

struct CalibrationDocument {
    CameraCalibration camera;
    CalibrationInfo info;
};

// JSON text of one calibration (pretty-printed, numbers in shortest round-trip form).
[[nodiscard]] std::string calibration_to_json(const CameraCalibration& cam,
                                              const CalibrationInfo& info = {});

// Reads a calibration from JSON text: a calibration object, or a whole flight.json (its
// "calibration" object, with width/height taken from the top level when the object lacks them).
// `origin` names the text in error messages.
[[nodiscard]] CalibrationExpected<CalibrationDocument> parse_calibration_json(
    std::string_view text, const std::string& origin = "calibration");

[[nodiscard]] CalibrationExpected<CalibrationDocument> load_calibration_file(
    const std::string& path);

// Writes atomically enough for a user tool: to `path` + ".tmp", then renamed over `path`, so a
// failed write leaves no half file.
[[nodiscard]] CalibrationExpected<Done> save_calibration_file(const std::string& path,
                                                              const CameraCalibration& cam,
                                                              const CalibrationInfo& info = {});

}  // namespace gs::vision
