#pragma once
// The camera calibration record of drone/: OpenCV's pinhole model with (k1, k2, p1, p2, k3), in
// pixels of the images it describes. One plain struct for datasets, the simulator's renderer and
// the pipeline (drone/ may not depend on vision/; app/pipeline.hpp converts it to vision's camera
// model). JSON shape: DATASET.md's flight.json "calibration" object plus optional "width",
// "height" and "source", the shape of assets/calibration/ardrone2_{front,bottom}.json.

#include "drone/core/file_error.hpp"
#include "drone/core/expected.hpp"

#include <nlohmann/json_fwd.hpp>
#include <opencv2/core.hpp>

#include <array>
#include <filesystem>
#include <optional>
#include <string>

namespace gs {

enum class CameraId { Front, Bottom };
std::string to_string(CameraId c);

struct CameraCalibration {
    double fx = 0, fy = 0, cx = 0, cy = 0;
    std::array<double, 5> dist{};  // k1, k2, p1, p2, k3
    int width = 0, height = 0;     // image size the intrinsics are for (0 = unknown)
    std::string source;            // where the numbers come from (free text)

    bool valid() const { return width > 0 && height > 0 && fx > 0 && fy > 0; }
};

// A problem with one key of a calibration object: callers turn it into their own error with the
// file name and position (flight.json reports "calibration.fx" at its line).
struct CalibrationIssue {
    DatasetErrorCode code = DatasetErrorCode::Malformed;
    std::string key;  // "fx", "dist", ... ; empty for the object itself
    std::string message;
};

// Parses a calibration object: fx, fy, cx, cy required (finite, focal lengths positive); dist of
// 4 or 5 numbers optional (missing = no distortion); width and height optional but together
// (1..65535); source optional.
[[nodiscard]] Expected<CameraCalibration, CalibrationIssue> calibration_from_json(
    const nlohmann::json& obj);
// The object back: fx, fy, cx, cy, dist; width/height when known and `with_extras`, source when
// set and `with_extras` (flight.json stores only the intrinsics: the size is the flight's).
nlohmann::json calibration_to_json(const CameraCalibration& c, bool with_extras = true);

// Reads a calibration file (errors name the file and, for a bad key, its line and column).
[[nodiscard]] Expected<CameraCalibration, DatasetError> load_calibration_file(
    const std::filesystem::path& file);
// Writes one (with width, height and source), through a temporary file and a rename.
[[nodiscard]] std::optional<DatasetError> save_calibration_file(const std::filesystem::path& file,
                                                                const CameraCalibration& c);

// The camera's default: `assets_dir`/calibration/ardrone2_{front,bottom}.json.
[[nodiscard]] Expected<CameraCalibration, DatasetError> default_calibration(
    CameraId camera, const std::filesystem::path& assets_dir = GS_ASSETS_DIR);
// The same numbers compiled in (ardrone_autonomy's camera files, PROTOCOL.md §6), for code that
// must not fail on a missing asset (the virtual drone); a test checks they equal the files.
CameraCalibration builtin_calibration(CameraId camera);

// Same intrinsics for another image size (focal lengths and centre scale, pixel centres stay
// centres; distortion and field of view unchanged). An unknown source size is taken as the target.
CameraCalibration scaled_to(const CameraCalibration& c, int width, int height);

// Undistorted normalised coordinates (x/z, y/z) -> distorted pixel (OpenCV's model).
cv::Point2d distort_to_pixel(const CameraCalibration& c, cv::Point2d normalised);
// Distorted pixel -> undistorted normalised coordinates (Newton iterations on the full model);
// nullopt when it does not converge (outside the model's invertible range).
std::optional<cv::Point2d> undistort_pixel(const CameraCalibration& c, cv::Point2d pixel);

}  // namespace gs
