#pragma once
// Whole-image undistortion for display (`replay --video`, the GUI, calibration checks): cv::remap
// with maps built once per calibration and image size, so each frame costs one remap and no
// allocation. Tracking does not use this; it undistorts points (CameraCalibration).

#include "drone/core/camera_calibration.hpp"

#include <opencv2/core.hpp>

namespace gs::vision {

enum class UndistortView {
    // Output camera matrix = input K: undistorted pixels line up with undistorted points (the
    // tracker's convention, what cv::undistort does); the barrel pushes the raw frame's periphery
    // outside the output.
    SameCameraMatrix,
    // Zoomed out so every source pixel is kept (black borders; getOptimalNewCameraMatrix alpha 1).
    AllPixels,
    // Zoomed out as far as possible without black borders (alpha 0, ROS's rectified image; for
    // the AR.Drone 2 front camera fx ≈ 460 instead of ≈ 567).
    ValidPixels,
};

class Undistorter {
public:
    Undistorter() = default;
    explicit Undistorter(const CameraCalibration& cal,
                         UndistortView view = UndistortView::SameCameraMatrix);

    // Changing the calibration or the view drops the maps; they are rebuilt on the next apply().
    void set_calibration(const CameraCalibration& cal);
    void set_view(UndistortView view);

    // The undistorted image, in a buffer owned by the Undistorter and reused by the next call.
    // A frame of a different size than the calibration is undistorted with the calibration scaled
    // to it. An invalid calibration or empty frame gives an empty Mat.
    [[nodiscard]] const cv::Mat& apply(const cv::Mat& raw);

    // The camera matrix of the output image (valid after apply()).
    [[nodiscard]] const cv::Matx33d& output_camera_matrix() const { return out_k_; }
    // How many times maps were built (to check the cache; one per calibration/size/view change).
    [[nodiscard]] int map_builds() const { return builds_; }

private:
    void build_maps(cv::Size size);

    CameraCalibration cal_{};
    UndistortView view_ = UndistortView::SameCameraMatrix;
    cv::Size map_size_{};
    cv::Mat map1_, map2_, out_;
    cv::Matx33d out_k_ = cv::Matx33d::eye();
    int builds_ = 0;
};

}  // namespace gs::vision
