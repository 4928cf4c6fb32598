// The real binary renders the window offscreen under Xvfb (Mesa software GL); the PNG is checked
// pixel by pixel at the rectangles the window reports in the JSON beside it. No X server = FAIL.
#include "offscreen_shot.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace gs::ui::test {
namespace {

namespace fs = std::filesystem;

fs::path temp_dir(const std::string& name) {
    const fs::path d = fs::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

cv::Vec3b pixel(const cv::Mat& img, double x, double y) {
    return img.at<cv::Vec3b>(static_cast<int>(y), static_cast<int>(x));  // BGR
}

TEST(Offscreen, DemoScreenshotShowsLeftRegionRedOthersGreenAndTheBattery) {
    const fs::path out = temp_dir("gs_ui_offscreen");
    const std::string cmd =
        under_xvfb(std::string(GS_BINARY) +
                   " --offscreen --demo --frames 6 --screenshot-every 3 --out " + out.string());
    const Proc r = run_logged(cmd, out / "log.txt");
    ASSERT_EQ(r.code, 0) << "offscreen render under xvfb-run failed (is Xvfb installed and can it "
                            "start?):\n"
                         << cmd << "\n"
                         << r.output;
    ASSERT_TRUE(fs::exists(out / "frame_000003.png")) << r.output;
    const Shot shot = read_shot(out, 6);
    const cv::Mat& img = shot.png;
    ASSERT_FALSE(img.empty()) << out / "frame_000006.png";
    EXPECT_EQ(img.cols, 1600);
    EXPECT_EQ(img.rows, 900);
    const nlohmann::json& layout = shot.layout;
    expect_left_bar_red_others_green(shot, 50.0);
    const auto& bars = layout.at("region_bars");
    ASSERT_EQ(bars.size(), 3u);
    // Left bar is left of the others and inside the image.
    const auto img_rect = layout.at("video_image");
    EXPECT_NEAR(bars[0].at("rect")[0].get<double>(), img_rect[0].get<double>(), 2.0);

    // Battery gauge: 67 % (the demo navdata) fills 67 % of the gauge with the "good" colour and
    // leaves the rest dark.
    const auto bat = layout.at("battery");
    EXPECT_EQ(bat.at("text"), "67%");
    const auto o = bat.at("outline"), f = bat.at("fill");
    const double inner = o[2].get<double>() - o[0].get<double>() - 4.0;
    const double fill_w = f[2].get<double>() - f[0].get<double>();
    EXPECT_NEAR(fill_w / inner, 0.67, 0.01);
    const double my = 0.5 * (f[1].get<double>() + f[3].get<double>());
    const cv::Vec3b in_fill = pixel(img, f[0].get<double>() + fill_w * 0.5, my);
    EXPECT_GT(in_fill[1], 170);  // green (70, 200, 100)
    EXPECT_LT(in_fill[2], 110);
    const cv::Vec3b past_fill =
        pixel(img, f[2].get<double>() + 0.5 * (o[2].get<double>() - 2 - f[2].get<double>()), my);
    EXPECT_LT(past_fill[1], 80) << "gauge beyond 67% should be empty";
    fs::remove_all(out);
}

TEST(Offscreen, WithoutADisplayTheProgramSaysSoInsteadOfCrashing) {
    const fs::path out = temp_dir("gs_ui_nodisplay");
    const Proc r =
        run_logged(std::string("env -u DISPLAY -u WAYLAND_DISPLAY ") + GS_BINARY, out / "log.txt");
    EXPECT_EQ(r.code, 3) << r.output;
    EXPECT_NE(r.output.find("no display"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("--help"), std::string::npos) << r.output;
    fs::remove_all(out);
}

// `ardrone-gs --help` lists the window's options, the demo mode among them.
TEST(Offscreen, HelpListsTheWindowOptionsWithTheDemo) {
    const fs::path out = temp_dir("gs_ui_help");
    const Proc r = run_logged(std::string(GS_BINARY) + " --help", out / "log.txt");
    EXPECT_EQ(r.code, 0) << r.output;
    for (const char* opt : {"--demo", "--offscreen", "--sim", "--replay", "--camera", "--frames",
                            "--screenshot-every", "--out"})
        EXPECT_NE(r.output.find(opt), std::string::npos) << opt << " missing from:\n" << r.output;
    fs::remove_all(out);
}

}  // namespace
}  // namespace gs::ui::test
