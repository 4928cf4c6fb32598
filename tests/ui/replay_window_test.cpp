// The window replaying a flight: a flight past a pillar on the left is rendered with the virtual
// drone's renderer and stored as a dataset (frames/ + frames.csv + flight.json, docs/dataset.md);
// the obstacle pipeline finds the frames where it flags only the left region; the real program then
// replays the flight offscreen under Xvfb (lock-stepped: window frame k shows dataset frame k)
// and the screenshot's region bars must be red on the left and green elsewhere, as decided.
#include "app/pipeline.hpp"
#include "drone/core/camera_calibration.hpp"
#include "drone/dataset/dataset.hpp"
#include "drone/dataset/dataset_source.hpp"
#include "drone/dataset/video_frames.hpp"
#include "drone/sim/renderer.hpp"
#include "drone/sim/scenarios.hpp"
#include "offscreen_shot.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

namespace {

namespace fs = std::filesystem;
using namespace gs;
using namespace gs::ui::test;

constexpr double kFps = 30.0;
constexpr double kStartX = 2.5;  // m along the flight line (the pillar's near face is at 7 m)
constexpr int kFrames = 120;     // 4 s at 1 m/s: up to 0.5 m before the pillar's face

// Straight flight at 1 m altitude and 1 m/s along the start heading of thesis_pillar_left.
void write_flight(const fs::path& dir) {
    auto scene = sim::resolve_scene("thesis_pillar_left");
    ASSERT_TRUE(scene) << sim::to_string(scene.error());
    const CameraCalibration cal = builtin_calibration(CameraId::Front);
    auto r = sim::Renderer::create(*scene, cal, sim::CameraKind::Front);
    ASSERT_TRUE(r);
    fs::create_directories(dir / "frames");
    nlohmann::json fj = {
        {"format", "ardrone-dataset"},
        {"version", 1},
        {"camera", "front"},
        {"width", cal.width},
        {"height", cal.height},
        {"fps", kFps},
        {"frames", kFrames},
        {"images", "frames"},
        {"source", "rendered (test)"},
        {"calibration",
         {{"fx", cal.fx}, {"fy", cal.fy}, {"cx", cal.cx}, {"cy", cal.cy}, {"dist", cal.dist}}}};
    std::ofstream(dir / "flight.json") << fj.dump(2);
    std::ofstream csv(dir / "frames.csv");
    csv << "frame,t_ms,roll_deg,pitch_deg,yaw_deg,vx_mps,vy_mps,vz_mps,altitude_m\n";
    cv::Mat img;
    for (int i = 0; i < kFrames; ++i) {
        const double t = i / kFps;
        sim::Pose p;
        p.x_m = scene->start.x_m + kStartX + 1.0 * t;
        p.y_m = scene->start.y_m;
        p.z_m = 1.0;
        r->render(p, img);
        char name[32];
        std::snprintf(name, sizeof name, "%06d.png", i);
        ASSERT_TRUE(
            cv::imwrite((dir / "frames" / name).string(), img, {cv::IMWRITE_PNG_COMPRESSION, 1}));
        csv << i << ',' << t * 1000.0 << ",0,0,0,1,0,0,1\n";
    }
}

// Per frame: which regions the pipeline (the window's own classifier path) flags.
std::vector<std::array<bool, 3>> classify(const fs::path& dir) {
    std::vector<std::array<bool, 3>> out;
    auto ds = dataset::Dataset::open(dir);
    EXPECT_TRUE(ds) << (ds ? "" : to_string(ds.error()));
    if (!ds) return out;
    auto frames = dataset::open_frames(*ds);
    EXPECT_TRUE(frames);
    if (!frames) return out;
    app::ObstaclePipeline pipe(std::string(vision::kDefaultClassifier), ds->calibration());
    const CameraCalibration calib = ds->calibration();
    dataset::DatasetSource src(std::move(*ds), std::move(*frames), SteadyClock::instance(),
                               Pacing::fastest());
    FrameSample f;
    while (src.next(f) == SourceStatus::Sample) {
        const auto& res = pipe.process(f);
        out.push_back({res.regions[0].unsafe, res.regions[1].unsafe, res.regions[2].unsafe});
    }
    (void)calib;
    return out;
}

TEST(ReplayWindow, OffscreenReplayOfALeftPillarFlightShowsTheLeftBarRedAndTheOthersGreen) {
    const fs::path root =
        fs::temp_directory_path() / ("gs_replay_window_" + std::to_string(getpid()));
    fs::remove_all(root);
    const fs::path flight = root / "flight";
    write_flight(flight);
    if (HasFatalFailure()) return;

    const auto flags = classify(flight);
    ASSERT_EQ(flags.size(), static_cast<std::size_t>(kFrames));
    // The last frame flagging the left region only (the pillar passes on the left).
    int k = -1;
    int left_only = 0, any_left = 0;
    for (int i = 0; i < kFrames; ++i) {
        const auto& f = flags[static_cast<std::size_t>(i)];
        if (f[0]) ++any_left;
        if (f[0] && !f[1] && !f[2]) {
            ++left_only;
            k = i;
        }
    }
    ASSERT_GE(k, 0) << "the classifier never flagged only the left region on this flight";
    std::cout << "left only on " << left_only << " frames (left at all: " << any_left
              << "), last at frame " << k << '\n';
    EXPECT_GE(left_only, 5) << "a left flag on a pillar passing on the left should last";

    const fs::path out = root / "shots";
    const int n = k + 1;  // window frame k (0-based) shows dataset frame k
    const std::string cmd =
        under_xvfb(std::string(GS_BINARY) + " --offscreen --width 1280 --height 720 --replay " +
                   flight.string() + " --frames " + std::to_string(n) + " --out " + out.string());
    const Proc r = run_logged(cmd, root / "log.txt");
    ASSERT_EQ(r.code, 0) << cmd << "\n" << r.output;
    const Shot shot = read_shot(out, n);
    ASSERT_FALSE(shot.png.empty()) << r.output;
    expect_left_bar_red_others_green(shot, 20.0);
    if (!std::getenv("GS_KEEP_TEST_OUTPUT")) fs::remove_all(root);
}

}  // namespace
