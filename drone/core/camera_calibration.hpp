#pragma once
// The camera calibration record: OpenCV's pinhole model with (k1, k2, p1, p2, k3), in pixels of
// the images it describes, and its one file codec. Datasets, the virtual drone's renderer, the
// classifiers, the odometry and the calibration tools all use this struct and these functions.
//
// JSON shape: docs/dataset.md's flight.json "calibration" object ({"fx","fy","cx","cy","dist"})
// plus optional "width" and "height" (together), "readout_ms" (a rolling shutter's readout time,
// written whenever known, in flight.json too) and notes ("camera", "rms_px", "std_dev", "views",
// "source"): the shape of assets/calibration/ardrone2_{front,bottom}.json and of what
// `calibrate` writes. Readers ignore keys they do not know, so the same file works for
// `--calibration FILE`, for the assets and inside flight.json.
//
// Vision moves points, not images: undistort_points and its inverse work on point coordinates,
// with the camera matrix itself as the "new" camera matrix (what cv::undistort does for an image,
// as the thesis used it).

#include "drone/core/assets.hpp"
#include "drone/core/expected.hpp"
#include "drone/core/file_error.hpp"
#include "drone/core/unknown.hpp"

#include <nlohmann/json_fwd.hpp>
#include <opencv2/core.hpp>

#include <array>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace gs::inline core {

enum class CameraId { Front, Bottom };
std::string to_string(CameraId c);

struct CameraCalibration {
    double fx = 0, fy = 0, cx = 0, cy = 0;
    std::array<double, 5> dist{};  // k1, k2, p1, p2, k3
    int width = 0, height = 0;     // image size the intrinsics are for (0 = unknown)
    // Rolling shutter: the time from the first row's readout to the last's (ms); 0 a global
    // shutter, NaN not stated (the classifier then assumes the AR.Drone 2 front camera's).
    double readout_ms = kUnknown;
    std::string source;  // where the numbers come from (free text)

    bool valid() const { return width > 0 && height > 0 && fx > 0 && fy > 0; }
    cv::Matx33d camera_matrix() const { return {fx, 0, cx, 0, fy, cy, 0, 0, 1}; }
    cv::Vec<double, 5> dist_coeffs() const { return {dist[0], dist[1], dist[2], dist[3], dist[4]}; }
    // The undistorted pixel a direction in camera coordinates (x right, y down, z forward) points
    // at: the pinhole projection. The caller makes sure z > 0 (a focus of expansion, say).
    cv::Point2d project(const cv::Vec3d& dir) const {
        return {fx * dir[0] / dir[2] + cx, fy * dir[1] / dir[2] + cy};
    }
    bool has_distortion() const;

    // The same camera for images resized to (w, h): focal lengths and centre scale (pixel
    // centres stay centres), distortion and field of view do not. An unknown size is taken as
    // (w, h) unscaled.
    CameraCalibration scaled_to(int w, int h) const;
    // This calibration with the size (w, h) when its own is unknown (intrinsics unchanged).
    CameraCalibration with_size_if_unknown(int w, int h) const;

    // A distortion-free camera with the given horizontal field of view, principal point at the
    // image centre (for synthetic scenes and for tests).
    static CameraCalibration ideal(int w, int h, double hfov_deg);

    // Raw (distorted) pixel -> undistorted pixel, iteratively (cv::undistortPoints with P = K).
    // `out` must have in.size() elements; in and out may alias.
    void undistort_points(std::span<const cv::Point2f> in, std::span<cv::Point2f> out) const;
    // Undistorted pixel -> raw (distorted) pixel, closed form.
    cv::Point2f distort_point(cv::Point2f undistorted) const;
};

// Undistorted normalised coordinates (x/z, y/z) -> distorted pixel (OpenCV's model).
cv::Point2d distort_to_pixel(const CameraCalibration& c, cv::Point2d normalised);
// Distorted pixel -> undistorted normalised coordinates (Newton iterations on the full model);
// nullopt when it does not converge (outside the model's invertible range).
std::optional<cv::Point2d> undistort_pixel(const CameraCalibration& c, cv::Point2d pixel);

// What a calibration file says besides the camera model. Unknown numbers are kUnknown, unknown
// text empty.
struct CalibrationInfo {
    std::string camera;  // "front", "bottom" or empty
    double rms_px = kUnknown;
    // One standard deviation of fx, fy, cx, cy, k1, k2, p1, p2, k3 (OpenCV's estimate).
    std::array<double, 9> std_dev{kUnknown, kUnknown, kUnknown, kUnknown, kUnknown,
                                  kUnknown, kUnknown, kUnknown, kUnknown};
    int views = 0;  // images used, 0 = unknown
};

struct CalibrationDocument {
    CameraCalibration camera;  // camera.source: the file's "source"
    CalibrationInfo info;
};

// A problem with one key of a calibration object: callers turn it into their own error with the
// file name and position (flight.json reports "calibration.fx" at its line).
struct CalibrationIssue {
    FileErrorCode code = FileErrorCode::Malformed;
    std::string key;  // "fx", "dist", ... ; empty for the object itself
    std::string message;
};

// Parses a calibration object: fx, fy, cx, cy required (finite, focal lengths positive); dist of
// 4 or 5 numbers optional (missing = no distortion); width and height optional but together
// (1..65535); readout_ms optional (0..1000); source optional.
[[nodiscard]] Expected<CameraCalibration, CalibrationIssue> calibration_from_json(
    const nlohmann::json& obj);
// The object back: fx, fy, cx, cy, dist; with `with_extras`, also the size when known, the notes
// of `info` that are known and the source when set (flight.json stores only the intrinsics: the
// size is the flight's).
nlohmann::json calibration_to_json(const CameraCalibration& c, bool with_extras = true,
                                   const CalibrationInfo& info = {});

// Reads a calibration from JSON text: a calibration object, or a whole flight.json (its
// "calibration" object, the size taken from the top level when the object lacks it). `name`
// names the text in errors, which give the line and column of a bad key.
[[nodiscard]] Expected<CalibrationDocument, FileError> parse_calibration(std::string_view text,
                                                                         const std::string& name);
// Reads a calibration file (at most 1 MiB).
[[nodiscard]] Expected<CalibrationDocument, FileError> load_calibration_document(
    const std::filesystem::path& file);
// The camera model of a calibration file.
[[nodiscard]] Expected<CameraCalibration, FileError> load_calibration_file(
    const std::filesystem::path& file);
// Writes one (with the size, the notes and the source) through a temporary file and a rename;
// refuses an invalid calibration.
[[nodiscard]] Expected<void, FileError> save_calibration_file(const std::filesystem::path& file,
                                                              const CameraCalibration& c,
                                                              const CalibrationInfo& info = {});

// The camera's default: `assets`/calibration/ardrone2_{front,bottom}.json.
[[nodiscard]] Expected<CameraCalibration, FileError> default_calibration(
    CameraId camera, const std::filesystem::path& assets = assets_dir());
// The same numbers compiled in (ardrone_autonomy's camera files, docs/protocol.md §6), for code
// that must not fail on a missing asset (the virtual drone); a test checks they equal the files.
CameraCalibration builtin_calibration(CameraId camera);

}  // namespace gs::inline core
