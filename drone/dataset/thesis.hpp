#pragma once
// The thesis' own capture layout (DATASET.md "Thesis-style image folders"): one image file per
// frame plus a text file with one line per image, "roll pitch yaw vx vy" (degrees, m/s,
// whitespace separated). Import reads it as a dataset (fps 25 unless told), export writes one.

#include "drone/dataset/dataset.hpp"
#include "drone/dataset/frame_store.hpp"

#include <filesystem>
#include <optional>
#include <string>

namespace gs {

struct ThesisImportOptions {
    double fps = 25;
    CameraId camera = CameraId::Front;
    std::string imu_file;  // empty: imu.txt, else the only .txt file in the folder
};

// The folder as an in-memory Dataset (images read in place; natural order: image_2 before
// image_10). The image count must equal the IMU line count.
Expected<Dataset, DatasetError> open_thesis_folder(const std::filesystem::path& dir,
                                                   const ThesisImportOptions& opts = {},
                                                   const DatasetOpenOptions& open_opts = {});

// Converts a thesis folder into a dataset directory `dst` (must not exist or be empty):
// flight.json (source "imported"), frames.csv, frames/ (the image files copied). Returns it opened.
Expected<Dataset, DatasetError> import_thesis(const std::filesystem::path& src,
                                              const std::filesystem::path& dst,
                                              const ThesisImportOptions& opts = {},
                                              const DatasetOpenOptions& open_opts = {});

// Writes `d` in the thesis layout into `dst`: 000000.png ... (pixels from `frames`) and imu.txt
// (unknown values written as "nan").
[[nodiscard]] std::optional<DatasetError> export_thesis(const Dataset& d, FrameStore& frames,
                                                        const std::filesystem::path& dst);

}  // namespace gs
