#pragma once
// The thesis' own capture layout (docs/dataset.md "Thesis-style image folders"): one image file per
// frame plus a text file with one line per image, "roll pitch yaw vx vy" (degrees, m/s,
// whitespace separated). Import reads it as a dataset (fps 25 unless told), export writes one.
//
// That line format is fixed (other tools write it), so what it cannot hold travels in side files
// beside it. Both are optional: a folder without them reads exactly as docs/dataset.md says.
//   imu_extra.csv   header row, then one row per image, in the order of the IMU lines, with
//                   frames.csv's columns and meaning (docs/dataset.md): `frame` (0, 1, 2 ...) is
//                   required; t_ms, vz_mps, altitude_m, gt_x_m, gt_y_m, gt_z_m and gt_yaw_deg
//                   are read when present (empty = unknown); roll pitch yaw vx vy come from the
//                   IMU text file only, other columns are ignored. With t_ms the frames keep
//                   their capture times instead of frame / fps.
//   imu_meta.json   {"fps": 30, "camera": "front", "calibration": {...}}: flight.json's keys and
//                   meaning, each optional; unknown keys are ignored (with a warning).
// labels.json and labels.csv (docs/dataset.md) beside the images are read as a dataset's. Export
// writes all of these, so export then import gives back the frames' times, attitude, velocities,
// altitude, ground truth, frame rate, calibration and labels: a replay decides the same.

#include "drone/dataset/dataset.hpp"
#include "drone/dataset/frame_store.hpp"

#include <filesystem>
#include <optional>
#include <string>

namespace gs::dataset {

inline constexpr double kThesisDefaultFps = 25;
inline constexpr const char* kThesisExtraFile = "imu_extra.csv";
inline constexpr const char* kThesisMetaFile = "imu_meta.json";

struct ThesisImportOptions {
    // The frame rate when told (frame n is then captured at n / fps, imu_extra.csv's t_ms is
    // ignored); else imu_meta.json's, else 25.
    std::optional<double> fps;
    std::optional<CameraId> camera;  // else imu_meta.json's, else front
    std::string imu_file;            // empty: imu.txt, else the only .txt file in the folder
};

// The folder as an in-memory Dataset (images read in place; natural order: image_2 before
// image_10). The image count must equal the IMU line count.
Expected<Dataset, FileError> open_thesis_folder(const std::filesystem::path& dir,
                                                const ThesisImportOptions& opts = {},
                                                const DatasetOpenOptions& open_opts = {});

// The folder's two texts read from memory as open_thesis_folder reads them (for fuzzing): the
// number of IMU lines of `imu_text` (imu.txt), after `meta_text` (imu_meta.json; empty: none)
// was checked, or the first error.
Expected<std::size_t, FileError> read_thesis_texts(const std::string& imu_text,
                                                   const std::string& meta_text);

// Converts a thesis folder into a dataset directory `dst` (must not exist or be empty):
// flight.json (source "imported"), frames.csv, frames/ (the image files copied), labels.* when
// the folder has them. Returns it opened.
Expected<Dataset, FileError> import_thesis(const std::filesystem::path& src,
                                           const std::filesystem::path& dst,
                                           const ThesisImportOptions& opts = {},
                                           const DatasetOpenOptions& open_opts = {});

// Writes `d` in the thesis layout into `dst`: 000000.png ... (pixels from `frames`) and imu.txt
// (unknown values written as "nan"), plus imu_extra.csv, imu_meta.json and the labels (above).
[[nodiscard]] std::optional<FileError> export_thesis(const Dataset& d, FrameStore& frames,
                                                     const std::filesystem::path& dst);

}  // namespace gs::dataset
