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
    in.concealed = s.concealed;
    in.repaired = s.repaired;
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

void mark_unknown(vision::FrameResult& r, vision::UnknownReason why) {
    for (auto& d : r.regions) {
        d.valid = false;
        d.unsafe = false;
        d.approach_only = false;
        d.unknown = why;
    }
    // The region bar drawn into replay videos says so too.
    for (std::size_t i = 0; i < r.overlay.bars.size() && i < r.regions.size(); ++i)
        r.overlay.bars[i].colour = vision::bar_colour(r.regions[i]);
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
    last_t_ns_.reset();
}

const vision::FrameResult& ObstaclePipeline::process(const FrameSample& s) {
    const bool gap = last_t_ns_ && s.t_ns - *last_t_ns_ > kGapNs;
    last_t_ns_ = s.t_ns;
    if (gap) classifier_->reset();  // tracks across the gap would join two different scenes
    const vision::FrameResult& r = classifier_->process(to_frame_input(s));
    if (!gap) return r;
    ++gaps_;
    marked_ = r;
    mark_unknown(marked_, vision::UnknownReason::Gap);
    return marked_;
}

}  // namespace gs::app
