// The window's camera calibration mode (issue 8) on a replayed camera: the 11 real AR.Drone 2
// chessboard frames (rjw57, 9x6, 50 mm) as a dataset, stepped through the session; the
// Calibration window shows the board, K captures a view only when the board is found and adds
// coverage, "Calibrate, save and apply" writes the drone's calibration and the pipeline uses it
// at once; the undistortion preview then shows the board's lines straight. Real threads (session,
// calibration worker): waits are bounded polls, never sleeps standing in for logic.
#include "app/gui_adapter.hpp"
#include "app/session.hpp"
#include "calibration_dataset.hpp"
#include "drone/core/camera_calibration.hpp"
#include "session_fixture.hpp"
#include "support/wait.hpp"

#include <GLFW/glfw3.h>
#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>

namespace gs::ui::test {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

// The 9x6 board's corners in an image, sub-pixel (OpenCV directly: vision/calibration.hpp cannot
// share a translation unit with the session's classifier header).
std::vector<cv::Point2f> find_board(const cv::Mat& bgr) {
    std::vector<cv::Point2f> c;
    cv::Mat grey;
    cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
    if (!cv::findChessboardCorners(grey, {9, 6}, c,
                                   cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE))
        return {};
    cv::cornerSubPix(grey, c, {5, 5}, {-1, -1},
                     {cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 40, 0.01});
    return c;
}

// Largest distance (px) of a corner from the least-squares line through its row or column.
double max_line_deviation(const std::vector<cv::Point2f>& c) {
    double worst = 0;
    auto dev = [&](const std::vector<cv::Point2f>& pts) {
        cv::Vec4f l;
        cv::fitLine(pts, l, cv::DIST_L2, 0, 1e-6, 1e-6);
        for (const auto& p : pts)
            worst = std::max(
                worst, std::abs(static_cast<double>((p.x - l[2]) * l[1] - (p.y - l[3]) * l[0])));
    };
    std::vector<cv::Point2f> pts;
    for (int r = 0; r < 6; ++r) {
        pts.clear();
        for (int k = 0; k < 9; ++k) pts.push_back(c[static_cast<std::size_t>(r * 9 + k)]);
        dev(pts);
    }
    for (int k = 0; k < 9; ++k) {
        pts.clear();
        for (int r = 0; r < 6; ++r) pts.push_back(c[static_cast<std::size_t>(r * 9 + k)]);
        dev(pts);
    }
    return worst;
}

std::vector<cv::Point2f> to_cv(const std::vector<Point2f>& v) {
    std::vector<cv::Point2f> out;
    for (const auto& p : v) out.emplace_back(p.x, p.y);
    return out;
}

class CalibrationMode : public SessionFixture {
protected:
    void SetUp() override {
        SessionFixture::SetUp();
        frame_period = std::chrono::milliseconds(5);
        root = fs::temp_directory_path() / ("gs_calib_mode_" + std::to_string(::getpid()));
        fs::remove_all(root);
        dataset = root / "chessboard";
        calib_file = root / "config" / "calibration_front.json";
    }
    void TearDown() override {
        SessionFixture::TearDown();
        if (!std::getenv("GS_KEEP_TEST_OUTPUT")) fs::remove_all(root);
    }
    void start() {
        app::SessionOptions so;
        so.replay_autoplay = false;
        so.calibration_file = calib_file;
        so.calibration_interval_ms = 30;
        make_session(so);
        ASSERT_TRUE(session->request(app::OpenReplay{dataset.string()}));
    }
    // A left click on a button the window reported in its layout (press, then release).
    Actions click(const char* button) {
        const Rect* r = gui.view().layout.button(button);
        EXPECT_NE(r, nullptr) << button;
        if (!r) return {};
        ImGuiIO& io = ImGui::GetIO();
        io.MousePos = {0.5f * (r->x0 + r->x1), 0.5f * (r->y0 + r->y1)};
        step();  // hover
        io.MouseDown[0] = true;
        step();
        io.MouseDown[0] = false;
        const Actions a = step();
        io.MousePos = {-FLT_MAX, -FLT_MAX};
        return a;
    }
    static InputState key_k() {
        InputState in;
        in.keys.set(static_cast<std::size_t>(GLFW_KEY_K));
        return in;
    }
    // Shows dataset frame k and waits until the calibration worker has checked it.
    bool show_frame(std::int64_t k) {
        step({}, [&](Actions& a) { a.replay_seek = k; });
        return run_until([&] { return snap.video.index == k && snap.calibration.frame == k; }, 10s);
    }
    // K pressed for one frame, then released; waits for the worker's answer.
    bool capture_with_k() {
        const std::uint64_t before = snap.calibration.captures;
        const Actions a = step(key_k());
        EXPECT_TRUE(a.calibration_capture);
        step();
        return run_until([&] { return snap.calibration.captures == before + 1; }, 10s);
    }

    fs::path root, dataset, calib_file;
};

TEST_F(CalibrationMode, CapturesRealChessboardViewsCalibratesSavesAndAppliesAtOnce) {
    ASSERT_EQ(write_chessboard_dataset(dataset), "");
    start();
    ASSERT_TRUE(run_until([&] { return snap.replay.open; }, 10s))
        << (snap.messages.empty() ? "" : snap.messages.back().text);
    ASSERT_EQ(snap.replay.frame_count, kChessboardFrames + 1);

    // K does nothing while the Calibration window is closed.
    EXPECT_FALSE(step(key_k()).calibration_capture);
    step();
    // Opening the window starts the mode with the default board, 9x6 inner corners, 50 mm.
    gui.view().open.calibration = true;
    const Actions opened = step();
    ASSERT_TRUE(opened.calibration_start);
    EXPECT_EQ(opened.calibration_start->cols, 9);
    EXPECT_EQ(opened.calibration_start->rows, 6);
    EXPECT_DOUBLE_EQ(opened.calibration_start->square_m, 0.05);
    ASSERT_TRUE(run_until([&] { return snap.calibration.active; }, 5s));
    EXPECT_EQ(snap.calibration.save_path, calib_file.string());
    EXPECT_TRUE(gui.view().layout.calibration.drawn);

    int kept = 0;
    std::vector<bool> kept_frame;
    for (int k = 0; k <= kChessboardFrames; ++k) {
        ASSERT_TRUE(show_frame(k))
            << "frame " << k << " never checked: " << snap.calibration.status;
        const bool board = k < kChessboardFrames;
        EXPECT_EQ(snap.calibration.board_found, board) << k << ": " << snap.calibration.status;
        if (board) {
            // The detected corners are drawn over the video.
            EXPECT_EQ(snap.calibration.corners.size(), 54u) << k;
            step();
            EXPECT_EQ(gui.view().layout.calibration.corners_drawn, 54) << k;
        }
        const bool adds = snap.calibration.adds_coverage;
        ASSERT_TRUE(capture_with_k()) << k;
        EXPECT_EQ(snap.calibration.last_capture_kept, adds)
            << k << ": " << snap.calibration.last_capture;
        kept_frame.push_back(snap.calibration.last_capture_kept);
        if (snap.calibration.last_capture_kept) ++kept;
        if (!board) {
            EXPECT_NE(snap.calibration.last_capture.find("board not found"), std::string::npos)
                << snap.calibration.last_capture;
        } else if (!snap.calibration.last_capture_kept) {
            EXPECT_NE(snap.calibration.last_capture.find("adds no coverage"), std::string::npos)
                << snap.calibration.last_capture;
        }
        EXPECT_EQ(snap.calibration.views, kept);
        std::printf("frame %2d: %s | views %d, rms %.3f px, coverage %.0f %%\n", k,
                    snap.calibration.last_capture.c_str(), snap.calibration.views,
                    snap.calibration.rms_px, 100 * snap.calibration.coverage_fraction);
    }
    EXPECT_TRUE(kept_frame[0]) << "the first view with a board is always kept";
    ASSERT_GE(kept, 3) << "too few views adding coverage to calibrate";

    // The same view again adds nothing: refused.
    ASSERT_TRUE(show_frame(0));
    EXPECT_TRUE(snap.calibration.board_found);
    EXPECT_FALSE(snap.calibration.adds_coverage);
    ASSERT_TRUE(capture_with_k());
    EXPECT_FALSE(snap.calibration.last_capture_kept);
    EXPECT_EQ(snap.calibration.views, kept);

    // Coverage map and the running error.
    EXPECT_EQ(snap.calibration.grid_cols, 16);
    EXPECT_EQ(snap.calibration.grid_rows, 9);
    EXPECT_GT(snap.calibration.coverage_fraction, 0.2);
    EXPECT_TRUE(snap.calibration.has_result) << snap.calibration.result_error;
    EXPECT_LT(snap.calibration.rms_px, 0.5);
    EXPECT_GT(gui.view().layout.calibration.coverage_map.w(), 100.0f);

    // Nothing is applied yet: the pipeline uses the dataset's (deliberately wrong) calibration.
    auto in_use = session->calibration().latest();
    ASSERT_TRUE(in_use);
    EXPECT_DOUBLE_EQ(in_use->camera.fx, 500.0);
    EXPECT_FALSE(fs::exists(calib_file));

    // "Calibrate, save and apply".
    click("calibration.save");
    ASSERT_TRUE(run_until([&] { return snap.calibration.applied; }, 15s))
        << snap.calibration.save_error;
    EXPECT_EQ(snap.calibration.saved_path, calib_file.string());
    EXPECT_TRUE(snap.calibration.save_error.empty()) << snap.calibration.save_error;

    // The file is the drone's calibration, in the calibration file shape every reader takes.
    auto saved = load_calibration_file(calib_file);
    ASSERT_TRUE(saved) << saved.error().message;
    std::printf("saved: fx %.2f fy %.2f cx %.2f cy %.2f k1 %.4f (%d views)\n", saved->fx, saved->fy,
                saved->cx, saved->cy, saved->dist[0], kept);
    EXPECT_EQ(saved->width, 640);
    EXPECT_EQ(saved->height, 360);
    EXPECT_NEAR(saved->fx, 568.0, 12.0);  // SOURCES.md reference 567.6 from all 11 views
    EXPECT_NEAR(saved->fy, 566.0, 12.0);
    EXPECT_NEAR(saved->cx, 320.0, 12.0);
    EXPECT_NEAR(saved->cy, 178.0, 12.0);
    EXPECT_LT(saved->dist[0], -0.4);  // the AR.Drone's strong barrel
    // ... applied at once: the pipeline uses exactly these numbers.
    in_use = session->calibration().latest();
    ASSERT_TRUE(in_use);
    EXPECT_EQ(in_use->origin, calib_file.string());
    EXPECT_NEAR(in_use->camera.fx, saved->fx, 1e-6);
    EXPECT_NEAR(in_use->camera.cy, saved->cy, 1e-6);
    EXPECT_NEAR(in_use->camera.dist[0], saved->dist[0], 1e-9);
    bool said = false;
    for (const auto& m : snap.messages) said = said || m.text.find("calibration applied") == 0;
    EXPECT_TRUE(said);

    // Undistortion preview with the calibration just applied: the board's rows and columns come
    // out straight in the image itself (checked on the frame whose board bends most), and the
    // corner overlay is moved onto it.
    gui.view().settings.overlay.undistort = true;
    double bent = 0, straight = 0;
    int worst = -1;
    for (int k = 0; k < kChessboardFrames; ++k) {
        ASSERT_TRUE(show_frame(k));
        ASSERT_TRUE(run_until([&] { return snap.video.undistorted && snap.video.index == k; }, 5s))
            << snap.video.undistort_note;
        const auto raw = find_board(session->output().latest().value()->frame.image);
        const auto und = find_board(snap.video.bgr);
        ASSERT_EQ(raw.size(), 54u) << k;
        if (und.size() != 54u) continue;  // the barrel's periphery leaves the undistorted frame
        const double b = max_line_deviation(raw), u = max_line_deviation(und);
        std::printf("frame %2d board lines: raw %.2f px off straight, undistorted %.2f px\n", k, b,
                    u);
        if (b > bent) {
            bent = b;
            straight = u;
            worst = k;
        }
    }
    ASSERT_GE(worst, 0) << "no board found in any undistorted frame";
    EXPECT_GT(bent, 1.5) << "frame " << worst;
    EXPECT_LT(straight, 0.6) << "frame " << worst;
    EXPECT_LT(straight, bent / 3) << "frame " << worst;
    ASSERT_TRUE(show_frame(worst));
    ASSERT_TRUE(run_until([&] { return snap.video.undistorted && snap.video.index == worst; }, 5s));
    step();
    EXPECT_TRUE(gui.view().layout.undistorted);
    EXPECT_EQ(gui.view().layout.calibration.corners_drawn, 54);
    const std::vector<cv::Point2f> und = find_board(snap.video.bgr);
    ASSERT_EQ(und.size(), 54u);
    EXPECT_LT(max_line_deviation(to_cv(snap.calibration.corners)), 0.6)
        << "the overlay's corners should lie on straight lines too";
    ASSERT_EQ(snap.calibration.corners.size(), 54u);
    double err = 0;
    for (std::size_t i = 0; i < 54; ++i) {
        const double dx = static_cast<double>(snap.calibration.corners[i].x - und[i].x);
        const double dy = static_cast<double>(snap.calibration.corners[i].y - und[i].y);
        err = std::max(err, std::hypot(dx, dy));
    }
    EXPECT_LT(err, 2.0) << "overlay corners not where the board is in the undistorted image";
}

TEST_F(CalibrationMode, UndoResetAndBoardChangeRestart) {
    ASSERT_EQ(write_chessboard_dataset(dataset), "");
    start();
    ASSERT_TRUE(run_until([&] { return snap.replay.open; }, 10s));
    gui.view().open.calibration = true;
    ASSERT_TRUE(run_until([&] { return snap.calibration.active; }, 5s));
    ASSERT_TRUE(show_frame(0));
    ASSERT_TRUE(capture_with_k());
    ASSERT_TRUE(show_frame(5));
    ASSERT_TRUE(capture_with_k());
    ASSERT_EQ(snap.calibration.views, 2);
    step({}, [](Actions& a) { a.calibration_undo = true; });
    ASSERT_TRUE(run_until([&] { return snap.calibration.views == 1; }, 5s));
    step({}, [](Actions& a) { a.calibration_reset = true; });
    ASSERT_TRUE(run_until([&] { return snap.calibration.views == 0; }, 5s));
    // Save with too few views: a clear message, no file.
    step({}, [](Actions& a) { a.calibration_save = true; });
    ASSERT_TRUE(run_until([&] { return snap.calibration.saves == 1; }, 5s));
    EXPECT_FALSE(snap.calibration.save_error.empty());
    EXPECT_FALSE(fs::exists(calib_file));
    // A wrong board size: the board is "not found" and nothing can be captured.
    gui.view().calib.cols = 7;
    step();
    EXPECT_NE(gui.view().layout.button("calibration.capture"), nullptr);
    step({}, [](Actions& a) { a.calibration_start = Actions::CalibrationBoard{7, 6, 0.05}; });
    ASSERT_TRUE(run_until(
        [&] { return snap.calibration.board_cols == 7 && snap.calibration.frame == 5; }, 5s));
    EXPECT_FALSE(snap.calibration.board_found) << snap.calibration.status;
    EXPECT_NE(snap.calibration.status.find("7x6"), std::string::npos) << snap.calibration.status;
    // Closing the window stops the mode.
    gui.view().open.calibration = false;
    const Actions closed = step();
    EXPECT_TRUE(closed.calibration_stop);
    ASSERT_TRUE(run_until([&] { return !snap.calibration.active; }, 5s));
}

TEST_F(CalibrationMode, AutoCaptureKeepsOnlyViewsThatAddCoverage) {
    ASSERT_EQ(write_chessboard_dataset(dataset), "");
    start();
    ASSERT_TRUE(run_until([&] { return snap.replay.open; }, 10s));
    gui.view().open.calibration = true;
    gui.view().calib.auto_capture = true;
    const Actions a = step();
    ASSERT_TRUE(a.calibration_start);
    ASSERT_TRUE(a.calibration_auto.value_or(false));
    ASSERT_TRUE(
        run_until([&] { return snap.calibration.active && snap.calibration.auto_capture; }, 5s));
    ASSERT_TRUE(show_frame(0));
    ASSERT_TRUE(run_until([&] { return snap.calibration.views == 1; }, 5s))
        << snap.calibration.last_capture;
    EXPECT_NE(snap.calibration.last_capture.find("auto"), std::string::npos);
    const std::uint64_t captures = snap.calibration.captures;
    // The same frame again is checked but adds nothing: no second view. The check of a frame
    // and the auto capture it triggers are published together, so the snapshot that shows the
    // frame checked shows what auto capture did with it.
    ASSERT_TRUE(show_frame(11));  // no board
    ASSERT_TRUE(show_frame(0));
    EXPECT_TRUE(snap.calibration.board_found) << snap.calibration.status;
    EXPECT_FALSE(snap.calibration.adds_coverage) << snap.calibration.status;
    EXPECT_EQ(snap.calibration.captures, captures) << snap.calibration.last_capture;
    EXPECT_EQ(snap.calibration.views, 1);
}

}  // namespace
}  // namespace gs::ui::test
