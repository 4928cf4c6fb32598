#include "vision/flow_classifier.hpp"

#include "vision/fit.hpp"

#include <opencv2/calib3d.hpp>

#include <algorithm>

namespace gs::vision {

const ParamTable<FlowParams>& FlowParams::table() {
    static const ParamTable<FlowParams> t = [] {
        ParamTable<FlowParams> tab;
        describe_tracker_params(tab);
        using P = FlowParams;
        tab.add("centre_band_px", &P::centre_band_px, 5, 400,
                "centre region half-width around the image centre")
            .add("velocity_window", &P::velocity_window, 2,
                 static_cast<double>(Trajectory::kHistory),
                 "frames for each trajectory's derotated image velocity")
            .add("min_track_length", &P::min_track_length, 2,
                 static_cast<double>(Trajectory::kHistory), "fewer points: no expansion rate")
            .add("min_foe_distance_px", &P::min_foe_distance_px, 1, 300,
                 "no rate for points this close to the focus of expansion")
            .add("use_velocity_for_foe", &P::use_velocity_for_foe, 0, 1,
                 "place the focus of expansion from navdata velocity when known")
            .add("side_inv_ttc_threshold", &P::side_inv_ttc_threshold, 0, 20,
                 "side unsafe above this expansion rate (1/time-to-contact, 1/s)")
            .add("side_min_support", &P::side_min_support, 1, 100,
                 "side score is the k-th largest trajectory rate")
            .add("centre_inv_ttc_threshold", &P::centre_inv_ttc_threshold, 0, 20,
                 "centre unsafe above this expansion rate (1/s)")
            .add("homography_ransac_px", &P::homography_ransac_px, 0.1, 20,
                 "centre homography RANSAC reprojection threshold")
            .add("homography_min_points", &P::homography_min_points, 4, 500,
                 "fewest centre points for a scale sample")
            .add("min_inlier_ratio", &P::min_inlier_ratio, 0, 1,
                 "reject a centre scale with fewer RANSAC inliers than this")
            .add("max_inv_ttc", &P::max_inv_ttc, 0.1, 100,
                 "reject a centre rate above this (1/s) as implausible")
            .add("max_rate_jump", &P::max_rate_jump, 0.01, 100,
                 "reject a centre rate this far from the recent median (1/s) ...")
            .add("max_rejections", &P::max_rejections, 0, 100,
                 "... unless that many in a row were rejected already")
            .add("centre_window", &P::centre_window, 1, 64,
                 "centre score: median of the last n accepted rates")
            .add("centre_max_age_s", &P::centre_max_age_s, 0.05, 10,
                 "forget accepted centre rates older than this")
            .add("confirm_frames", &P::confirm_frames, 1, 30,
                 "a decision must hold this many frames")
            .add("colour_max", &P::colour_max, 0.01, 20, "overlay: red at this rate (1/s)");
        return tab;
    }();
    return t;
}

FlowClassifier::FlowClassifier(const CameraCalibration& calib, const FlowParams& p)
    : TrackingClassifier(calib), p_(p) {
    s_left_ = add_series("left.score");
    s_left_thr_ = add_series("left.threshold");
    s_right_ = add_series("right.score");
    s_right_thr_ = add_series("right.threshold");
    s_centre_ = add_series("centre.score");
    s_centre_thr_ = add_series("centre.threshold");
    s_scale_raw_ = add_series("centre.scale_raw");
    s_rate_raw_ = add_series("centre.rate_raw");
    s_rejected_ = add_series("centre.rejected");
    reconfigure();
}

ParamStatus FlowClassifier::set_param(std::string_view name, double value) {
    bool resets = false;
    const ParamStatus s = FlowParams::table().set(p_, name, value, &resets);
    if (s == ParamStatus::Ok && resets) reconfigure();
    return s;
}

ParamMapErrors FlowClassifier::params_from_map(const ParamMap& m) {
    bool resets = false;
    ParamMapErrors e = FlowParams::table().from_map(p_, m, &resets);
    if (resets) reconfigure();
    return e;
}

void FlowClassifier::on_reset() {
    centre_rates_.clear();
    streak_ = {};
    rejections_ = 0;
    derot_ = cv::Matx33d::eye();
}

void FlowClassifier::confirm(Region r, bool raw) {
    const auto i = static_cast<std::size_t>(r);
    streak_[i] = raw ? streak_[i] + 1 : 0;
    result_.regions[i].unsafe = streak_[i] >= p_.confirm_frames;
}

void FlowClassifier::classify(const FrameInput& in) {
    const double vf = p_.use_velocity_for_foe ? in.vx_mps : kNaN;
    foe_ = vision::focus_of_expansion(calib_, in.attitude.roll_deg, in.attitude.pitch_deg, vf,
                                      in.vy_mps, in.vz_mps);
    if (std::isnan(foe_.x))  // not moving forward: no expansion is meaningful; use the centre
        foe_ = {static_cast<float>(calib_.cx), static_cast<float>(calib_.cy)};
    derot_ =
        have_prev_ ? rotation_homography(calib_, prev_attitude_, in.attitude) : cv::Matx33d::eye();
    classify_sides();
    classify_centre(in);
    const auto& r = result_.regions;
    plot(s_left_, r[0].score);
    plot(s_left_thr_, r[0].threshold);
    plot(s_right_, r[2].score);
    plot(s_right_thr_, r[2].threshold);
    plot(s_centre_, r[1].score);
    plot(s_centre_thr_, r[1].threshold);
}

void FlowClassifier::classify_sides() {
    const auto& tracks = tracker_.tracks();
    for (auto& v : side_rates_) v.clear();
    const auto win = static_cast<std::size_t>(p_.velocity_window);
    const auto min_len = static_cast<std::size_t>(std::max(2, p_.min_track_length));
    const double min_d2 = p_.min_foe_distance_px * p_.min_foe_distance_px;
    for (std::size_t i = 0; i < tracks.size(); ++i) {
        const Trajectory& t = tracks[i];
        const std::size_t n = std::min(win, t.history_size());
        if (n < min_len) continue;
        ts_.resize(n);
        xs_.resize(n);
        ys_.resize(n);
        const double t0 = t.at_back(0).t_s;
        for (std::size_t k = 0; k < n; ++k) {
            const TrackPoint& q = t.at_back(n - 1 - k);
            ts_[k] = q.t_s - t0;
            xs_[k] = q.derot.x;
            ys_[k] = q.derot.y;
        }
        const LineFit fx = fit_line(ts_, xs_);
        const LineFit fy = fit_line(ts_, ys_);
        if (!fx.ok || !fy.ok) continue;
        // Radial component of the translational image velocity about the FOE, divided by the
        // distance: (u . d) / |d|^2 is 1/TTC for a point approached head-on or passed by, the
        // x and y versions of (dx/dt)/(x - cx) combined by least squares.
        const cv::Point2f d = t.undist - foe_;
        const double d2 = static_cast<double>(d.dot(d));
        if (d2 < min_d2) continue;
        const double rate =
            (fx.slope * static_cast<double>(d.x) + fy.slope * static_cast<double>(d.y)) / d2;
        track_score_[i] = rate;
        side_rates_[static_cast<std::size_t>(region_of(t.at_back(0).stab.x))].push_back(rate);
    }
    for (Region r : {Region::Left, Region::Right}) {
        const auto ri = static_cast<std::size_t>(r);
        RegionDecision& d = result_.regions[ri];
        d.threshold = p_.side_inv_ttc_threshold;
        d.support = static_cast<int>(side_rates_[ri].size());
        d.score = kth_largest_inplace(side_rates_[ri], p_.side_min_support);
        d.valid = !std::isnan(d.score);
        confirm(r, d.valid && d.score > d.threshold);
    }
}

double FlowClassifier::recent_median(double now_s) {
    scratch_.clear();
    for (std::size_t k = centre_rates_.size(); k-- > 0;) {
        const RateSample& s = centre_rates_[k];
        if (now_s - s.t_s > p_.centre_max_age_s) break;
        scratch_.push_back(s.rate);
        if (static_cast<int>(scratch_.size()) >= p_.centre_window) break;
    }
    return median_inplace(scratch_);  // NaN when empty; scratch_ keeps the samples
}

void FlowClassifier::classify_centre(const FrameInput& in) {
    RegionDecision& d = result_.regions[1];
    d.threshold = p_.centre_inv_ttc_threshold;
    const auto& tracks = tracker_.tracks();
    src_.clear();
    dst_.clear();
    centre_tracks_.clear();
    const cv::Point2f pp(static_cast<float>(calib_.cx), static_cast<float>(calib_.cy));
    for (std::size_t i = 0; i < tracks.size(); ++i) {
        const Trajectory& t = tracks[i];
        if (t.length < 2 || region_of(t.at_back(0).stab.x) != Region::Centre) continue;
        // Previous position as it would look after the attitude change: the homography between
        // these and the current points is then the translational one only.
        // Centred on the principal point, where the local scale is read.
        src_.push_back(apply_homography(derot_, t.undist_prev) - pp);
        dst_.push_back(t.undist - pp);
        centre_tracks_.push_back(i);
    }
    const double now_s = static_cast<double>(in.t_ns) * 1e-9;
    const double dt = have_prev_ ? static_cast<double>(in.t_ns - prev_t_ns_) * 1e-9 : 0.0;
    double scale = kNaN, rate = kNaN;
    bool rejected = false;
    if (dt > 0 && static_cast<int>(src_.size()) >= std::max(4, p_.homography_min_points)) {
        cv::theRNG().state = 0x5EED5EEDULL;  // RANSAC sampling: same flight, same decisions
        const cv::Mat hm = cv::findHomography(src_, dst_, cv::RANSAC, p_.homography_ransac_px,
                                              inliers_, 2000, 0.995);
        if (!hm.empty()) {
            scale = homography_local_scale(cv::Matx33d(hm));
            const auto inl = static_cast<double>(cv::countNonZero(inliers_));
            const double ratio = inl / static_cast<double>(src_.size());
            const double r = (scale - 1) / dt;
            const double ref = recent_median(now_s);
            const bool jump = !std::isnan(ref) && std::abs(r - ref) > p_.max_rate_jump &&
                              rejections_ < p_.max_rejections;
            if (std::isnan(r) || std::abs(r) > p_.max_inv_ttc || ratio < p_.min_inlier_ratio ||
                jump) {
                rejected = true;
                ++rejections_;
            } else {
                rate = r;
                rejections_ = 0;
                centre_rates_.push({now_s, rate});
            }
        }
    }
    plot(s_scale_raw_, scale);
    plot(s_rate_raw_, rate);
    plot(s_rejected_, rejected ? 1.0 : 0.0);

    const double med = recent_median(now_s);
    d.support = static_cast<int>(src_.size());
    // Half the window at least, so one lucky sample cannot decide.
    d.valid = static_cast<int>(scratch_.size()) >= std::max(1, (p_.centre_window + 1) / 2);
    d.score = d.valid ? med : kNaN;
    confirm(Region::Centre, d.valid && d.score > d.threshold);
}

void FlowClassifier::add_overlay_points() {
    const auto& tracks = tracker_.tracks();
    Overlay& o = result_.overlay;
    for (std::size_t i = 0; i < tracks.size(); ++i) {
        const double s = track_score_[i];
        if (std::isnan(s)) continue;
        o.points.push_back({tracks[i].raw, 4, blue_to_red(s / p_.colour_max), false});
    }
    for (std::size_t i : centre_tracks_) o.points.push_back({tracks[i].raw, 2, kYellow, true});
    o.points.push_back({calib_.distort_point(foe_), 7, kWhite, false});
}

}  // namespace gs::vision
