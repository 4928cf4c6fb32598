#include "app/pipeline.hpp"

namespace gs::app {

vision::FrameInput to_frame_input(const FrameSample& s) {
    vision::FrameInput in;
    in.image = s.image;
    in.t_ns = s.t_ns;
    in.attitude.roll_deg = s.nav.roll_deg;
    in.attitude.pitch_deg = s.nav.pitch_deg;
    in.attitude.yaw_deg = s.nav.yaw_deg;
    in.vx_mps = s.nav.vx_mps;
    in.vy_mps = s.nav.vy_mps;
    in.vz_mps = s.nav.vz_mps;
    in.altitude_m = s.nav.altitude_m;
    return in;
}

vision::OdometryInput to_odometry_input(const NavState& nav, TimeNs t_ns, const cv::Mat& bottom) {
    vision::OdometryInput in;
    in.t_ns = t_ns;
    in.bottom = bottom;
    in.bottom_distance_m = nav.altitude_m;  // the ultrasonic altimeter: distance to the floor
    in.roll_deg = nav.roll_deg;
    in.pitch_deg = nav.pitch_deg;
    in.yaw_deg = nav.yaw_deg;
    in.vx_mps = nav.vx_mps;
    in.vy_mps = nav.vy_mps;
    return in;
}

ObstaclePipeline::ObstaclePipeline(std::string classifier, const CameraCalibration& calibration)
    : name_(std::move(classifier)), calib_(calibration) {
    classifier_ = vision::make_classifier(name_, calib_);
}

bool ObstaclePipeline::select(const std::string& name) {
    auto c = vision::make_classifier(name, calib_);
    if (!c) return false;
    classifier_ = std::move(c);
    name_ = name;
    return true;
}

void ObstaclePipeline::set_calibration(const CameraCalibration& calibration) {
    calib_ = calibration;
    if (classifier_) classifier_->set_calibration(calib_);
}

void ObstaclePipeline::reset() {
    if (classifier_) classifier_->reset();
}

const vision::FrameResult& ObstaclePipeline::process(const FrameSample& s) {
    return classifier_->process(to_frame_input(s));
}

}  // namespace gs::app
