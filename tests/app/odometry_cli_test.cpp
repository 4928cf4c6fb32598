// `ardrone-gs odometry` run as a process (GS_BINARY) on a short generated translation flight (the
// thesis' §5.1.2 translation test, 10 s of it): two cameras and the bottom camera alone must beat
// the thesis' per-sample mean absolute errors (table 6.2) and stay under 2 % end-point error; the
// outputs are the files the README names. Plus the refusals.
#include "cli_test_util.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

namespace fs = std::filesystem;
using gs::test::CmdResult;
using gs::test::read_text;
using gs::test::run_cli;
using gs::test::scratch_dir;

// Thesis table 6.2 (translation test), mean absolute error per sample.
constexpr double kThesisX_cm = 0.3671;
constexpr double kThesisY_cm = 0.4170;
constexpr double kThesisRot_deg = 0.1247;

nlohmann::json summary(const fs::path& out) {
    return nlohmann::json::parse(read_text(out / "summary.json"));
}

// Removes a scratch directory, and its per-process parent once empty.
void remove_scratch(const fs::path& dir) {
    std::error_code ec;
    fs::remove_all(dir, ec);
    fs::remove(dir.parent_path(), ec);  // only if empty
}

void expect_beats_thesis(const nlohmann::json& j) {
    EXPECT_EQ(j["invalid"].get<int>(), 0);
    EXPECT_LT(j["x_cm"]["mean"].get<double>(), kThesisX_cm);
    EXPECT_LT(j["y_cm"]["mean"].get<double>(), kThesisY_cm);
    EXPECT_LT(j["rotation_deg"]["mean"].get<double>(), kThesisRot_deg);
    EXPECT_GT(j["distance_travelled_m"].get<double>(), 1.0);
    EXPECT_LT(j["end_error_pct"].get<double>(), 2.0);
}

TEST(OdometryCli, ShortTranslationFlightBeatsTheThesis) {
    const fs::path root = scratch_dir("odometry_cli", "translation");
    const fs::path data = root / "flight", out2 = root / "two", out1 = root / "single";
    // 10 s at 15 fps: 1 s still, then 1.5 m of the first 1.6 m leg (with the hand-held wobble).
    CmdResult r =
        run_cli("odometry " + data.string() +
                " --generate translation --duration 10 --seed 1 --summary --out " + out2.string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_NE(r.out.find("generated translation (seed 1): 151 frames"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("two cameras (bottom + top)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("Rotation Axis"), std::string::npos) << r.out;
    // The two-camera layout the README documents.
    for (const char* f : {"flight.json", "frames.csv", "distances.csv", "top.json",
                          "frames/000150.jpg", "top/000150.jpg"})
        EXPECT_TRUE(fs::exists(data / f)) << f;
    EXPECT_EQ(read_text(data / "distances.csv").substr(0, 21), "frame,bottom_m,top_m\n");
    const nlohmann::json two = summary(out2);
    EXPECT_EQ(two["cameras"].get<int>(), 2);
    EXPECT_EQ(two["samples"].get<int>(), 151);
    EXPECT_EQ(two["x_cm"]["n"].get<int>(), 150);
    expect_beats_thesis(two);
    EXPECT_TRUE(fs::exists(out2 / "errors.txt"));
    const std::string csv = read_text(out2 / "samples.csv");
    EXPECT_EQ(csv.substr(0, 30), "frame,t_ms,valid,bottom_status");
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 152);  // header + 151 samples

    // The bottom camera alone on the same flight (the AR.Drone's case).
    r = run_cli("odometry " + data.string() + " --single --summary --out " + out1.string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_NE(r.out.find("single camera (bottom + altitude)"), std::string::npos) << r.out;
    const nlohmann::json one = summary(out1);
    EXPECT_EQ(one["cameras"].get<int>(), 1);
    expect_beats_thesis(one);
    if (!HasFailure()) remove_scratch(root);  // 11 MB of frames; kept to look at on failure
}

// Thesis table 6.1 (hover test), mean absolute error per sample.
constexpr double kThesisHoverX_cm = 0.170;
constexpr double kThesisHoverY_cm = 0.148;

TEST(OdometryCli, HoverUnderImuNoiseBeatsTheThesis) {
    // Issue 17 point 4: an onboard estimator's attitude (0.1° white noise, a 0.3° bias) must not
    // raise the per-sample error above the thesis' on the AR.Drone's bottom camera alone. The
    // defaults (the image tilt fused with the navdata, odo.image_tilt=1) keep it well below;
    // levelling by the navdata alone (odo.image_tilt=0) lets the noise into the translation.
    const fs::path root = scratch_dir("odometry_cli", "hover_imu");
    const fs::path data = root / "flight", fused = root / "fused", nav = root / "nav";
    CmdResult r = run_cli("odometry " + data.string() +
                          " --generate hover --no-top --duration 20 --seed 1 --imu-noise 0.1 "
                          "--imu-bias 0.3 --summary --out " +
                          fused.string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const nlohmann::json f = summary(fused);
    EXPECT_EQ(f["cameras"].get<int>(), 1);
    EXPECT_EQ(f["invalid"].get<int>(), 0);
    EXPECT_LT(f["x_cm"]["mean"].get<double>(), kThesisHoverX_cm / 2);
    EXPECT_LT(f["y_cm"]["mean"].get<double>(), kThesisHoverY_cm / 2);
    EXPECT_GT(f["distance_travelled_m"].get<double>(), 0.2);  // the hand-held wobble
    EXPECT_LT(f["end_error_pct"].get<double>(), 2.0);

    r = run_cli("odometry " + data.string() + " --single --set odo.image_tilt=0 --summary --out " +
                nav.string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const nlohmann::json n = summary(nav);
    EXPECT_GT(n["x_cm"]["mean"].get<double>(), kThesisHoverX_cm);
    EXPECT_GT(n["y_cm"]["mean"].get<double>(), kThesisHoverY_cm);
    if (!HasFailure()) remove_scratch(root);
}

TEST(OdometryCli, RefusesBadArguments) {
    const fs::path root = scratch_dir("odometry_cli", "refusals");
    CmdResult r = run_cli("odometry " + (root / "a").string() + " --generate loop");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.out.find("unknown test 'loop'"), std::string::npos) << r.out;
    r = run_cli("odometry " + (root / "missing").string());
    EXPECT_NE(r.exit_code, 0) << r.out;
    r = run_cli("odometry " + (root / "b").string() +
                " --generate hover --duration 0.2 --yaw compass");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.out.find("unknown --yaw 'compass'"), std::string::npos) << r.out;
    r = run_cli("odometry " + (root / "b").string() + " --set filter.spike_rotation_deg=500");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.out.find("--set filter.spike_rotation_deg"), std::string::npos) << r.out;
    if (!HasFailure()) remove_scratch(root);
}

}  // namespace
