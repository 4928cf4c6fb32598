// Chessboard calibration on 11 real AR.Drone 2 front-camera frames (rjw57, 9×6 board, 50 mm
// squares; SOURCES.md reference: rms 0.20 px, fx 567.6, fy 565.9, cx 320.2, cy 178.2), the
// straightness of undistorted board lines, coverage, outlier rejection and bad input.
#include "vision/calibration.hpp"
#include "drone/core/camera_calibration.hpp"
#include "vision/undistort.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

namespace {

using namespace gs::vision;
using gs::CalibrationInfo;
using gs::CameraCalibration;
using gs::load_calibration_document;
using gs::save_calibration_file;

const BoardSpec kBoard{9, 6, 0.05};
constexpr int kFrames = 11;

std::string frame_path(int i) {
    char name[32];
    std::snprintf(name, sizeof name, "frame%04d.jpg", i);
    return std::string(GS_FIXTURES_DIR) + "/real/calibration/rjw57_ardrone2_front_chessboard/" +
           name;
}

cv::Mat load_frame(int i) {
    cv::Mat m = cv::imread(frame_path(i), cv::IMREAD_COLOR);
    EXPECT_FALSE(m.empty()) << frame_path(i);
    return m;
}

// Detected once for the whole suite (each detection is ~20 ms, but many tests need them).
const std::vector<std::vector<cv::Point2f>>& real_views() {
    static const std::vector<std::vector<cv::Point2f>> views = [] {
        std::vector<std::vector<cv::Point2f>> v;
        for (int i = 0; i < kFrames; ++i) {
            const BoardDetection d = detect_board(load_frame(i), kBoard);
            if (d.found()) v.push_back(d.corners);
        }
        return v;
    }();
    return views;
}

const CalibrationResult& real_result() {
    static const CalibrationResult r = [] {
        auto c = calibrate_views(real_views(), kBoard, {640, 360});
        EXPECT_TRUE(c.has_value()) << c.error().message();
        return c ? *c : CalibrationResult{};
    }();
    return r;
}

TEST(BoardSize, ParsesColsByRows) {
    ASSERT_TRUE(parse_board_size("9x6"));
    EXPECT_EQ(*parse_board_size("9x6"), cv::Size(9, 6));
    EXPECT_EQ(*parse_board_size("7X5"), cv::Size(7, 5));
    EXPECT_FALSE(parse_board_size("9"));
    EXPECT_FALSE(parse_board_size("9x"));
    EXPECT_FALSE(parse_board_size("x6"));
    EXPECT_FALSE(parse_board_size("2x6"));  // OpenCV needs more than 2 corners per side
    EXPECT_FALSE(parse_board_size("9x6x2"));
    EXPECT_FALSE(parse_board_size("-9x6"));
    EXPECT_FALSE(parse_board_size("1000x6"));
}

TEST(DetectBoard, FindsTheBoardInEveryRealFrame) {
    for (int i = 0; i < kFrames; ++i) {
        const BoardDetection d = detect_board(load_frame(i), kBoard);
        EXPECT_TRUE(d.found()) << i << ": " << to_string(d.status);
        EXPECT_EQ(d.corners.size(), 54U);
        EXPECT_EQ(d.image_size, cv::Size(640, 360));
        // estimateChessboardSharpness: the frames are sharp (edge width ~2-3.4 px).
        EXPECT_GT(d.sharpness_px, 1.0);
        EXPECT_LT(d.sharpness_px, 4.0);
    }
}

TEST(Calibrate, RealFramesMatchTheReference) {
    ASSERT_EQ(real_views().size(), static_cast<std::size_t>(kFrames));
    const CalibrationResult& r = real_result();
    const CameraCalibration& c = r.camera;
    EXPECT_EQ(c.width, 640);
    EXPECT_EQ(c.height, 360);
    EXPECT_GT(r.rms_px, 0.1);
    EXPECT_LT(r.rms_px, 0.3);
    EXPECT_NEAR(c.fx, 567.6, 5.0);
    EXPECT_NEAR(c.fy, 565.9, 5.0);
    EXPECT_NEAR(c.cx, 320.2, 5.0);
    EXPECT_NEAR(c.cy, 178.2, 5.0);
    EXPECT_NEAR(c.dist[0], -0.552, 0.03);  // strong barrel, as every published front calibration
    // All 11 views are good: none rejected, all used.
    EXPECT_TRUE(r.rejected.empty());
    EXPECT_EQ(r.used_views(), kFrames);
    for (int i = 0; i < kFrames; ++i) {
        EXPECT_LT(r.view_rms_px[static_cast<std::size_t>(i)], 0.5) << i;
    }
    // Uncertainty: finite, positive, and a focal length known to about a pixel.
    for (double s : r.std_dev) {
        EXPECT_TRUE(std::isfinite(s));
        EXPECT_GT(s, 0.0);
    }
    EXPECT_LT(r.std_dev[0], 3.0);
    EXPECT_LT(r.std_dev[2], 5.0);
}

TEST(Calibrate, UndistortedBoardLinesAreStraight) {
    const CalibrationResult& r = real_result();
    double worst_raw = 0, worst_undist = 0;
    for (const auto& v : real_views()) {
        const double raw = max_line_deviation_px(v, kBoard);
        const double und = max_line_deviation_px(undistort_corners(v, r.camera), kBoard);
        worst_raw = std::max(worst_raw, raw);
        worst_undist = std::max(worst_undist, und);
        EXPECT_LT(und, 0.6);
    }
    // The barrel bends the raw rows/columns (these boards stay within 0.71 of the half-diagonal,
    // so by a few pixels); the model takes that out down to corner noise.
    EXPECT_GT(worst_raw, 1.5);
    EXPECT_GT(worst_raw, 4 * worst_undist);
    EXPECT_LT(worst_undist, 0.6);
    std::printf("line deviation: raw max %.2f px, undistorted max %.2f px\n", worst_raw,
                worst_undist);
}

TEST(Undistorter, RemappedImageHasStraightBoardLines) {
    const CalibrationResult& r = real_result();
    Undistorter u(r.camera);
    int checked = 0;
    double worst = 0;
    for (int i = 0; i < kFrames; ++i) {
        const cv::Mat& out = u.apply(load_frame(i));
        ASSERT_EQ(out.size(), cv::Size(640, 360));
        // A board is detected again in the undistorted image where it was not cropped away.
        const BoardDetection d = detect_board(out, kBoard);
        if (!d.found()) continue;
        ++checked;
        worst = std::max(worst, max_line_deviation_px(d.corners, kBoard));
    }
    EXPECT_GE(checked, 8);
    EXPECT_LT(worst, 0.8);  // detection on a resampled image, a little noisier than the points
    EXPECT_EQ(u.map_builds(), 1);  // one map for all frames of one size
    std::printf("undistorted images: %d boards, max line deviation %.2f px\n", checked, worst);
}

TEST(Undistorter, RebuildsMapsOnlyWhenSomethingChanges) {
    CameraCalibration cal = real_result().camera;
    Undistorter u(cal);
    const cv::Mat img = load_frame(0);
    (void)u.apply(img);
    (void)u.apply(img);
    EXPECT_EQ(u.map_builds(), 1);
    cv::Mat half;
    cv::resize(img, half, {320, 180});
    EXPECT_EQ(u.apply(half).size(), cv::Size(320, 180));
    EXPECT_EQ(u.map_builds(), 2);
    u.set_view(UndistortView::ValidPixels);
    (void)u.apply(img);
    EXPECT_EQ(u.map_builds(), 3);
    // Barrel distortion: the undistorted frame is larger than the raw one, so showing every valid
    // pixel zooms out. ROS's rectified P matrices for AR.Drone 2 front calibrations (alpha 0,
    // docs/protocol.md §6.2) have fx 459-474.
    const double valid_fx = u.output_camera_matrix()(0, 0);
    EXPECT_GT(valid_fx, 430.0);
    EXPECT_LT(valid_fx, 500.0);
    u.set_view(UndistortView::AllPixels);
    (void)u.apply(img);
    EXPECT_LT(u.output_camera_matrix()(0, 0), valid_fx);
    std::printf("output fx: same %.1f, valid pixels %.1f, all pixels %.1f\n", cal.fx, valid_fx,
                u.output_camera_matrix()(0, 0));
    EXPECT_TRUE(u.apply(cv::Mat()).empty());
    EXPECT_TRUE(Undistorter(CameraCalibration{}).apply(img).empty());
}

TEST(Calibrate, RejectsAViewWhoseErrorStandsOut) {
    std::vector<std::vector<cv::Point2f>> views = real_views();
    ASSERT_EQ(views.size(), static_cast<std::size_t>(kFrames));
    // View 4 gets a misdetection: every other corner shifted by 3 px (a board that moved during
    // the exposure, or corners snapped to the wrong edge).
    for (std::size_t i = 0; i < views[4].size(); i += 2) views[4][i] += cv::Point2f(3.f, -2.f);
    auto r = calibrate_views(views, kBoard, {640, 360});
    ASSERT_TRUE(r) << r.error().message();
    ASSERT_EQ(r->rejected.size(), 1U);
    EXPECT_EQ(r->rejected[0], 4);
    EXPECT_FALSE(r->view_used[4]);
    EXPECT_EQ(r->used_views(), kFrames - 1);
    EXPECT_GT(r->view_rms_px[4], 1.0);  // re-posed against the final model: still far off
    EXPECT_LT(r->rms_px, 0.3);
    EXPECT_NEAR(r->camera.fx, real_result().camera.fx, 2.0);
    EXPECT_NEAR(r->camera.cy, real_result().camera.cy, 2.0);
    // Without rejection the bad view drags the error up.
    CalibrationOptions keep_all;
    keep_all.max_rejected_fraction = 0;
    auto all = calibrate_views(views, kBoard, {640, 360}, keep_all);
    ASSERT_TRUE(all);
    EXPECT_TRUE(all->rejected.empty());
    EXPECT_GT(all->rms_px, 2 * r->rms_px);
}

TEST(Calibrate, TooFewViewsIsAnError) {
    const auto& v = real_views();
    ASSERT_GE(v.size(), 2U);
    std::vector<std::vector<cv::Point2f>> two(v.begin(), v.begin() + 2);
    auto r = calibrate_views(two, kBoard, {640, 360});
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().kind, CalibrationErrorKind::TooFewViews);
    auto none = calibrate_views({}, kBoard, {640, 360});
    ASSERT_FALSE(none);
    EXPECT_EQ(none.error().kind, CalibrationErrorKind::TooFewViews);
}

TEST(Calibrate, CornerCountMustMatchTheBoard) {
    auto r = calibrate_views(real_views(), BoardSpec{8, 6, 0.05}, {640, 360});
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().kind, CalibrationErrorKind::BadBoardSpec);
    auto bad_square = calibrate_views(real_views(), BoardSpec{9, 6, 0.0}, {640, 360});
    ASSERT_FALSE(bad_square);
    EXPECT_EQ(bad_square.error().kind, CalibrationErrorKind::BadBoardSpec);
}

TEST(DetectBoard, WrongBoardSizeIsNotFound) {
    const cv::Mat img = load_frame(0);
    for (const BoardSpec b :
         {BoardSpec{7, 7, 0.05}, BoardSpec{10, 6, 0.05}, BoardSpec{9, 5, 0.05}}) {
        const BoardDetection d = detect_board(img, b);
        EXPECT_EQ(d.status, DetectStatus::NotFound) << b.cols << "x" << b.rows;
        EXPECT_TRUE(d.corners.empty());
    }
}

TEST(DetectBoard, PartialBoardIsNotFound) {
    const cv::Mat img = load_frame(0);
    const BoardDetection full = detect_board(img, kBoard);
    ASSERT_TRUE(full.found());
    // Cut the image through the middle of the board.
    float minx = 1e9f, maxx = 0;
    for (const auto& p : full.corners) {
        minx = std::min(minx, p.x);
        maxx = std::max(maxx, p.x);
    }
    const int cut = static_cast<int>((minx + maxx) / 2);
    const cv::Mat left = img(cv::Rect(0, 0, cut, img.rows)).clone();
    EXPECT_EQ(detect_board(left, kBoard).status, DetectStatus::NotFound);
}

TEST(DetectBoard, BlurryBoardIsRefused) {
    const cv::Mat img = load_frame(0);
    cv::Mat blurred;
    cv::GaussianBlur(img, blurred, cv::Size(0, 0), 3.0);
    const BoardDetection d = detect_board(blurred, kBoard);
    // Still found, but its edges are ~8 px wide (sharp frames: 1.8-3.4 px): refused as blurry.
    EXPECT_EQ(d.status, DetectStatus::Blurry) << "sharpness " << d.sharpness_px;
    EXPECT_GT(d.sharpness_px, DetectOptions{}.max_blur_px);
    EXPECT_EQ(d.corners.size(), 54U);  // kept for display
    std::printf("blurred frame: %s, sharpness %.2f px\n", to_string(d.status), d.sharpness_px);
}

TEST(DetectBoard, EmptyAndBlankImages) {
    EXPECT_EQ(detect_board(cv::Mat(), kBoard).status, DetectStatus::EmptyImage);
    EXPECT_EQ(detect_board(cv::Mat(360, 640, CV_8UC1, cv::Scalar(128)), kBoard).status,
              DetectStatus::NotFound);
    DetectOptions sb;
    sb.sb_fallback = true;
    EXPECT_EQ(detect_board(cv::Mat(360, 640, CV_8UC3, cv::Scalar(0, 0, 0)), kBoard, sb).status,
              DetectStatus::NotFound);
}

TEST(Coverage, CountsCellsWhoseCentreIsInsideTheBoard) {
    CoverageMap m({640, 360}, 16, 9);  // 40×40 px cells, centres at 20, 60, ...
    // A board whose hull is (almost) the top-left quarter: centres x 20..300 (8), y 20..140 (4).
    const std::vector<cv::Point2f> tl{{0, 0}, {319, 0}, {319, 179}, {0, 179}};
    EXPECT_EQ(m.new_cells(tl), 32);
    m.add(tl);
    EXPECT_DOUBLE_EQ(m.fraction(), 32.0 / 144.0);
    EXPECT_EQ(m.corner_regions_covered(), 1);
    EXPECT_EQ(m.count(0, 0), 1);
    EXPECT_EQ(m.count(8, 0), 0);
    EXPECT_EQ(m.new_cells(tl), 0);  // the same view again adds nothing
    // The board reached the image corner: radius fraction 1.
    EXPECT_DOUBLE_EQ(m.max_radius_fraction(), 1.0);
    // A central board overlapping it: centres x 260..380 (4) × y 100..260 (5, the boundary
    // counts) = 20 cells, of which x 260, 300 × y 100, 140 are already covered.
    const std::vector<cv::Point2f> mid{{240, 100}, {400, 100}, {400, 260}, {240, 260}};
    EXPECT_EQ(m.new_cells(mid), 16);
    m.add(mid);
    EXPECT_DOUBLE_EQ(m.fraction(), 48.0 / 144.0);
    EXPECT_EQ(m.corner_regions_covered(), 1);  // the middle is no corner
    const std::vector<cv::Point2f> all{{0, 0}, {640, 0}, {640, 360}, {0, 360}};
    m.add(all);
    EXPECT_DOUBLE_EQ(m.fraction(), 1.0);
    EXPECT_EQ(m.corner_regions_covered(), 4);
    EXPECT_EQ(m.views(), 3);
}

TEST(Coverage, RealFramesReport) {
    const CoverageMap& c = real_result().coverage;
    EXPECT_EQ(c.views(), kFrames);
    // The rjw57 boards sit mostly in the middle of the frame: they cover part of the grid, and
    // not all four corners (a reason to offer the coverage map to the user).
    EXPECT_GT(c.fraction(), 0.2);
    EXPECT_LT(c.fraction(), 1.0);
    EXPECT_GT(c.max_radius_fraction(), 0.5);
    EXPECT_LE(c.max_radius_fraction(), 1.0);
    std::printf("rjw57 coverage: %.0f %% of cells, %d/4 corner regions, radius %.2f\n",
                100 * c.fraction(), c.corner_regions_covered(), c.max_radius_fraction());
}

TEST(CalibrationSession, AddsFramesKeepsCoverageAndRecalibrates) {
    CalibrationSession s(kBoard);
    EXPECT_TRUE(std::isnan(s.rms_px()));
    const ViewResult first = s.add_frame(load_frame(0));
    EXPECT_TRUE(first.accepted());
    EXPECT_GT(first.new_cells, 0);
    for (int i = 1; i < 3; ++i) {
        const ViewResult f = s.add_frame(load_frame(i), /*require_new_coverage=*/false);
        EXPECT_EQ(f.status, FrameStatus::Accepted) << i << ": " << to_string(f.status);
        EXPECT_EQ(f.detection.corners.size(), 54U);
    }
    ASSERT_TRUE(s.result()) << (s.last_error() ? s.last_error()->message() : "");
    EXPECT_LT(s.rms_px(), 0.5);
    EXPECT_GT(s.coverage().fraction(), 0.0);
    // The same frame again covers nothing new.
    const ViewResult again = s.add_frame(load_frame(0));
    EXPECT_EQ(again.status, FrameStatus::NoNewCoverage);
    EXPECT_EQ(again.new_cells, 0);
    EXPECT_EQ(s.view_count(), 3U);
    // check() keeps nothing.
    const ViewResult peek = s.check(load_frame(5));
    EXPECT_TRUE(peek.accepted());
    EXPECT_EQ(s.view_count(), 3U);
    // ... and its detection can be added without detecting again.
    EXPECT_TRUE(s.add_detection(peek.detection, false).accepted());
    EXPECT_EQ(s.view_count(), 4U);
    for (int i = 6; i < kFrames; ++i) (void)s.add_frame(load_frame(i), false);
    ASSERT_TRUE(s.result());
    EXPECT_NEAR(s.result()->camera.fx, 567.6, 8.0);
    s.remove_last_view();
    EXPECT_EQ(s.view_count(), 8U);
    EXPECT_EQ(s.coverage().views(), 8);
}

TEST(CalibrationSession, RefusesAFrameOfAnotherSize) {
    CalibrationSession s(kBoard);
    ASSERT_TRUE(s.add_frame(load_frame(0)).accepted());
    cv::Mat small;
    cv::resize(load_frame(1), small, {320, 180});
    const ViewResult f = s.add_frame(small);
    EXPECT_EQ(f.status, FrameStatus::SizeMismatch);
    EXPECT_EQ(s.view_count(), 1U);
}

TEST(CalibrationSession, SaveNeedsACalibration) {
    CalibrationSession s(kBoard);
    const std::string path = "/tmp/gs_calib_session_unsaved.json";
    std::remove(path.c_str());
    auto r = s.save(path);
    ASSERT_FALSE(r);
    EXPECT_EQ(r.error().kind, CalibrationErrorKind::TooFewViews);
    EXPECT_FALSE(std::ifstream(path).good());
}

TEST(CalibrationFile, RoundTripsThroughJson) {
    const CalibrationResult& r = real_result();
    CalibrationInfo info = r.info();
    info.camera = "front";
    CameraCalibration camera = r.camera;
    camera.source = "test";
    const std::string path = "/tmp/gs_calib_roundtrip.json";
    ASSERT_TRUE(save_calibration_file(path, camera, info));
    auto back = load_calibration_document(path);
    ASSERT_TRUE(back) << to_string(back.error());
    EXPECT_EQ(back->camera.width, 640);
    EXPECT_EQ(back->camera.height, 360);
    EXPECT_DOUBLE_EQ(back->camera.fx, r.camera.fx);
    EXPECT_DOUBLE_EQ(back->camera.cy, r.camera.cy);
    for (std::size_t i = 0; i < 5; ++i) EXPECT_DOUBLE_EQ(back->camera.dist[i], r.camera.dist[i]);
    EXPECT_DOUBLE_EQ(back->info.rms_px, r.rms_px);
    EXPECT_DOUBLE_EQ(back->info.std_dev[0], r.std_dev[0]);
    EXPECT_DOUBLE_EQ(back->info.std_dev[8], r.std_dev[8]);
    EXPECT_EQ(back->info.views, kFrames);
    EXPECT_EQ(back->info.camera, "front");
    EXPECT_EQ(back->camera.source, "test");
    std::remove(path.c_str());
}

TEST(CalibrationFile, PublishedCalibrationsAgreeWithOurs) {
    // The five front YAMLs of SOURCES.md agree on fx 560-570; ours must land in that family.
    const CalibrationResult& r = real_result();
    EXPECT_GT(r.camera.fx, 560.0);
    EXPECT_LT(r.camera.fx, 575.0);
}

}  // namespace
