#pragma once
// The interactive camera calibration mode behind the window's Calibration window: a worker
// thread around a CalibrationSession (vision/calibration.hpp) fed with the live or replayed
// video. It checks the newest frame for the board, keeps a view on request (or automatically)
// only when CalibrationSession accepts it (board found and sharp, same image size, new coverage),
// recalibrates as views come in, and on request calibrates, saves the calibration file and hands
// the result to the caller to apply.
//
// Threads: the board detection (~20-40 ms per 640x360 frame with a board, a few ms without, more
// on a loaded machine) runs only on the worker, never on the caller's thread. offer() stores a
// header of the newest frame and returns (no copy, no wait); the worker checks at most one frame
// every `interval_ms`, always the newest (frames in between are skipped, never queued). Commands
// are queued and handled in order on the worker. State goes out through the `publish` callback,
// called on the worker thread after every detection and command.
//
// This header keeps vision/calibration.hpp (OpenCV calib3d) out of the session's includes.

#include "drone/core/camera_calibration.hpp"
#include "drone/core/unknown.hpp"

#include <opencv2/core.hpp>

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace gs::vision {

// A chessboard by its inner corners and square size (BoardSpec's numbers).
struct CalibrationBoard {
    int cols = 9;
    int rows = 6;
    double square_m = 0.05;
    [[nodiscard]] bool valid() const;
};

// What a check of the latest frame found.
enum class ViewCheck {
    None,           // nothing checked yet
    AddsCoverage,   // board found and sharp; a capture would be kept
    NoNewCoverage,  // board found and sharp, but it covers only cells already covered
    NotFound,
    Blurry,
    SizeMismatch,  // the frame size differs from the kept views'
    EmptyImage,
};
[[nodiscard]] const char* to_string(ViewCheck c);

struct CalibrationModeState {
    bool active = false;
    CalibrationBoard board;
    bool auto_capture = false;
    std::string save_path;

    // The latest checked frame.
    std::uint64_t source_id = 0;
    std::int64_t frame = -1;
    std::uint64_t detections = 0;
    ViewCheck check = ViewCheck::None;
    std::vector<cv::Point2f> corners;  // rows*cols, row by row; also when blurry (for display)
    cv::Size image_size{};
    int new_cells = 0;  // coverage cells a capture would add
    double detect_ms = kUnknown;

    // Kept views and their coverage (grid_cols * grid_rows counts, row by row, in pixels of
    // coverage_size).
    int views = 0;
    int min_views = 3;
    cv::Size coverage_size{};
    int grid_cols = 0, grid_rows = 0;
    std::vector<int> coverage;
    double coverage_fraction = 0;
    int corner_regions = 0;  // of 4

    // The running calibration (after min_views views).
    bool has_result = false;
    CameraCalibration camera;
    double rms_px = kUnknown;
    int used_views = 0;
    std::string result_error;  // why the latest calibration attempt failed

    std::uint64_t captures = 0;  // capture attempts handled (manual and automatic)
    bool last_capture_kept = false;
    std::string last_capture;  // "view 4 kept (frame 12, +9 cells)" / "frame 3 not kept: ..."

    std::uint64_t saves = 0;  // save requests handled
    std::string saved_path;   // the file last written
    std::string save_error;   // why the last save failed
};

struct CalibrationModeOptions {
    std::string save_path;         // where save() writes (empty: save() reports it cannot)
    std::string camera = "front";  // camera name stored in the file
    int interval_ms = 150;         // at most one detection per this many ms (0: every new frame)
    int auto_interval_ms = 1000;   // auto capture keeps at most one view per this many ms
};

class CalibrationMode {
public:
    using Publish = std::function<void(const CalibrationModeState&)>;
    // A calibration just saved to `path` (source: the note written into the file).
    using Saved = std::function<void(const CameraCalibration& camera, const std::string& source,
                                     const std::string& path)>;

    CalibrationMode(CalibrationModeOptions opts, Publish publish, Saved saved);
    ~CalibrationMode();  // stops and joins the worker
    CalibrationMode(const CalibrationMode&) = delete;
    CalibrationMode& operator=(const CalibrationMode&) = delete;

    // Commands, handled in order on the worker. start() (re)starts with `board`, forgetting
    // earlier views; stop() forgets everything and lets go of the frame.
    void start(const CalibrationBoard& board);
    void stop();
    void capture();  // keeps the newest frame if CalibrationSession accepts it
    void undo();     // forgets the last kept view
    void reset();    // forgets every view
    void set_auto_capture(bool on);
    void save();  // calibrates from the kept views, writes save_path, calls `saved`

    // The newest frame. Ignored while the mode is off unless `even_inactive` (the frame on screen
    // when the mode starts, for a paused replay that sends no new one).
    void offer(const cv::Mat& image, std::int64_t index, std::uint64_t source_id,
               bool even_inactive = false);
    [[nodiscard]] bool active() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace gs::vision
