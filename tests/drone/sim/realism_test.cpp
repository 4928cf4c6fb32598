// The realism layer (drone/sim/realism.hpp): each effect measured in its output, in the units it
// is given in. A distortion-free 320x240 camera with a 60 degree field of view (f = 277 px)
// keeps the expected pixel figures simple.

#include "drone/sim/realism.hpp"
#include "drone/dataset/dataset.hpp"
#include "drone/sim/obstacle_flights.hpp"
#include "drone/sim/scene.hpp"
#include "drone/video/h264_decoder.hpp"

#include <gtest/gtest.h>
#include <unistd.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

namespace gs::sim {
namespace {

constexpr int kW = 320, kH = 240;
const CameraCalibration kCam = CameraCalibration::ideal(kW, kH, 60);
constexpr double kDeg = std::numbers::pi / 180;

// Dark left half, bright right half: a vertical edge at x = 160.
cv::Mat edge_image() {
    cv::Mat m(kH, kW, CV_8UC3, cv::Scalar(40, 40, 40));
    m(cv::Rect(kW / 2, 0, kW / 2, kH)).setTo(cv::Scalar(200, 200, 200));
    return m;
}

// Where row y crosses the level halfway between dark and bright (sub-pixel, first crossing).
double edge_x(const cv::Mat& img, int y, double level = 120) {
    const std::uint8_t* p = img.ptr<std::uint8_t>(y);
    for (int x = 1; x < img.cols; ++x) {
        const double a = p[3 * (x - 1)], b = p[3 * x];
        if (a < level && b >= level) return x - 1 + (level - a) / (b - a);
    }
    return -1;
}

// Pixels from 10 % to 90 % of the step along row y.
double edge_width(const cv::Mat& img, int y) {
    return edge_x(img, y, 40 + 0.9 * 160) - edge_x(img, y, 40 + 0.1 * 160);
}

CameraMotion yawing(double deg_s) {
    CameraMotion m;
    m.omega_rad_s = {0, deg_s * kDeg, 0};  // about the camera's y axis (down): a yaw
    return m;
}

TEST(Realism, RollingShutterShearsAVerticalEdgeByTheReadoutTimesTheYawRate) {
    RealismOptions o;
    o.rolling_shutter_ms = 25;
    CameraEffects fx(kCam, o, 1);
    cv::Mat img = edge_image();
    fx.apply(img, 0, yawing(90), {});
    const double f = kCam.fx;
    // Row y is read (y / (H-1) - 0.5) * 25 ms from the frame's time: the edge, still in the
    // world, sits f * omega * tau to the left of where the frame's middle row has it.
    const double expected = f * 90 * kDeg * 0.025;  // 10.9 px from first row to last
    EXPECT_NEAR(edge_x(img, 0) - edge_x(img, kH - 1), expected, 0.3);
    const double still_x = edge_x(edge_image(), kH / 2);
    EXPECT_NEAR(edge_x(img, kH / 2), still_x, 0.1);
    // Turning the other way shears the other way; no rotation, no shear.
    cv::Mat back = edge_image();
    CameraEffects fx2(kCam, o, 1);
    fx2.apply(back, 0, yawing(-90), {});
    EXPECT_NEAR(edge_x(back, 0) - edge_x(back, kH - 1), -expected, 0.3);
    cv::Mat still = edge_image();
    CameraEffects fx3(kCam, o, 1);
    fx3.apply(still, 0, CameraMotion{}, {});
    EXPECT_NEAR(edge_x(still, 0) - edge_x(still, kH - 1), 0, 0.05);
}

TEST(Realism, MotionBlurSpreadsAnEdgeOverTheExposureAtTheRotationRate) {
    RealismOptions o;
    o.exposure_ms = 12;
    CameraEffects fx(kCam, o, 1);
    cv::Mat img = edge_image();
    fx.apply(img, 0, yawing(90), {});
    // A box exposure smears the step into a ramp f * omega * T long: 10-90 % is 80 % of it.
    const double ramp = kCam.fx * 90 * kDeg * 0.012;  // 5.2 px
    EXPECT_NEAR(edge_width(img, kH / 2), 0.8 * ramp, 0.6);
    // Twice the rate, twice the blur; the edge stays centred (exposure centred on the frame).
    cv::Mat fast = edge_image();
    CameraEffects fx2(kCam, o, 1);
    fx2.apply(fast, 0, yawing(180), {});
    EXPECT_NEAR(edge_width(fast, kH / 2), 1.6 * ramp, 0.8);
    EXPECT_NEAR(edge_x(fast, kH / 2), edge_x(edge_image(), kH / 2), 0.5);
}

TEST(Realism, MotionBlurFromTranslationGrowsAsTheSurfaceNears) {
    RealismOptions o;
    o.exposure_ms = 12;
    CameraMotion m;
    m.v_mps = {1.0, 0, 0};  // sideways at 1 m/s
    // A surface 0.5 m away: the image moves f * v / Z = 554 px/s, 6.6 px in 12 ms.
    std::vector<float> near(std::size_t(kW) * kH, 1 / 0.5f), far(std::size_t(kW) * kH, 0.0f);
    cv::Mat a = edge_image(), b = edge_image();
    CameraEffects(kCam, o, 1).apply(a, 0, m, near);
    CameraEffects(kCam, o, 1).apply(b, 0, m, far);
    EXPECT_NEAR(edge_width(a, kH / 2), 0.8 * kCam.fx * 1.0 / 0.5 * 0.012, 0.6);
    EXPECT_LT(edge_width(b, kH / 2), 1.0) << "at infinity translation does not move the image";
}

TEST(Realism, VignettingDarkensTheCornersByItsPercentage) {
    RealismOptions o;
    o.vignetting_pct = 30;
    CameraEffects fx(kCam, o, 1);
    cv::Mat img(kH, kW, CV_8UC3, cv::Scalar(200, 200, 200));
    fx.apply(img, 0, {}, {});
    EXPECT_NEAR(img.at<cv::Vec3b>(0, 0)[0], 140, 1);
    EXPECT_NEAR(img.at<cv::Vec3b>(kH - 1, kW - 1)[1], 140, 1);
    EXPECT_NEAR(img.at<cv::Vec3b>(kH / 2, kW / 2)[2], 200, 1);
}

TEST(Realism, ShotNoiseHasItsStandardDeviationAtMidGreyAndGrowsWithTheSignal) {
    RealismOptions o;
    o.noise_pct = 2;  // 5.1 DN at mid grey
    auto sigma_at = [&](int level) {
        CameraEffects fx(kCam, o, 7);
        cv::Mat img(kH, kW, CV_8UC3, cv::Scalar::all(level));
        fx.apply(img, 0, {}, {});
        cv::Scalar mean, sd;
        cv::meanStdDev(img.reshape(1), mean, sd);
        EXPECT_NEAR(mean[0], level, 0.3);
        return sd[0];
    };
    EXPECT_NEAR(sigma_at(128), 0.02 * 255, 0.25);
    EXPECT_NEAR(sigma_at(32), 0.02 * 255 * 0.5, 0.25);  // shot noise: sqrt(32 / 128)
    // Seeded: the same seed, the same noise; another seed, other noise.
    cv::Mat a(kH, kW, CV_8UC3, cv::Scalar::all(128)), b = a.clone(), c = a.clone();
    CameraEffects(kCam, o, 7).apply(a, 0, {}, {});
    CameraEffects(kCam, o, 7).apply(b, 0, {}, {});
    CameraEffects(kCam, o, 8).apply(c, 0, {}, {});
    EXPECT_EQ(cv::norm(a, b, cv::NORM_L1), 0);
    EXPECT_GT(cv::norm(a, c, cv::NORM_L1), 0);
}

TEST(Realism, AutoExposureStepsTheGainByItsPercentage) {
    RealismOptions o;
    o.exposure_step_pct = 15;
    o.exposure_step_interval_s = 1;
    CameraEffects fx(kCam, o, 3);
    int steps = 0;
    double last = 100;
    for (int k = 0; k < 600; ++k) {  // 20 s at 30 fps
        cv::Mat img(kH, kW, CV_8UC3, cv::Scalar::all(100));
        fx.apply(img, k / 30.0, {}, {});
        const double m = cv::mean(img)[0];
        EXPECT_NEAR(m, 100 * fx.exposure_gain(), 0.51);
        if (std::abs(m - last) > 1) {
            ++steps;
            const double ratio = m > last ? m / last : last / m;
            EXPECT_NEAR(ratio, 1.15, 0.012) << "frame " << k;
        }
        EXPECT_LE(fx.exposure_gain(), std::pow(1.15, 3) + 1e-9);
        EXPECT_GE(fx.exposure_gain(), std::pow(1.15, -3) - 1e-9);
        last = m;
    }
    EXPECT_GT(steps, 8);  // about one a second
    EXPECT_LT(steps, 35);
}

TEST(Realism, FlickerBandsTheRowsAtTheMainsFrequencyThroughTheRollingShutter) {
    RealismOptions o;
    o.flicker_pct = 3;
    o.flicker_hz = 100;
    o.rolling_shutter_ms = 25;  // 2.5 periods of 100 Hz from the first row to the last
    CameraEffects fx(kCam, o, 5);
    cv::Mat img(kH, kW, CV_8UC3, cv::Scalar::all(128));
    fx.apply(img, 0.5, CameraMotion{}, {});
    // Least squares of the row means on sin, cos (of the row's time at 100 Hz) and 1.
    cv::Mat A(kH, 3, CV_64F), v(kH, 1, CV_64F), x;
    for (int y = 0; y < kH; ++y) {
        const double t = 0.5 + (double(y) / (kH - 1) - 0.5) * 0.025;
        A.at<double>(y, 0) = std::sin(2 * std::numbers::pi * 100 * t);
        A.at<double>(y, 1) = std::cos(2 * std::numbers::pi * 100 * t);
        A.at<double>(y, 2) = 1;
        v.at<double>(y) = cv::mean(img.row(y))[0];
    }
    ASSERT_TRUE(cv::solve(A, v, x, cv::DECOMP_SVD));
    EXPECT_NEAR(std::hypot(x.at<double>(0), x.at<double>(1)), 0.03 * 128, 0.3);
    EXPECT_NEAR(x.at<double>(2), 128, 0.3);
    // What the fit leaves is the rounding to 8 bits and the fit, no other frequency
    // (amplitude 3.84).
    const cv::Mat resid = v - A * x;
    EXPECT_LT(cv::norm(resid, cv::NORM_INF), 0.75);
}

TEST(Realism, SliceLossCutsTheTailOfTheShareOfPFramesAndNeverAnIdr) {
    StreamDamage d(10, 11);
    int cut = 0;
    for (int k = 0; k < 3000; ++k) {
        std::vector<std::uint8_t> au(400, 0x5a);
        const std::uint8_t head[] = {0, 0, 0, 1, 0x67, 1, 2, 3, 0, 0, 0, 1, 0x41};
        std::copy(std::begin(head), std::end(head), au.begin());
        const bool idr = k % 15 == 0;
        const bool hit = d.apply(au, idr);
        if (idr) {
            EXPECT_FALSE(hit);
        }
        if (hit) {
            ++cut;
            EXPECT_LT(au.size(), 400U);
            EXPECT_GT(au.size(), 13U + 8);  // the slice header stays
        } else {
            EXPECT_EQ(au.size(), 400U);
        }
    }
    EXPECT_EQ(cut, d.damaged());
    EXPECT_NEAR(cut, 0.10 * 2800, 3 * std::sqrt(2800 * 0.1 * 0.9));
}

NavState at(double t_s, double roll_deg) {
    NavState s;
    s.t_ns = TimeNs(std::llround(t_s * 1e9));
    s.roll_deg = roll_deg;
    s.pitch_deg = s.yaw_deg = 0;
    s.vx_mps = s.vy_mps = s.vz_mps = 0;
    s.altitude_m = 1;
    return s;
}

TEST(Realism, NavdataLatencyDelaysTheSampleByItsOffsetWithItsJitter) {
    RealismOptions o;
    o.nav_latency_ms = 30;
    NavdataEffects late(o, 1);
    // Roll ramping at 10 deg/s, sampled at 30 Hz: 30 ms late reads 0.3 deg low.
    for (int k = 0; k < 60; ++k) {
        late.push_truth(at(k / 30.0, 10 * k / 30.0));
        if (k > 3) {
            EXPECT_NEAR(late.sample(at(k / 30.0, 0).t_ns).roll_deg, 10 * k / 30.0 - 0.3, 1e-6);
        }
    }
    o.nav_jitter_ms = 10;
    NavdataEffects jittery(o, 2);
    double sum = 0, sum2 = 0;
    int n = 0;
    for (int k = 0; k < 3000; ++k) {
        jittery.push_truth(at(k / 30.0, 10 * k / 30.0));
        if (k < 5) continue;
        const double lag_ms = (10 * k / 30.0 - jittery.sample(at(k / 30.0, 0).t_ns).roll_deg) * 100;
        sum += lag_ms;
        sum2 += lag_ms * lag_ms;
        ++n;
    }
    const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
    EXPECT_NEAR(mean, 30, 0.7);
    EXPECT_NEAR(sd, 10, 0.7);
}

TEST(Realism, NavdataBiasesDriftSlowlyWithTheirStationarySpread) {
    RealismOptions o;
    o.attitude_bias_deg = 0.3;
    o.velocity_bias_mps = 0.03;
    o.bias_tau_s = 10;
    NavdataEffects nav(o, 4);
    double s2 = 0, v2 = 0, step2 = 0, prev = 0;
    const int n = 30 * 2000;  // 2000 s at 30 Hz: 200 correlation times
    for (int k = 0; k < n; ++k) {
        nav.push_truth(at(k / 30.0, 0));
        const NavState s = nav.sample(at(k / 30.0, 0).t_ns);
        s2 += s.roll_deg * s.roll_deg / n;
        v2 += s.vx_mps * s.vx_mps / n;
        if (k > 0) step2 += (s.roll_deg - prev) * (s.roll_deg - prev) / (n - 1);
        prev = s.roll_deg;
    }
    EXPECT_NEAR(std::sqrt(s2), 0.3, 0.06);
    EXPECT_NEAR(std::sqrt(v2), 0.03, 0.006);
    // Slow: from one frame to the next it moves sigma * sqrt(2 dt / tau) = 0.023 deg, not 0.3.
    EXPECT_NEAR(std::sqrt(step2), 0.3 * std::sqrt(2.0 / 30 / 10), 0.004);
}

TEST(Realism, OptionsRoundTripThroughFlightJsonAndAreChecked) {
    const RealismOptions r = RealismOptions::real_camera();
    RealismOptions back;
    ASSERT_FALSE(RealismOptions::from_json(r.to_json(), back));
    EXPECT_EQ(back.to_json(), r.to_json());
    RealismOptions bad;
    bad.noise_pct = -1;
    ASSERT_TRUE(bad.check());
    EXPECT_NE(bad.check()->find("noise_pct"), std::string::npos);
    EXPECT_TRUE(RealismOptions::from_json({{"exposure_ms", "12"}}, back));
}

TEST(Realism, AGeneratedFlightRecordsItsRealismAndDiffersOnlyWhereItShould) {
    auto scene = load_scene(std::string(GS_ASSETS_DIR) + "/scenes/thesis_pillar_center.json");
    ASSERT_TRUE(scene) << to_string(scene.error());
    ObstacleFlightInfo f = scenario_flight(*scene, 1.5, 3);
    f.params.max_record_s = 0.5;
    f.params.bitrate_bps = 400'000;
    const auto root =
        std::filesystem::temp_directory_path() / ("gs_realism_" + std::to_string(::getpid()));
    std::filesystem::remove_all(root);
    ASSERT_TRUE(write_obstacle_flight(root / "clean", f));
    f.params.realism = RealismOptions::real_camera();
    auto real = write_obstacle_flight(root / "real", f);
    ASSERT_TRUE(real) << real.error();
    auto d = dataset::Dataset::open(root / "real");
    ASSERT_TRUE(d) << to_string(d.error());
    for (const auto& w : d->warnings()) EXPECT_EQ(w.find("realism"), std::string::npos) << w;
    std::ifstream in(root / "real" / "flight.json");
    const nlohmann::json j = nlohmann::json::parse(in);
    ASSERT_TRUE(j.contains("realism"));
    EXPECT_DOUBLE_EQ(j["realism"]["rolling_shutter_ms"].get<double>(), 25);
    EXPECT_DOUBLE_EQ(j["realism"]["video_bitrate_kbps"].get<double>(), 400);
    EXPECT_EQ(j["realism"]["slices_lost"].get<int>(), real->slices_lost);
    std::ifstream clean_in(root / "clean" / "flight.json");
    EXPECT_FALSE(nlohmann::json::parse(clean_in).contains("realism"));
    // Same flight, same ground truth; the navdata is late and biased, not the pose.
    auto c = dataset::Dataset::open(root / "clean");
    ASSERT_TRUE(c);
    ASSERT_EQ(c->frame_count(), d->frame_count());
    for (std::int64_t k = 0; k < c->frame_count(); ++k)
        EXPECT_DOUBLE_EQ(c->frames()[std::size_t(k)].gt.x_m, d->frames()[std::size_t(k)].gt.x_m);
    std::filesystem::remove_all(root);
}

// Every frame of a generated flight's video.h264, decoded.
std::vector<cv::Mat> decode_flight(const std::filesystem::path& dir) {
    std::ifstream in(dir / "video.h264", std::ios::binary);
    const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                          std::istreambuf_iterator<char>());
    video::H264Decoder dec;
    std::vector<cv::Mat> frames;
    std::span<const std::uint8_t> rest(bytes);
    while (!rest.empty()) {
        const std::size_t n = std::max<std::size_t>(1, video::access_unit_size(rest));
        cv::Mat out;
        auto st = dec.decode({rest.first(n), std::nullopt, 0, 0, std::nullopt}, out);
        if (st && !out.empty()) frames.push_back(out.clone());
        rest = rest.subspan(n);
    }
    return frames;
}

// A flight of `scene_name` (`seconds` recorded at most, 4 Mbit/s) with realism `r`, written
// under `root`.
std::filesystem::path write_flight(const std::filesystem::path& root, const std::string& name,
                                   const std::string& scene_name, const RealismOptions& r,
                                   double seconds = 0.8) {
    auto scene = load_scene(std::string(GS_ASSETS_DIR) + "/scenes/" + scene_name + ".json");
    EXPECT_TRUE(scene);
    ObstacleFlightInfo f = scenario_flight(*scene, 1.0, 5);
    f.params.max_record_s = seconds;
    f.params.bitrate_bps = 4'000'000;
    f.params.realism = r;
    auto written = write_obstacle_flight(root / name, f);
    EXPECT_TRUE(written) << (written ? "" : written.error());
    return root / name;
}

// Where the debug PNGs go (GS_REALISM_PNG_DIR), if anywhere.
void save_png(const std::string& name, const cv::Mat& img) {
    if (const char* d = std::getenv("GS_REALISM_PNG_DIR"))
        cv::imwrite(std::string(d) + "/" + name, img);
}

// Mean Sobel gradient magnitude of `img` (grey) over `mask`.
double mean_gradient(const cv::Mat& bgr, const cv::Mat& mask) {
    cv::Mat g, gx, gy, mag;
    cv::cvtColor(bgr, g, cv::COLOR_BGR2GRAY);
    cv::Sobel(g, gx, CV_32F, 1, 0);
    cv::Sobel(g, gy, CV_32F, 0, 1);
    cv::magnitude(gx, gy, mag);
    return cv::mean(mag, mask)[0];
}

TEST(Realism, LowTextureWallsRepaintTheirShareOfTheWallsPlainFromTheSeed) {
    auto scene = load_scene(std::string(GS_ASSETS_DIR) + "/scenes/thesis_pillar_left.json");
    ASSERT_TRUE(scene);
    RealismOptions o;
    Scene s0 = *scene;
    EXPECT_TRUE(apply_scene_effects(s0, o, 1).plain_walls.empty());
    EXPECT_TRUE(s0.room.wall_front == scene->room.wall_front);
    o.low_texture_walls_pct = 50;
    Scene a = *scene, b = *scene;
    const auto ea = apply_scene_effects(a, o, 1), eb = apply_scene_effects(b, o, 1);
    ASSERT_EQ(ea.plain_walls.size(), 2u);
    EXPECT_EQ(ea.plain_walls, eb.plain_walls);
    int plain = 0;
    for (const TextureSpec* t :
         {&a.room.wall_front, &a.room.wall_back, &a.room.wall_left, &a.room.wall_right})
        plain += t->kind == TextureKind::Plain;
    EXPECT_EQ(plain, 2);
    // Other seeds pick other walls (some of 20 differ from seed 1's pick).
    bool other = false;
    for (std::uint64_t seed = 2; seed < 22 && !other; ++seed) {
        Scene c = *scene;
        other = apply_scene_effects(c, o, seed).plain_walls != ea.plain_walls;
    }
    EXPECT_TRUE(other);
    o.low_texture_walls_pct = 100;
    Scene d = *scene;
    EXPECT_EQ(apply_scene_effects(d, o, 1).plain_walls.size(), 4u);
}

TEST(Realism, AFlightWithPlainWallsHasLessTextureOnItsWalls) {
    const auto root =
        std::filesystem::temp_directory_path() / ("gs_realism_walls_" + std::to_string(::getpid()));
    std::filesystem::remove_all(root);
    RealismOptions plain;
    plain.low_texture_walls_pct = 100;
    const auto dir0 = write_flight(root, "textured", "thesis_pillar_left", {});
    const auto dir1 = write_flight(root, "plain", "thesis_pillar_left", plain);
    std::ifstream in(dir1 / "flight.json");
    const nlohmann::json j = nlohmann::json::parse(in);
    EXPECT_DOUBLE_EQ(j["realism"]["low_texture_walls_pct"].get<double>(), 100);
    EXPECT_EQ(j["realism"]["plain_walls"].size(), 4u);
    const auto f0 = decode_flight(dir0), f1 = decode_flight(dir1);
    ASSERT_FALSE(f0.empty());
    ASSERT_EQ(f0.size(), f1.size());
    for (std::size_t k : {std::size_t(0), f0.size() - 1}) {
        // The walls are where the two flights differ (the same poses, only the walls changed),
        // eroded away from the wall edges.
        cv::Mat diff, grey, mask;
        cv::absdiff(f0[k], f1[k], diff);
        cv::cvtColor(diff, grey, cv::COLOR_BGR2GRAY);
        cv::threshold(grey, mask, 12, 255, cv::THRESH_BINARY);
        cv::morphologyEx(mask, mask, cv::MORPH_CLOSE, cv::Mat::ones(9, 9, CV_8U));
        cv::erode(mask, mask, cv::Mat::ones(7, 7, CV_8U));
        ASSERT_GT(cv::countNonZero(mask), 640 * 360 / 20) << "the walls fill part of the view";
        const double g0 = mean_gradient(f0[k], mask), g1 = mean_gradient(f1[k], mask);
        EXPECT_LT(g1, 0.5 * g0) << "frame " << k << ": textured " << g0 << ", plain " << g1;
        save_png("walls_textured_" + std::to_string(k) + ".png", f0[k]);
        save_png("walls_plain_" + std::to_string(k) + ".png", f1[k]);
        save_png("walls_mask_" + std::to_string(k) + ".png", mask);
    }
    std::filesystem::remove_all(root);
}

TEST(Realism, AGlossyFloorChangesTheFloorOfAGeneratedFlightAndNotTheWalls) {
    const auto root =
        std::filesystem::temp_directory_path() / ("gs_realism_floor_" + std::to_string(::getpid()));
    std::filesystem::remove_all(root);
    RealismOptions gloss;
    gloss.glossy_floor_pct = 40;
    gloss.glossy_floor_blur_deg = 1.5;
    const auto dir0 = write_flight(root, "matte", "thesis_pillar_center", {});
    const auto dir1 = write_flight(root, "glossy", "thesis_pillar_center", gloss);
    std::ifstream in(dir1 / "flight.json");
    const nlohmann::json j = nlohmann::json::parse(in);
    EXPECT_DOUBLE_EQ(j["realism"]["glossy_floor_pct"].get<double>(), 40);
    EXPECT_DOUBLE_EQ(j["realism"]["glossy_floor_blur_deg"].get<double>(), 1.5);
    const auto f0 = decode_flight(dir0), f1 = decode_flight(dir1);
    ASSERT_FALSE(f0.empty());
    ASSERT_EQ(f0.size(), f1.size());
    const cv::Mat a = f0.back(), b = f1.back();
    save_png("floor_matte.png", a);
    save_png("floor_glossy.png", b);
    // The bottom rows are floor; the top 60 rows walls and ceiling (only coding noise differs).
    cv::Mat diff;
    cv::absdiff(a, b, diff);
    const double floor_diff = cv::mean(diff.rowRange(260, 360))[0];
    const double top_diff = cv::mean(diff.rowRange(0, 60))[0];
    EXPECT_GT(floor_diff, 5.0);
    EXPECT_LT(top_diff, 3.0);
    EXPECT_GT(floor_diff, 3 * top_diff) << "floor " << floor_diff << ", top " << top_diff;
    std::filesystem::remove_all(root);
}

TEST(Realism, PeoplePlansAreSeededAndStartBeyondTheClearance) {
    auto scene = load_scene(std::string(GS_ASSETS_DIR) + "/scenes/thesis_pillar_left.json");
    ASSERT_TRUE(scene);
    RealismOptions o;
    EXPECT_TRUE(plan_people(o, scene->room, 0, 0, 0, 1.25, 1).empty());
    o.people_crossing = 3;
    const auto a = plan_people(o, scene->room, 0, 0, 0, 1.25, 1);
    const auto b = plan_people(o, scene->room, 0, 0, 0, 1.25, 1);
    ASSERT_EQ(a.size(), 3u);
    for (std::size_t k = 0; k < a.size(); ++k) {
        EXPECT_EQ(a[k].to_json(), b[k].to_json());
        // Crossing the flight line (y = 0) at least 7 m beyond where a drone at 1.25 m/s is then.
        EXPECT_NEAR(a[k].cross_y_m, 0, 1e-9);
        EXPECT_GE(a[k].cross_x_m - 1.25 * a[k].cross_s, 7 - 1e-9);
        EXPECT_LT(a[k].cross_x_m, scene->room.x_max_m);
        // Walking across, wall to wall.
        EXPECT_NEAR(std::abs(a[k].dir_y), 1, 1e-9);
        EXPECT_LT(a[k].from_s, a[k].cross_s);
        EXPECT_GT(a[k].to_s, a[k].cross_s);
    }
    EXPECT_NE(a[0].to_json(), plan_people(o, scene->room, 0, 0, 0, 1.25, 2)[0].to_json());
    o.people_crossing = 1.5;
    EXPECT_TRUE(o.check());
}

TEST(Realism, PeopleCrossAheadOfAGeneratedFlightNeverNearTheDroneAndInViewForSeconds) {
    const auto root = std::filesystem::temp_directory_path() /
                      ("gs_realism_people_" + std::to_string(::getpid()));
    std::filesystem::remove_all(root);
    RealismOptions people;
    people.people_crossing = 2;
    people.person_speed_mps = 1.3;
    const auto dir0 = write_flight(root, "empty", "thesis_pillar_left", {}, 20);
    const auto dir1 = write_flight(root, "people", "thesis_pillar_left", people, 20);
    auto d = dataset::Dataset::open(dir1);
    ASSERT_TRUE(d) << to_string(d.error());
    std::ifstream in(dir1 / "flight.json");
    const nlohmann::json j = nlohmann::json::parse(in);
    ASSERT_TRUE(j["realism"].contains("people"));
    const auto& pj = j["realism"]["people"];
    ASSERT_EQ(pj.size(), 2u);
    // The flight still completes: it passes the pillar as without people.
    auto e = dataset::Dataset::open(dir0);
    ASSERT_TRUE(e);
    EXPECT_EQ(d->frame_count(), e->frame_count());
    auto scene = load_scene(std::string(GS_ASSETS_DIR) + "/scenes/thesis_pillar_left.json");
    ASSERT_TRUE(scene);
    auto renderer =
        Renderer::create(*scene, builtin_calibration(CameraId::Front), CameraKind::Front);
    ASSERT_TRUE(renderer);
    const auto f0 = decode_flight(dir0), f1 = decode_flight(dir1);
    ASSERT_EQ(f0.size(), f1.size());
    const double fps = 30;
    for (std::size_t k = 0; k < pj.size(); ++k) {
        PersonTrack q;
        q.cross_s = pj[k]["cross_s"].get<double>();
        q.cross_x_m = pj[k]["cross_xy_m"][0].get<double>();
        q.cross_y_m = pj[k]["cross_xy_m"][1].get<double>();
        q.dir_x = pj[k]["direction"][0].get<double>();
        q.dir_y = pj[k]["direction"][1].get<double>();
        q.from_s = pj[k]["from_s"].get<double>();
        q.to_s = pj[k]["to_s"].get<double>();
        q.speed_mps = pj[k]["speed_mps"].get<double>();
        EXPECT_DOUBLE_EQ(q.speed_mps, 1.3);
        double min_dist = 1e9, at_cross = -1, seen_s = 0, shown = 0;
        int shown_n = 0;
        for (const auto& row : d->frames()) {
            const double t = double(row.nav.t_ns) * 1e-9;
            if (!q.present(t)) continue;
            const Obstacle box = q.at(t);
            min_dist = std::min(min_dist, footprint_distance(box, row.gt.x_m, row.gt.y_m));
            if (std::abs(t - q.cross_s) <= 0.5 / fps)
                at_cross = std::hypot(row.gt.x_m - q.cross_x_m, row.gt.y_m - q.cross_y_m);
            const Pose pose{row.gt.x_m, row.gt.y_m, row.gt.z_m, 0, 0, row.gt.yaw_deg};
            const auto px = renderer->project(pose, box.x_m, box.y_m, 0.9);
            if (px && px->x >= 0 && px->x < 640 && px->y >= 0 && px->y < 360) {
                seen_s += 1 / fps;
                // Where the person is, the image differs from the flight without people.
                const cv::Rect r =
                    cv::Rect(int(px->x) - 3, int(px->y) - 3, 7, 7) & cv::Rect(0, 0, 640, 360);
                cv::Mat diff;
                cv::absdiff(f0[std::size_t(row.frame)](r), f1[std::size_t(row.frame)](r), diff);
                shown += cv::mean(diff)[0];
                ++shown_n;
                if (shown_n == 30)
                    save_png("people_" + std::to_string(k) + ".png", f1[std::size_t(row.frame)]);
            }
        }
        EXPECT_GE(min_dist, 2.0) << "person " << k;
        if (q.cross_s < double(d->frame_count()) / fps) {
            EXPECT_GE(at_cross, 6.0) << "person " << k << " crosses at " << q.cross_s << " s";
        }
        if (k == 0) {
            EXPECT_GE(seen_s, 5.0) << "the first person is in view for " << seen_s << " s";
            ASSERT_GT(shown_n, 0);
            EXPECT_GT(shown / shown_n, 10.0) << "the person is drawn where they are";
        }
        std::printf(
            "person %zu: crosses at %.2f s, (%.2f, %.2f); drone %.2f m away then; "
            "closest %.2f m; in view %.1f s; %.1f DN where drawn\n",
            k, q.cross_s, q.cross_x_m, q.cross_y_m, at_cross, min_dist, seen_s,
            shown_n ? shown / shown_n : 0.0);
    }
    std::filesystem::remove_all(root);
}

}  // namespace
}  // namespace gs::sim
