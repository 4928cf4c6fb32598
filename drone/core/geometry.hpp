#pragma once
// The one geometry vocabulary of the project, on Eigen (docs/architecture.md). Every rotation,
// attitude and pose of the virtual drone, the classifiers and the odometry is built here; OpenCV
// types appear only at OpenCV calls (to_cv / from_cv below).
//
// Frames, named in every function and variable that crosses them:
//   body    FRD: x forward, y right, z down (the AR.Drone's and the thesis' axes).
//   level   the body frame turned back by roll and pitch: x along the heading, z down.
//   world   x forward at the start heading, y right, z down (NED-like; the flight model reports
//           height as z up and converts at the boundary: world_point()).
//   camera  x image right, y image down, z optical axis (OpenCV's).
// Attitude (docs/dataset.md): roll positive = right side down, pitch positive = nose up, yaw
// positive = clockwise seen from above; world_from_body = Rz(yaw) Ry(pitch) Rx(roll) (ZYX).
// tests/drone/core/geometry_test.cpp pins every one of these conventions.

#include "drone/core/geometry_fwd.hpp"  // kRadPerDeg, kDegPerRad, Mount

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <cmath>

namespace gs::geom {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat2 = Eigen::Matrix2d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;
using Pose3 = Eigen::Isometry3d;

// ---- Attitude -------------------------------------------------------------------------------

// Elementary right-handed rotations about the body axes (angles in radians).
inline Eigen::AngleAxisd about_x(double rad) {
    return {rad, Vec3::UnitX()};
}
inline Eigen::AngleAxisd about_y(double rad) {
    return {rad, Vec3::UnitY()};
}
inline Eigen::AngleAxisd about_z(double rad) {
    return {rad, Vec3::UnitZ()};
}

// world_from_body for an attitude in degrees (ZYX: yaw, then pitch, then roll).
inline Quat world_from_body(double roll_deg, double pitch_deg, double yaw_deg) {
    return Quat(about_z(yaw_deg * kRadPerDeg) * about_y(pitch_deg * kRadPerDeg) *
                about_x(roll_deg * kRadPerDeg));
}

// level_from_body: the tilt alone (roll, pitch), the heading left out.
inline Quat level_from_body(double roll_deg, double pitch_deg) {
    return Quat(about_y(pitch_deg * kRadPerDeg) * about_x(roll_deg * kRadPerDeg));
}

// The same attitudes as rotation matrices, multiplied out factor by factor (the renderer and the
// derotation use them per frame; the order of operations is fixed here, once).
inline Mat3 world_from_body_matrix(double roll_deg, double pitch_deg, double yaw_deg) {
    return about_z(yaw_deg * kRadPerDeg).toRotationMatrix() *
           about_y(pitch_deg * kRadPerDeg).toRotationMatrix() *
           about_x(roll_deg * kRadPerDeg).toRotationMatrix();
}
inline Mat3 level_from_body_matrix(double roll_deg, double pitch_deg) {
    return about_y(pitch_deg * kRadPerDeg).toRotationMatrix() *
           about_x(roll_deg * kRadPerDeg).toRotationMatrix();
}

// A rotation vector (axis times angle, radians) as a rotation; the zero vector is the identity.
inline Mat3 rotation_from_vector(const Vec3& v_rad) {
    const double a = v_rad.norm();
    if (!(a > 0)) return Mat3::Identity();
    return Eigen::AngleAxisd(a, v_rad / a).toRotationMatrix();
}
// The rotation vector of a rotation matrix (projected onto the rotations first, so a matrix
// that is a rotation only up to rounding or scale gives the nearest rotation's vector).
Vec3 vector_from_rotation(const Mat3& r);

// ---- Heading (the horizontal plane) ---------------------------------------------------------

// world_from_level in the horizontal plane: (forward, right) along the heading -> (x, y) world.
inline Eigen::Rotation2Dd world_from_heading(double yaw_deg) {
    return Eigen::Rotation2Dd(yaw_deg * kRadPerDeg);
}

// ---- Cameras on the body --------------------------------------------------------------------

// body_from_camera: the camera's axes (x right, y down, z optical) as columns in body FRD.
const Mat3& body_from_camera(Mount m);

// The rotation of camera frames that a body rotation causes: camera_from_body R body_from_camera.
inline Mat3 camera_rotation(Mount m, const Mat3& body_rotation) {
    const Mat3& b = body_from_camera(m);
    return b.transpose() * body_rotation * b;
}

// A camera's pose in the world for a body at `world_from_body` (its centre at the body's).
inline Pose3 world_from_camera(const Pose3& world_from_body, Mount m) {
    Pose3 p = world_from_body;
    p.linear() = world_from_body.linear() * body_from_camera(m);
    return p;
}

// A body pose: its attitude and its position in world FRD.
inline Pose3 world_from_body_pose(const Vec3& position_world, double roll_deg, double pitch_deg,
                                  double yaw_deg) {
    Pose3 p = Pose3::Identity();
    p.linear() = world_from_body_matrix(roll_deg, pitch_deg, yaw_deg);
    p.translation() = position_world;
    return p;
}

// A point given with its height up (the scene files' and the flight model's z) in world FRD.
inline Vec3 world_point(double x_m, double y_m, double z_up_m) {
    return {x_m, y_m, -z_up_m};
}

// ---- Pinhole ------------------------------------------------------------------------------

// K R K^-1 (the image motion of a pure camera rotation), normalised to h(2,2) = 1.
inline Mat3 rotation_homography(const Mat3& k, const Mat3& camera_rotation) {
    const Mat3 h = k * camera_rotation * k.inverse();
    return h / h(2, 2);
}

// ---- OpenCV at the boundary ----------------------------------------------------------------

// Any fixed-size Eigen matrix or expression to the OpenCV matrix (or vector) of its shape.
template <typename Derived>
auto to_cv(const Eigen::MatrixBase<Derived>& e) {
    constexpr int R = Derived::RowsAtCompileTime, C = Derived::ColsAtCompileTime;
    static_assert(R > 0 && C > 0, "fixed-size matrices only");
    const Eigen::Matrix<double, R, C> m = e;  // evaluated once
    cv::Matx<double, R, C> out;
    for (int i = 0; i < R; ++i)
        for (int j = 0; j < C; ++j) out(i, j) = m(i, j);
    if constexpr (C == 1)
        return cv::Vec<double, R>(out.val);
    else
        return out;
}
// An OpenCV matrix (cv::Vec included) to the Eigen matrix of its shape.
template <int R, int C>
Eigen::Matrix<double, R, C> from_cv(const cv::Matx<double, R, C>& m) {
    Eigen::Matrix<double, R, C> out;
    for (int i = 0; i < R; ++i)
        for (int j = 0; j < C; ++j) out(i, j) = m(i, j);
    return out;
}
template <int N>
Eigen::Matrix<double, N, 1> from_cv(const cv::Vec<double, N>& v) {
    return from_cv(static_cast<const cv::Matx<double, N, 1>&>(v));
}

}  // namespace gs::geom
