// The calibration mode in the real program, offscreen under Xvfb: the 11 real chessboard frames
// replayed lock-stepped with the Calibration window open and auto capture on; the screenshot's
// JSON says the board corners were drawn over the video and views were kept with a running RMS,
// and the coverage map shows covered (green) cells. A second run with the undistortion preview
// shows the undistorted image. Set GS_KEEP_TEST_OUTPUT=1 to keep the PNGs (their folder is
// printed).
#include "calibration_dataset.hpp"
#include "offscreen_shot.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace gs::ui::test {
namespace {

namespace fs = std::filesystem;

Shot offscreen(const fs::path& dataset, const fs::path& out, const std::string& extra, int frames,
               std::string& output) {
    const std::string cmd =
        under_xvfb(std::string(GS_BINARY) + " --offscreen --width 1600 --height 900 --replay " +
                   dataset.string() + " --frames " + std::to_string(frames) + " --out " +
                   out.string() + " " + extra);
    const Proc r = run_logged(cmd, out.parent_path() / (out.filename().string() + ".log"));
    output = r.output;
    EXPECT_EQ(r.code, 0) << cmd << "\n" << output;
    return read_shot(out, frames);
}

TEST(CalibrationOffscreen, AutoCaptureOnRealChessboardFramesShowsBoardCoverageAndError) {
    const fs::path root =
        fs::temp_directory_path() / ("gs_calib_offscreen_" + std::to_string(getpid()));
    fs::remove_all(root);
    const fs::path dataset = root / "chessboard";
    ChessboardDatasetOptions o;
    o.add_empty_frame = false;
    ASSERT_EQ(write_chessboard_dataset(dataset, o), "");

    // Window frame k shows dataset frame k: the last screenshot is frame 10, all 11 checked.
    std::string output;
    const Shot s = offscreen(dataset, root / "shots", "--auto-capture", kChessboardFrames, output);
    ASSERT_FALSE(s.png.empty()) << output;
    ASSERT_TRUE(s.layout.is_object()) << output;
    const auto& c = s.layout.at("calibration");
    EXPECT_TRUE(c.at("drawn").get<bool>());
    EXPECT_EQ(c.at("corners_drawn").get<int>(), 54) << c.dump();
    const int views = c.at("views").get<int>();
    EXPECT_GE(views, 3) << c.dump();
    ASSERT_TRUE(c.at("rms_px").is_number()) << c.dump();
    EXPECT_LT(c.at("rms_px").get<double>(), 0.5);
    EXPECT_NE(c.at("status").get<std::string>().find("board found"), std::string::npos) << c.dump();
    std::cout << "calibration window: " << c.dump() << '\n';

    // Covered cells are tinted green in the coverage map.
    const auto m = c.at("coverage_map");
    const int x0 = m[0].get<int>(), y0 = m[1].get<int>(), x1 = m[2].get<int>(),
              y1 = m[3].get<int>();
    ASSERT_GT(x1 - x0, 100);
    ASSERT_GT(y1 - y0, 50);
    int green = 0, total = 0;
    for (int y = y0 + 2; y < y1 - 2; y += 3)
        for (int x = x0 + 2; x < x1 - 2; x += 3) {
            const cv::Vec3b p = s.png.at<cv::Vec3b>(y, x);  // BGR
            ++total;
            if (p[1] > p[2] + 30 && p[1] > p[0] + 10) ++green;
        }
    std::cout << "coverage map: " << green << " of " << total << " samples green\n";
    EXPECT_GT(green, total / 10) << "coverage map shows no covered cells";

    // The undistortion preview (with the dataset's calibration: here fx 500 without distortion
    // the remap is the identity, so check the flag the window reports and that it drew).
    const Shot u = offscreen(dataset, root / "shots_undistorted", "--undistort-preview", 2, output);
    ASSERT_TRUE(u.layout.is_object()) << output;
    EXPECT_TRUE(u.layout.at("undistorted").get<bool>());

    if (std::getenv("GS_KEEP_TEST_OUTPUT"))
        std::cout << "screenshots kept in " << root << '\n';
    else
        fs::remove_all(root);
}

TEST(CalibrationOffscreen, UndistortionPreviewStraightensTheBoardOfARealFrame) {
    const fs::path root =
        fs::temp_directory_path() / ("gs_calib_undist_" + std::to_string(getpid()));
    fs::remove_all(root);
    const fs::path dataset = root / "chessboard";
    // The dataset carries the calibration the window's calibration mode computes from these
    // frames (CalibrationMode.CapturesRealChessboardViews...: 8 views, RMS 0.17 px), so the
    // preview removes the strong barrel (the straightness itself is measured in that test).
    ChessboardDatasetOptions o;
    o.add_empty_frame = false;
    CameraCalibration& cal = o.calibration;
    cal.fx = 569.39;
    cal.fy = 567.65;
    cal.cx = 320.92;
    cal.cy = 176.33;
    cal.dist = {-0.5525, 0.4121, -0.0005, 0.0, -0.1494};
    ASSERT_EQ(write_chessboard_dataset(dataset, o), "");
    std::string output;
    const Shot u =
        offscreen(dataset, root / "shots", "--undistort-preview --calibration-window", 4, output);
    ASSERT_FALSE(u.png.empty()) << output;
    EXPECT_TRUE(u.layout.at("undistorted").get<bool>());
    EXPECT_EQ(u.layout.at("calibration").at("corners_drawn").get<int>(), 54);
    if (std::getenv("GS_KEEP_TEST_OUTPUT"))
        std::cout << "screenshots kept in " << root << '\n';
    else
        fs::remove_all(root);
}

}  // namespace
}  // namespace gs::ui::test
