#pragma once
// Reading a flight dataset (the format of docs/dataset.md, version 1): flight.json, frames.csv,
// navdata.csv, labels.*, and where the frames are (video.h264 and/or frames/). Opening validates
// everything that is cheap to validate and reports the first problem as a FileError naming the
// file, line and column. No file is read outside the dataset directory: neither the paths named
// in flight.json nor the fixed names (navdata.csv, labels.*, raw/ ...) may lead out of it through
// ".." or symlinks. Pixels are not read here: see frame_store.hpp.

#include "drone/core/assets.hpp"
#include "drone/core/camera_calibration.hpp"
#include "drone/core/expected.hpp"
#include "drone/core/file_error.hpp"
#include "drone/core/file_io.hpp"
#include "drone/core/sample.hpp"
#include "drone/dataset/annexb.hpp"

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace gs::dataset {

// flight.json.
struct DatasetInfo {
    int version = 1;
    CameraId camera = CameraId::Front;
    int width = 0, height = 0;
    double fps = 0;
    std::optional<std::int64_t> frames;  // declared row count of frames.csv
    std::string video = "video.h264";    // relative to the dataset directory
    std::string images = "frames";
    std::optional<CameraCalibration> calibration;  // as stored in the file
    std::string source;
};

// Ground-truth camera pose (docs/dataset.md frames.csv gt_* columns); NaN = not measured.
struct GroundTruthPose {
    double x_m = kUnknown, y_m = kUnknown, z_m = kUnknown, yaw_deg = kUnknown;
};

// One row of frames.csv. nav.t_ns is the capture time from the start of the flight.
struct FrameRow {
    std::int64_t frame = 0;
    NavState nav;
    GroundTruthPose gt;
};

enum class Scenario { Left, Right, Center, None };
std::string to_string(Scenario s);

// labels.json: the scenario plus the file's full text (other keys are free-form).
struct FlightLabels {
    Scenario scenario = Scenario::None;
    std::string json;  // the whole object, as read (or to write)
};

// One row of labels.csv; NaN when there is no obstacle.
struct LabelRow {
    std::int64_t frame = 0;
    double distance_m = kUnknown;
    double lateral_m = kUnknown;
};

// Upper bounds that make a dataset "absurd" rather than big.
struct DatasetLimits {
    int max_dimension = 8192;  // width, height
    double max_fps = 1000;
    std::int64_t max_frames = 10'000'000;
    std::uintmax_t max_json_bytes = 4u << 20;
    std::uintmax_t max_csv_bytes = 1024u << 20;
};

struct DatasetOpenOptions {
    std::filesystem::path assets_dir = core::assets_dir();  // for the default calibration
    DatasetLimits limits;
};

class Dataset {
public:
    static Expected<Dataset, FileError> open(const std::filesystem::path& dir,
                                             const DatasetOpenOptions& opts = {});

    const std::filesystem::path& dir() const { return dir_; }
    const DatasetInfo& info() const { return info_; }
    // flight.json's calibration, else the camera default (scaled to the frame size).
    const CameraCalibration& calibration() const { return calibration_; }
    bool calibration_is_default() const { return calibration_is_default_; }

    const std::vector<FrameRow>& frames() const { return frames_; }
    std::int64_t frame_count() const { return static_cast<std::int64_t>(frames_.size()); }
    // navdata.csv rows (empty when the file is absent).
    const std::vector<NavState>& navdata() const { return navdata_; }
    bool has_navdata() const { return has_navdata_; }

    // Resolved video.h264 path when the file exists (the source of truth for pixels).
    const std::optional<std::filesystem::path>& video_path() const { return video_path_; }
    // Where each frame's access unit is in video.h264 (one per frames.csv row).
    const std::vector<AccessUnitSpan>& video_units() const { return video_units_; }
    // One image per frame (frames/NNNNNN.png or .jpg), in frame order; empty when absent.
    const std::vector<std::filesystem::path>& image_files() const { return image_files_; }

    const std::optional<FlightLabels>& labels() const { return labels_; }
    const std::optional<std::vector<LabelRow>>& label_rows() const { return label_rows_; }
    // raw/ directory when present.
    std::optional<std::filesystem::path> raw_dir() const;

    // Things a reader should mention once (unknown keys, extra images, scaled calibration).
    const std::vector<std::string>& warnings() const { return warnings_; }

    // Assembles a dataset in memory (thesis import, tests); no file is read. The calibration
    // counts as the camera default unless info.calibration is set.
    static Dataset from_parts(std::filesystem::path dir, DatasetInfo info, CameraCalibration calib,
                              std::vector<FrameRow> frames,
                              std::vector<std::filesystem::path> images,
                              std::optional<FlightLabels> labels = std::nullopt,
                              std::optional<std::vector<LabelRow>> label_rows = std::nullopt,
                              std::vector<std::string> warnings = {});

private:
    std::filesystem::path dir_;
    DatasetInfo info_;
    CameraCalibration calibration_;
    bool calibration_is_default_ = false;
    std::vector<FrameRow> frames_;
    std::vector<NavState> navdata_;
    bool has_navdata_ = false;
    std::optional<std::filesystem::path> video_path_;
    std::vector<AccessUnitSpan> video_units_;
    std::vector<std::filesystem::path> image_files_;
    std::optional<FlightLabels> labels_;
    std::optional<std::vector<LabelRow>> label_rows_;
    bool has_raw_ = false;
    std::vector<std::string> warnings_;
};

// Pieces of the reader usable on their own (writer tests, thesis import, tools).
Expected<DatasetInfo, FileError> parse_flight_json(const std::string& text,
                                                   const DatasetLimits& limits = {},
                                                   std::vector<std::string>* warnings = nullptr);
Expected<std::vector<FrameRow>, FileError> parse_frames_csv(std::string text);
// A last line cut short (no newline, too few fields) is left out with a warning in `warnings`.
Expected<std::vector<NavState>, FileError> parse_navdata_csv(
    std::string text, std::vector<std::string>* warnings = nullptr);
Expected<FlightLabels, FileError> parse_labels_json(const std::string& text);
Expected<std::vector<LabelRow>, FileError> parse_labels_csv(std::string text);

// A relative path from metadata resolved under `dir`, or UnsafePath when it is absolute, has a
// ".." component, or (through symlinks) lands outside `dir`.
Expected<std::filesystem::path, FileError> resolve_inside(const std::filesystem::path& dir,
                                                          const std::string& relative,
                                                          const std::string& what);

// A file or folder with a fixed name (navdata.csv, raw, raw/at.log ...) under `dir`, or
// UnsafePath naming it when it exists and (through symlinks) lands outside `dir`: a reader opens
// nothing outside the dataset directory. An absent file is returned as is (the caller decides).
Expected<std::filesystem::path, FileError> resolve_fixed(const std::filesystem::path& dir,
                                                         const std::string& name);

// labels.json and labels.csv of a dataset directory (docs/dataset.md), each unset when its file is
// absent; a file that is there but unsafe, too large or malformed is an error.
struct DatasetLabels {
    std::optional<FlightLabels> flight;
    std::optional<std::vector<LabelRow>> rows;
};
Expected<DatasetLabels, FileError> read_labels(const std::filesystem::path& dir,
                                               const DatasetLimits& limits);

}  // namespace gs::dataset
