#include "app/live_odometry.hpp"

#include "app/pipeline.hpp"

namespace gs::app {

vision::OdometryParams LiveOdometry::live_params() {
    vision::OdometryParams p;
    p.spike_translation_m = 0.25;
    return p;
}

LiveOdometry::LiveOdometry(const CameraCalibration& bottom, const vision::OdometryParams& params)
    : calib_(bottom), params_(params) {
    path_.reserve(kMaxPathPoints);
    nav_path_.reserve(kMaxPathPoints);
}

LiveOdometry::~LiveOdometry() = default;

void LiveOdometry::set_calibration(const CameraCalibration& bottom) {
    calib_ = bottom;
    vo_.reset();  // rebuilt with the new model on the next frame
    fresh_ = true;
}

void LiveOdometry::restart() {
    fresh_ = true;
}

void LiveOdometry::push_path(const vision::PlanarPose& p, const vision::PlanarPose& nav) {
    if (path_.size() >= kMaxPathPoints) {
        // Full: keep every other point (the run's first stays) and sample half as often.
        std::size_t k = 0;
        for (std::size_t i = 0; i < path_.size(); i += 2, ++k) {
            path_[k] = path_[i];
            nav_path_[k] = nav_path_[i];
        }
        path_.resize(k);
        nav_path_.resize(k);
        stride_ *= 2;
    }
    path_.push_back(p);
    nav_path_.push_back(nav);
}

void LiveOdometry::process(const FrameSample& f, OdometryOutput& out) {
    out.active = !f.image.empty();
    out.distance_m = f.nav.altitude_m;
    if (!out.active) return;
    if (!vo_ || f.image.cols != vo_width_ || f.image.rows != vo_height_) {
        const CameraCalibration cam = calib_.scaled_to(f.image.cols, f.image.rows);
        vo_ = std::make_unique<vision::VisualOdometry>(cam, std::nullopt, params_);
        vo_width_ = f.image.cols;
        vo_height_ = f.image.rows;
        fresh_ = true;
    }
    if (fresh_) {
        fresh_ = false;
        ++run_;
        vo_->reset({0.0, 0.0, known(f.nav.yaw_deg) ? f.nav.yaw_deg : 0.0});
        path_.clear();
        nav_path_.clear();
        stride_ = 1;
        samples_ = invalid_ = spikes_ = gated_ = 0;
        ms_sum_ = 0;
        start_t_ns_ = f.t_ns;
    }

    const vision::OdometrySample& s = vo_->update(to_odometry_input(f.nav, f.t_ns, f.image));
    if (s.index > 0) {
        ++samples_;
        invalid_ += s.valid ? 0 : 1;
        spikes_ += s.out.spike_zeroed ? 1 : 0;
        gated_ += s.out.rotation_gated ? 1 : 0;
        ms_sum_ += s.total_ms;
    }
    const bool on_stride = s.index % stride_ == 0;
    if (on_stride) push_path(s.pose, s.nav_pose);

    out.run = run_;
    out.sample = s;
    out.path.assign(path_.begin(), path_.end());
    out.nav_path.assign(nav_path_.begin(), nav_path_.end());
    if (!on_stride) {  // the newest pose always ends the published path
        out.path.push_back(s.pose);
        out.nav_path.push_back(s.nav_pose);
    }
    out.path_stride = stride_;
    out.start_t_ns = start_t_ns_;
    out.samples = samples_;
    out.invalid = invalid_;
    out.spike_zeroed = spikes_;
    out.rotation_gated = gated_;
    out.ms_mean = samples_ > 0 ? ms_sum_ / static_cast<double>(samples_) : kUnknown;
}

}  // namespace gs::app
