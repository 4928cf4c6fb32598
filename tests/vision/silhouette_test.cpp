// The outline cue (vision/silhouette.hpp) on rendered scanline scenes: surfaces at known depths
// seen by an ideal 640 x 360 camera flying straight ahead at 1 m/s, 30 frames/s. Each image
// column looks along one ray; the nearest surface it meets gives its brightness (a plain surface
// one grey, a textured one a fixed random pattern painted on it), so the ends' motions follow
// the geometry exactly and nothing is told to the cue but the pictures, the FOE and the rotation.

#include "vision/silhouette.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

using namespace gs::vision;
using gs::CameraCalibration;

namespace {

constexpr int kW = 640, kH = 360;
constexpr double kFps = 30, kSpeed = 1.0;

// A vertical strip of surface facing the camera: lateral extent [x0, x1] (m) at depth z (m, at
// time 0; the camera closes in at kSpeed), plain (grey) or textured around that grey.
struct Surface {
    double x0, x1, z;
    double grey;
    bool textured;
};

double texture(double lateral_m) {
    // A fixed pattern painted on the surface: 5 cm cells of pseudo-random grey, +-40.
    const auto cell = static_cast<std::int64_t>(std::floor(lateral_m / 0.05));
    std::uint64_t h = static_cast<std::uint64_t>(cell) * 0x9E3779B97F4A7C15ull;
    h ^= h >> 29;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 32;
    return static_cast<double>(h % 81) - 40.0;
}

// The frame at time t; the camera yawed by `shift_px` (all columns moved right by it, the
// small-rotation approximation a homography of pure translation describes exactly).
cv::Mat render(const CameraCalibration& cal, const std::vector<Surface>& scene, double t,
               double shift_px) {
    cv::Mat img(kH, kW, CV_8UC1);
    constexpr int kSub = 8;  // rays per column: the edges land between pixels as a lens's do
    for (int x = 0; x < kW; ++x) {
        double sum = 0;
        for (int k = 0; k < kSub; ++k) {
            const double px = x - 0.5 + (k + 0.5) / kSub;
            const double u = (px - shift_px - cal.cx) / cal.fx;  // ray slope before the yaw
            double best_z = 1e9, grey = 90;                      // beyond everything: a dim void
            for (const Surface& s : scene) {
                const double z = s.z - kSpeed * t;
                const double lateral = u * z;
                if (z > 0.05 && z < best_z && lateral >= s.x0 && lateral <= s.x1) {
                    best_z = z;
                    grey = s.grey + (s.textured ? texture(lateral) : 0.0);
                }
            }
            sum += grey;
        }
        const auto v = static_cast<std::uint8_t>(std::clamp(std::lround(sum / kSub), 0L, 255L));
        for (int y = 0; y < kH; ++y) img.at<std::uint8_t>(y, x) = v;
    }
    return img;
}

struct Flight {
    std::vector<SilhouetteResult> results;
    std::vector<double> t;
};

Flight fly(const std::vector<Surface>& scene, int frames, double yaw_px_per_frame = 0) {
    const CameraCalibration cal = CameraCalibration::ideal(kW, kH, 92);
    SilhouetteCue cue;
    Flight run;
    const cv::Point2f foe(static_cast<float>(cal.cx), static_cast<float>(cal.cy));
    for (int k = 0; k < frames; ++k) {
        const double t = k / kFps;
        const cv::Mat img = render(cal, scene, t, yaw_px_per_frame * k);
        const cv::Point2f foe_k(foe.x + static_cast<float>(yaw_px_per_frame * k), foe.y);
        const cv::Matx33d rotation(1, 0, yaw_px_per_frame, 0, 1, 0, 0, 0, 1);
        run.results.push_back(cue.update(img, cal, foe_k, rotation, t));
        run.t.push_back(t);
    }
    return run;
}

// The true rate of a surface at depth z0 (time 0) at the middle of the fit's window ending at t.
double true_rate(double z0, double t, int window) {
    const double mid = t - 0.5 * (window - 1) / kFps;
    return kSpeed / (z0 - kSpeed * mid);
}

}  // namespace

TEST(Silhouette, APlainObstacleAheadLoomsAtOneOverTimeToContact) {
    // A plain 0.6 m pillar from 4 m to 2.5 m, a textured wall 4 m behind it.
    const std::vector<Surface> scene{{-0.3, 0.3, 4.0, 180, false}, {-20, 20, 8.0, 100, true}};
    const Flight run = fly(scene, 45);
    int measured = 0;
    for (std::size_t k = 10; k < run.results.size(); ++k) {
        const SilhouetteResult& r = run.results[k];
        ASSERT_TRUE(r.run) << k;
        // Neither end moves with the wall's texture beside it (each gains on it, if little
        // while the pillar is far), and the two move as one surface.
        EXPECT_GT(r.own_left, -0.5) << k;
        EXPECT_GT(r.own_right, -0.5) << k;
        EXPECT_TRUE(r.one_surface) << k;
        ASSERT_FALSE(std::isnan(r.rate)) << k;
        // Each end is placed to a few tenths of a pixel against the texture sliding behind it:
        // over a third of a second that is up to a quarter of the rate.
        const double truth = true_rate(4.0, run.t[k], SilhouetteParams{}.window);
        EXPECT_NEAR(r.rate, truth, 0.25 * truth) << k;
        ++measured;
    }
    EXPECT_EQ(measured, 35);
}

TEST(Silhouette, TheCameraYawingDoesNotChangeTheRate) {
    // The same pillar, the camera turning 2 px a frame (about 5 degrees/s): the width does not
    // care, and with the rotation taken off the ends still expand about the FOE alone.
    const std::vector<Surface> scene{{-0.3, 0.3, 4.0, 180, false}, {-20, 20, 8.0, 100, true}};
    const Flight run = fly(scene, 45, 2.0);
    for (std::size_t k = 10; k < run.results.size(); ++k) {
        const SilhouetteResult& r = run.results[k];
        ASSERT_TRUE(r.one_surface) << k;
        EXPECT_NEAR(r.shift_px, 0, 1.0) << k;
        const double truth = true_rate(4.0, run.t[k], SilhouetteParams{}.window);
        EXPECT_NEAR(r.rate, truth, 0.25 * truth) << k;
    }
}

TEST(Silhouette, AGapBetweenTexturedPostsIsNotAnObstacle) {
    // Two textured posts 0.8 m apart at 3 m, a plain far wall between them at 12 m: the run
    // between the posts widens at the posts' rate, but its ends move with the posts' texture.
    const std::vector<Surface> scene{
        {-1.5, -0.4, 3.0, 110, true}, {0.4, 1.5, 3.0, 110, true}, {-30, 30, 12.0, 200, false}};
    const Flight run = fly(scene, 40);
    int runs = 0;
    for (std::size_t k = 10; k < run.results.size(); ++k) {
        const SilhouetteResult& r = run.results[k];
        if (!r.run) continue;
        ++runs;
        EXPECT_GT(r.width_rate, 0.25) << k;  // the widening is there ...
        EXPECT_LT(std::abs(r.own_left), 1.5) << k;
        EXPECT_LT(std::abs(r.own_right), 1.5) << k;
        EXPECT_TRUE(std::isnan(r.rate)) << k;  // ... and read as no obstacle
    }
    EXPECT_GE(runs, 25);
}

TEST(Silhouette, ANearPostBesideAPlainFarWallIsNotOneSurface) {
    // A textured post at 1.8 m left of the flight line (its edge 0.4 m from it), a plain far
    // wall at 10 m beyond, which ends 2.5 m to the right against a dimmer plain one: the run
    // widens faster than the threshold as the post's edge sweeps out, but its far end hardly
    // moves, so its motion is not one surface's expansion about the FOE.
    const std::vector<Surface> scene{
        {-1.5, -0.4, 1.8, 110, true}, {-30, 2.5, 10.0, 200, false}, {2.5, 30, 10.0, 150, false}};
    const Flight run = fly(scene, 30);
    int runs = 0;
    for (std::size_t k = 10; k < run.results.size(); ++k) {
        const SilhouetteResult& r = run.results[k];
        ASSERT_TRUE(r.run) << k;
        ++runs;
        EXPECT_GT(r.width_rate, 0.3) << k;          // the trap: it widens fast enough to alarm
        EXPECT_LT(r.own_left, 1.5) << k;            // the end does not cover the post's texture
        EXPECT_TRUE(std::isnan(r.own_right)) << k;  // plain beside the far end
        EXPECT_FALSE(r.one_surface) << k;
        EXPECT_TRUE(std::isnan(r.rate)) << k;
    }
    EXPECT_EQ(runs, 20);
}

TEST(Silhouette, ARunWithOneFarEndIsNotRead) {
    // A plain surface at 3 m from 0.4 m left of the flight line to 0.9 m right of it, before a
    // textured wall at 9 m that carries a patch of the surface's own grey from 0.5 m to 4.5 m:
    // the surface's right end does not show, and the run reaches the patch's far end, which
    // moves with the wall. The left end covers the wall's texture, but the run's width grows
    // slower than the surface looms, and its ends do not part about the FOE: not read (the
    // points judge the surface, or it stays unknown).
    const std::vector<Surface> scene{
        {-0.4, 0.9, 3.0, 190, false}, {0.5, 4.5, 8.99, 190, false}, {-30, 30, 9.0, 100, true}};
    const Flight run = fly(scene, 30);
    int judged = 0;
    for (std::size_t k = 12; k < run.results.size(); ++k) {
        const SilhouetteResult& r = run.results[k];
        ASSERT_TRUE(r.run) << k;
        EXPECT_GT(r.own_left, 1.5) << k;
        EXPECT_LT(std::abs(r.own_right), 1.5) << k;
        EXPECT_LT(r.width_rate, 0.7 * true_rate(3.0, run.t[k], SilhouetteParams{}.window)) << k;
        EXPECT_FALSE(r.one_surface) << k;
        EXPECT_TRUE(std::isnan(r.rate)) << k;
        ++judged;
    }
    EXPECT_EQ(judged, 18);
}

TEST(Silhouette, NoRunWithoutAFocusOfExpansionOrOnAnEdge) {
    const CameraCalibration cal = CameraCalibration::ideal(kW, kH, 92);
    const std::vector<Surface> scene{{-0.3, 0.3, 4.0, 180, false}, {-20, 20, 8.0, 100, true}};
    const cv::Mat img = render(cal, scene, 0, 0);
    SilhouetteCue cue;
    EXPECT_FALSE(cue.update(img, cal, {NAN, 100}, cv::Matx33d::eye(), 0).run);
    EXPECT_FALSE(cue.update(img, cal, {-5, 100}, cv::Matx33d::eye(), 0.03).run);
    EXPECT_FALSE(cue.update(cv::Mat(), cal, {320, 180}, cv::Matx33d::eye(), 0.06).run);
    // The FOE on the wall's texture: no plain run around it.
    EXPECT_FALSE(cue.update(img, cal, {40, 180}, cv::Matx33d::eye(), 0.09).run);
    // On the pillar: a run, not yet a rate.
    const SilhouetteResult& r = cue.update(img, cal, {320, 180}, cv::Matx33d::eye(), 0.12);
    EXPECT_TRUE(r.run);
    EXPECT_TRUE(std::isnan(r.rate));
}
