#pragma once
// The obstacle pipeline: frames from any source (live link, virtual drone, dataset) through one
// classifier. The same code runs behind the window, `replay` and `eval`, so a flight gives the
// same decisions wherever it is played.

#include "drone/core/sample.hpp"
#include "drone/dataset/dataset.hpp"
#include "vision/classifier.hpp"
#include "vision/odometry.hpp"

#include <memory>
#include <string>

namespace gs::app {

// The classifier's input for one frame: the image header (no copy), capture time and the
// attitude and velocities at capture time.
vision::FrameInput to_frame_input(const FrameSample& s);
// The odometry's input for one bottom-camera frame captured at `t_ns` with `nav` (NavState at
// capture time): the altimeter as the distance to the floor, attitude and velocities.
vision::OdometryInput to_odometry_input(const NavState& nav, TimeNs t_ns, const cv::Mat& bottom);

class ObstaclePipeline {
public:
    // Throws nothing: an unknown classifier name leaves the pipeline without one (ok() false).
    ObstaclePipeline(std::string classifier, const CameraCalibration& calibration);

    bool ok() const { return classifier_ != nullptr; }
    const std::string& classifier_name() const { return name_; }
    // Switches classifier (state reset). False for an unknown name (the current one stays).
    bool select(const std::string& name);
    void set_calibration(const CameraCalibration& calibration);
    void reset();

    const vision::FrameResult& process(const FrameSample& s);
    vision::ObstacleClassifier& classifier() { return *classifier_; }
    const vision::ObstacleClassifier& classifier() const { return *classifier_; }

private:
    std::string name_;
    CameraCalibration calib_;
    std::unique_ptr<vision::ObstacleClassifier> classifier_;
};

}  // namespace gs::app
