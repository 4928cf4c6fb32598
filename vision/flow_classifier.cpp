#include "vision/flow_classifier.hpp"
#include "drone/core/unknown.hpp"

#include "vision/fit.hpp"

#include <opencv2/calib3d.hpp>

#include <algorithm>

namespace gs::vision {

const ParamTable<FlowParams>& FlowParams::table() {
    static const ParamTable<FlowParams> t = [] {
        ParamTable<FlowParams> tab;
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
            .add("foe_sigma_k", &P::foe_sigma_k, 0, 20,
                 "also keep this many standard errors of the FOE's place away from it")
            .add("max_tangential_ratio", &P::max_tangential_ratio, 0, 10,
                 "distrust a point whose flow across the FOE ray exceeds this share of ...")
            .add("flow_noise_px_s", &P::flow_noise_px_s, 0, 200,
                 "... its radial flow plus this (px/s)")
            .add("corridor", &P::corridor, 0, 1,
                 "place points in metres from the navdata velocity; only the corridor counts")
            .add("min_speed_mps", &P::min_speed_mps, 0.01, 5,
                 "slower than this: no corridor (depth too uncertain)")
            .add("corridor_half_width_m", &P::corridor_half_width_m, 0.05, 20,
                 "corridor: farther to the side than this is not in the way")
            .add("floor_clearance_m", &P::floor_clearance_m, 0, 5,
                 "corridor: lower than this above the floor is the floor (needs altitude)")
            .add("corridor_up_m", &P::corridor_up_m, 0, 20,
                 "corridor: higher than this above the camera is overhead")
            .add("side_inv_ttc_threshold", &P::side_inv_ttc_threshold, 0, 20,
                 "side unsafe above this expansion rate (1/time-to-contact, 1/s)")
            .add("side_min_support", &P::side_min_support, 1, 100,
                 "side score is the k-th largest corridor point rate")
            .add("centre_inv_ttc_threshold", &P::centre_inv_ttc_threshold, 0, 20,
                 "centre unsafe above this expansion rate (points or homography, 1/s)")
            .add("centre_min_support", &P::centre_min_support, 1, 100,
                 "centre point score is the k-th largest corridor point rate")
            .add("centre_homography", &P::centre_homography, 0, 1,
                 "also read the centre band's homography expansion rate")
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
                 "homography rate: median of the last n accepted rates")
            .add("centre_max_age_s", &P::centre_max_age_s, 0.05, 10,
                 "forget accepted centre rates older than this")
            .add("confirm_frames", &P::confirm_frames, 1, 30,
                 "a decision must hold this many frames")
            .add("colour_max", &P::colour_max, 0.01, 20, "overlay: red at this rate (1/s)");
        describe_tracker_params(tab);  // after the classifier's own: what users tune first
        return tab;
    }();
    return t;
}

FlowClassifier::FlowClassifier(const CameraCalibration& calib, const FlowParams& p)
    : TrackingClassifier(calib), p_(p) {
    s_centre_points_ = add_series("centre.points_rate");
    s_centre_hom_ = add_series("centre.homography_rate");
    s_scale_raw_ = add_series("centre.scale_raw");
    s_rate_raw_ = add_series("centre.rate_raw");
    s_rejected_ = add_series("centre.rejected");
    s_hazards_ = add_series("corridor.points");
    s_residual_yaw_ = add_series("derotation.residual_yaw_deg");
    s_residual_pitch_ = add_series("derotation.residual_pitch_deg");
    reconfigure();
}

void FlowClassifier::on_reset() {
    centre_rates_.clear();
    class_.clear();
    metric_ = false;
    level_velocity_.clear();
    streak_ = {};
    rejections_ = 0;
    derot_ = cv::Matx33d::eye();
}

void FlowClassifier::confirm(Region r, bool raw) {
    const auto i = static_cast<std::size_t>(r);
    streak_[i] = raw ? streak_[i] + 1 : 0;
    result_.regions[i].unsafe = streak_[i] >= p_.confirm_frames;
}

const cv::Point2f* FlowClassifier::prepare(const FrameInput& in) {
    const Attitude& a = in.attitude;
    const bool have_v = p_.use_velocity_for_foe && !std::isnan(in.vx_mps) && !std::isnan(in.vy_mps);
    cv::Vec3d v(0, 0, 0);
    if (have_v) {
        // navdata vz is up; the level frame is (forward, right, down). The velocity is noisy from
        // sample to sample, and a few centimetres per second across the path move the FOE by tens
        // of pixels at low speed: average it over the frames the point velocities are fitted
        // over, which also makes the depth below (speed / rate) use the speed of those frames.
        level_velocity_.push({in.vx_mps, in.vy_mps, std::isnan(in.vz_mps) ? 0.0 : -in.vz_mps});
        const std::size_t n = std::min<std::size_t>(
            level_velocity_.size(), static_cast<std::size_t>(std::max(1, p_.velocity_window)));
        for (std::size_t k = 0; k < n; ++k) v += level_velocity_[level_velocity_.size() - 1 - k];
        v *= 1.0 / static_cast<double>(n);
        // How well that places the FOE: the scatter of the samples across the mean direction,
        // as a standard error (pixels). Slow flight, manoeuvres and noisy navdata widen it.
        const double speed_l = cv::norm(v);
        double across = 0;
        if (n >= 2 && speed_l > 1e-6) {
            const cv::Vec3d dir = v * (1.0 / speed_l);
            for (std::size_t k = 0; k < n; ++k) {
                const cv::Vec3d e = level_velocity_[level_velocity_.size() - 1 - k] - v;
                const cv::Vec3d perp = e - e.dot(dir) * dir;
                across += perp.dot(perp);
            }
            across = std::sqrt(across / static_cast<double>(n - 1) / static_cast<double>(n));
        }
        foe_sigma_px_ = speed_l > 1e-6 ? calib_.fx * across / speed_l : 0.0;
    } else {
        level_velocity_.clear();
    }
    cam_velocity_ =
        have_v ? camera_velocity(a.roll_deg, a.pitch_deg, v[0], v[1], v[2]) : cv::Vec3d(0, 0, 0);
    const double speed = cv::norm(cam_velocity_);
    // Hovering, the direction of travel is noise: assume forward flight, the thesis' premise.
    if (have_v && speed >= p_.min_speed_mps && cam_velocity_[2] > 0.2 * speed) {
        foe_ = {static_cast<float>(calib_.fx * cam_velocity_[0] / cam_velocity_[2] + calib_.cx),
                static_cast<float>(calib_.fy * cam_velocity_[1] / cam_velocity_[2] + calib_.cy)};
        metric_ = p_.corridor;
    } else {
        foe_ = vision::focus_of_expansion(calib_, a.roll_deg, a.pitch_deg, kUnknown, kUnknown,
                                          kUnknown);
        if (std::isnan(foe_.x))
            foe_ = {static_cast<float>(calib_.cx), static_cast<float>(calib_.cy)};
        metric_ = false;
    }
    return &foe_;
}

void FlowClassifier::classify(const FrameInput& in) {
    derot_ =
        have_prev_ ? rotation_homography(calib_, prev_attitude_, in.attitude) : cv::Matx33d::eye();
    // The centre homography uses the refined derotation too.
    derot_ = small_rotation_homography(calib_, tracker_.residual_rotation_deg() * (CV_PI / 180.0)) *
             derot_;
    plot(s_residual_yaw_, -tracker_.residual_rotation_deg()[1]);
    plot(s_residual_pitch_, -tracker_.residual_rotation_deg()[0]);
    rate_points(in);
    const double hom = p_.centre_homography ? homography_rate(in) : kUnknown;

    int hazards = 0;
    for (Region r : kRegions) {
        const auto ri = static_cast<std::size_t>(r);
        const bool centre = r == Region::Centre;
        const int k = centre ? p_.centre_min_support : p_.side_min_support;
        RegionDecision& d = result_.regions[ri];
        d.threshold = centre ? p_.centre_inv_ttc_threshold : p_.side_inv_ttc_threshold;
        d.support = static_cast<int>(hazard_[ri].size());
        hazards += d.support;
        // Enough rated points to judge the region; fewer than k of them in the corridor: 0.
        const bool judged = rated_count_[ri] >= k;
        double score =
            d.support >= k ? kth_largest_inplace(hazard_[ri], k) : (judged ? 0.0 : kUnknown);
        bool raw = !std::isnan(score) && score > d.threshold;
        if (centre) {
            plot(s_centre_points_, score);
            plot(s_centre_hom_, hom);
            if (!std::isnan(hom)) {
                score = std::isnan(score) ? hom : std::max(score, hom);
                raw = score > d.threshold;
            }
        }
        d.score = score;
        d.valid = !std::isnan(score);
        d.unknown = d.valid ? UnknownReason::None : UnknownReason::TooFewPoints;
        confirm(r, raw);
    }
    plot(s_hazards_, hazards);
}

void FlowClassifier::rate_points(const FrameInput& in) {
    const auto& tracks = tracker_.tracks();
    class_.assign(tracks.size(), PointClass::Unrated);
    for (auto& v : hazard_) v.clear();
    rated_count_.assign(3, 0);
    const auto win = static_cast<std::size_t>(p_.velocity_window);
    const auto min_len = static_cast<std::size_t>(std::max(2, p_.min_track_length));
    // Near the FOE a few pixels of error in its place swamp the rate: keep clear of it by the
    // larger of the fixed margin and foe_sigma_k standard errors of where it is.
    const double min_d =
        std::max(p_.min_foe_distance_px, metric_ ? p_.foe_sigma_k * foe_sigma_px_ : 0.0);
    const double min_d2 = min_d * min_d;
    const cv::Matx33d level = level_from_camera(in.attitude.roll_deg, in.attitude.pitch_deg);
    const double floor_down = in.altitude_m - p_.floor_clearance_m;  // NaN: no floor test
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
            xs_[k] = static_cast<double>(q.derot.x);
            ys_[k] = static_cast<double>(q.derot.y);
        }
        const LineFit fx = fit_line(ts_, xs_);
        const LineFit fy = fit_line(ts_, ys_);
        if (!fx.ok || !fy.ok) continue;
        // The fitted velocity is the one at the window's mean time, `lag` seconds ago: measure
        // the point where it was then (its translational motion since taken off the current
        // position), so rate, depth and position below all refer to one instant.
        double lag = 0;
        for (double v : ts_) lag -= v;
        lag /= static_cast<double>(n);
        const double mx = static_cast<double>(t.undist.x) - fx.slope * lag;
        const double my = static_cast<double>(t.undist.y) - fy.slope * lag;
        const double dx = mx - static_cast<double>(foe_.x), dy = my - static_cast<double>(foe_.y);
        const double d2 = dx * dx + dy * dy;
        if (d2 < min_d2) continue;
        const double dn = std::sqrt(d2);
        // Radial flow about the FOE divided by the distance to it: 1/TTC for a static point, the
        // x and y versions of (dx/dt)/(x - x_foe) combined by least squares.
        const double radial = (fx.slope * dx + fy.slope * dy) / dn;
        const double tangential = (fx.slope * dy - fy.slope * dx) / dn;
        const double rate_then = radial / dn;
        // Time to contact now is `lag` less than it was then.
        const double ttc_now = 1.0 / rate_then - lag;
        const double rate = !(rate_then > 0) ? rate_then : ttc_now > 0.01 ? 1.0 / ttc_now : 100.0;
        const auto ri = static_cast<std::size_t>(region_of(t.at_back(0).stab.x));
        ++rated_count_[ri];
        track_score_[i] = rate;
        if (std::abs(tangential) >
            p_.max_tangential_ratio * std::abs(radial) + p_.flow_noise_px_s) {
            class_[i] = PointClass::Inconsistent;
            continue;
        }
        if (!(rate > 0)) continue;  // receding or still: never an obstacle
        if (metric_) {
            // Depth along the optical axis from the time to contact and the forward speed, then
            // the point in the level frame: beside the corridor, floor, or overhead?
            const double z = cam_velocity_[2] / rate_then;
            const cv::Vec3d pc((mx - calib_.cx) / calib_.fx * z, (my - calib_.cy) / calib_.fy * z,
                               z);
            const cv::Vec3d pl = level * pc;
            const bool beside = std::abs(pl[1]) > p_.corridor_half_width_m;
            const bool floor = !std::isnan(floor_down) && pl[2] > floor_down;
            const bool overhead = pl[2] < -p_.corridor_up_m;
            if (beside || floor || overhead) {
                class_[i] = PointClass::Outside;
                continue;
            }
        }
        class_[i] = PointClass::Hazard;
        hazard_[ri].push_back(rate);
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

double FlowClassifier::homography_rate(const FrameInput& in) {
    const auto& tracks = tracker_.tracks();
    src_.clear();
    dst_.clear();
    const cv::Point2f pp(static_cast<float>(calib_.cx), static_cast<float>(calib_.cy));
    for (std::size_t i = 0; i < tracks.size(); ++i) {
        const Trajectory& t = tracks[i];
        if (t.length < 2 || region_of(t.at_back(0).stab.x) != Region::Centre) continue;
        // Previous position as it would look after the attitude change: the homography between
        // these and the current points is then the translational one only.
        // Centred on the principal point, where the local scale is read.
        src_.push_back(apply_homography(derot_, t.undist_prev) - pp);
        dst_.push_back(t.undist - pp);
    }
    const double now_s = static_cast<double>(in.t_ns) * 1e-9;
    const double dt = have_prev_ ? static_cast<double>(in.t_ns - prev_t_ns_) * 1e-9 : 0.0;
    double rate = kUnknown, scale = kUnknown;
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
    // Half the window at least, so one lucky sample cannot decide.
    const bool enough =
        static_cast<int>(scratch_.size()) >= std::max(1, (p_.centre_window + 1) / 2);
    return enough ? med : kUnknown;
}

void FlowClassifier::add_overlay_points() {
    // Rings (the trajectories layer): corridor points coloured by 1/TTC, blue to red at
    // colour_max; points still being judged small and blue; points placed outside the corridor
    // or with inconsistent flow small and grey. Filled dots (the centre band layer): the band's
    // points. The white ring is the focus of expansion.
    const auto& tracks = tracker_.tracks();
    Overlay& o = result_.overlay;
    for (std::size_t i = 0; i < tracks.size(); ++i) {
        const double s = track_score_[i];
        if (std::isnan(s)) continue;
        switch (class_[i]) {
            case PointClass::Hazard:
                o.points.push_back({tracks[i].raw, 5, blue_to_red(s / p_.colour_max), false});
                break;
            case PointClass::Unrated:
                o.points.push_back({tracks[i].raw, 3, blue_to_red(0), false});
                break;
            case PointClass::Outside:
            case PointClass::Inconsistent:
                o.points.push_back({tracks[i].raw, 2, kGrey, false});
                break;
        }
    }
    for (const Trajectory& t : tracks)
        if (region_of(t.at_back(0).stab.x) == Region::Centre)
            o.points.push_back({t.raw, 1.5f, kYellow, true});
    o.points.push_back({calib_.distort_point(foe_), 7, kWhite, false});
}

}  // namespace gs::vision
