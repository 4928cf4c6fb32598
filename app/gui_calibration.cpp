#ifdef GS_HAVE_GUI

// Calibration view: the calibration mode's state in words (what to do next), the coverage, the
// result and the calibration in use.

#include "app/gui_adapter.hpp"

#include <cstdio>

namespace gs::app {

void GuiAdapter::fill_calibration(ui::GuiSnapshot& s) {
    session_.calibration_mode().read_if_newer(mode_gen_, mode_);
    const vision::CalibrationModeState& m = mode_;
    ui::CalibrationView& cv = s.calibration;
    cv.active = m.active;
    cv.board_cols = m.board.cols;
    cv.board_rows = m.board.rows;
    cv.square_m = m.board.square_m;
    cv.auto_capture = m.auto_capture;
    cv.save_path = m.save_path;

    using vision::ViewCheck;
    const bool current = m.active && m.frame >= 0 && m.source_id == source_.id && out_;
    cv.frame = current ? m.frame : -1;
    cv.detections = m.detections;
    cv.detect_ms = m.detect_ms;
    cv.board_found =
        current && (m.check == ViewCheck::AddsCoverage || m.check == ViewCheck::NoNewCoverage);
    cv.adds_coverage = current && m.check == ViewCheck::AddsCoverage;
    cv.new_cells = current ? m.new_cells : 0;
    char buf[192];
    if (!m.active) {
        cv.status = m.result_error.empty() ? "calibration mode off" : m.result_error;
    } else if (!current) {
        cv.status = "waiting for video";
    } else {
        switch (m.check) {
            case ViewCheck::None:
                cv.status = "waiting for video";
                break;
            case ViewCheck::AddsCoverage:
                std::snprintf(buf, sizeof buf, "board found: +%d cells, capture it", m.new_cells);
                cv.status = buf;
                break;
            case ViewCheck::NoNewCoverage:
                cv.status = "board found, adds no coverage: move it to an uncovered area";
                break;
            case ViewCheck::NotFound:
                std::snprintf(buf, sizeof buf,
                              "no %dx%d board found (inner corners; the whole board in view)",
                              m.board.cols, m.board.rows);
                cv.status = buf;
                break;
            case ViewCheck::Blurry:
                cv.status = "board blurry: hold it still";
                break;
            case ViewCheck::SizeMismatch:
                cv.status = "frame size differs from the kept views";
                break;
            case ViewCheck::EmptyImage:
                cv.status = "empty frame";
                break;
        }
    }
    // Corners in pixels of the frame shown (moved onto the undistorted image under the preview).
    cv.corners.clear();
    if (current && (cv.board_found || m.check == ViewCheck::Blurry) &&
        m.image_size.width == out_->frame.image.cols &&
        m.image_size.height == out_->frame.image.rows) {
        std::vector<cv::Point2f> pts = m.corners;
        if (s.video.undistorted && !pts.empty()) shown_cal_.undistort_points(pts, pts);
        for (const auto& p : pts) cv.corners.push_back({p.x, p.y});
    }

    cv.image_w = m.views > 0 ? m.coverage_size.width : m.image_size.width;
    cv.image_h = m.views > 0 ? m.coverage_size.height : m.image_size.height;
    cv.grid_cols = m.grid_cols;
    cv.grid_rows = m.grid_rows;
    cv.coverage = m.coverage;
    cv.coverage_fraction = m.coverage_fraction;
    cv.corner_regions = m.corner_regions;

    cv.views = m.views;
    cv.min_views = m.min_views;
    cv.has_result = m.has_result;
    cv.rms_px = m.has_result ? m.rms_px : kUnknown;
    cv.fx = m.has_result ? m.camera.fx : kUnknown;
    cv.fy = m.has_result ? m.camera.fy : kUnknown;
    cv.cx = m.has_result ? m.camera.cx : kUnknown;
    cv.cy = m.has_result ? m.camera.cy : kUnknown;
    cv.dist = m.has_result ? m.camera.dist : std::array<double, 5>{};
    cv.result_error = m.active ? m.result_error : std::string{};
    cv.captures = m.captures;
    cv.last_capture_kept = m.last_capture_kept;
    cv.last_capture = m.last_capture;
    cv.saves = m.saves;
    cv.saved_path = m.saved_path;
    cv.save_error = m.save_error;
    cv.applied = !m.saved_path.empty() && calib_.origin == m.saved_path;
    const CameraCalibration& u = calib_.camera;
    std::snprintf(buf, sizeof buf, "fx %.1f fy %.1f cx %.1f cy %.1f k1 %.3f, %dx%d", u.fx, u.fy,
                  u.cx, u.cy, u.dist[0], u.width, u.height);
    cv.in_use = std::string(buf) + " (" + calib_.origin + ")";
}

}  // namespace gs::app

#endif  // GS_HAVE_GUI
