// drone/core/geometry: the project's conventions, pinned once. Attitude signs (roll right side
// down, pitch nose up, yaw clockwise seen from above), the ZYX order, the camera mounts' axes on
// the body, the heading rotation, the pinhole rotation homography's direction, rotation vectors,
// and the OpenCV boundary conversions. Everything else (renderer, flight model, derotation,
// odometry) builds on these functions, so a sign flipped here fails here first.

#include "drone/core/geometry.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace gs::geom {
namespace {

constexpr double kTol = 1e-12;

void expect_vec(const Vec3& got, const Vec3& want, double tol = kTol) {
    EXPECT_NEAR(got.x(), want.x(), tol) << got.transpose() << " vs " << want.transpose();
    EXPECT_NEAR(got.y(), want.y(), tol) << got.transpose() << " vs " << want.transpose();
    EXPECT_NEAR(got.z(), want.z(), tol) << got.transpose() << " vs " << want.transpose();
}

const Vec3 kForward = Vec3::UnitX(), kRight = Vec3::UnitY(), kDown = Vec3::UnitZ();

TEST(GeometryConventions, PositiveRollTurnsTheRightSideDown) {
    const Quat q = world_from_body(30, 0, 0);
    const Vec3 right_wing = q * kRight;
    EXPECT_GT(right_wing.z(), 0.4);  // z is down: the right side went down
    expect_vec(q * kForward, kForward);
}

TEST(GeometryConventions, PositivePitchLiftsTheNose) {
    const Vec3 nose = world_from_body(0, 10, 0) * kForward;
    EXPECT_LT(nose.z(), -0.1);  // up
    EXPECT_GT(nose.x(), 0.9);
    expect_vec(world_from_body(0, 10, 0) * kRight, kRight);
}

TEST(GeometryConventions, PositiveYawTurnsClockwiseSeenFromAbove) {
    // Seen from above (looking down +z) with x up the page and y to the right, turning the
    // nose from x towards y is clockwise.
    const Vec3 nose = world_from_body(0, 0, 90) * kForward;
    expect_vec(nose, kRight);
    expect_vec(world_from_body(0, 0, 90) * kDown, kDown);
}

TEST(GeometryConventions, AttitudeIsYawThenPitchThenRoll) {
    const double r = 7, p = -12, y = 130;
    const Mat3 want = (about_z(y * kRadPerDeg) * about_y(p * kRadPerDeg) * about_x(r * kRadPerDeg))
                          .toRotationMatrix();
    EXPECT_TRUE(world_from_body(r, p, y).toRotationMatrix().isApprox(want, kTol));
    EXPECT_TRUE(world_from_body_matrix(r, p, y).isApprox(want, kTol));
    // Roll is about the pitched body's forward axis: a rolled-then-pitched body keeps its nose
    // in the vertical plane of the heading.
    const Vec3 nose = world_from_body(40, 20, 0) * kForward;
    EXPECT_NEAR(nose.y(), 0.0, kTol);
    // Level = the attitude without the heading.
    EXPECT_TRUE(level_from_body_matrix(r, p).isApprox(world_from_body_matrix(r, p, 0), kTol));
    EXPECT_TRUE(level_from_body(r, p).isApprox(world_from_body(r, p, 0), kTol));
}

TEST(GeometryConventions, HeadingTurnsForwardTowardsRight) {
    const Vec2 v = world_from_heading(90) * Vec2(1, 0);  // 1 m forward at heading 90°
    EXPECT_NEAR(v.x(), 0.0, kTol);
    EXPECT_NEAR(v.y(), 1.0, kTol);
    // The same as the 3-D attitude's horizontal part.
    const Vec3 v3 = world_from_body(0, 0, 33) * Vec3(0.4, -0.7, 0);
    const Vec2 v2 = world_from_heading(33) * Vec2(0.4, -0.7);
    EXPECT_NEAR(v3.x(), v2.x(), kTol);
    EXPECT_NEAR(v3.y(), v2.y(), kTol);
}

TEST(GeometryConventions, FrontCameraLooksForwardImageRightIsBodyRight) {
    const Mat3& b = body_from_camera(Mount::Front);
    expect_vec(b * Vec3::UnitZ(), kForward);  // optical axis
    expect_vec(b * Vec3::UnitX(), kRight);    // image right
    expect_vec(b * Vec3::UnitY(), kDown);     // image down
}

TEST(GeometryConventions, BottomCameraLooksDownImageUpIsForward) {
    const Mat3& b = body_from_camera(Mount::Bottom);
    expect_vec(b * Vec3::UnitZ(), kDown);
    expect_vec(b * Vec3::UnitX(), kRight);
    expect_vec(b * -Vec3::UnitY(), kForward);
}

TEST(GeometryConventions, TopCameraLooksUpImageRightIsBodyLeft) {
    const Mat3& b = body_from_camera(Mount::Top);
    expect_vec(b * Vec3::UnitZ(), -kDown);
    expect_vec(b * Vec3::UnitX(), -kRight);
    expect_vec(b * -Vec3::UnitY(), kForward);
}

TEST(GeometryConventions, CameraMountsAreProperRotations) {
    for (Mount m : {Mount::Front, Mount::Bottom, Mount::Top}) {
        const Mat3& b = body_from_camera(m);
        EXPECT_NEAR(b.determinant(), 1.0, kTol);
        EXPECT_TRUE((b * b.transpose()).isIdentity(kTol));
    }
}

TEST(GeometryConventions, PitchingUpMovesTheFrontImageDown) {
    // A point straight ahead; the drone pitches nose up: in the front camera the point is now
    // below the centre (image y down).
    const Pose3 body = world_from_body_pose(Vec3::Zero(), 0, 5, 0);
    const Pose3 cam = world_from_camera(body, Mount::Front);
    const Vec3 p_cam = cam.inverse() * Vec3(10, 0, 0);
    EXPECT_GT(p_cam.z(), 0);
    EXPECT_GT(p_cam.y() / p_cam.z(), 0.05);
    // Rolling right side down turns the scene counter-clockwise on screen: a point ahead and
    // to the right appears higher (y smaller) than level.
    const Pose3 rolled =
        world_from_camera(world_from_body_pose(Vec3::Zero(), 10, 0, 0), Mount::Front);
    const Vec3 q = rolled.inverse() * Vec3(10, 3, 0);
    EXPECT_LT(q.y() / q.z(), -0.05);
}

TEST(GeometryConventions, PosesPlaceTheCameraAtTheBody) {
    const Pose3 body = world_from_body_pose(world_point(1, 2, 1.5), 0, 0, 90);
    expect_vec(body.translation(), Vec3(1, 2, -1.5));
    const Pose3 cam = world_from_camera(body, Mount::Front);
    // A point 3 m ahead of a drone heading 90° (world +y) is on the optical axis.
    expect_vec(cam.inverse() * Vec3(1, 5, -1.5), Vec3(0, 0, 3));
}

TEST(GeometryConventions, RotationHomographyMovesPointsLikeTheCamera) {
    Mat3 k;
    k << 500, 0, 320, 0, 500, 180, 0, 0, 1;
    // The camera turns right (about its y axis, image down): a far point's image moves left.
    const Mat3 cam_rotation = about_y(2 * kRadPerDeg).toRotationMatrix().transpose();
    const Mat3 h = rotation_homography(k, cam_rotation);
    const Vec3 p = h * Vec3(320, 180, 1);
    EXPECT_LT(p.x() / p.z(), 320 - 10);
    EXPECT_NEAR(p.y() / p.z(), 180, 1e-9);
    EXPECT_NEAR(h(2, 2), 1.0, kTol);
}

TEST(GeometryConventions, RotationVectorsRoundTrip) {
    const Vec3 v(0.01, -0.03, 0.2);
    const Mat3 r = rotation_from_vector(v);
    expect_vec(vector_from_rotation(r), v);
    EXPECT_TRUE(rotation_from_vector(Vec3::Zero()).isIdentity(0));
    expect_vec(vector_from_rotation(Mat3::Identity()), Vec3::Zero());
    // A scaled rotation still gives its rotation's vector.
    expect_vec(vector_from_rotation(r * 1.01), v, 1e-12);
    // Right-handed: a positive z rotation turns x towards y.
    expect_vec(rotation_from_vector(Vec3(0, 0, std::numbers::pi / 2)) * kForward, kRight);
    EXPECT_TRUE(std::isnan(vector_from_rotation(-Mat3::Identity()).x()));
}

TEST(GeometryConventions, OpenCvConversionsKeepRowsAndColumns) {
    Mat3 m;
    m << 1, 2, 3, 4, 5, 6, 7, 8, 9;
    const cv::Matx33d c = to_cv(m);
    EXPECT_EQ(c(0, 2), 3);
    EXPECT_EQ(c(2, 0), 7);
    EXPECT_EQ(from_cv(c), m);
    Mat2 m2;
    m2 << 1, 2, 3, 4;
    EXPECT_EQ(to_cv(m2)(0, 1), 2);
    EXPECT_EQ(from_cv(to_cv(m2)), m2);
    EXPECT_EQ(from_cv(to_cv(Vec3(1, 2, 3))), Vec3(1, 2, 3));
}

}  // namespace
}  // namespace gs::geom
