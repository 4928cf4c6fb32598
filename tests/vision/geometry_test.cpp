// Attitude geometry: the rotation a set of tracked points shows beyond what the navdata
// explained (the flow classifier's derotation refinement), and the tracker's spread over a grid.

#include "vision/geometry.hpp"
#include "synthetic_helpers.hpp"
#include "vision/tracker.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

using namespace gs::vision;
using gs::CameraCalibration;

namespace {

// Points scattered over the image, each moved by a translation toward `foe` (expansion rate
// `rate` per frame, different per point as depths differ) and then by the small rotation
// omega, with Gaussian pixel noise.
void flow_field(const CameraCalibration& c, cv::Point2f foe, const cv::Vec3d& omega,
                double noise_px, std::uint32_t seed, std::vector<cv::Point2f>& pred,
                std::vector<cv::Point2f>& cur) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> ux(10, c.width - 10), uy(10, c.height - 10),
        ur(0.0, 0.03);
    std::normal_distribution<double> n(0, noise_px);
    const cv::Matx33d h = small_rotation_homography(c, omega);
    pred.clear();
    cur.clear();
    for (int i = 0; i < 200; ++i) {
        const cv::Point2f p(static_cast<float>(ux(rng)), static_cast<float>(uy(rng)));
        const double r = ur(rng);  // 0 (far) .. 3 % a frame (near)
        const cv::Point2f moved = p + (p - foe) * static_cast<float>(r);
        const cv::Point2f q = apply_homography(h, moved);
        pred.push_back(p);
        cur.push_back({q.x + static_cast<float>(n(rng)), q.y + static_cast<float>(n(rng))});
    }
}

}  // namespace

TEST(ResidualRotation, RecoversASmallRotationUnderForwardFlight) {
    const CameraCalibration c = CameraCalibration::ideal(640, 360, 80);
    const cv::Point2f foe(350, 150);
    RotationFitScratch scratch;
    for (const cv::Vec3d& w_deg : {cv::Vec3d(0.4, -0.3, 0.2), cv::Vec3d(-1.0, 0, 0),
                                   cv::Vec3d(0, 0.8, 0), cv::Vec3d(0, 0, -0.6)}) {
        std::vector<cv::Point2f> pred, cur;
        flow_field(c, foe, w_deg * kRadPerDeg, 0.2, 7, pred, cur);
        cv::Vec3d w;
        ASSERT_TRUE(estimate_residual_rotation(c, pred, cur, foe, 30, 1.0, 12, scratch, w));
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(w[k] / kRadPerDeg, w_deg[k], 0.02) << "axis " << k << " of " << w_deg;
    }
}

TEST(ResidualRotation, NoRotationReadsZeroAndOutliersDoNotPullIt) {
    const CameraCalibration c = CameraCalibration::ideal(640, 360, 80);
    const cv::Point2f foe(320, 180);
    std::vector<cv::Point2f> pred, cur;
    flow_field(c, foe, {0, 0, 0}, 0.2, 11, pred, cur);
    // One point in ten slipped by 15 px across its ray (a tracking error).
    for (std::size_t i = 0; i < cur.size(); i += 10) cur[i] += cv::Point2f(0, 15);
    RotationFitScratch scratch;
    cv::Vec3d w;
    ASSERT_TRUE(estimate_residual_rotation(c, pred, cur, foe, 30, 1.0, 12, scratch, w));
    EXPECT_LT(cv::norm(w) / kRadPerDeg, 0.03);
}

TEST(ResidualRotation, TooFewPointsGiveNoEstimate) {
    const CameraCalibration c = CameraCalibration::ideal(640, 360, 80);
    const cv::Point2f foe(320, 180);
    std::vector<cv::Point2f> pred, cur;
    flow_field(c, foe, {0.01, 0, 0}, 0.0, 3, pred, cur);
    pred.resize(5);
    cur.resize(5);
    RotationFitScratch scratch;
    cv::Vec3d w(1, 1, 1);
    EXPECT_FALSE(estimate_residual_rotation(c, pred, cur, foe, 30, 1.0, 12, scratch, w));
    EXPECT_EQ(w, cv::Vec3d(0, 0, 0));
}

TEST(TrackerGrid, ABusyBackgroundCannotTakeEverySlot) {
    // Fine, strong texture on the top half of the view only at first; a weakly textured lower
    // half. With the grid every cell holds at most its share and the lower cells get tracks.
    const CameraCalibration c = CameraCalibration::ideal(640, 360, 60);
    cv::Mat img = gs::vision::make_texture(640, 360, 5);
    cv::Mat lower = img(cv::Rect(0, 180, 640, 180));
    lower.convertTo(lower, -1, 0.15, 110);  // low contrast: weaker corners
    for (const bool grid : {false, true}) {
        TrackerParams p;
        p.max_tracks = 120;
        p.detect_interval = 1;
        if (grid) {
            p.grid_cols = 4;
            p.grid_rows = 3;
        }
        TrajectoryTracker t;
        t.configure(c, p);
        for (int f = 0; f < 4; ++f) t.update(img, f * 40'000'000LL, 0, cv::Matx33d::eye());
        int lower_tracks = 0;
        std::vector<int> per_cell(12, 0);
        for (const Trajectory& tr : t.tracks()) {
            lower_tracks += tr.raw.y >= 240 ? 1 : 0;
            const int cx = std::min(3, static_cast<int>(tr.raw.x / 160));
            const int cy = std::min(2, static_cast<int>(tr.raw.y / 120));
            ++per_cell[static_cast<std::size_t>(cy * 4 + cx)];
        }
        if (grid) {
            for (int n : per_cell) EXPECT_LE(n, 10);  // ceil(120 / 12)
            EXPECT_GE(lower_tracks, 30);              // the bottom row's four cells fill up
        } else {
            EXPECT_LT(lower_tracks, 10) << "the test scene should starve the lower half";
        }
    }
}
