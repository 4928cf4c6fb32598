// Visual odometry (thesis §3.1.5, eq. 3.13-3.20, 6.1, 6.2): the pure pieces against hand-computed
// cases, the filters at their thresholds, the eq. 6.2 trajectory on hand-drawn paths, and the
// whole estimator (Shi-Tomasi + LK + RANSAC homography) on synthetic views of a textured floor and
// ceiling under known motion.
//
// Conventions (vision/odometry.hpp, docs/dataset.md): body x forward, y right, yaw clockwise seen
// from above; world x north, y east. Image x right, y down. A downward camera has image right =
// body right and image up = body forward; an upward camera has image up = body forward and image
// right = body left.
#include "vision/odometry.hpp"
#include "drone/core/geometry.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

using namespace gs::vision;
using gs::CameraCalibration;
namespace geom = gs::geom;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

cv::Matx22d rot2(double deg) {
    const double c = std::cos(deg * kDeg), s = std::sin(deg * kDeg);
    return {c, -s, s, c};
}

// A homography [R T; 0 1] in pixels.
cv::Matx33d homography(const cv::Matx22d& r, double tx, double ty) {
    return {r(0, 0), r(0, 1), tx, r(1, 0), r(1, 1), ty, 0, 0, 1};
}

BodyMotion motion(double forward_m, double right_m, double yaw_deg) {
    BodyMotion m;
    m.forward_m = forward_m;
    m.right_m = right_m;
    m.yaw_deg = yaw_deg;
    m.r_body = rot2(-yaw_deg);  // the body-axes point motion of a yaw (see body_motion_from_...)
    return m;
}

// ---- Synthetic views of a textured plane -----------------------------------------------------

CameraCalibration synthetic_camera() {
    return CameraCalibration::ideal(640, 360, 70);  // fx = fy = 320 / tan 35° = 457.0 px
}

// A plane (floor or ceiling) as a texture: `px_per_m` texels per metre, world origin at the
// texture centre, north up, east right (as seen from above).
struct PlaneTexture {
    cv::Mat texture;
    double px_per_m = 0;
};

// Random blobs a few texels across (uniform noise upsampled), good Shi-Tomasi corners everywhere.
PlaneTexture make_plane_texture(double px_per_m, double size_m, std::uint64_t seed) {
    const int n = static_cast<int>(std::lround(px_per_m * size_m));
    cv::Mat noise(n / 4, n / 4, CV_8U);
    cv::RNG rng(seed);
    rng.fill(noise, cv::RNG::UNIFORM, 0, 256);
    PlaneTexture p;
    cv::resize(noise, p.texture, cv::Size(n, n), 0, 0, cv::INTER_CUBIC);
    cv::GaussianBlur(p.texture, p.texture, cv::Size(0, 0), 1.0);
    p.px_per_m = px_per_m;
    return p;
}

// The view of the plane at `distance_m` along the optical axis from a level camera on a body at
// `pose` (world x north, y east, yaw clockwise from above).
cv::Mat render_view(const PlaneTexture& plane, const CameraCalibration& cal, CameraMount mount,
                    double distance_m, const PlanarPose& pose) {
    // Pixel -> metres in the camera frame on the plane (x right, y down).
    const double ax = distance_m / cal.fx, ay = distance_m / cal.fy;
    const cv::Matx33d cam{ax, 0, -ax * cal.cx, 0, ay, -ay * cal.cy, 0, 0, 1};
    // Camera -> body (forward, right): forward = -camera y, right = +-camera x (mirrored on top).
    const double rs = mount == CameraMount::Top ? -1.0 : 1.0;
    const cv::Matx33d body{0, -1, 0, rs, 0, 0, 0, 0, 1};
    // Body -> world.
    const double c = std::cos(pose.yaw_deg * kDeg), s = std::sin(pose.yaw_deg * kDeg);
    const cv::Matx33d world{c, -s, pose.x_m, s, c, pose.y_m, 0, 0, 1};
    // World -> texel: east right, north up, origin at the centre.
    const double k = plane.px_per_m, o = (plane.texture.cols - 1) / 2.0;
    const cv::Matx33d texel{0, k, o, -k, 0, o, 0, 0, 1};
    const cv::Matx33d m = texel * world * body * cam;  // output pixel -> texel
    cv::Mat img;
    cv::warpPerspective(plane.texture, img, cv::Mat(m), cv::Size(cal.width, cal.height),
                        cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_REPLICATE);
    return img;
}

// Pose after a sample of (forward, right, yaw): the translation is in the body frame at the new
// pose, as the estimator reports it (eq. 6.2 sums the yaw including the sample).
PlanarPose advance(const PlanarPose& p, double forward_m, double right_m, double yaw_deg) {
    PlanarPose q = p;
    q.yaw_deg += yaw_deg;
    const double c = std::cos(q.yaw_deg * kDeg), s = std::sin(q.yaw_deg * kDeg);
    q.x_m += c * forward_m - s * right_m;
    q.y_m += s * forward_m + c * right_m;
    return q;
}

constexpr double kFloorDistance_m = 1.2;
constexpr double kCeilingDistance_m = 2.9;

// Texel density ~1.3x the image's on the plane, so the warp does not alias.
const PlaneTexture& floor_texture() {
    static const PlaneTexture t =
        make_plane_texture(1.3 * 457.0 / kFloorDistance_m, 4.0, 0x0D0F100Bu);
    return t;
}
const PlaneTexture& ceiling_texture() {
    static const PlaneTexture t =
        make_plane_texture(1.3 * 457.0 / kCeilingDistance_m, 7.0, 0xCE111Eu);
    return t;
}

OdometryInput bottom_input(const PlanarPose& pose, std::int64_t i) {
    OdometryInput in;
    in.t_ns = i * 66'666'667;
    in.bottom = render_view(floor_texture(), synthetic_camera(), CameraMount::Bottom,
                            kFloorDistance_m, pose);
    in.bottom_distance_m = kFloorDistance_m;
    return in;
}

OdometryInput two_camera_input(const PlanarPose& pose, std::int64_t i) {
    OdometryInput in = bottom_input(pose, i);
    in.top = render_view(ceiling_texture(), synthetic_camera(), CameraMount::Top,
                         kCeilingDistance_m, pose);
    in.top_distance_m = kCeilingDistance_m;
    return in;
}

// Mean absolute grey-level difference, over the image centre, between the view from `moved`
// and the view from the origin shifted by (dx, dy) px.
double shift_residual(CameraMount mount, const PlanarPose& moved, double dx, double dy) {
    const CameraCalibration cal = synthetic_camera();
    const bool top = mount == CameraMount::Top;
    const PlaneTexture& tex = top ? ceiling_texture() : floor_texture();
    const double d = top ? kCeilingDistance_m : kFloorDistance_m;
    const cv::Mat a = render_view(tex, cal, mount, d, {});
    const cv::Mat b = render_view(tex, cal, mount, d, moved);
    cv::Mat shifted;
    const cv::Matx23d tr{1, 0, dx, 0, 1, dy};
    cv::warpAffine(a, shifted, cv::Mat(tr), a.size(), cv::INTER_LINEAR);
    const cv::Rect roi(160, 90, 320, 180);
    return cv::norm(shifted(roi), b(roi), cv::NORM_L1) / roi.area();
}

// Tolerances of the synthetic runs: 0.5 mm is 0.2 px on the floor 1.2 m away, 0.015° is 0.1 px at
// the image corners. (Measured about the principal point: under 0.05 mm and 0.007°.)
constexpr double kTolM = 0.0005;
constexpr double kTolDeg = 0.015;

}  // namespace

// ---- Homography decomposition (eq. 3.13, 3.18) -----------------------------------------------

TEST(OdometryHomography, PureRotationGivesTheAngleAndNoTranslation) {
    const HomographyParts p = decompose_homography(homography(rot2(10), 0, 0));
    ASSERT_TRUE(p.ok);
    EXPECT_NEAR(p.angle_rad, 10 * kDeg, 1e-12);
    EXPECT_NEAR(p.r(0, 0), std::cos(10 * kDeg), 1e-12);
    EXPECT_NEAR(p.r(1, 0), std::sin(10 * kDeg), 1e-12);
    EXPECT_EQ(p.t, cv::Vec2d(0, 0));
    EXPECT_EQ(p.s, cv::Vec2d(0, 0));
    // Negative and beyond 90 degrees: atan2 keeps the quadrant.
    EXPECT_NEAR(decompose_homography(homography(rot2(-35), 0, 0)).angle_rad, -35 * kDeg, 1e-12);
    EXPECT_NEAR(decompose_homography(homography(rot2(120), 0, 0)).angle_rad, 120 * kDeg, 1e-12);
}

TEST(OdometryHomography, PureTranslationGivesTheTranslationAndZeroAngle) {
    const HomographyParts p = decompose_homography(homography(cv::Matx22d::eye(), 12.5, -3.25));
    ASSERT_TRUE(p.ok);
    EXPECT_DOUBLE_EQ(p.t[0], 12.5);
    EXPECT_DOUBLE_EQ(p.t[1], -3.25);
    EXPECT_DOUBLE_EQ(p.angle_rad, 0.0);
    EXPECT_EQ(p.r, cv::Matx22d::eye());
}

TEST(OdometryHomography, RotationAndTranslationNormalisedByH33) {
    // The same homography times 2.5 (h33 = 2.5): the parts are those of the normalised one.
    const cv::Matx33d h = homography(rot2(30), 52.825, 12.01) * 2.5;
    const HomographyParts p = decompose_homography(h);
    ASSERT_TRUE(p.ok);
    EXPECT_NEAR(p.angle_rad, 30 * kDeg, 1e-12);
    EXPECT_NEAR(p.t[0], 52.825, 1e-12);
    EXPECT_NEAR(p.t[1], 12.01, 1e-12);
    EXPECT_NEAR(p.r(0, 1), -0.5, 1e-12);
    EXPECT_NEAR(p.r(1, 1), std::sqrt(3.0) / 2, 1e-12);
}

TEST(OdometryHomography, ThesisExampleIsTakenAsIsWithoutOrthonormalising) {
    // Eq. 3.11 has a non-orthogonal, non-unit rotation block; the code does not orthonormalise:
    // the block is returned as it is and the angle is atan2(r3, r1) (eq. 3.18) of its first
    // column, atan2(0.0182, 0.9598) = 1.0863286°.
    const cv::Matx33d h(0.9598, -0.0337, 52.8250, 0.0182, 0.9659, 12.0100, 1e-5, -2e-5, 1);
    const HomographyParts p = decompose_homography(h);
    ASSERT_TRUE(p.ok);
    EXPECT_NEAR(p.angle_rad / kDeg, 1.0863286415936617, 1e-12);
    EXPECT_DOUBLE_EQ(p.r(0, 0), 0.9598);
    EXPECT_DOUBLE_EQ(p.r(0, 1), -0.0337);
    EXPECT_DOUBLE_EQ(p.r(1, 0), 0.0182);
    EXPECT_DOUBLE_EQ(p.r(1, 1), 0.9659);
    EXPECT_DOUBLE_EQ(p.t[0], 52.825);
    EXPECT_DOUBLE_EQ(p.t[1], 12.01);
    EXPECT_DOUBLE_EQ(p.s[0], 1e-5);  // the skew row (ignored by the method)
    EXPECT_DOUBLE_EQ(p.s[1], -2e-5);
    // A uniformly scaled block (zoom) has the same angle.
    const HomographyParts z = decompose_homography(homography(rot2(20) * 1.25, 0, 0));
    EXPECT_NEAR(z.angle_rad, 20 * kDeg, 1e-12);
    EXPECT_NEAR(z.r(0, 0), 1.25 * std::cos(20 * kDeg), 1e-12);
}

TEST(OdometryHomography, DegenerateH33IsRejected) {
    EXPECT_FALSE(decompose_homography(cv::Matx33d(1, 0, 3, 0, 1, 4, 0, 0, 0)).ok);
    EXPECT_FALSE(decompose_homography(cv::Matx33d(1, 0, 3, 0, 1, 4, 0, 0, std::nan(""))).ok);
    EXPECT_FALSE(decompose_homography(cv::Matx33d(1, 0, std::nan(""), 0, 1, 4, 0, 0, 1)).ok);
}

// ---- Pixels to metres (eq. 3.14-3.15) --------------------------------------------------------

TEST(OdometryMetres, PixelsToMetresByHand) {
    // 20 px at fx = 400 px and 1.5 m: 20 / 400 x 1.5 = 0.075 m; -12 px at fy = 300: -0.06 m.
    const cv::Vec2d m = pixels_to_metres({20, -12}, 400, 300, 1.5);
    EXPECT_NEAR(m[0], 0.075, 1e-15);
    EXPECT_NEAR(m[1], -0.06, 1e-15);
    // Linear in the distance.
    const cv::Vec2d m2 = pixels_to_metres({20, -12}, 400, 300, 3.0);
    EXPECT_NEAR(m2[0], 0.15, 1e-15);
    EXPECT_NEAR(m2[1], -0.12, 1e-15);
}

TEST(OdometryMetres, FocalLengthInPixelsIsFocalOverPixelPitch) {
    // 3.6 mm lens, 4.8 mm wide sensor, 640 px: pixel pitch 7.5 µm, F = 3.6 / 0.0075 = 480 px.
    // (Eq. 3.15 as printed, f W / w, would give 0.027 — dimensionally a length, not pixels.)
    EXPECT_NEAR(focal_length_px(3.6, 4.8, 640), 480.0, 1e-12);
    EXPECT_NEAR(focal_length_px(3.6e-3, 2.7e-3, 360), 480.0, 1e-9);
}

TEST(OdometryMetres, BottomCameraTranslationByHand) {
    // Downward camera, fx = 500, fy = 400 px, 2 m: floor points moving 10 px right and 8 px down
    // in the image mean the camera moved 10/500 x 2 = 0.04 m left and 8/400 x 2 = 0.04 m forward.
    const BodyMotion m = body_motion_from_homography(homography(cv::Matx22d::eye(), 10, 8), 500,
                                                     400, 2.0, CameraMount::Bottom);
    EXPECT_NEAR(m.forward_m, 0.04, 1e-12);
    EXPECT_NEAR(m.right_m, -0.04, 1e-12);
    EXPECT_NEAR(m.yaw_deg, 0, 1e-12);
    // Other values, to separate the axes: 5 px right, -20 px (up) at 1 m.
    const BodyMotion n = body_motion_from_homography(homography(cv::Matx22d::eye(), 5, -20), 500,
                                                     400, 1.0, CameraMount::Bottom);
    EXPECT_NEAR(n.forward_m, -0.05, 1e-12);  // points move up: the camera moved back 20/400
    EXPECT_NEAR(n.right_m, -0.01, 1e-12);    // 5/500
}

TEST(OdometryMetres, TopCameraAxesAreMirrored) {
    // Upward camera: image right = body left. Ceiling points moving 10 px right mean the body
    // moved right (the opposite of the bottom camera); up/down is as for the bottom camera.
    const BodyMotion m = body_motion_from_homography(homography(cv::Matx22d::eye(), 10, 8), 500,
                                                     400, 2.0, CameraMount::Top);
    EXPECT_NEAR(m.forward_m, 0.04, 1e-12);
    EXPECT_NEAR(m.right_m, 0.04, 1e-12);
    // A yaw: the floor seen from above turns the other way (R(-a) in image coordinates, y down),
    // the ceiling seen from below the same way as the body (R(+a)); both are yaw +a.
    const BodyMotion b =
        body_motion_from_homography(homography(rot2(-4), 0, 0), 500, 500, 2.0, CameraMount::Bottom);
    const BodyMotion t =
        body_motion_from_homography(homography(rot2(4), 0, 0), 500, 500, 2.0, CameraMount::Top);
    EXPECT_NEAR(b.yaw_deg, 4, 1e-12);
    EXPECT_NEAR(t.yaw_deg, 4, 1e-12);
    EXPECT_NEAR(b.forward_m, 0, 1e-12);
    EXPECT_NEAR(t.right_m, 0, 1e-12);
}

TEST(OdometryMetres, RotationAndTranslationReportTheCurrentFrameDisplacement) {
    // Yaw +5° and a camera displacement of (forward 0.03, right 0.01) m in the current body frame,
    // 2 m over the floor, f = 400 px: in camera axes the displacement is (0.01, -0.03) m, so the
    // points move by -(0.01, -0.03) / 2 x 400 = (-2, +6) px, and the block is R(-5°).
    const BodyMotion m = body_motion_from_homography(homography(rot2(-5), -2, 6), 400, 400, 2.0,
                                                     CameraMount::Bottom);
    EXPECT_NEAR(m.forward_m, 0.03, 1e-12);
    EXPECT_NEAR(m.right_m, 0.01, 1e-12);
    EXPECT_NEAR(m.yaw_deg, 5, 1e-12);
    EXPECT_NEAR(m.r_body(0, 0), std::cos(5 * kDeg), 1e-12);
}

// ---- Two cameras (eq. 3.16-3.18) -------------------------------------------------------------

TEST(OdometryCombine, TranslationsAreAveragedInMetres) {
    // Same motion seen 1.2 m and 3 m away is the same in metres; differing estimates average.
    const BodyMotion c = combine_motions(motion(0.02, -0.01, 0), motion(0.04, 0.03, 0));
    EXPECT_NEAR(c.forward_m, 0.03, 1e-15);
    EXPECT_NEAR(c.right_m, 0.01, 1e-15);
    EXPECT_NEAR(c.yaw_deg, 0, 1e-12);
    // From pixels: bottom 1.2 m and top 3 m away, f = 400 px, 0.03 m forward: bottom points
    // move 10 px down, top points 4 px down (eq. 3.16 with both distances).
    const BodyMotion b = body_motion_from_homography(homography(cv::Matx22d::eye(), 0, 10), 400,
                                                     400, 1.2, CameraMount::Bottom);
    const BodyMotion t = body_motion_from_homography(homography(cv::Matx22d::eye(), 0, 4), 400, 400,
                                                     3.0, CameraMount::Top);
    const BodyMotion bt = combine_motions(b, t);
    EXPECT_NEAR(bt.forward_m, 0.03, 1e-12);
    EXPECT_NEAR(bt.right_m, 0, 1e-12);
}

TEST(OdometryCombine, RotationMatricesAreAveragedThenAtan2) {
    // Two rotations: the mean matrix points halfway (10° and 20° -> 15°).
    EXPECT_NEAR(combine_motions(motion(0, 0, 10), motion(0, 0, 20)).yaw_deg, 15, 1e-12);
    // The matrices are averaged, not the angles: 2 I and R(90°) average to [1 -0.5; 0.5 1],
    // atan2(0.5, 1) = 26.565°, not 45°.
    BodyMotion a, b;
    a.r_body = cv::Matx22d::eye() * 2.0;
    b.r_body = rot2(90);
    const BodyMotion c = combine_motions(a, b);
    EXPECT_NEAR(c.r_body(0, 0), 1.0, 1e-12);
    EXPECT_NEAR(c.r_body(0, 1), -0.5, 1e-12);
    EXPECT_NEAR(c.r_body(1, 0), 0.5, 1e-12);
    EXPECT_NEAR(c.yaw_deg, -26.56505117707799, 1e-10);  // body point motion R(+a) is yaw -a
}

TEST(OdometryCombine, MirroredTopCameraAgreesWithBottomOnYaw) {
    // The raw 2x2 blocks of the two cameras turn opposite ways for one yaw (R(-3°) below,
    // R(+3°) above); averaged raw, as eq. 3.17 literally reads, they would cancel to 0°. In body
    // axes both are yaw +3°, and the combination is +3°.
    const BodyMotion b =
        body_motion_from_homography(homography(rot2(-3), 0, 0), 450, 450, 1.2, CameraMount::Bottom);
    const BodyMotion t =
        body_motion_from_homography(homography(rot2(3), 0, 0), 450, 450, 3.0, CameraMount::Top);
    EXPECT_NEAR(combine_motions(b, t).yaw_deg, 3, 1e-12);
    const HomographyParts raw_b = decompose_homography(homography(rot2(-3), 0, 0));
    const HomographyParts raw_t = decompose_homography(homography(rot2(3), 0, 0));
    const cv::Matx22d raw_mean = (raw_b.r + raw_t.r) * 0.5;
    EXPECT_NEAR(std::atan2(raw_mean(1, 0), raw_mean(0, 0)), 0, 1e-12);
}

// ---- Filters (eq. 3.19, 3.20, the 1° rotation gate) ------------------------------------------

TEST(OdometryFilter, ThesisDefaults) {
    const OdometryFilterParams p;
    EXPECT_TRUE(p.spike_filter);
    EXPECT_DOUBLE_EQ(p.spike_translation_m, 0.06);
    EXPECT_DOUBLE_EQ(p.spike_rotation_deg, 6.0);
    EXPECT_TRUE(p.rotation_gate);
    EXPECT_DOUBLE_EQ(p.rotation_gate_deg, 1.0);
    EXPECT_EQ(p.smoothing_samples, 1);  // the thesis' results are unsmoothed
}

TEST(OdometryFilter, TranslationSpikeAtSixCentimetres) {
    OdometryFilter f;
    for (double v : {0.0599, 0.06, -0.0599}) {
        FilteredMotion o = f.apply(v, 0.01, 0.5);
        EXPECT_FALSE(o.spike_zeroed) << v;
        EXPECT_DOUBLE_EQ(o.forward_m, v);
        EXPECT_DOUBLE_EQ(o.right_m, 0.01);
        EXPECT_DOUBLE_EQ(o.yaw_deg, 0.5);
        o = f.apply(0.01, v, 0.5);
        EXPECT_FALSE(o.spike_zeroed) << v;
        EXPECT_DOUBLE_EQ(o.right_m, v);
    }
    for (double v : {0.0601, -0.0601, 0.5}) {
        // Either axis over 6 cm zeroes all three estimates.
        FilteredMotion o = f.apply(v, 0.01, 0.5);
        EXPECT_TRUE(o.spike_zeroed) << v;
        EXPECT_FALSE(o.rotation_gated);
        EXPECT_EQ(o.forward_m, 0.0);
        EXPECT_EQ(o.right_m, 0.0);
        EXPECT_EQ(o.yaw_deg, 0.0);
        o = f.apply(0.01, v, 0.5);
        EXPECT_TRUE(o.spike_zeroed) << v;
        EXPECT_EQ(o.forward_m, 0.0);
        EXPECT_EQ(o.yaw_deg, 0.0);
    }
}

TEST(OdometryFilter, RotationSpikeAtSixDegrees) {
    OdometryFilter f;
    // 5.99°: no spike, but over the 1° gate, so the translation goes and the rotation stays.
    for (double yaw : {5.99, -5.99, 6.0}) {
        const FilteredMotion o = f.apply(0.02, 0.01, yaw);
        EXPECT_FALSE(o.spike_zeroed) << yaw;
        EXPECT_TRUE(o.rotation_gated) << yaw;
        EXPECT_DOUBLE_EQ(o.yaw_deg, yaw);
        EXPECT_EQ(o.forward_m, 0.0);
    }
    for (double yaw : {6.01, -6.01, 45.0}) {
        const FilteredMotion o = f.apply(0.02, 0.01, yaw);
        EXPECT_TRUE(o.spike_zeroed) << yaw;
        EXPECT_EQ(o.yaw_deg, 0.0);
        EXPECT_EQ(o.forward_m, 0.0);
        EXPECT_EQ(o.right_m, 0.0);
    }
}

TEST(OdometryFilter, RotationGateAtOneDegree) {
    OdometryFilter f;
    for (double yaw : {0.99, -0.99, 1.0}) {
        const FilteredMotion o = f.apply(0.02, -0.03, yaw);
        EXPECT_FALSE(o.rotation_gated) << yaw;
        EXPECT_DOUBLE_EQ(o.forward_m, 0.02);
        EXPECT_DOUBLE_EQ(o.right_m, -0.03);
        EXPECT_DOUBLE_EQ(o.yaw_deg, yaw);
    }
    for (double yaw : {1.01, -1.01, 3.0}) {
        const FilteredMotion o = f.apply(0.02, -0.03, yaw);
        EXPECT_TRUE(o.rotation_gated) << yaw;
        EXPECT_FALSE(o.spike_zeroed);
        EXPECT_EQ(o.forward_m, 0.0);
        EXPECT_EQ(o.right_m, 0.0);
        EXPECT_DOUBLE_EQ(o.yaw_deg, yaw);  // the rotation itself is kept
    }
}

TEST(OdometryFilter, ThresholdsAreParameters) {
    OdometryFilterParams p;
    p.spike_translation_m = 0.10;
    p.spike_rotation_deg = 10;
    p.rotation_gate_deg = 3;
    OdometryFilter f(p);
    FilteredMotion o = f.apply(0.08, -0.09, 2.5);  // under all three moved thresholds
    EXPECT_FALSE(o.spike_zeroed);
    EXPECT_FALSE(o.rotation_gated);
    EXPECT_DOUBLE_EQ(o.forward_m, 0.08);
    EXPECT_DOUBLE_EQ(o.right_m, -0.09);
    o = f.apply(0.101, 0, 0);
    EXPECT_TRUE(o.spike_zeroed);
    o = f.apply(0.01, 0, 8);  // over the 3° gate, under the 10° spike
    EXPECT_FALSE(o.spike_zeroed);
    EXPECT_TRUE(o.rotation_gated);
    EXPECT_DOUBLE_EQ(o.yaw_deg, 8);
    o = f.apply(0.01, 0, 10.5);
    EXPECT_TRUE(o.spike_zeroed);

    // Lower thresholds than the thesis'.
    OdometryFilterParams q;
    q.spike_translation_m = 0.02;
    q.rotation_gate_deg = 0.25;
    OdometryFilter g(q);
    EXPECT_TRUE(g.apply(0.03, 0, 0).spike_zeroed);
    EXPECT_TRUE(g.apply(0.01, 0, 0.3).rotation_gated);
    EXPECT_FALSE(g.apply(0.01, 0, 0.2).rotation_gated);

    // Each filter can be switched off.
    OdometryFilterParams off;
    off.spike_filter = false;
    off.rotation_gate = false;
    OdometryFilter h(off);
    o = h.apply(0.5, -0.7, 30);
    EXPECT_FALSE(o.spike_zeroed);
    EXPECT_FALSE(o.rotation_gated);
    EXPECT_DOUBLE_EQ(o.forward_m, 0.5);
    EXPECT_DOUBLE_EQ(o.right_m, -0.7);
    EXPECT_DOUBLE_EQ(o.yaw_deg, 30);

    // The parameter table names them, and setting them by name moves the behaviour.
    OdometryParams op;
    const auto err = odometry_param_table().from_map(
        op, {{"filter.spike_translation_m", "0.1"}, {"filter.rotation_gate_deg", "2"}});
    ASSERT_TRUE(err.ok());
    OdometryFilter named(op.filter());
    EXPECT_FALSE(named.apply(0.08, 0, 1.5).spike_zeroed);
    EXPECT_FALSE(named.apply(0.08, 0, 1.5).rotation_gated);
    EXPECT_TRUE(named.apply(0.08, 0, 2.5).rotation_gated);
}

TEST(OdometryFilter, FourSampleSmoothingByHand) {
    OdometryFilterParams p;
    p.smoothing_samples = 4;
    OdometryFilter f(p);
    // x: 1, 2, 3, 4, 5 cm then a 10 cm spike (zeroed before the average), y: -1 .. -5, 0.
    const double xs[] = {0.01, 0.02, 0.03, 0.04, 0.05, 0.10, 0.02};
    const double ys[] = {-0.01, -0.02, -0.03, -0.04, -0.05, 0.0, 0.0};
    const double yaws[] = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7};
    // Eq. 3.19 (fewer samples at the start: the mean of those there are).
    const double ex[] = {0.01,
                         0.015,
                         0.02,
                         0.025,
                         (0.02 + 0.03 + 0.04 + 0.05) / 4,
                         (0.03 + 0.04 + 0.05 + 0.0) / 4,
                         (0.04 + 0.05 + 0.0 + 0.02) / 4};
    const double ey[] = {-0.01,
                         -0.015,
                         -0.02,
                         -0.025,
                         -(0.02 + 0.03 + 0.04 + 0.05) / 4,
                         -(0.03 + 0.04 + 0.05) / 4,
                         -(0.04 + 0.05) / 4};
    for (int i = 0; i < 7; ++i) {
        const FilteredMotion o = f.apply(xs[i], ys[i], yaws[i]);
        EXPECT_NEAR(o.forward_m, ex[i], 1e-15) << i;
        EXPECT_NEAR(o.right_m, ey[i], 1e-15) << i;
        // Only x and y are smoothed (eq. 3.19); the spike zeroes the rotation of its sample.
        EXPECT_DOUBLE_EQ(o.yaw_deg, i == 5 ? 0.0 : yaws[i]) << i;
        EXPECT_EQ(o.spike_zeroed, i == 5) << i;
    }
    // reset() empties the window.
    f.reset();
    EXPECT_NEAR(f.apply(0.04, 0.0, 0).forward_m, 0.04, 1e-15);
    EXPECT_NEAR(f.apply(0.00, 0.0, 0).forward_m, 0.02, 1e-15);

    // The window is a parameter: 2 samples.
    p.smoothing_samples = 2;
    OdometryFilter two(p);
    EXPECT_NEAR(two.apply(0.01, 0, 0).forward_m, 0.01, 1e-15);
    EXPECT_NEAR(two.apply(0.03, 0, 0).forward_m, 0.02, 1e-15);
    EXPECT_NEAR(two.apply(0.05, 0, 0).forward_m, 0.04, 1e-15);
    // 1 = off.
    p.smoothing_samples = 1;
    OdometryFilter one(p);
    EXPECT_DOUBLE_EQ(one.apply(0.01, 0, 0).forward_m, 0.01);
    EXPECT_DOUBLE_EQ(one.apply(0.03, 0, 0).forward_m, 0.03);
}

// ---- Trajectory (eq. 6.2) and evaluation (eq. 6.1) -------------------------------------------

TEST(OdometryTrajectory, SquareOfForwardStepsAndRightTurns) {
    // 1 m forward, turn 90° clockwise, four times: north, east, south, west, back home.
    TrajectoryIntegrator t;
    const double expect[][3] = {{1, 0, 0},   {1, 0, 90},  {1, 1, 90},  {1, 1, 180},
                                {0, 1, 180}, {0, 1, 270}, {0, 0, 270}, {0, 0, 360}};
    int k = 0;
    for (int side = 0; side < 4; ++side) {
        for (const auto& step : {std::array<double, 3>{1, 0, 0}, std::array<double, 3>{0, 0, 90}}) {
            const PlanarPose& p = t.add(step[0], step[1], step[2]);
            EXPECT_NEAR(p.x_m, expect[k][0], 1e-12) << k;
            EXPECT_NEAR(p.y_m, expect[k][1], 1e-12) << k;
            EXPECT_NEAR(p.yaw_deg, expect[k][2], 1e-12) << k;
            ++k;
        }
    }
}

TEST(OdometryTrajectory, LPathAndTheSampleRotationComesFirst) {
    // Eq. 6.2 rotates T_i by the yaw summed up to and including sample i.
    TrajectoryIntegrator t;
    t.add(0.5, 0, 0);
    EXPECT_NEAR(t.pose().x_m, 0.5, 1e-12);
    t.add(0, 0.25, 0);  // sideways right: east
    EXPECT_NEAR(t.pose().x_m, 0.5, 1e-12);
    EXPECT_NEAR(t.pose().y_m, 0.25, 1e-12);
    t.add(0.3, 0, 90);  // turn and step in one sample: the step goes east
    EXPECT_NEAR(t.pose().x_m, 0.5, 1e-12);
    EXPECT_NEAR(t.pose().y_m, 0.55, 1e-12);
    t.add(0, 0.2, 0);  // facing east, right is south
    EXPECT_NEAR(t.pose().x_m, 0.3, 1e-12);
    EXPECT_NEAR(t.pose().y_m, 0.55, 1e-12);
    // 30°: forward 1 m goes (cos 30, sin 30).
    TrajectoryIntegrator u;
    u.add(1, 0, 30);
    EXPECT_NEAR(u.pose().x_m, std::sqrt(3.0) / 2, 1e-12);
    EXPECT_NEAR(u.pose().y_m, 0.5, 1e-12);
    // A start pose: facing east at (2, 3).
    TrajectoryIntegrator v({2, 3, 90});
    v.add(1, 0, 0);
    EXPECT_NEAR(v.pose().x_m, 2, 1e-12);
    EXPECT_NEAR(v.pose().y_m, 4, 1e-12);
    v.reset();
    EXPECT_EQ(v.pose().x_m, 0);
    EXPECT_EQ(v.pose().yaw_deg, 0);
}

TEST(OdometryTrajectory, TruthFromPosesInvertsTheIntegration) {
    // (0,0,0) -> (1,0,90): in the new frame (facing east) the step north is 1 m to the left.
    const std::vector<PlanarPose> poses{{0, 0, 0}, {1, 0, 90}, {1, 2, 90}, {1, 2, -170}};
    const std::vector<SampleTruth> gt = truth_from_poses(poses);
    ASSERT_EQ(gt.size(), 4u);
    EXPECT_EQ(gt[0].forward_m, 0);
    EXPECT_NEAR(gt[1].forward_m, 0, 1e-12);
    EXPECT_NEAR(gt[1].right_m, -1, 1e-12);
    EXPECT_NEAR(gt[1].yaw_deg, 90, 1e-12);
    EXPECT_NEAR(gt[2].forward_m, 2, 1e-12);
    EXPECT_NEAR(gt[2].right_m, 0, 1e-12);
    EXPECT_NEAR(gt[3].yaw_deg, 100, 1e-12);  // 90 -> -170 is +100° wrapped
    TrajectoryIntegrator t;
    for (std::size_t i = 1; i < gt.size(); ++i)
        t.add(gt[i].forward_m, gt[i].right_m, gt[i].yaw_deg);
    EXPECT_NEAR(t.pose().x_m, 1, 1e-12);
    EXPECT_NEAR(t.pose().y_m, 2, 1e-12);
    EXPECT_NEAR(wrap_deg(t.pose().yaw_deg), -170, 1e-12);
}

TEST(OdometryTrajectory, WrapDeg) {
    EXPECT_NEAR(wrap_deg(190), -170, 1e-12);
    EXPECT_NEAR(wrap_deg(-190), 170, 1e-12);
    EXPECT_NEAR(wrap_deg(720 + 5), 5, 1e-12);
    EXPECT_NEAR(wrap_deg(180), -180, 1e-12);
    EXPECT_NEAR(wrap_deg(-0.5), -0.5, 1e-12);
}

TEST(OdometryTrajectory, MeanAbsoluteErrorsAndEndPointByHand) {
    // Truth: 1 m north then 1 m east (2 m travelled). Estimates: 1.1 m forward, then 0.9 m
    // right with 1° of rotation; integrated end (1.1, 0.9).
    const std::vector<PlanarPose> truth{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}};
    std::vector<OdometrySample> s(3);
    s[1].out = {1.1, 0.0, 0.0, false, false};
    s[1].pose = {1.1, 0, 0};
    s[2].out = {0.0, 0.9, 1.0, false, false};
    s[2].pose = {1.1, 0.9, 1.0};
    const OdometryErrors e = evaluate_odometry(s, truth);
    ASSERT_EQ(e.x.n, 2);
    EXPECT_NEAR(e.x.mean, 0.05, 1e-12);  // |1.1 - 1|, |0 - 0|
    EXPECT_NEAR(e.x.max, 0.1, 1e-12);
    EXPECT_NEAR(e.x.min, 0.0, 1e-12);
    EXPECT_NEAR(e.y.mean, 0.05, 1e-12);  // 0, |0.9 - 1|
    EXPECT_NEAR(e.yaw.mean, 0.5, 1e-12);
    EXPECT_NEAR(e.distance_travelled_m, 2.0, 1e-12);
    EXPECT_NEAR(e.end_error_m, std::hypot(0.1, 0.1), 1e-12);
    EXPECT_NEAR(e.end_error_pct, 100 * std::hypot(0.1, 0.1) / 2, 1e-10);
    EXPECT_NEAR(e.end_yaw_error_deg, 1.0, 1e-12);
    EXPECT_NEAR(e.max_path_error_m, std::hypot(0.1, 0.1), 1e-12);
    EXPECT_TRUE(e.yaw_nav_abs_deg.empty());  // no navdata yaw in the samples

    const std::vector<double> v{1, 3, 2, std::nan("")};
    const ErrorStats st = error_stats(v);
    EXPECT_EQ(st.n, 3);
    EXPECT_DOUBLE_EQ(st.min, 1);
    EXPECT_DOUBLE_EQ(st.max, 3);
    EXPECT_DOUBLE_EQ(st.mean, 2);
}

// ---- The estimator on synthetic planar motion ------------------------------------------------

TEST(OdometrySynthetic, RendererMatchesTheFrameConventions) {
    // The test's own renderer, checked against the conventions by image shifts: 5 cm forward
    // moves the floor 5 cm x f / D = 19 px down in the bottom image and the ceiling 7.9 px down
    // in the top image; 5 cm right moves the floor left and the ceiling right (mirrored).
    const CameraCalibration cal = synthetic_camera();
    const double k_b = 0.05 * cal.fx / kFloorDistance_m, k_t = 0.05 * cal.fx / kCeilingDistance_m;
    EXPECT_LT(shift_residual(CameraMount::Bottom, {0.05, 0, 0}, 0, k_b), 3.0);
    EXPECT_LT(shift_residual(CameraMount::Bottom, {0, 0.05, 0}, -k_b, 0), 3.0);
    EXPECT_LT(shift_residual(CameraMount::Top, {0.05, 0, 0}, 0, k_t), 3.0);
    EXPECT_LT(shift_residual(CameraMount::Top, {0, 0.05, 0}, k_t, 0), 3.0);
    // A wrong direction does not match.
    EXPECT_GT(shift_residual(CameraMount::Bottom, {0, 0.05, 0}, k_b, 0), 10.0);
    EXPECT_GT(shift_residual(CameraMount::Top, {0, 0.05, 0}, -k_t, 0), 10.0);
}

TEST(OdometrySynthetic, BottomCameraRecoversKnownMotions) {
    struct Case {
        double forward_m, right_m, yaw_deg;
    };
    // Under the 1° gate and the 6 cm spike bound, in all directions.
    const Case cases[] = {{0.04, 0, 0},       {0, 0.05, 0},          {-0.03, -0.02, 0},
                          {0.03, -0.02, 0.6}, {-0.015, 0.035, -0.9}, {0, 0, 0}};
    VisualOdometry vo(synthetic_camera(), std::nullopt);
    EXPECT_FALSE(vo.two_cameras());
    for (const Case& c : cases) {
        const PlanarPose p0{0.2, -0.1, 15};
        const PlanarPose p1 = advance(p0, c.forward_m, c.right_m, c.yaw_deg);
        vo.reset(p0);
        const OdometrySample& s0 = vo.update(bottom_input(p0, 0));
        EXPECT_EQ(s0.bottom.status, CameraStatus::First);
        const OdometrySample& s = vo.update(bottom_input(p1, 1));
        SCOPED_TRACE(::testing::Message() << c.forward_m << ", " << c.right_m << ", " << c.yaw_deg);
        ASSERT_TRUE(s.valid) << to_string(s.bottom.status);
        EXPECT_GT(s.bottom.inliers, 200);
        EXPECT_NEAR(s.out.forward_m, c.forward_m, kTolM);
        EXPECT_NEAR(s.out.right_m, c.right_m, kTolM);
        EXPECT_NEAR(s.out.yaw_deg, c.yaw_deg, kTolDeg);
        EXPECT_FALSE(s.out.spike_zeroed);
        EXPECT_FALSE(s.out.rotation_gated);
        // Integrated from the start pose (eq. 6.2) to the true pose.
        EXPECT_NEAR(s.pose.x_m, p1.x_m, kTolM);
        EXPECT_NEAR(s.pose.y_m, p1.y_m, kTolM);
        EXPECT_NEAR(s.pose.yaw_deg, p1.yaw_deg, kTolDeg);
        // And the truth the evaluation derives from the poses is the same motion.
        const std::vector<PlanarPose> poses{p0, p1};
        const SampleTruth gt = truth_from_poses(poses)[1];
        EXPECT_NEAR(gt.forward_m, c.forward_m, 1e-12);
        EXPECT_NEAR(gt.right_m, c.right_m, 1e-12);
    }
}

TEST(OdometrySynthetic, PureYawIsNoTranslationAboutThePrincipalPoint) {
    // 4° in one sample, gate off to see the translation the estimator would report.
    OdometryParams p;
    p.rotation_gate = false;
    VisualOdometry vo(synthetic_camera(), std::nullopt, p);
    const PlanarPose p0{0, 0, -20};
    const PlanarPose p1 = advance(p0, 0, 0, 4);
    vo.update(bottom_input(p0, 0));
    const OdometrySample& s = vo.update(bottom_input(p1, 1));
    ASSERT_TRUE(s.valid);
    EXPECT_NEAR(s.out.yaw_deg, 4, kTolDeg);
    EXPECT_NEAR(s.out.forward_m, 0, kTolM);
    EXPECT_NEAR(s.out.right_m, 0, kTolM);
    // With the default gate, the same sample keeps the rotation and zeroes the translation.
    VisualOdometry gated(synthetic_camera(), std::nullopt);
    gated.update(bottom_input(p0, 0));
    const OdometrySample& g = gated.update(bottom_input(p1, 1));
    EXPECT_TRUE(g.out.rotation_gated);
    EXPECT_NEAR(g.out.yaw_deg, 4, kTolDeg);
    EXPECT_EQ(g.out.forward_m, 0.0);
}

TEST(OdometrySynthetic, ThesisPixelOriginTurnsAYawIntoTranslation) {
    // About the pixel origin (the thesis), a yaw of a about the principal point c has
    // H = [R, c - R c] with R = R(-a) for the floor: the translation c - R c, in metres by eq.
    // 3.14, is reported as motion (5 cm for 3°).
    OdometryParams p;
    p.centre_on_principal_point = false;
    p.rotation_gate = false;
    const CameraCalibration cal = synthetic_camera();
    VisualOdometry vo(cal, std::nullopt, p);
    const PlanarPose p0{0, 0, 0};
    const PlanarPose p1 = advance(p0, 0, 0, 3);
    vo.update(bottom_input(p0, 0));
    const OdometrySample& s = vo.update(bottom_input(p1, 1));
    ASSERT_TRUE(s.valid);
    const cv::Vec2d c{cal.cx, cal.cy};
    const cv::Vec2d t_px = c - rot2(-3) * c;
    // Image (x right, y down) -> body: forward = t_y D / fy, right = -t_x D / fx.
    const double fwd = t_px[1] / cal.fy * kFloorDistance_m;
    const double right = -t_px[0] / cal.fx * kFloorDistance_m;
    EXPECT_GT(std::hypot(fwd, right), 0.045);
    EXPECT_NEAR(s.out.forward_m, fwd, 2 * kTolM);
    EXPECT_NEAR(s.out.right_m, right, 2 * kTolM);
    EXPECT_NEAR(s.out.yaw_deg, 3, 2 * kTolDeg);
}

TEST(OdometrySynthetic, TwoCamerasCombineFloorAndMirroredCeiling) {
    VisualOdometry vo(synthetic_camera(), synthetic_camera());
    EXPECT_TRUE(vo.two_cameras());
    const PlanarPose p0{-0.3, 0.4, 100};
    const PlanarPose p1 = advance(p0, 0.025, -0.035, 0.7);
    vo.reset(p0);
    vo.update(two_camera_input(p0, 0));
    const OdometrySample& s = vo.update(two_camera_input(p1, 1));
    ASSERT_TRUE(s.bottom.ok()) << to_string(s.bottom.status);
    ASSERT_TRUE(s.top.ok()) << to_string(s.top.status);
    // Each camera alone, the top one through its mirrored axes and its own distance.
    EXPECT_NEAR(s.bottom.motion.forward_m, 0.025, kTolM);
    EXPECT_NEAR(s.bottom.motion.right_m, -0.035, kTolM);
    EXPECT_NEAR(s.bottom.motion.yaw_deg, 0.7, kTolDeg);
    EXPECT_NEAR(s.top.motion.forward_m, 0.025, 2 * kTolM);
    EXPECT_NEAR(s.top.motion.right_m, -0.035, 2 * kTolM);
    EXPECT_NEAR(s.top.motion.yaw_deg, 0.7, kTolDeg);
    // Combined (eq. 3.16-3.18).
    EXPECT_NEAR(s.raw.forward_m, (s.bottom.motion.forward_m + s.top.motion.forward_m) / 2, 1e-12);
    EXPECT_NEAR(s.out.forward_m, 0.025, kTolM);
    EXPECT_NEAR(s.out.right_m, -0.035, kTolM);
    EXPECT_NEAR(s.out.yaw_deg, 0.7, kTolDeg);
    EXPECT_NEAR(s.pose.x_m, p1.x_m, kTolM);
    EXPECT_NEAR(s.pose.y_m, p1.y_m, kTolM);
}

TEST(OdometrySynthetic, DistanceScalesTheTranslation) {
    // The same images with the distance sensor reading twice the height: twice the translation
    // (eq. 3.14), the same rotation.
    VisualOdometry vo(synthetic_camera(), std::nullopt);
    const PlanarPose p0{};
    const PlanarPose p1 = advance(p0, 0.02, 0.01, 0.5);
    OdometryInput a = bottom_input(p0, 0), b = bottom_input(p1, 1);
    a.bottom_distance_m = b.bottom_distance_m = 2 * kFloorDistance_m;
    vo.update(a);
    const OdometrySample& s = vo.update(b);
    ASSERT_TRUE(s.valid);
    EXPECT_NEAR(s.out.forward_m, 0.04, 2 * kTolM);
    EXPECT_NEAR(s.out.right_m, 0.02, 2 * kTolM);
    EXPECT_NEAR(s.out.yaw_deg, 0.5, kTolDeg);
}

TEST(OdometrySynthetic, FlightIntegratesToTheTruePath) {
    // Twelve samples: forward, a slow turn under the gate, sideways; the integrated path ends
    // within a few millimetres of the truth.
    struct Step {
        double f, r, yaw;
    };
    std::vector<Step> steps;
    for (int i = 0; i < 4; ++i) steps.push_back({0.04, 0.002, 0});
    for (int i = 0; i < 4; ++i) steps.push_back({0.01, 0, 0.8});
    for (int i = 0; i < 4; ++i) steps.push_back({-0.005, 0.045, -0.1});
    VisualOdometry vo(synthetic_camera(), std::nullopt);
    std::vector<PlanarPose> truth{{0.1, 0.1, 45}};
    vo.reset(truth[0]);
    std::vector<OdometrySample> samples;
    samples.push_back(vo.update(bottom_input(truth[0], 0)));
    for (std::size_t i = 0; i < steps.size(); ++i) {
        truth.push_back(advance(truth.back(), steps[i].f, steps[i].r, steps[i].yaw));
        samples.push_back(vo.update(bottom_input(truth.back(), std::int64_t(i + 1))));
        ASSERT_TRUE(samples.back().valid) << i;
    }
    ASSERT_EQ(vo.path().size(), truth.size());
    const OdometryErrors e = evaluate_odometry(samples, truth);
    EXPECT_EQ(e.x.n, 12);
    EXPECT_LT(e.x.mean, 0.2 * kTolM);
    EXPECT_LT(e.y.mean, 0.2 * kTolM);
    EXPECT_LT(e.yaw.mean, 0.5 * kTolDeg);
    EXPECT_NEAR(e.distance_travelled_m,
                4 * std::hypot(0.04, 0.002) + 4 * 0.01 + 4 * std::hypot(0.005, 0.045), 1e-9);
    EXPECT_LT(e.end_error_m, 3 * kTolM);
    EXPECT_LT(e.end_error_pct, 1.0);
    EXPECT_NEAR(vo.path().back().yaw_deg, truth.back().yaw_deg, 4 * kTolDeg);
}

TEST(OdometrySynthetic, NavdataYawReplacesOrFusesTheVisualRotation) {
    // Visual 0.5°, navdata heading 179.5° -> -179.7° (+0.8° across the wrap).
    const PlanarPose p0{};
    const PlanarPose p1 = advance(p0, 0.01, 0, 0.5);
    for (YawSource src : {YawSource::Visual, YawSource::Navdata, YawSource::Fused}) {
        OdometryParams p;
        p.yaw_source = src;
        p.yaw_fusion_weight = 0.25;
        VisualOdometry vo(synthetic_camera(), std::nullopt, p);
        OdometryInput a = bottom_input(p0, 0), b = bottom_input(p1, 1);
        a.yaw_deg = 179.5;
        b.yaw_deg = -179.7;
        vo.update(a);
        const OdometrySample& s = vo.update(b);
        ASSERT_TRUE(s.valid);
        EXPECT_NEAR(s.yaw_navdata_deg, 0.8, 1e-9);
        EXPECT_NEAR(s.yaw_visual_deg, 0.5, kTolDeg);
        const double expect = src == YawSource::Visual    ? 0.5
                              : src == YawSource::Navdata ? 0.8
                                                          : 0.25 * 0.8 + 0.75 * 0.5;
        EXPECT_NEAR(s.out.yaw_deg, expect, kTolDeg) << to_string(src);
        EXPECT_NEAR(s.out.forward_m, 0.01, kTolM);
    }
    EXPECT_EQ(yaw_source_from_string("fused"), YawSource::Fused);
    EXPECT_FALSE(yaw_source_from_string("compass").has_value());
}

TEST(OdometrySynthetic, TexturelessFloorGivesNoEstimate) {
    VisualOdometry vo(synthetic_camera(), std::nullopt);
    OdometryInput in;
    in.bottom = cv::Mat(360, 640, CV_8U, cv::Scalar(128));
    in.bottom_distance_m = 1.0;
    vo.update(in);
    in.t_ns = 66'666'667;
    const OdometrySample& s = vo.update(in);
    EXPECT_FALSE(s.valid);
    EXPECT_EQ(s.bottom.status, CameraStatus::TooFewPoints);
    EXPECT_EQ(s.out.forward_m, 0.0);
    EXPECT_EQ(s.out.yaw_deg, 0.0);
    EXPECT_EQ(s.pose.x_m, 0.0);
    // Without a distance reading a textured floor gives no metric estimate either.
    VisualOdometry nd(synthetic_camera(), std::nullopt);
    OdometryInput a = bottom_input({}, 0), b = bottom_input({0.02, 0, 0}, 1);
    a.bottom_distance_m = b.bottom_distance_m = std::nan("");
    nd.update(a);
    EXPECT_EQ(nd.update(b).bottom.status, CameraStatus::NoDistance);
}

namespace {

// The bottom camera's view when the body is tilted by roll and pitch (FRD, aerospace ZYX: level
// from body = Ry(pitch) Rx(roll); pitch up lifts the nose, so the belly and the camera look
// forward). Built from the level view by the pure-rotation homography K B^T R B K^-1 (tilted
// pixel -> level pixel), B the camera's axes in the body (geom::body_from_camera).
cv::Mat tilted_bottom_view(const PlanarPose& pose, double roll_deg, double pitch_deg) {
    const CameraCalibration cal = synthetic_camera();
    // A level view with a margin, so the tilted view does not reach past its border.
    CameraCalibration wide = cal;
    wide.width += 200;
    wide.height += 200;
    wide.cx += 100;
    wide.cy += 100;
    const cv::Mat level =
        render_view(floor_texture(), wide, CameraMount::Bottom, kFloorDistance_m, pose);
    const geom::Mat3 k_in = geom::from_cv(cal.camera_matrix());
    const geom::Mat3 k_wide = geom::from_cv(wide.camera_matrix());
    const cv::Matx33d m =
        geom::to_cv(k_wide *
                    geom::camera_rotation(CameraMount::Bottom,
                                          geom::level_from_body_matrix(roll_deg, pitch_deg)) *
                    k_in.inverse());
    cv::Mat img;
    cv::warpPerspective(level, img, cv::Mat(m), cv::Size(cal.width, cal.height),
                        cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_REPLICATE);
    return img;
}

}  // namespace

TEST(OdometrySynthetic, TiltChangeIsNotMotionWithTiltCompensation) {
    // The body stays put and pitches up 1.5° and rolls right 1°: the camera's view moves by
    // D tan(angle) on the floor, about 3 cm forward and 2 cm left at 1.2 m. Without the navdata
    // attitude (the thesis) that is reported as motion; with it (the default) it is not.
    const PlanarPose p{0.1, 0.2, 30};
    auto input = [&](double roll, double pitch, std::int64_t i) {
        OdometryInput in = bottom_input(p, i);
        in.bottom = tilted_bottom_view(p, roll, pitch);
        in.roll_deg = roll;
        in.pitch_deg = pitch;
        return in;
    };
    const double roll = 1.0, pitch = 1.5;
    OdometryParams off;
    off.tilt_compensation = false;
    off.image_tilt = false;                           // nor from the images (see the next test)
    ASSERT_TRUE(OdometryParams{}.tilt_compensation);  // the default
    VisualOdometry plain(synthetic_camera(), std::nullopt, off);
    plain.update(input(0, 0, 0));
    const OdometrySample& a = plain.update(input(roll, pitch, 1));
    ASSERT_TRUE(a.valid);
    // The camera looks D tan(pitch) further forward and D tan(roll) further left: the floor
    // seems to have moved back and right, i.e. the drone forward and left.
    EXPECT_NEAR(a.out.forward_m, kFloorDistance_m * std::tan(pitch * kDeg), 3 * kTolM);
    EXPECT_NEAR(a.out.right_m, -kFloorDistance_m * std::tan(roll * kDeg), 3 * kTolM);
    VisualOdometry levelled(synthetic_camera(), std::nullopt);
    levelled.update(input(0, 0, 0));
    const OdometrySample& b = levelled.update(input(roll, pitch, 1));
    ASSERT_TRUE(b.valid);
    EXPECT_NEAR(b.out.forward_m, 0, kTolM);
    EXPECT_NEAR(b.out.right_m, 0, kTolM);
    EXPECT_NEAR(b.out.yaw_deg, 0, kTolDeg);
}

TEST(OdometrySynthetic, ImageTiltCorrectsAnAttitudeTheNavdataGotWrong) {
    // The body stays put and tilts by 1° roll and 1.5° pitch, but the navdata reports the change
    // 0.3° short on both axes (an estimator's noise and drifting bias): levelling by it alone
    // leaves 0.3° of tilt, D tan(0.3°) = 6 mm of false motion at 1.2 m. The homography's
    // projective part sees the missed tilt and takes it off (odo.image_tilt); without navdata
    // attitude at all it takes off the whole tilt change.
    const PlanarPose p{0.1, 0.2, 30};
    const double roll = 1.0, pitch = 1.5, err = 0.3;
    auto input = [&](double true_roll, double true_pitch, double nav_roll, double nav_pitch,
                     std::int64_t i) {
        OdometryInput in = bottom_input(p, i);
        in.bottom = tilted_bottom_view(p, true_roll, true_pitch);
        in.roll_deg = nav_roll;
        in.pitch_deg = nav_pitch;
        return in;
    };
    const double missed_m = kFloorDistance_m * std::tan(err * kDeg);
    OdometryParams nav_only;
    nav_only.image_tilt = false;
    OdometryParams image;
    image.image_tilt = true;
    VisualOdometry a(synthetic_camera(), std::nullopt, nav_only);
    a.update(input(0, 0, 0, 0, 0));
    const OdometrySample& sa = a.update(input(roll, pitch, roll - err, pitch - err, 1));
    ASSERT_TRUE(sa.valid);
    EXPECT_NEAR(sa.out.forward_m, missed_m, 0.3 * missed_m);  // the missed pitch reads as motion
    EXPECT_NEAR(sa.out.right_m, -missed_m, 0.3 * missed_m);

    // The images' share of the fused change: the navdata's error per sample is assumed twice the
    // images' (0.1° against 0.05°), so w = 0.8 of the missed tilt is taken off and a fifth of
    // the false motion is left.
    const double vi = image.image_tilt_sigma_deg * image.image_tilt_sigma_deg;
    const double vn = image.nav_tilt_sigma_deg * image.nav_tilt_sigma_deg;
    const double w = vn / (vn + vi);
    ASSERT_NEAR(w, 0.8, 1e-9);
    VisualOdometry b(synthetic_camera(), std::nullopt, image);
    b.update(input(0, 0, 0, 0, 0));
    const OdometrySample& sb = b.update(input(roll, pitch, roll - err, pitch - err, 1));
    ASSERT_TRUE(sb.valid);
    EXPECT_NEAR(sb.out.forward_m, (1 - w) * missed_m, kTolM);
    EXPECT_NEAR(sb.out.right_m, -(1 - w) * missed_m, kTolM);
    EXPECT_NEAR(sb.out.yaw_deg, 0, kTolDeg);
    // What the images took off: w of the missed 0.3° on each axis.
    const cv::Vec2d c = sb.bottom.tilt_correction_deg;
    EXPECT_NEAR(std::hypot(c[0], c[1]), w * std::hypot(err, err), 0.03);

    const double nan = std::nan("");
    VisualOdometry c0(synthetic_camera(), std::nullopt, image);
    c0.update(input(0, 0, nan, nan, 0));
    const OdometrySample& sc = c0.update(input(roll, pitch, nan, nan, 1));
    ASSERT_TRUE(sc.valid);
    EXPECT_NEAR(sc.out.forward_m, 0, 2 * kTolM);
    EXPECT_NEAR(sc.out.right_m, 0, 2 * kTolM);
}

TEST(OdometrySynthetic, ImageTiltFusionKeepsImuNoiseOutOfTheTranslation) {
    // Issue 17 point 4 on a synthetic flight: the body moves 5 mm forward per sample and wobbles
    // by about 1° in roll and pitch; the navdata attitude is the truth plus a 0.3° bias and 0.1°
    // of white noise. Levelling by the navdata alone turns the noise's change into false motion
    // (0.14° x 1.2 m = 3 mm per sample); the image tilt fused with it (odo.image_tilt) keeps the
    // per-sample error under a millimetre, and, because each frame is levelled the same way in
    // the two samples it takes part in, the levelling error does not add up along the path.
    constexpr int kSamples = 40;
    constexpr double kStep_m = 0.005;
    std::mt19937_64 rng(17);
    auto gaussian = [&] {  // Box-Muller on the portable engine
        const double u1 = (static_cast<double>(rng() >> 11) + 1.0) * 0x1.0p-53;
        const double u2 = static_cast<double>(rng() >> 11) * 0x1.0p-53;
        return std::sqrt(-2 * std::log(u1)) * std::cos(2 * std::numbers::pi * u2);
    };
    std::vector<OdometryInput> inputs;
    for (int i = 0; i < kSamples; ++i) {
        const PlanarPose p{kStep_m * i, 0.1, 0};  // heading 0: world x is body forward
        const double roll = 1.0 * std::sin(0.4 * i), pitch = 0.8 * std::cos(0.3 * i);
        OdometryInput in = bottom_input(p, i);
        in.bottom = tilted_bottom_view(p, roll, pitch);
        in.roll_deg = roll + 0.3 + 0.1 * gaussian();
        in.pitch_deg = pitch - 0.3 + 0.1 * gaussian();
        inputs.push_back(std::move(in));
    }
    struct Run {
        double mean_err_m = 0, end_err_m = 0;
    };
    auto run = [&](const OdometryParams& params) {
        VisualOdometry vo(synthetic_camera(), std::nullopt, params);
        Run r;
        double forward = 0, right = 0;
        for (int i = 0; i < kSamples; ++i) {
            const OdometrySample& s = vo.update(inputs[std::size_t(i)]);
            if (i == 0) continue;
            EXPECT_TRUE(s.valid) << i;
            r.mean_err_m += (std::abs(s.raw.forward_m - kStep_m) + std::abs(s.raw.right_m)) / 2;
            forward += s.raw.forward_m;
            right += s.raw.right_m;
        }
        r.mean_err_m /= kSamples - 1;
        r.end_err_m = std::hypot(forward - kStep_m * (kSamples - 1), right);
        return r;
    };
    OdometryParams nav_only;
    nav_only.image_tilt = false;
    OdometryParams with_image;
    with_image.image_tilt = true;
    const Run nav = run(nav_only), fused = run(with_image);
    EXPECT_GT(nav.mean_err_m, 0.0015);  // what the noise does without the images
    EXPECT_LT(fused.mean_err_m, 0.0005);
    EXPECT_LT(fused.mean_err_m, nav.mean_err_m / 4);
    EXPECT_LT(fused.end_err_m, 0.004);  // of 19.5 cm
}

TEST(OdometrySynthetic, ImageTiltUnderAConstantNavdataBiasDoesNotTurnAYawIntoDrift) {
    // The body hovers and yaws back and forth by ±60° (up to 6° per sample, so most samples are
    // rotation-gated) with a small wobble; the navdata attitude is exact but for a constant 0.3°
    // bias on roll and pitch. Levelled by that attitude, the two frames of a sample are tilted
    // the same way in the body, which the yaw turns into a tilt change the images see and take
    // off, so the levelling carried from frame to frame lags the navdata's while the body turns.
    // Along counted samples that lag telescopes, but a gated sample's translation is zeroed: the
    // next counted sample then paid for the catch-up, every swing (9 mm after four swings
    // before the levelling restarted from the navdata after a skipped sample; 0.05 mm with the
    // navdata levelling alone).
    constexpr int kSamples = 240;
    std::vector<OdometryInput> inputs;
    std::vector<PlanarPose> truth;
    for (int i = 0; i < kSamples; ++i) {
        const double yaw = 60 * std::sin(2 * std::numbers::pi * i / 60.0);
        const PlanarPose p{0.1, 0.2, yaw};
        const double roll = 0.5 * std::sin(0.4 * i), pitch = 0.4 * std::cos(0.3 * i);
        OdometryInput in = bottom_input(p, i);
        in.bottom = tilted_bottom_view(p, roll, pitch);
        in.roll_deg = roll + 0.3;
        in.pitch_deg = pitch - 0.3;
        inputs.push_back(std::move(in));
        truth.push_back(p);
    }
    auto end_error_m = [&](const OdometryParams& params) {
        VisualOdometry vo(synthetic_camera(), std::nullopt, params);
        PlanarPose path = truth[0];
        int gated = 0;
        for (int i = 0; i < kSamples; ++i) {
            const OdometrySample& s = vo.update(inputs[std::size_t(i)]);
            if (i == 0) continue;
            EXPECT_TRUE(s.valid) << i;
            gated += s.out.rotation_gated;
            // The translation in the body frame of the later frame, placed by the true heading.
            path = advance({path.x_m, path.y_m, truth[std::size_t(i)].yaw_deg}, s.out.forward_m,
                           s.out.right_m, 0);
        }
        EXPECT_GT(gated, kSamples / 2);
        return std::hypot(path.x_m - truth.back().x_m, path.y_m - truth.back().y_m);
    };
    OdometryParams nav_only;
    nav_only.image_tilt = false;
    const OdometryParams defaults;
    ASSERT_TRUE(defaults.image_tilt);
    EXPECT_LT(end_error_m(nav_only), 0.0005);
    EXPECT_LT(end_error_m(defaults), 0.0015);  // 0.8 mm
}
