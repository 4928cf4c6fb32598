// Ego-motion from tracked points (vision/ego_motion.hpp): rotation and focus of expansion under
// known synthetic flow, moving objects as outliers, navdata priors used or rejected.

#include "vision/ego_motion.hpp"

#include "vision/common.hpp"
#include "vision/stabilisation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

using namespace gs::vision;

namespace {

// Points scattered over the image, each moved by a translation toward the camera (expansion
// about `foe` at a rate per frame that differs per point as depths differ) and then by the small
// rotation omega, with Gaussian pixel noise.
void flow_field(const CameraCalibration& c, cv::Point2f foe, const cv::Vec3d& omega,
                double noise_px, std::uint32_t seed, std::vector<cv::Point2f>& pred,
                std::vector<cv::Point2f>& cur, double max_rate = 0.03, int count = 200) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> ux(10, c.width - 10), uy(10, c.height - 10),
        ur(0.0, max_rate);
    std::normal_distribution<double> n(0, noise_px);
    const cv::Matx33d h = small_rotation_homography(c, omega);
    pred.clear();
    cur.clear();
    for (int i = 0; i < count; ++i) {
        const cv::Point2f p(static_cast<float>(ux(rng)), static_cast<float>(uy(rng)));
        const double r = ur(rng);  // 0 (far) .. max_rate a frame (near)
        const cv::Point2f moved = p + (p - foe) * static_cast<float>(r);
        const cv::Point2f q = apply_homography(h, moved);
        pred.push_back(p);
        cur.push_back({q.x + static_cast<float>(n(rng)), q.y + static_cast<float>(n(rng))});
    }
}

const CameraCalibration kCam = CameraCalibration::ideal(640, 360, 80);

}  // namespace

TEST(EgoMotion, RecoversRotationAndFocusOfExpansionWithoutNavdata) {
    EgoMotionEstimator est;
    for (const cv::Point2f foe : {cv::Point2f(320, 180), cv::Point2f(400, 150)}) {
        for (const cv::Vec3d& w_deg : {cv::Vec3d(0.4, -0.3, 0.2), cv::Vec3d(-1.0, 0, 0),
                                       cv::Vec3d(0, 0.8, 0), cv::Vec3d(0, 0, -0.6)}) {
            std::vector<cv::Point2f> pred, cur;
            flow_field(kCam, foe, w_deg * kRadPerDeg, 0.2, 7, pred, cur);
            const EgoMotion& m = est.estimate(kCam, pred, cur, {}, {});
            ASSERT_TRUE(m.valid);
            ASSERT_EQ(m.translation, EgoMotion::Translation::Known);
            for (int k = 0; k < 3; ++k)
                EXPECT_NEAR(m.correction_rad[k] / kRadPerDeg, w_deg[k], 0.03)
                    << "axis " << k << " of " << w_deg;
            // Within three of its own standard errors (a few pixels at 0.2 px of noise).
            EXPECT_LT(m.foe_sigma_px, 8);
            EXPECT_LT(cv::norm(m.foe - foe), std::max(4.0, 3 * m.foe_sigma_px)) << w_deg;
            EXPECT_GT(m.direction[2], 0.9);  // forward
        }
    }
}

TEST(EgoMotion, SlippedPointsAreOutliersAndDoNotPullTheEstimate) {
    std::vector<cv::Point2f> pred, cur;
    flow_field(kCam, {320, 180}, {0, 0, 0}, 0.2, 11, pred, cur);
    // One point in ten slipped by 15 px across its ray (a tracking error).
    for (std::size_t i = 0; i < cur.size(); i += 10) cur[i] += cv::Point2f(0, 15);
    EgoMotionEstimator est;
    const EgoMotion& m = est.estimate(kCam, pred, cur, {}, {});
    ASSERT_TRUE(m.valid);
    EXPECT_LT(cv::norm(m.correction_rad) / kRadPerDeg, 0.1);
    for (std::size_t i = 0; i < cur.size(); ++i) {
        if (i % 10 == 0 && std::abs(pred[i].x - 320) > 40) {
            EXPECT_TRUE(est.outlier(i)) << i;
        }
    }
    EXPECT_LE(m.outliers, 25);
}

TEST(EgoMotion, AStillCameraSeesNoTranslationAndALoomingHandStandsOut) {
    // Background still (tracking noise only); 30 % of the points on an object in the right half
    // expanding about its own centre, as a hand coming toward a camera on a table.
    std::mt19937 rng(3);
    std::normal_distribution<double> n(0, 0.25);
    std::uniform_real_distribution<double> ux(10, 630), uy(10, 350), hx(380, 560), hy(80, 280);
    std::vector<cv::Point2f> pred, cur;
    std::vector<bool> on_hand;
    for (int i = 0; i < 200; ++i) {
        const bool hand = i % 10 < 3;
        const cv::Point2f p(static_cast<float>(hand ? hx(rng) : ux(rng)),
                            static_cast<float>(hand ? hy(rng) : uy(rng)));
        cv::Point2f q = p;
        if (hand) q = p + (p - cv::Point2f(470, 180)) * 0.06f;  // TTC ~ 17 frames
        pred.push_back(p);
        cur.push_back({q.x + static_cast<float>(n(rng)), q.y + static_cast<float>(n(rng))});
        on_hand.push_back(hand);
    }
    EgoMotionEstimator est;
    const EgoMotion& m = est.estimate(kCam, pred, cur, {}, {});
    ASSERT_TRUE(m.valid);
    // The hand does not turn the camera: no rotation is read into its expansion.
    EXPECT_LT(cv::norm(m.correction_rad) / kRadPerDeg, 0.05);
    // Two readings explain these images equally: a still camera and a moving hand (its points
    // stand out), or a camera moving toward the hand with the background far away (the FOE on
    // the hand). Either way the hand's expansion is what approaches.
    if (m.translation == EgoMotion::Translation::None) {
        int hand_out = 0, bg_out = 0, hand_far = 0;
        for (std::size_t i = 0; i < pred.size(); ++i) {
            const bool far_from_centre = cv::norm(pred[i] - cv::Point2f(470, 180)) > 30;
            if (on_hand[i] && far_from_centre) {
                ++hand_far;
                hand_out += est.outlier(i);
            }
            if (!on_hand[i]) bg_out += est.outlier(i);
        }
        EXPECT_GE(hand_out, hand_far * 9 / 10);
        EXPECT_LE(bg_out, 2);
    } else {
        ASSERT_EQ(m.translation, EgoMotion::Translation::Known);
        EXPECT_LT(cv::norm(m.foe - cv::Point2f(470, 180)), 10);
    }
}

TEST(EgoMotion, AStillCameraWithNothingMovingSeesNoTranslation) {
    std::mt19937 rng(4);
    std::normal_distribution<double> n(0, 0.25);
    std::uniform_real_distribution<double> ux(10, 630), uy(10, 350);
    std::vector<cv::Point2f> pred, cur;
    for (int i = 0; i < 150; ++i) {
        const cv::Point2f p(static_cast<float>(ux(rng)), static_cast<float>(uy(rng)));
        pred.push_back(p);
        cur.push_back({p.x + static_cast<float>(n(rng)), p.y + static_cast<float>(n(rng))});
    }
    EgoMotionEstimator est;
    const EgoMotion& m = est.estimate(kCam, pred, cur, {}, {});
    ASSERT_TRUE(m.valid);
    EXPECT_EQ(m.translation, EgoMotion::Translation::None);
    EXPECT_LE(m.outliers, 2);
    EXPECT_LT(m.translation_px, 0.5);
}

// A camera on a table or a hovering drone filmed without navdata: the static majority of the
// points barely moves (a compressed video's still blocks: 0.05 px), while people and hands move
// 15 % of them by pixels in no common pattern. That is a still camera with moving things in
// front of it, also right after a flight (the estimator keeps a translation it has seen for a
// few frames unless the scene says otherwise); ego.still_k off, a camera that was flying stays
// "translating", and so many moving points are more than the few the rule for stillness allows.
TEST(EgoMotion, AStillMajorityIsAStillCameraWhateverAFewMovingThingsDo) {
    for (const double still_k : {0.5, 0.0}) {
        EgoMotionParams p;
        p.still_k = still_k;
        EgoMotionEstimator est;
        std::vector<cv::Point2f> pred, cur;
        for (std::uint32_t f = 0; f < 4; ++f) {  // flying toward (320, 180)
            flow_field(kCam, {320, 180}, {0, 0, 0}, 0.2, 20 + f, pred, cur);
            ASSERT_EQ(est.estimate(kCam, pred, cur, {}, p).translation,
                      EgoMotion::Translation::Known);
        }
        std::mt19937 rng(5);
        std::normal_distribution<double> n(0, 0.05), jump(0, 8);
        std::uniform_real_distribution<double> ux(10, 630), uy(10, 350);
        int still_frames = 0;
        for (int f = 0; f < 6; ++f) {
            pred.clear();
            cur.clear();
            std::vector<bool> moving;
            for (int i = 0; i < 200; ++i) {
                const cv::Point2f q(static_cast<float>(ux(rng)), static_cast<float>(uy(rng)));
                const bool m = i % 20 < 3;
                const double sx = m ? jump(rng) : n(rng), sy = m ? jump(rng) : n(rng);
                pred.push_back(q);
                cur.push_back(q + cv::Point2f(static_cast<float>(sx), static_cast<float>(sy)));
                moving.push_back(m && std::hypot(sx, sy) > 2);
            }
            const EgoMotion& m = est.estimate(kCam, pred, cur, {}, p);
            ASSERT_TRUE(m.valid);
            if (m.translation != EgoMotion::Translation::None) continue;
            ++still_frames;
            EXPECT_LT(cv::norm(m.correction_rad) / kRadPerDeg, 0.02);
            for (std::size_t i = 0; i < moving.size(); ++i)
                if (moving[i]) {
                    EXPECT_TRUE(est.outlier(i)) << i;  // judged as moving by themselves
                }
        }
        if (still_k > 0) {
            EXPECT_EQ(still_frames, 6);
        } else {
            EXPECT_EQ(still_frames, 0);
        }
    }
}

TEST(EgoMotion, AConsistentNavdataRotationIsUsedAWrongOneRejected) {
    // The points were already moved by the navdata rotation (pred); what is left is either small
    // (the navdata was right) or 2 degrees of yaw it missed (a stale sample).
    EgoMotionEstimator est;
    EgoPrior prior;
    prior.rotation = true;
    prior.rotation_sigma_deg = 0.15;
    std::vector<cv::Point2f> pred, cur;
    flow_field(kCam, {320, 180}, cv::Vec3d(0, 0.05, 0) * kRadPerDeg, 0.2, 5, pred, cur);
    const EgoMotion& ok = est.estimate(kCam, pred, cur, prior, {});
    ASSERT_TRUE(ok.valid);
    EXPECT_TRUE(ok.prior_rotation_used);
    EXPECT_FALSE(ok.prior_rotation_rejected);
    // The images alone see the 0.05 degrees; fused with the prior, one frame moves it less.
    EXPECT_NEAR(ok.image_rad[1] / kRadPerDeg, 0.05, 0.03);
    EXPECT_GE(ok.image_var[1], std::pow(0.3 * kRadPerDeg, 2));
    EXPECT_LT(std::abs(ok.correction_rad[1]), std::abs(ok.image_rad[1]));

    flow_field(kCam, {320, 180}, cv::Vec3d(0, 2.0, 0) * kRadPerDeg, 0.2, 5, pred, cur);
    const EgoMotion& bad = est.estimate(kCam, pred, cur, prior, {});
    ASSERT_TRUE(bad.valid);
    EXPECT_TRUE(bad.prior_rotation_rejected);
    EXPECT_NEAR(bad.correction_rad[1] / kRadPerDeg, 2.0, 0.05);
}

TEST(EgoMotion, AVelocityDirectionTheImagesContradictIsRejected) {
    std::vector<cv::Point2f> pred, cur;
    const cv::Point2f foe(320, 180);
    flow_field(kCam, foe, {0, 0, 0}, 0.2, 9, pred, cur);
    EgoMotionEstimator est;
    EgoPrior prior;
    prior.translation_sigma_rad = 0.02;
    // Agreeing: straight ahead.
    prior.translation = {0, 0, 1};
    const EgoMotion& ok = est.estimate(kCam, pred, cur, prior, {});
    ASSERT_EQ(ok.translation, EgoMotion::Translation::Known);
    EXPECT_FALSE(ok.prior_translation_rejected);
    EXPECT_NEAR(ok.foe.x, foe.x, 3);
    // A biased velocity: 12 degrees to the right of the true direction.
    const double a = 12 * kRadPerDeg;
    prior.translation = {std::sin(a), 0, std::cos(a)};
    const EgoMotion& bad = est.estimate(kCam, pred, cur, prior, {});
    ASSERT_EQ(bad.translation, EgoMotion::Translation::Known);
    EXPECT_TRUE(bad.prior_translation_rejected);
    EXPECT_NEAR(bad.foe.x, foe.x, 4);
}

TEST(EgoMotion, SidewaysMotionHasNoReliableFocusOfExpansionInTheImage) {
    // Translation to the right: parallel flow to the left, FOE at infinity.
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> ux(10, 630), uy(10, 350), ud(2.0, 8.0);
    std::normal_distribution<double> n(0, 0.2);
    std::vector<cv::Point2f> pred, cur;
    for (int i = 0; i < 150; ++i) {
        const cv::Point2f p(static_cast<float>(ux(rng)), static_cast<float>(uy(rng)));
        pred.push_back(p);
        cur.push_back({p.x - static_cast<float>(ud(rng)) + static_cast<float>(n(rng)),
                       p.y + static_cast<float>(n(rng))});
    }
    EgoMotionEstimator est;
    // Without navdata this is not taken as a translation (its FOE cannot be placed): a still
    // camera, everything moving by itself, none of it approaching.
    const EgoMotion& blind = est.estimate(kCam, pred, cur, {}, {});
    ASSERT_TRUE(blind.valid);
    EXPECT_EQ(blind.translation, EgoMotion::Translation::None);
    // With a navdata velocity to the right it is one, whose FOE lies far outside the image.
    EgoPrior prior;
    prior.translation = {1, 0, 0};
    prior.translation_sigma_rad = 0.05;
    const EgoMotion& m = est.estimate(kCam, pred, cur, prior, {});
    ASSERT_TRUE(m.valid);
    ASSERT_EQ(m.translation, EgoMotion::Translation::Known);
    EXPECT_FALSE(m.prior_translation_rejected);
    EXPECT_GT(std::abs(m.direction[0]), 0.95);
    EXPECT_TRUE(std::isnan(m.foe.x) || m.foe_sigma_px > 40);
}

TEST(EgoMotion, TooFewPointsGiveNoEstimate) {
    std::vector<cv::Point2f> pred, cur;
    flow_field(kCam, {320, 180}, {0.01, 0, 0}, 0.0, 3, pred, cur);
    pred.resize(5);
    cur.resize(5);
    EgoMotionEstimator est;
    const EgoMotion& m = est.estimate(kCam, pred, cur, {}, {});
    EXPECT_FALSE(m.valid);
    EXPECT_EQ(m.translation, EgoMotion::Translation::Unknown);
    EXPECT_EQ(m.correction_rad, cv::Vec3d(0, 0, 0));
}

// NavdataRateError: what the images say of the navdata rotation, followed as an IMU errs.
namespace {
constexpr double kRad = CV_PI / 180.0;                                // per degree
const cv::Vec3d kImageVar = cv::Vec3d::all(std::pow(0.3 * kRad, 2));  // the image floor
}  // namespace

TEST(NavdataRateError, ASteadyPullWhileFlyingStraightIsNotTakenForAGyroBias) {
    // Two seconds of straight flight where the images, pulled by a close obstacle on one side,
    // read 0.08 degrees of yaw a frame that the navdata does not have (2.4 deg/s: no gyro errs
    // so). Followed as a random walk it would be learnt within a second; as a bias of at most
    // about 0.5 deg/s it stays a small fraction of the pull.
    NavdataRateError f;
    const double dt = 1.0 / 30;
    cv::Vec3d corr;
    for (int i = 0; i < 60; ++i) corr = f.update({0, 0.08 * kRad, 0}, kImageVar, {0, 0, 0}, dt);
    EXPECT_GT(corr[1], 0.0);
    EXPECT_LT(corr[1], 0.2 * 0.08 * kRad);
    EXPECT_LT(std::abs(f.bias_rad_s(1)), 0.5 * kRad);
    EXPECT_EQ(corr[0], 0.0);  // the other axes saw nothing
}

TEST(NavdataRateError, AScaleErrorIsLearntWhileTurningAndFollowsTheRate) {
    // The navdata reads 12 deg/s of a 15 deg/s yaw (80 %): 3 deg/s, 0.12 degrees a frame at 25
    // fps, missing. With a scale prior that allows such an IMU (20 %, not the default's 3 %),
    // after two seconds of turning most of it is learnt, as a scale: when the turn slows to
    // 5 deg/s (4 read), the correction shrinks with it instead of staying 0.12.
    RateErrorParams wide;
    wide.scale_sigma = 0.2;
    NavdataRateError f(wide);
    const double dt = 1.0 / 25;
    cv::Vec3d corr;
    for (int i = 0; i < 50; ++i)
        corr = f.update({0, 3.0 * kRad * dt, 0}, kImageVar, {0, 12.0 * kRad * dt, 0}, dt);
    EXPECT_NEAR(corr[1], 0.12 * kRad, 0.03 * kRad);
    EXPECT_NEAR(f.scale(1), 0.25, 0.07);
    corr = f.update({0, 1.0 * kRad * dt, 0}, kImageVar, {0, 4.0 * kRad * dt, 0}, dt);
    EXPECT_NEAR(corr[1], 0.04 * kRad, 0.015 * kRad);
}

TEST(NavdataRateError, APitchRateTheImagesReadShortInAnAccelerationIsNotLearntAsAScale) {
    // A drone pitching its nose up at 10 deg/s for a second while it speeds up: the floor's
    // growing expansion and the pitch rate look alike, and the images read the rate 35 % short
    // (the realism suite's take-offs). A MEMS gyro errs by a few per cent: with the default
    // prior the filter learns little of it and the derotation keeps most of the navdata's rate;
    // with a 20 % prior it learns most of the misreading, a third of the pitch left in the flow.
    const double dt = 1.0 / 30, nav = 10.0 * kRad * dt;
    const auto fly = [&](const RateErrorParams& p) {
        NavdataRateError f(p);
        cv::Vec3d corr;
        for (int i = 0; i < 30; ++i)
            corr = f.update({-0.35 * nav, 0, 0}, kImageVar, {nav, 0, 0}, dt);
        return std::pair{corr[0], f.scale(0)};
    };
    const auto [corr, scale] = fly(RateErrorParams{});
    EXPECT_GT(scale, -0.06);
    EXPECT_GT(corr, -0.06 * nav);  // under 6 % of the rate taken away
    RateErrorParams wide;
    wide.scale_sigma = 0.2;
    const auto [corr_wide, scale_wide] = fly(wide);
    EXPECT_LT(scale_wide, -0.2);
    EXPECT_LT(corr_wide, -0.2 * nav);
}

TEST(NavdataRateError, ANavdataAFrameLateIsFoundAndItsErrorTakenFromTheImages) {
    // Three seconds of pitching back and forth (0.5 degrees a frame at most, a 12-frame period)
    // with the navdata one frame late: each frame it reports the last frame's rotation, off by
    // up to 0.26 degrees whenever the rate changes, an error no bias or scale follows. The images
    // see each frame's rotation. The filter finds the lag (the shift at which the navdata
    // matches the images) and, allowing for a lag that size times the change of rate, takes
    // much of that error from the images: the derotation's error over the last second is under
    // 60 % of the navdata's (the images' own noise, 0.3 degrees a frame, limits what it takes).
    const double dt = 1.0 / 30, amp = 0.5 * kRad;
    const auto truth = [&](int k) { return amp * std::sin(2 * CV_PI * k / 12.0); };
    NavdataRateError f;
    double nav_err = 0, left = 0;
    for (int k = 1; k <= 90; ++k) {
        const double nav = truth(k - 1);
        const double corr = f.update({truth(k) - nav, 0, 0}, kImageVar, {nav, 0, 0}, dt)[0];
        if (k > 60) {
            nav_err += std::abs(truth(k) - nav);
            left += std::abs(truth(k) - nav - corr);
        }
    }
    EXPECT_NEAR(f.lag_s(), dt, 0.3 * dt);
    EXPECT_LT(left, 0.6 * nav_err);
    // With the lag not allowed for, the same flight keeps most of the navdata's error.
    RateErrorParams none;
    none.latency_sigma_s = 0;
    NavdataRateError g(none);
    double left_none = 0;
    for (int k = 1; k <= 90; ++k) {
        const double nav = truth(k - 1);
        const double corr = g.update({truth(k) - nav, 0, 0}, kImageVar, {nav, 0, 0}, dt)[0];
        if (k > 60) left_none += std::abs(truth(k) - nav - corr);
    }
    std::printf(
        "derotation error over the last second: navdata %.3f deg, with the lag allowed "
        "for %.3f, without %.3f\n",
        nav_err / kRad, left / kRad, left_none / kRad);
    EXPECT_GT(left_none, 0.9 * nav_err);
    EXPECT_LT(left, 0.7 * left_none);
}

TEST(NavdataRateError, ANavdataInStepWithTheImagesHasNoLagAndAOneFrameMisreadingIsNotTakenIn) {
    // The same manoeuvre with the navdata on time and the images reading each frame within a
    // few hundredths of a degree of it: no lag is found. Then the pitch rate steps and the
    // images read that frame 0.5 degrees off (a near obstacle's flow taken for rotation): with
    // no lag to allow for, the correction takes in little of it.
    const double dt = 1.0 / 30, amp = 0.5 * kRad;
    const auto truth = [&](int k) { return amp * std::sin(2 * CV_PI * k / 12.0); };
    NavdataRateError f;
    for (int k = 1; k <= 90; ++k) {
        const double noise = (k % 3 - 1) * 0.03 * kRad;
        f.update({noise, 0, 0}, kImageVar, {truth(k), 0, 0}, dt);
    }
    EXPECT_LT(f.lag_s(), 0.1 * dt);
    const double miss = 0.5 * kRad;
    const double corr = f.update({miss, 0, 0}, kImageVar, {truth(91) + 1.0 * kRad, 0, 0}, dt)[0];
    EXPECT_LT(std::abs(corr), 0.2 * miss);
}

TEST(NavdataRateError, NoFrameTimeChangesNothing) {
    NavdataRateError f;
    EXPECT_EQ(f.update({0.01, 0.01, 0.01}, kImageVar, {0.1, 0.1, 0.1}, 0.0), cv::Vec3d(0, 0, 0));
    EXPECT_EQ(f.update({0.01, 0.01, 0.01}, kImageVar, {0.1, 0.1, 0.1}, -0.04), cv::Vec3d(0, 0, 0));
    EXPECT_EQ(f.bias_rad_s(0), 0.0);
    EXPECT_EQ(f.scale(0), 0.0);
}
