#pragma once
// Chessboard camera calibration (pinhole + k1 k2 p1 p2 k3, thesis §3.1.2 / §4.2): board detection
// with sub-pixel corners, cv::calibrateCamera with per-parameter uncertainty, rejection of views
// whose reprojection error stands out, and a coverage map of the image area the boards reached.
// CalibrationSession is what both `ardrone-gs calibrate` and the GUI's calibration mode drive:
// feed frames, read the detection/coverage/running RMS, save.

#include "drone/core/camera_calibration.hpp"
#include "drone/core/unknown.hpp"
#include "vision/calibration_error.hpp"

#include <opencv2/core.hpp>

#include <array>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace gs::vision {

// A chessboard by its inner corners (a board of 10×7 squares has 9×6 inner corners).
struct BoardSpec {
    int cols = 9;
    int rows = 6;
    double square_m = 0.05;

    [[nodiscard]] bool valid() const;
    [[nodiscard]] cv::Size pattern_size() const { return {cols, rows}; }
    [[nodiscard]] int corner_count() const { return cols * rows; }
    // Corner positions on the board plane (z = 0), row by row, in metres.
    [[nodiscard]] std::vector<cv::Point3f> object_points() const;
};

// "9x6" (or "9X6", "9*6") -> cols 9, rows 6; nullopt when malformed or < 3 or > 100 per side.
[[nodiscard]] std::optional<cv::Size> parse_board_size(std::string_view text);

struct DetectOptions {
    // cv::CALIB_CB_FAST_CHECK: frames without a board are rejected in milliseconds instead of
    // ~0.3-4 s (it still finds the board in all rjw57 frames; --sb covers the hard cases).
    bool fast_check = true;
    // When the classic detector fails, try cv::findChessboardCornersSB (more robust to poor
    // lighting, but ~2 s per 640×360 frame here: opt-in for files, never for live video).
    bool sb_fallback = false;
    // Boards whose mean edge width (cv::estimateChessboardSharpness) exceeds this are blurry.
    // Sharp AR.Drone 2 frames measure 1.8-3.4 px.
    double max_blur_px = 5.0;
};

enum class DetectStatus { Found, NotFound, Blurry, EmptyImage };
[[nodiscard]] const char* to_string(DetectStatus s);

struct BoardDetection {
    DetectStatus status = DetectStatus::NotFound;
    // rows*cols sub-pixel corners, row by row (also filled when Blurry, for display).
    std::vector<cv::Point2f> corners;
    double sharpness_px = kUnknown;  // mean edge width, lower = sharper
    cv::Size image_size{};

    [[nodiscard]] bool found() const { return status == DetectStatus::Found; }
};

// Finds the board in a grey or BGR image and refines the corners to sub-pixel, with a search
// window sized to the board's square size in the image.
[[nodiscard]] BoardDetection detect_board(const cv::Mat& image, const BoardSpec& board,
                                          const DetectOptions& opts = {});

// A grid over the image; a cell is covered by a view when its centre lies inside the convex hull
// of that view's corners. Radial distortion is largest at the image corners, so coverage there is
// reported separately.
class CoverageMap {
public:
    CoverageMap() = default;
    explicit CoverageMap(cv::Size image_size, int grid_cols = 16, int grid_rows = 9);

    // Cells the view would cover that no earlier view covered.
    [[nodiscard]] int new_cells(std::span<const cv::Point2f> corners) const;
    void add(std::span<const cv::Point2f> corners);

    [[nodiscard]] cv::Size image_size() const { return image_size_; }
    [[nodiscard]] int grid_cols() const { return cols_; }
    [[nodiscard]] int grid_rows() const { return rows_; }
    // Views covering cell (col, row).
    [[nodiscard]] int count(int col, int row) const;
    // The cell rectangle in image pixels (for drawing).
    [[nodiscard]] cv::Rect2d cell_rect(int col, int row) const;
    // Covered cells / all cells, 0..1.
    [[nodiscard]] double fraction() const;
    // Of the four corner regions (outer quarter of the width and of the height), how many hold a
    // covered cell.
    [[nodiscard]] int corner_regions_covered() const;
    // Farthest board corner from the image centre, as a fraction of the half-diagonal (0..1).
    [[nodiscard]] double max_radius_fraction() const { return max_radius_; }
    [[nodiscard]] int views() const { return views_; }

private:
    [[nodiscard]] std::vector<int> cells_of(std::span<const cv::Point2f> corners) const;
    [[nodiscard]] bool in_corner_region(int col, int row) const;

    cv::Size image_size_{};
    int cols_ = 0, rows_ = 0;
    std::vector<int> counts_;
    double max_radius_ = 0;
    int views_ = 0;
};

struct CalibrationOptions {
    int min_views = 3;
    // A view is an outlier when its RMS exceeds both median + k·1.4826·MAD and ratio·median
    // (the ratio keeps a uniformly good set intact: MAD of near-equal errors is tiny).
    double outlier_mad_k = 3.0;
    double outlier_min_ratio = 2.0;
    // At most this fraction of the views is rejected, worst first, one per recalibration.
    double max_rejected_fraction = 0.5;
    bool fix_k3 = false;  // fit k1 k2 p1 p2 only (few or central views)
};

struct CalibrationResult {
    CameraCalibration camera;
    // One standard deviation of fx, fy, cx, cy, k1, k2, p1, p2, k3.
    std::array<double, 9> std_dev{};
    double rms_px = 0;  // over the used views' corners
    // Per input view: RMS reprojection error against the final model (rejected views are
    // re-posed with solvePnP, so their number says how far off they are).
    std::vector<double> view_rms_px;
    std::vector<bool> view_used;
    std::vector<int> rejected;  // indices of views rejected as outliers, in rejection order
    CoverageMap coverage;       // of the used views
    int used_views() const;
    // The file notes: rms, std_dev, views (the camera name left for the caller).
    [[nodiscard]] CalibrationInfo info() const;
};

// Calibrates from detected corner sets (each rows*cols, row by row) of one image size.
[[nodiscard]] Expected<CalibrationResult, CalibrationError> calibrate_views(
    std::span<const std::vector<cv::Point2f>> views, const BoardSpec& board, cv::Size image_size,
    const CalibrationOptions& opts = {});

// Straightness of a board's rows and columns: the largest distance (px) of a corner from the
// total-least-squares line through its row or column. A pinhole view of a flat board gives 0 up
// to corner noise; barrel distortion bends the lines.
[[nodiscard]] double max_line_deviation_px(std::span<const cv::Point2f> corners,
                                           const BoardSpec& board);

// Undistorted corner positions with the camera matrix kept (cv::undistortPoints with P = K,
// iterated to convergence for the AR.Drone's k1 ≈ -0.55).
[[nodiscard]] std::vector<cv::Point2f> undistort_corners(std::span<const cv::Point2f> corners,
                                                         const CameraCalibration& cam);

enum class FrameStatus { Accepted, NotFound, Blurry, EmptyImage, SizeMismatch, NoNewCoverage };
[[nodiscard]] const char* to_string(FrameStatus s);

struct ViewResult {
    FrameStatus status = FrameStatus::NotFound;
    BoardDetection detection;
    int new_cells = 0;  // coverage cells this view adds
    [[nodiscard]] bool adds_coverage() const { return new_cells > 0; }
    [[nodiscard]] bool accepted() const { return status == FrameStatus::Accepted; }
};

struct SessionOptions {
    DetectOptions detect;
    CalibrationOptions calibration;
    int grid_cols = 16;
    int grid_rows = 9;
    // Recalibrate after each accepted view once min_views are in (tens of ms for 20 views).
    bool recalibrate_on_add = true;
};

// An interactive or batch calibration: frames in, detections + coverage + running calibration out.
// Not thread-safe; the GUI owns one and calls it from one thread.
class CalibrationSession {
public:
    explicit CalibrationSession(BoardSpec board, SessionOptions opts = {});

    // Detection and coverage gain for a frame, keeping nothing (the live preview).
    [[nodiscard]] ViewResult check(const cv::Mat& image) const;
    // Detects and keeps the view when the board is found and sharp, the image size matches the
    // earlier views, and (if require_new_coverage) it covers a cell no kept view covers.
    ViewResult add_frame(const cv::Mat& image, bool require_new_coverage = true);
    // The same with a detection already made (from check()), without detecting again.
    ViewResult add_detection(const BoardDetection& detection, bool require_new_coverage = true);

    // Calibrates from the kept views now; the result is also kept (result(), rms_px()).
    Expected<CalibrationResult, CalibrationError> calibrate();

    [[nodiscard]] const BoardSpec& board() const { return board_; }
    [[nodiscard]] std::size_t view_count() const { return views_.size(); }
    [[nodiscard]] const std::vector<std::vector<cv::Point2f>>& views() const { return views_; }
    [[nodiscard]] std::optional<cv::Size> image_size() const { return image_size_; }
    // Coverage of all kept views (empty grid before the first view).
    [[nodiscard]] const CoverageMap& coverage() const { return coverage_; }
    // The latest successful calibration, and the error of the latest attempt (if it failed).
    [[nodiscard]] const std::optional<CalibrationResult>& result() const { return result_; }
    [[nodiscard]] const std::optional<CalibrationError>& last_error() const { return last_error_; }
    // RMS of the latest calibration, NaN before one exists.
    [[nodiscard]] double rms_px() const;

    // Forgets the last kept view (a bad capture) and recalibrates.
    void remove_last_view();
    void reset();

    // Saves the latest calibration (camera name from `info`, numbers from the result; `source`:
    // where the numbers come from, written into the file).
    [[nodiscard]] Expected<void, CalibrationError> save(const std::string& path,
                                                        CalibrationInfo info = {},
                                                        std::string source = {}) const;

private:
    void rebuild_coverage();
    void recalibrate_if_enough();

    BoardSpec board_;
    SessionOptions opts_;
    std::vector<std::vector<cv::Point2f>> views_;
    std::optional<cv::Size> image_size_;
    CoverageMap coverage_;
    std::optional<CalibrationResult> result_;
    std::optional<CalibrationError> last_error_;
};

}  // namespace gs::vision
