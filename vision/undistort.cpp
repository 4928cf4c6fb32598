#include "vision/undistort.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace gs::vision {

Undistorter::Undistorter(const CameraCalibration& cal, UndistortView view)
    : cal_(cal), view_(view) {}

void Undistorter::set_calibration(const CameraCalibration& cal) {
    cal_ = cal;
    map_size_ = {};
}

void Undistorter::set_view(UndistortView view) {
    if (view != view_) map_size_ = {};
    view_ = view;
}

void Undistorter::build_maps(cv::Size size) {
    const CameraCalibration c = (size.width == cal_.width && size.height == cal_.height)
                                    ? cal_
                                    : cal_.scaled_to(size.width, size.height);
    const cv::Matx33d k = c.camera_matrix();
    const cv::Vec<double, 5> d = c.dist_coeffs();
    switch (view_) {
        case UndistortView::SameCameraMatrix:
            out_k_ = k;
            break;
        case UndistortView::AllPixels:
            out_k_ = cv::getOptimalNewCameraMatrix(k, d, size, 1.0, size);
            break;
        case UndistortView::ValidPixels:
            out_k_ = cv::getOptimalNewCameraMatrix(k, d, size, 0.0, size);
            break;
    }
    cv::initUndistortRectifyMap(k, d, cv::noArray(), out_k_, size, CV_16SC2, map1_, map2_);
    map_size_ = size;
    ++builds_;
}

const cv::Mat& Undistorter::apply(const cv::Mat& raw) {
    if (raw.empty() || !cal_.valid()) {
        out_.release();
        return out_;
    }
    if (raw.size() != map_size_) build_maps(raw.size());
    cv::remap(raw, out_, map1_, map2_, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
    return out_;
}

}  // namespace gs::vision
