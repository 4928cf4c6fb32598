#include "drone/core/geometry.hpp"

#include <Eigen/SVD>

namespace gs::geom {

Vec3 vector_from_rotation(const Mat3& r) {
    // Nearest rotation (U V^T of the SVD), as cv::Rodrigues does before taking the angle.
    const Eigen::JacobiSVD<Mat3> svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Mat3 q = svd.matrixU() * svd.matrixV().transpose();
    if (q.determinant() < 0) return Vec3::Constant(std::nan(""));
    const Eigen::AngleAxisd a(q);
    return a.axis() * a.angle();
}

const Mat3& body_from_camera(Mount m) {
    static const Mat3 front = (Mat3() << 0, 0, 1, 1, 0, 0, 0, 1, 0).finished();
    static const Mat3 bottom = (Mat3() << 0, -1, 0, 1, 0, 0, 0, 0, 1).finished();
    static const Mat3 top = (Mat3() << 0, -1, 0, -1, 0, 0, 0, 0, -1).finished();
    switch (m) {
        case Mount::Front:
            return front;
        case Mount::Bottom:
            return bottom;
        case Mount::Top:
            return top;
    }
    return front;
}

}  // namespace gs::geom
