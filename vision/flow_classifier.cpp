#include "vision/flow_classifier.hpp"
#include "drone/core/unknown.hpp"

#include "vision/fit.hpp"

#include <opencv2/calib3d.hpp>

#include <algorithm>
#include <limits>
#include <span>
#include <utility>

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
            .add("aperture_edge_ratio", &P::aperture_edge_ratio, 0, 1,
                 "a point whose structure tensor's eigenvalues differ by more than this ratio "
                 "is an edge: only its flow across the edge is used")
            .add("aperture_min_cos", &P::aperture_min_cos, 0, 1,
                 "an edge point is not rated when its edge normal's cosine with the FOE ray is "
                 "below this")
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
            .add("ground_fit_margin", &P::ground_fit_margin, 0, 10,
                 "floor from the flow: a point within (1 + this) of the floor's rate at its row "
                 "is the floor (0 = off)")
            .add("ground_fit_always", &P::ground_fit_always, 0, 1,
                 "floor from the flow also when the altitude is known (0: only without it)")
            .add("ground_height_m", &P::ground_height_m, 0, 20,
                 "without speed or altitude: place the corridor with the floor fit and this "
                 "height above the floor (0: no corridor)")
            .add("ground_fit_quantile", &P::ground_fit_quantile, 0.01, 0.99,
                 "floor from the flow: the floor's slope is this quantile of rate / depth below "
                 "the horizon")
            .add("ground_fit_min_dh_px", &P::ground_fit_min_dh_px, 1, 1000,
                 "floor from the flow: only points this far below the horizon fit it")
            .add("ground_fit_min_points", &P::ground_fit_min_points, 3, 1000,
                 "floor from the flow: fewest points for a fit")
            .add("corridor_up_m", &P::corridor_up_m, 0, 20,
                 "corridor: higher than this above the camera is overhead")
            .add("assumed_speed_mps", &P::assumed_speed_mps, 0, 10,
                 "without a navdata velocity, place the corridor with this speed (0: no corridor)")
            .add("velocity_bias_mps", &P::velocity_bias_mps, 0, 2,
                 "navdata velocity direction trusted to this (m/s across the path)")
            .add("max_foe_sigma_px", &P::max_foe_sigma_px, 1, 1000,
                 "use the images' FOE when its standard error is below this")
            .add("image_foe_floor_px", &P::image_foe_floor_px, 0, 200,
                 "the images' FOE is never taken as better known than this")
            .add("fused_image_foe_floor_px", &P::fused_image_foe_floor_px, 0, 200,
                 "fused with the navdata's, the images' FOE counts as known no better than this")
            .add("image_foe_bias_mps", &P::image_foe_bias_mps, 0, 2,
                 "fused with the navdata's, the images' FOE counts as known no better than fx x "
                 "this / speed (0 = off)")
            .add("foe_gate", &P::foe_gate, 0.5, 100,
                 "navdata FOE rejected this many standard errors from the images'")
            .add("foe_arbitrate", &P::foe_arbitrate, 0, 2,
                 "the points' fitted flows pick the FOE they run radially from: 0 off (beyond "
                 "foe_gate the images decide), 1 beyond foe_gate, 2 also within it (see ratio)")
            .add("foe_arbitrate_ratio", &P::foe_arbitrate_ratio, 0, 1,
                 "mode 2, within foe_gate: the navdata's FOE replaces the fused one when its "
                 "misfit is under this share of the fused one's")
            .add("foe_overrule_ratio", &P::foe_overrule_ratio, 0, 1,
                 "beyond foe_gate: the images' FOE replaces the navdata's only when its misfit "
                 "is under this share of the navdata's (1: the smaller misfit)")
            .add("foe_arbitrate_min_points", &P::foe_arbitrate_min_points, 3, 1000,
                 "fewer points to arbitrate with: within foe_gate the fused FOE, beyond it the "
                 "navdata's")
            .add("max_rotation_dps", &P::max_rotation_dps, 1, 2000,
                 "regions unknown while the camera turns faster than this")
            .add("near_foe_rows", &P::near_foe_rows, 0, 1,
                 "rate static points too near the FOE by how fast they part from their "
                 "neighbours in the same image row")
            .add("near_foe_row_px", &P::near_foe_row_px, 1, 100,
                 "near the FOE: neighbours within this many pixels of the point's row")
            .add("near_foe_growth", &P::near_foe_growth, 0, 10,
                 "near the FOE: a pair must part at least this times as fast over the window's "
                 "later half as over its first (0: no test)")
            .add("looming", &P::looming, 0, 1,
                 "judge points that do not move with the scene by their own looming")
            .add("corridor_foe_k", &P::corridor_foe_k, 0, 5,
                 "a static point is beside the corridor only with the FOE this many standard "
                 "errors nearer it (0: the FOE as placed)")
            .add("moving_corridor", &P::moving_corridor, 0, 1,
                 "a moving point counts only when its bearing's drift brings it into the flight "
                 "corridor by the time it arrives (needs a speed)")
            .add("loom_radius_px", &P::loom_radius_px, 5, 640,
                 "looming: neighbours within this distance")
            .add("loom_min_neighbours", &P::loom_min_neighbours, 1, 100,
                 "looming: fewest neighbours for a rate")
            .add("loom_min_spread_px", &P::loom_min_spread_px, 1, 300,
                 "looming: pairs closer than this are left out (tracking noise dominates)")
            .add("max_moving_share", &P::max_moving_share, 0, 1,
                 "more of the rated points than this moving against the camera motion: regions "
                 "unknown (1: never)")
            .add("loom_consistency", &P::loom_consistency, 0, 1,
                 "a static point whose like-rated neighbours spread slower than this share of "
                 "its rate is moving (0: off)")
            .add("confirm_radius_px", &P::confirm_radius_px, 5, 1000,
                 "a side point that must be borne out looks this far for like-rated neighbours")
            .add("loom_confirm_sides", &P::loom_confirm_sides, 0, 1,
                 "flying forward, a side point counts only when its neighbours bear its rate out")
            .add("history_check", &P::history_check, 0, 1,
                 "a point that sat nearer the FOE than this share of where its rate puts a "
                 "static point in its past is moving (0: off)")
            .add("history_min_s", &P::history_min_s, 0.05, 2,
                 "history check: only for a past this far before the rate's window")
            .add("history_noise_px", &P::history_noise_px, 0, 100,
                 "history check: a past position this much nearer the FOE is still static")
            .add("history_slow", &P::history_slow, 0, 1,
                 "history check: a point that covered less than this share of the way a static "
                 "point with its rate would have since a past position is not rated (0: off)")
            .add("fb_static", &P::fb_static, 0, 1,
                 "with track.fb_max_px: a point that missed is not rated as static (0: misses "
                 "only keep points out of a moving object's looming)")
            .add("fb_lost_px", &P::fb_lost_px, 0, 100,
                 "with track.fb_max_px, flying forward: a point rated as static whose fit "
                 "window holds a step that missed its track-back by more than this (px: a lost "
                 "track) counts only where its region was unsafe last frame (0: off)")
            .add("moving_frames", &P::moving_frames, 1, 30,
                 "a point is moving after this many frames off the camera's motion")
            .add("side_inv_ttc_threshold", &P::side_inv_ttc_threshold, 0, 20,
                 "side unsafe above this expansion rate (1/time-to-contact, 1/s)")
            .add("side_min_support", &P::side_min_support, 1, 100,
                 "side score is the k-th largest corridor point rate")
            .add("centre_inv_ttc_threshold", &P::centre_inv_ttc_threshold, 0, 20,
                 "centre unsafe above this expansion rate (points, homography or outline, 1/s)")
            .add("centre_min_support", &P::centre_min_support, 1, 100,
                 "centre point score is the k-th largest corridor point rate")
            .add("centre_homography", &P::centre_homography, 0, 1,
                 "also read the centre band's homography expansion rate")
            .add("centre_silhouette", &P::centre_silhouette, 0, 1,
                 "also read the widening of the plain run around the FOE whose ends are a near "
                 "surface's outline (a plain obstacle)")
            .add("silhouette_step_grey", &P::silhouette_step_grey, 1, 100,
                 "outline: a brightness step this large (grey levels) ends the plain run")
            .add("silhouette_own_px", &P::silhouette_own_px, 0, 20,
                 "outline: an end that moved outward over the texture beside it this far (px, "
                 "over its last 10 px of path) is a near surface's")
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
            .add("lag_allowance_s", &P::lag_allowance_s, -0.2, 0.2,
                 "navdata lag allowed for in the floor test while the pitch rate changes: a "
                 "static point is placed as far as its radial flow less what such a lag adds to "
                 "it allows (s; negative: navdata early; 0: off)")
            .add("lag_min_pitch_accel", &P::lag_min_pitch_accel, 0, 100,
                 "the lag is allowed for only while the pitch rate changes faster than this "
                 "(rad/s^2): slower is the rate's noise")
            .add("confirm_frames", &P::confirm_frames, 1, 30,
                 "a decision must hold this many frames")
            .add("loom_confirm_young", &P::loom_confirm_young, 0, 1,
                 "flying forward, a point too young for the history check counts in the centre "
                 "too only when its neighbours bear it out")
            .add("side_confirm_frames", &P::side_confirm_frames, 0, 30,
                 "in flight (the FOE from the motion) a side region's raw decision must hold "
                 "this many frames (0: confirm_frames)")
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
    s_centre_sil_ = add_series("centre.outline_rate");
    s_scale_raw_ = add_series("centre.scale_raw");
    s_rate_raw_ = add_series("centre.rate_raw");
    s_rejected_ = add_series("centre.rejected");
    s_hazards_ = add_series("corridor.points");
    s_residual_yaw_ = add_series("derotation.residual_yaw_deg");
    s_residual_pitch_ = add_series("derotation.residual_pitch_deg");
    s_lag_allowance_ = add_series("derotation.lag_allowance_px_s");
    // The camera's auto-exposure: this frame's brightness over the last one's when it stepped
    // (track.step_gain_min), 1 otherwise.
    s_exposure_step_ = add_series("track.exposure_step");
    // What the images alone say of the navdata rotation's error this frame (before the filter).
    s_image_yaw_ = add_series("derotation.image_yaw_deg");
    s_image_pitch_ = add_series("derotation.image_pitch_deg");
    s_foe_sigma_ = add_series("ego.foe_sigma_px");
    s_prior_rejected_ = add_series("ego.navdata_rejected");
    s_moving_ = add_series("ego.moving_points");
    s_foe_img_x_ = add_series("ego.foe_x_px");
    s_foe_nav_x_ = add_series("foe.navdata_x_px");
    s_foe_x_ = add_series("foe.x_px");
    s_foe_img_y_ = add_series("ego.foe_y_px");
    s_foe_nav_y_ = add_series("foe.navdata_y_px");
    s_foe_y_ = add_series("foe.y_px");
    reconfigure();
}

void FlowClassifier::on_reset() {
    silhouette_.reset();
    centre_rates_.clear();
    class_.clear();
    metric_ = false;
    level_velocity_.clear();
    image_dirs_.clear();
    foe_source_ = FoeSource::None;
    nav_moving_ = false;
    nav_slow_ = false;
    nav_starting_ = false;
    odometer_.clear();
    streak_ = {};
    rejections_ = 0;
    derot_ = cv::Matx33d::eye();
    pitch_t_.clear();
    pitch_w_.clear();
    pitch_slopes_.clear();
    rate_prev_t_ = kUnknown;
}

void FlowClassifier::note_nav_rate(const FrameInput& in) {
    const auto win = static_cast<std::size_t>(std::max(2, p_.velocity_window));
    const double t = static_cast<double>(in.t_ns) * 1e-9;
    // The pitch rate over the last frame (the images' correction included: its error is the
    // navdata's); no navdata attitude, no navdata lag.
    const bool nav = in.attitude.complete();
    const double dt = t - rate_prev_t_;  // NaN: no frame with navdata before
    rate_prev_t_ = nav ? t : kUnknown;
    if (!nav) {
        pitch_t_.clear();
        pitch_w_.clear();
    } else if (dt > 0) {
        if (pitch_t_.size() >= win) {
            pitch_t_.erase(pitch_t_.begin());
            pitch_w_.erase(pitch_w_.begin());
        }
        pitch_t_.push_back(t);
        pitch_w_.push_back(tracker_.rotation_rad()[0] / dt);
    }
    pitch_slopes_.assign(win + 1, 0.0);
    const std::size_t m = pitch_t_.size();
    const std::span<const double> ts(pitch_t_), ws(pitch_w_);
    for (std::size_t n = 2; n <= m; ++n) {
        const LineFit f = fit_line(ts.last(n), ws.last(n));
        if (f.ok) pitch_slopes_[n] = f.slope;
    }
    // A track longer than the navdata's run: the slope over that run.
    for (std::size_t n = m + 1; m >= 2 && n <= win; ++n) pitch_slopes_[n] = pitch_slopes_[m];
}

double FlowClassifier::lag_pitch_accel(std::size_t n) const {
    if (p_.lag_allowance_s == 0 || n >= pitch_slopes_.size()) return 0;
    // Only in a manoeuvre: a slope under lag_min_pitch_accel is the rate's noise (or a cruise's
    // wobble), and allowing for it would take a real obstacle's points off the path.
    const double slope = pitch_slopes_[n];
    return std::abs(slope) > p_.lag_min_pitch_accel ? slope : 0.0;
}

double FlowClassifier::lag_flow_px_s(const WindowFit& w, double ay) const {
    // A navdata L late derotates with the pitch rate of L before: the fit's vertical flow is off
    // by -fy L (the rate's slope) (image y down; a positive rate about the camera's x axis is
    // the nose going down, which moves the scene up). The allowance is what that adds to the
    // flow of a point below the principal point (ay > 0), the floor's: a point it takes flow
    // from is nearer than it reads, and nothing is placed nearer. Not above it, nor for yaw or
    // roll: allowing for those took real obstacles' points off the path in the closed loop (the
    // upper half of a pillar ahead while the drone pitches up to brake; a side pillar's while
    // the held heading wobbles).
    if (!(ay > 0)) return 0;
    return std::max(0.0, -p_.lag_allowance_s * calib_.fy * lag_pitch_accel(w.n) * ay);
}

void FlowClassifier::confirm(Region r, bool raw) {
    const auto i = static_cast<std::size_t>(r);
    // A damaged frame's evidence (concealed, or repaired: FrameInput) does not count toward the
    // streak: with a clean frame before it, it would confirm an alarm that motion measured across
    // the damage raised. It holds the streak, so a standing alarm is kept.
    streak_[i] = raw ? streak_[i] + (damaged_ ? 0 : 1) : 0;
    // In flight (the FOE from the camera's motion) a side region needs side_confirm_frames: a
    // side alarm only holds back the roll toward that side, and a few frames more there take out
    // most brief alarms on things passing by. The centre keeps confirm_frames: its alarm brakes,
    // and a thin obstacle ahead at a low speed holds its raw alarm for few frames in a row. A
    // still camera, judging only what approaches it (a hand reaching for the lens, in view for a
    // few frames), also keeps confirm_frames.
    const bool flying = foe_source_ == FoeSource::Images || foe_source_ == FoeSource::Navdata;
    const int need = flying && r != Region::Centre && p_.side_confirm_frames > 0
                         ? p_.side_confirm_frames
                         : p_.confirm_frames;
    RegionDecision& d = result_.regions[i];
    d.unsafe = streak_[i] >= need;
    if (raw && damaged_ && !d.unsafe) {
        // Unsafe by this frame's evidence alone, which is not trusted: not known to be clear.
        d.valid = false;
        d.approach_only = false;
        d.unknown = UnknownReason::DamagedFrame;
    }
}

void FlowClassifier::prepare(const FrameInput& in, EgoPrior& prior) {
    const Attitude& a = in.attitude;
    const bool have_v = p_.use_velocity_for_foe && !std::isnan(in.vx_mps) && !std::isnan(in.vy_mps);
    nav_moving_ = false;
    nav_slow_ = false;
    nav_starting_ = false;
    nav_speed_ = kUnknown;
    nav_forward_mps_ = kUnknown;
    // The distance flown forward, for check_history: the trapezoid between this sample and the
    // last (signed: hovering jitter and a drift backward add nothing).
    const double t_s = static_cast<double>(in.t_ns) * 1e-9;
    const double sp = have_v ? in.vx_mps : kUnknown;
    if (odometer_.empty() || !(t_s > odometer_.back().t_s) || std::isnan(sp)) {
        odometer_.clear();  // a gap in the speed, or time not moving on: start again
        if (!std::isnan(sp)) odometer_.push({t_s, 0.0, sp});
    } else {
        const Odometer& last = odometer_.back();
        odometer_.push({t_s, last.s_m + 0.5 * (sp + last.v_mps) * (t_s - last.t_s), sp});
    }
    if (!have_v) {
        level_velocity_.clear();
        return;
    }
    // navdata vz is up; the level frame is (forward, right, down). The velocity is noisy from
    // sample to sample, and a few centimetres per second across the path move the FOE by tens
    // of pixels at low speed: average it over the frames the point velocities are fitted over,
    // which also makes the depth below (speed / rate) use the speed of those frames.
    level_velocity_.push({in.vx_mps, in.vy_mps, std::isnan(in.vz_mps) ? 0.0 : -in.vz_mps});
    const std::size_t n = std::min<std::size_t>(
        level_velocity_.size(), static_cast<std::size_t>(std::max(1, p_.velocity_window)));
    cv::Vec3d v(0, 0, 0);
    for (std::size_t k = 0; k < n; ++k) v += level_velocity_[level_velocity_.size() - 1 - k];
    v *= 1.0 / static_cast<double>(n);
    // How well that places the FOE: the scatter of the samples across the mean direction, as a
    // standard error, and a bias floor (an onboard estimator's error is not white).
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
    const cv::Vec3d c = camera_velocity(a.roll_deg, a.pitch_deg, v[0], v[1], v[2]);
    const double speed = cv::norm(c);
    nav_speed_ = speed;
    nav_forward_mps_ = v[0];
    // Hovering only when every sample of the window is slow: a drone pitching into its first
    // metres has a slow mean but moves (and a still camera's view of it would take the static
    // scene's expansion for approaching things).
    double fastest = 0;
    for (std::size_t k = 0; k < n; ++k)
        fastest = std::max(fastest, cv::norm(level_velocity_[level_velocity_.size() - 1 - k]));
    nav_slow_ = speed < p_.min_speed_mps && fastest < p_.min_speed_mps;
    nav_starting_ = speed < p_.min_speed_mps && !nav_slow_;
    // Hovering, the direction of travel is noise; backward or sideways, nothing ahead approaches.
    if (!(speed >= p_.min_speed_mps && c[2] > 0.2 * speed)) return;
    nav_moving_ = true;
    nav_dir_ = c * (1.0 / speed);
    const double sigma_rad = std::hypot(across, p_.velocity_bias_mps) / speed;
    nav_sigma_px_ = calib_.fx * sigma_rad / std::max(0.2, nav_dir_[2] * nav_dir_[2]);
    prior.translation = nav_dir_;
    prior.translation_sigma_rad = sigma_rad;
}

bool FlowClassifier::choose_foe(const FrameInput& in, UnknownReason& why) {
    const EgoMotion& em = tracker_.ego();
    metric_ = false;
    foe_source_ = FoeSource::None;
    cam_velocity_ = {0, 0, 0};
    const double dt = have_prev_ ? static_cast<double>(in.t_ns - prev_t_ns_) * 1e-9 : 0.0;
    const double rate_dps = dt > 0 ? cv::norm(tracker_.rotation_rad()) / dt * 180.0 / CV_PI : 0.0;
    if (rate_dps > p_.max_rotation_dps) {
        why = UnknownReason::Rotating;
        image_dirs_.clear();
        return false;
    }
    // The images' FOE over the frames the point rates are fitted over: its mean, and how well
    // that is known from the frames' own scatter (the per-frame errors are correlated and the
    // fit's own standard error is optimistic on real footage), never better than a floor.
    if (p_.ego_motion && em.valid && em.translation == EgoMotion::Translation::Known &&
        em.direction[2] > 0.2)
        image_dirs_.push({em.direction, em.foe_sigma_px});
    else
        image_dirs_.clear();
    const std::size_t n = std::min<std::size_t>(
        image_dirs_.size(), static_cast<std::size_t>(std::max(1, p_.velocity_window)));
    cv::Point2d img_foe(0, 0);
    double img_sigma = kUnknown;
    // Three frames at least: a translation seen in one frame may be a person walking past.
    if (n >= 3) {
        // Median and median absolute deviation per axis: one frame whose FOE went astray (a
        // few points on a moving object) does not move it.
        for (int axis = 0; axis < 2; ++axis) {
            scratch_.clear();
            for (std::size_t k = 0; k < n; ++k) {
                const cv::Point2d foe = calib_.project(image_dirs_[image_dirs_.size() - 1 - k].dir);
                scratch_.push_back(axis == 0 ? foe.x : foe.y);
            }
            const double med = median_inplace(scratch_);
            for (double& v : scratch_) v = std::abs(v - med);
            const double mad = median_inplace(scratch_);
            (axis == 0 ? img_foe.x : img_foe.y) = med;
            // 1.4826 MAD estimates a standard deviation; the median's error is 1.25 / sqrt(n)
            // of that.
            const double se = 1.4826 * mad * 1.25 / std::sqrt(static_cast<double>(n));
            img_sigma = axis == 0 ? se : std::max(img_sigma, se);
        }
        img_sigma = std::max(img_sigma, p_.image_foe_floor_px);
    }
    const bool img_ok = !std::isnan(img_sigma) && img_sigma <= p_.max_foe_sigma_px;
    const cv::Point2d nav_foe = calib_.project(nav_dir_);
    nav_rejected_ = false;
    img_overruled_ = false;
    if (img_ok && nav_moving_) {
        // Both: inverse-variance fusion, unless they disagree beyond what their errors allow
        // (a biased velocity, a stale sample; or the images' FOE traded for a rotation): then
        // the navdata's, unless the points' fitted flows plainly run radially from the images'
        // (foe_arbitrate, foe_overrule_ratio); without the arbitration, the images'.
        // Agreeing, the navdata's still replaces the fused one when the points plainly say so.
        const double s_img = std::max(img_sigma, p_.fused_image_foe_floor_px);
        // The weight: also no better than the bias a rotation error gives at this speed.
        const double s_w = p_.image_foe_bias_mps > 0 && nav_speed_ > 0
                               ? std::max(s_img, calib_.fx * p_.image_foe_bias_mps / nav_speed_)
                               : s_img;
        const double v_img = s_w * s_w, v_nav = nav_sigma_px_ * nav_sigma_px_;
        const double v_own = s_img * s_img;  // for the exclusion circle
        const cv::Point2d d = img_foe - nav_foe;
        if (d.dot(d) > p_.foe_gate * p_.foe_gate * (v_img + v_nav)) {
            // One of them is wrong. The images' FOE replaces the navdata's only when the points'
            // fitted flows plainly run radially from it (foe_overrule_ratio): over the realism
            // suites' 3850 such frames the navdata's was the nearer to the true FOE in every one
            // (12 px off at the median, the images' 170), yet the images' misfit was the smaller
            // in half of them (README). Without points to tell, the navdata's.
            const double nav_misfit = p_.foe_arbitrate ? radial_misfit(nav_foe) : kUnknown;
            const double img_misfit = p_.foe_arbitrate ? radial_misfit(img_foe) : kUnknown;
            img_overruled_ = p_.foe_arbitrate && !(img_misfit < p_.foe_overrule_ratio * nav_misfit);
            nav_rejected_ = !img_overruled_;
            foe_ = cv::Point2f(img_overruled_ ? nav_foe : img_foe);
            foe_sigma_px_ = img_overruled_ ? nav_sigma_px_ : img_sigma;
        } else {
            const cv::Point2d fused = (img_foe * v_nav + nav_foe * v_img) * (1.0 / (v_img + v_nav));
            const double nav_misfit = p_.foe_arbitrate >= 2 ? radial_misfit(nav_foe) : kUnknown;
            const double fused_misfit = p_.foe_arbitrate >= 2 ? radial_misfit(fused) : kUnknown;
            img_overruled_ = nav_misfit < p_.foe_arbitrate_ratio * fused_misfit;
            foe_ = cv::Point2f(img_overruled_ ? nav_foe : fused);
            // The fused place, weighted with the floor; its error, with the images' own (the
            // floor is about where their FOE sits, not how far a point must keep from it).
            foe_sigma_px_ =
                img_overruled_ ? nav_sigma_px_ : std::sqrt(v_own * v_nav / (v_own + v_nav));
        }
        foe_source_ = img_overruled_ ? FoeSource::Navdata : FoeSource::Images;
    } else if (img_ok) {
        foe_ = cv::Point2f(img_foe);
        foe_sigma_px_ = img_sigma;
        foe_source_ = FoeSource::Images;
    } else if (nav_moving_) {
        foe_ = cv::Point2f(nav_foe);
        foe_sigma_px_ = nav_sigma_px_;
        foe_source_ = FoeSource::Navdata;
    } else if ((p_.ego_motion && em.valid && em.translation == EgoMotion::Translation::None &&
                !nav_starting_) ||
               nav_slow_) {
        // Nothing static moves in the images (still, or everything too far to matter), or the
        // navdata says the drone hovers: no static point is approaching.
        foe_source_ = FoeSource::Still;
        foe_sigma_px_ = 0;
        return true;
    } else if (!p_.ego_motion) {
        // No ego-motion from the images asked for: the thesis' premise, forward flight (the
        // FOE where the level forward direction appears), every point judged by its TTC.
        const cv::Point2f f = vision::focus_of_expansion(
            calib_, in.attitude.roll_deg, in.attitude.pitch_deg, kUnknown, kUnknown, kUnknown);
        foe_ = std::isnan(f.x)
                   ? cv::Point2f(static_cast<float>(calib_.cx), static_cast<float>(calib_.cy))
                   : f;
        foe_sigma_px_ = 0;
        foe_source_ = FoeSource::Navdata;
        return true;
    } else {
        why = em.points < p_.ego_min_points ? UnknownReason::TooFewPoints
                                            : UnknownReason::NoEgoMotion;
        return false;
    }
    cv::Vec3d use_dir((static_cast<double>(foe_.x) - calib_.cx) / calib_.fx,
                      (static_cast<double>(foe_.y) - calib_.cy) / calib_.fy, 1.0);
    use_dir *= 1.0 / cv::norm(use_dir);
    // The speed for the corridor: the navdata's when it has one, else an assumed one.
    const double speed = !std::isnan(nav_speed_) ? nav_speed_ : p_.assumed_speed_mps;
    cam_velocity_ = use_dir * speed;
    metric_ = p_.corridor && speed >= p_.min_speed_mps;
    return true;
}

void FlowClassifier::all_unknown(UnknownReason why) {
    for (Region r : kRegions) {
        RegionDecision& d = result_.regions[static_cast<std::size_t>(r)];
        d.threshold = r == Region::Centre ? p_.centre_inv_ttc_threshold : p_.side_inv_ttc_threshold;
        d.score = kUnknown;
        d.valid = false;
        d.approach_only = false;
        d.unknown = why;
        d.support = 0;
        d.edge_m = kUnknown;
        confirm(r, false);  // and not unsafe
    }
}

void FlowClassifier::classify(const FrameInput& in) {
    note_nav_rate(in);
    // Where a lost track may count (fb_lost_px): in a region unsafe last frame.
    for (std::size_t r = 0; r < 3; ++r)
        keep_lost_[r] = result_.regions[r].valid && result_.regions[r].unsafe;
    // The allowance over a whole fit window for a point straight below the principal point (the
    // floor ahead): positive when the lag adds to its flow, negative when it takes from it (and
    // none is made).
    const double accel = lag_pitch_accel(static_cast<std::size_t>(std::max(2, p_.velocity_window)));
    plot(s_lag_allowance_, !in.attitude.complete() ? kUnknown
                           : accel == 0            ? 0.0
                                                   : -p_.lag_allowance_s * calib_.fy * accel);
    plot(s_exposure_step_, tracker_.exposure_step());
    // The whole rotation (navdata's and the images' correction), for the centre homography.
    derot_ = small_rotation_homography(calib_, tracker_.rotation_rad());
    plot(s_residual_yaw_, -tracker_.image_correction_deg()[1]);
    plot(s_residual_pitch_, -tracker_.image_correction_deg()[0]);
    const EgoMotion& em = tracker_.ego();
    const bool nav_judged = em.valid && (em.prior_rotation_used || em.prior_rotation_rejected);
    plot(s_image_yaw_, nav_judged ? -em.image_rad[1] * 180.0 / CV_PI : kUnknown);
    plot(s_image_pitch_, nav_judged ? -em.image_rad[0] * 180.0 / CV_PI : kUnknown);
    UnknownReason why = UnknownReason::None;
    fits_current_ = false;
    const bool known = choose_foe(in, why);
    plot(s_prior_rejected_, em.prior_rotation_rejected || nav_rejected_ ? 1 : 0);
    const bool img_known = em.translation == EgoMotion::Translation::Known;
    const bool foe_known = known && foe_source_ != FoeSource::Still;
    plot(s_foe_img_x_, img_known ? static_cast<double>(em.foe.x) : kUnknown);
    plot(s_foe_img_y_, img_known ? static_cast<double>(em.foe.y) : kUnknown);
    const cv::Point2d nav_foe =
        nav_moving_ ? calib_.project(nav_dir_) : cv::Point2d(kUnknown, kUnknown);
    plot(s_foe_nav_x_, nav_foe.x);
    plot(s_foe_nav_y_, nav_foe.y);
    plot(s_foe_x_, foe_known ? static_cast<double>(foe_.x) : kUnknown);
    plot(s_foe_y_, foe_known ? static_cast<double>(foe_.y) : kUnknown);
    plot(s_foe_sigma_, foe_known ? foe_sigma_px_ : kUnknown);
    const double outline = outline_rate(in, foe_known);
    if (!known) {
        const auto& tracks = tracker_.tracks();
        class_.assign(tracks.size(), PointClass::Unrated);
        all_unknown(why);
        // The centre homography still measures its scale (plots), without a decision.
        plot(s_centre_points_, kUnknown);
        plot(s_centre_hom_, p_.centre_homography ? homography_rate(in) : kUnknown);
        plot(s_hazards_, 0);
        plot(s_moving_, 0);
        return;
    }
    // Where the points are relative to the level camera, and how far down the floor is: the
    // corridor tests of the static and the moving points share them.
    const cv::Matx33d level = level_from_camera(in.attitude.roll_deg, in.attitude.pitch_deg);
    const double floor_down = in.altitude_m - p_.floor_clearance_m;  // NaN: no floor test
    rate_points(level, floor_down);
    if (p_.ground_fit_margin > 0 && (p_.ground_fit_always || std::isnan(in.altitude_m)))
        reject_ground();
    // Most of the scene cannot be moving: when more than max_moving_share of the points rated
    // move against the camera motion in use, that motion is wrong (the drone pitching into its
    // first metres while the navdata still reads it as hovering), and their looming says
    // nothing: the regions are unknown.
    std::size_t rated = 0;
    for (std::size_t r = 0; r < 3; ++r)
        rated += static_cast<std::size_t>(rated_count_[r] + lost_rated_[r]);
    if (p_.max_moving_share < 1 && rated >= 10 &&
        static_cast<double>(moving_idx_.size()) >
            p_.max_moving_share * static_cast<double>(rated)) {
        all_unknown(UnknownReason::MotionContradicted);
        plot(s_centre_points_, kUnknown);
        plot(s_centre_hom_, kUnknown);
        plot(s_hazards_, 0);
        plot(s_moving_, static_cast<double>(moving_idx_.size()));
        return;
    }
    if (p_.looming) {
        check_history();
        check_static_looming();
        rate_moving_points(level, floor_down);
    }
    // A lost track (fb_lost_px) counts only where the region was unsafe last frame: it may keep
    // an alarm going (a near surface at the end of a close pass), not raise one (a person's
    // plain clothes walking off the path), nor hold a raw alarm until it is confirmed.
    for (std::size_t r = 0; r < 3; ++r)
        if (keep_lost_[r]) rated_count_[r] += std::exchange(lost_rated_[r], 0);
    for (std::size_t i = 0; i < class_.size(); ++i) {
        if (class_[i] != PointClass::Hazard) continue;
        const auto r = static_cast<std::size_t>(region_of(tracker_.tracks()[i].at_back(0).stab.x));
        if (i < lost_.size() && lost_[i] && !keep_lost_[r]) {
            class_[i] = PointClass::Lost;
            continue;
        }
        hazard_[r].push_back(track_score_[i]);
        hazard_lat_[r].push_back(i < lateral_m_.size() ? lateral_m_[i] : kUnknown);
    }
    plot(s_moving_, static_cast<double>(moving_idx_.size()));
    const double hom =
        p_.centre_homography && foe_source_ != FoeSource::Still ? homography_rate(in) : kUnknown;

    int hazards = 0;
    for (Region r : kRegions) {
        const auto ri = static_cast<std::size_t>(r);
        const bool centre = r == Region::Centre;
        const int k = centre ? p_.centre_min_support : p_.side_min_support;
        RegionDecision& d = result_.regions[ri];
        d.threshold = centre ? p_.centre_inv_ttc_threshold : p_.side_inv_ttc_threshold;
        d.support = static_cast<int>(hazard_[ri].size());
        hazards += d.support;
        d.edge_m = centre ? kUnknown : region_edge(r, d.threshold, k);
        // Enough rated points to judge the region; fewer than k of them in the corridor: 0.
        const bool judged = rated_count_[ri] >= k;
        double score =
            d.support >= k ? kth_largest_inplace(hazard_[ri], k) : (judged ? 0.0 : kUnknown);
        bool raw = !std::isnan(score) && score > d.threshold;
        if (centre) {
            plot(s_centre_points_, score);
            plot(s_centre_hom_, hom);
            for (double channel : {hom, outline}) {
                if (std::isnan(channel)) continue;
                score = std::isnan(score) ? channel : std::max(score, channel);
                raw = score > d.threshold;
            }
        }
        d.score = score;
        d.valid = !std::isnan(score);
        d.approach_only = d.valid && foe_source_ == FoeSource::Still;
        d.unknown = d.valid ? UnknownReason::None : UnknownReason::TooFewPoints;
        confirm(r, raw);
    }
    plot(s_hazards_, hazards);
}

double FlowClassifier::region_edge(Region r, double threshold, int k) {
    // Before hazard_ is reordered by the score's selection. Distances toward the region's own
    // side: the k-th smallest is the innermost edge that k of the points rated unsafe share.
    const auto ri = static_cast<std::size_t>(r);
    const double toward = r == Region::Right ? 1.0 : -1.0;
    auto& v = edge_scratch_;
    v.clear();
    for (std::size_t j = 0; j < hazard_[ri].size() && j < hazard_lat_[ri].size(); ++j)
        if (hazard_[ri][j] > threshold && std::isfinite(hazard_lat_[ri][j]))
            v.push_back(toward * hazard_lat_[ri][j]);
    if (k < 1 || static_cast<int>(v.size()) < k) return kUnknown;
    const auto kth = v.begin() + (k - 1);
    std::nth_element(v.begin(), kth, v.end());
    return *kth;
}

double FlowClassifier::outline_rate(const FrameInput& in, bool foe_known) {
    if (!p_.centre_silhouette || !foe_known || tracker_.grey().empty()) {
        silhouette_.lose();
        plot(s_centre_sil_, kUnknown);
        return kUnknown;
    }
    SilhouetteParams sp;
    sp.step_grey = p_.silhouette_step_grey;
    sp.own_min_px = p_.silhouette_own_px;
    sp.window = p_.velocity_window;
    silhouette_.set_params(sp);
    const SilhouetteResult& r = silhouette_.update(tracker_.grey(), calib_, foe_, derot_,
                                                   static_cast<double>(in.t_ns) * 1e-9);
    // Damaged pictures are not read (their outline is the decoder's guess).
    const double rate = damaged_ ? kUnknown : r.rate;
    plot(s_centre_sil_, rate);
    return rate;
}

const std::vector<FlowClassifier::WindowFit>& FlowClassifier::window_fits() {
    if (fits_current_) return fits_;
    fits_current_ = true;
    const auto& tracks = tracker_.tracks();
    fits_.assign(tracks.size(), WindowFit{});
    const auto win = static_cast<std::size_t>(p_.velocity_window);
    const auto min_len = static_cast<std::size_t>(std::max(2, p_.min_track_length));
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
        // The fitted velocity is the one at the window's mean time, `lag` seconds ago: measure
        // the point where it was then (its translational motion since taken off the current
        // position), so rate, depth and position all refer to one instant.
        double lag = 0;
        for (double v : ts_) lag -= v;
        lag /= static_cast<double>(n);
        WindowFit& w = fits_[i];
        w.ok = true;
        w.n = n;
        w.t0 = t0;
        w.lag = lag;
        w.vx = fx.slope;
        w.vy = fy.slope;
        w.mx = static_cast<double>(t.undist.x) - fx.slope * lag;
        w.my = static_cast<double>(t.undist.y) - fy.slope * lag;
        w.dx = fx.intercept - fx.slope * lag;
        w.dy = fy.intercept - fy.slope * lag;
    }
    return fits_;
}

double FlowClassifier::radial_misfit(const cv::Point2d& foe) {
    const auto& tracks = tracker_.tracks();
    const double min_d2 = p_.min_foe_distance_px * p_.min_foe_distance_px;
    const double min_v2 = p_.flow_noise_px_s * p_.flow_noise_px_s;
    const std::vector<WindowFit>& fits = window_fits();
    scratch_.clear();
    for (std::size_t i = 0; i < fits.size(); ++i) {
        const WindowFit& w = fits[i];
        if (!w.ok || off_motion(tracks[i])) continue;
        const double dx = w.mx - foe.x, dy = w.my - foe.y;
        const double d2 = dx * dx + dy * dy, v2 = w.vx * w.vx + w.vy * w.vy;
        if (d2 < min_d2 || v2 < min_v2) continue;
        const double dn = std::sqrt(d2);
        const double radial = std::abs(w.vx * dx + w.vy * dy) / dn;
        const double across = std::abs(w.vx * dy - w.vy * dx) / dn;
        scratch_.push_back(across / (radial + across));
    }
    if (static_cast<int>(scratch_.size()) < p_.foe_arbitrate_min_points) return kUnknown;
    return median_inplace(scratch_);
}

void FlowClassifier::rate_points(const cv::Matx33d& level, double floor_down) {
    const auto& tracks = tracker_.tracks();
    class_.assign(tracks.size(), PointClass::Unrated);
    ground_dh_.assign(tracks.size(), kUnknown);
    ground_dx_.assign(tracks.size(), kUnknown);
    past_.assign(tracks.size(), Past{kUnknown, kUnknown, kUnknown, 0, 0, 0, 0});
    for (auto& v : hazard_) v.clear();
    for (auto& v : hazard_lat_) v.clear();
    lateral_m_.assign(tracks.size(), kUnknown);
    rated_count_.assign(3, 0);
    lost_.assign(tracks.size(), 0);
    lost_rated_ = {0, 0, 0};
    moving_idx_.clear();
    near_idx_.clear();
    const auto win = static_cast<std::size_t>(p_.velocity_window);
    const auto min_len = static_cast<std::size_t>(std::max(2, p_.min_track_length));
    const bool still = foe_source_ == FoeSource::Still;
    // Still, no point is rated by its flow: no window fits needed.
    const std::vector<WindowFit>* fits = still ? nullptr : &window_fits();
    // Near the FOE a few pixels of error in its place swamp the rate: keep clear of it by the
    // larger of the fixed margin and foe_sigma_k standard errors of where it is.
    const double min_d = std::max(p_.min_foe_distance_px, p_.foe_sigma_k * foe_sigma_px_);
    const double min_d2 = min_d * min_d;
    // The horizon through the FOE, level with the roll the tracker uses (the floor fit).
    const double roll = tracker_.roll_deg() * CV_PI / 180.0;
    const double cos_r = std::cos(roll), sin_r = std::sin(roll);
    for (std::size_t i = 0; i < tracks.size(); ++i) {
        const Trajectory& t = tracks[i];
        const std::size_t n = std::min(win, t.history_size());
        if (n < min_len) continue;
        const auto ri = static_cast<std::size_t>(region_of(t.at_back(0).stab.x));
        // The ego-motion estimate found it off the camera's motion for a few frames: a moving
        // object, judged by its own looming (rate_moving_points) ...
        const bool moving = off_motion(t);
        if (still) {
            if (moving) {
                class_[i] = PointClass::Moving;
                moving_idx_.push_back(i);
            } else {
                track_score_[i] = 0;  // the scene is still: a static point is not approaching
            }
            ++rated_count_[ri];
            continue;
        }
        const WindowFit& w = (*fits)[i];
        if (!w.ok) continue;
        // A lost track (fb_lost_px) judged as a static point may keep an alarm, not raise one
        // (see classify); one judged as moving, by its looming, is guarded by fb_max_px there.
        const bool lost = nav_moving_ && p_.fb_lost_px > 0 &&
                          fb_missed(t, n, std::max(p_.fb_lost_px, p_.fb_max_px));
        const double t0 = w.t0, lag = w.lag, mx = w.mx, my = w.my;
        const double vx = w.vx, vy = w.vy;
        const double dx = mx - static_cast<double>(foe_.x), dy = my - static_cast<double>(foe_.y);
        const double d2 = dx * dx + dy * dy;
        if (d2 < min_d2) {
            if (!moving && p_.near_foe_rows && !fb_unrated(t, n)) {
                lost_[i] = lost ? 1 : 0;
                near_idx_.push_back(i);
            }
            continue;
        }
        const double dn = std::sqrt(d2);
        ground_dh_[i] = -sin_r * dx + cos_r * dy;
        ground_dx_[i] = cos_r * dx + sin_r * dy;
        // Radial flow about the FOE divided by the distance to it: 1/TTC for a static point, the
        // x and y versions of (dx/dt)/(x - x_foe) combined by least squares.
        double radial = (vx * dx + vy * dy) / dn;
        double tangential = (vx * dy - vy * dx) / dn;
        // On an edge only the flow across it is measured; along it LK guesses, and the point
        // slides (a wall's foot, the line between two plain walls: lines toward the FOE, along
        // which a slide is a radial flow, a false approach). Such a point's radial flow comes
        // from its flow across the edge alone, and when the edge runs too near the FOE's
        // direction for that, it is not rated.
        const Aperture ap = aperture(t, dx / dn, dy / dn);
        if (ap.edge) {
            if (std::abs(ap.cos) < p_.aperture_min_cos) {
                class_[i] = PointClass::Aperture;
                continue;
            }
            radial = (vx * ap.nx + vy * ap.ny) / ap.cos;
            tangential = 0;  // not measured
        }
        const double rate_then = radial / dn;
        // What the navdata's lag could have made of the radial flow (lag_allowance_s; 0 with
        // the allowance off or outside a manoeuvre).
        const double lag_px_s =
            radial > 0 ? lag_flow_px_s(w, ap.edge ? ap.ny / ap.cos : dy / dn) : 0.0;
        {
            // Where it was, for check_history: along the direction its flow is measured in (the
            // edge's normal on an edge), its translation-only path taken back from then.
            double ux = dx / dn, uy = dy / dn;
            if (ap.edge) {
                const double sgn = ap.cos < 0 ? -1.0 : 1.0;
                ux = sgn * ap.nx;
                uy = sgn * ap.ny;
            }
            past_[i] = {t0 - lag, rate_then, dx * ux + dy * uy, ux, uy, w.dx, w.dy};
        }
        const double rate = rate_now(rate_then, lag);
        // Below the path only as far along its ray as the navdata's lag could have moved it
        // (lag_allowance_s): the depth from the radial flow without what the lag could have
        // added to it (all of it the lag's: at any depth, not placed on the path).
        const double vscale = radial > lag_px_s ? radial / (radial - lag_px_s)
                                                : std::numeric_limits<double>::infinity();
        // With track.fb_max_px set and fb_static, flying forward, a point LK could not track
        // back to where it came from in a frame of the fit window is not rated as a static
        // point: its flow may be a slip along a repeating pattern (a tiled floor) or an
        // occluding edge dragging it (a person walking past), not the scene's.
        const bool fb_miss = fb_unrated(t, n);
        if (fb_miss && !moving) continue;
        track_score_[i] = rate;
        const bool across =
            std::abs(tangential) > p_.max_tangential_ratio * std::abs(radial) + p_.flow_noise_px_s;
        // ... unless its flow, over the fit window, is radial from the FOE used (which may be
        // the navdata's where the images' own was off): then it is a static point after all.
        if (moving && (across || radial < -p_.flow_noise_px_s)) {
            ++rated_count_[ri];
            class_[i] = PointClass::Moving;
            moving_idx_.push_back(i);
            track_score_[i] = kUnknown;
            continue;
        }
        lost_[i] = lost ? 1 : 0;
        count_rated(i, ri);
        if (across || fb_miss) {
            class_[i] = PointClass::Inconsistent;
            continue;
        }
        if (!(rate > 0)) continue;  // receding or still: never an obstacle
        if (outside_corridor(mx, my, rate_then, level, floor_down, vscale, &lateral_m_[i])) {
            class_[i] = PointClass::Outside;
            continue;
        }
        class_[i] = PointClass::Hazard;  // counted in classify, unless its looming says not
    }
    if (!near_idx_.empty()) rate_near_foe(level, floor_down);
}

bool FlowClassifier::outside_corridor(double mx, double my, double rate_then,
                                      const cv::Matx33d& level, double floor_down,
                                      double vertical_scale, double* lateral) const {
    if (lateral != nullptr) *lateral = kUnknown;
    if (!metric_) return false;
    // Depth along the optical axis from the time to contact and the forward speed, then the
    // point in the level frame: beside the corridor, floor, or overhead?
    const double z = cam_velocity_[2] / rate_then;
    const cv::Vec3d pc((mx - calib_.cx) / calib_.fx * z, (my - calib_.cy) / calib_.fy * z, z);
    // Its offset from the flight line grows with the square of its distance from the FOE (the
    // depth goes as that distance over the radial flow): with the FOE corridor_foe_k of its
    // standard errors nearer, is it still beside?
    double across = 1;
    if (p_.corridor_foe_k > 0) {
        const double dn =
            std::hypot(mx - static_cast<double>(foe_.x), my - static_cast<double>(foe_.y));
        const double s = dn > 0 ? std::max(0.0, dn - p_.corridor_foe_k * foe_sigma_px_) / dn : 1.0;
        across = s * s;
    }
    return outside_corridor(pc, level, floor_down, across, vertical_scale, lateral);
}

bool FlowClassifier::outside_corridor(const cv::Vec3d& pc, const cv::Matx33d& level,
                                      double floor_down, double across, double vertical_scale,
                                      double* lateral) const {
    const cv::Vec3d pl = level * pc;
    // Across the path: measured from the flight line (the direction of travel).
    const cv::Vec3d dir_l = level * cam_velocity_;
    const double dnorm = cv::norm(dir_l);
    const double along = dnorm > 0 ? pl.dot(dir_l) / dnorm : 0.0;
    const cv::Vec3d off = dnorm > 0 ? pl - along * dir_l * (1.0 / dnorm) : pl;
    const bool beside = std::abs(off[1]) * across > p_.corridor_half_width_m;
    if (lateral != nullptr) *lateral = off[1];
    // Below or above the path: the point as far along its ray as its depth may be
    // (vertical_scale >= 1, lag_allowance_s: only for points below the principal point).
    const double down = pl[2] * vertical_scale;
    const bool floor = !std::isnan(floor_down) && down > floor_down;
    const bool overhead = down < -p_.corridor_up_m;
    return beside || floor || overhead;
}

void FlowClassifier::rate_near_foe(const cv::Matx33d& level, double floor_down) {
    // See FlowParams::near_foe_rows. Candidates for neighbours: static tracks with a window fit
    // whose motion along the row is measured (not on a row-like edge).
    const auto& tracks = tracker_.tracks();
    const std::vector<WindowFit>& fits = window_fits();
    const auto win = static_cast<std::size_t>(p_.velocity_window);
    const auto min_len = static_cast<std::size_t>(std::max(4, p_.min_track_length));
    row_measured_.assign(tracks.size(), 0);
    for (std::size_t b = 0; b < tracks.size(); ++b) {
        const Trajectory& t = tracks[b];
        if (!fits[b].ok || off_motion(t) || class_[b] == PointClass::Moving ||
            std::min(win, t.history_size()) < min_len)
            continue;
        const Aperture ap = aperture(t, 1.0, 0.0);
        row_measured_[b] = !ap.edge || std::abs(ap.cos) >= p_.aperture_min_cos ? 1 : 0;
    }
    const double r2max = p_.loom_radius_px * p_.loom_radius_px;
    const double min_sx = p_.loom_min_spread_px;
    for (std::size_t a : near_idx_) {
        if (!row_measured_[a]) continue;
        const Trajectory& ta = tracks[a];
        loom_.clear();
        near_r1_.clear();
        near_r2_.clear();
        for (std::size_t b = 0; b < tracks.size(); ++b) {
            if (b == a || !row_measured_[b]) continue;
            const Trajectory& tb = tracks[b];
            const cv::Point2f d_now = ta.at_back(0).derot - tb.at_back(0).derot;
            const double sx = static_cast<double>(d_now.x);
            if (std::abs(static_cast<double>(d_now.y)) > p_.near_foe_row_px ||
                std::abs(sx) < min_sx || sx * sx > r2max)
                continue;
            const std::size_t n = std::min({win, ta.history_size(), tb.history_size()});
            if (n < min_len) continue;
            const std::size_t mid = (n - 1) / 2;
            const double s_then = static_cast<double>(ta.at_back(n - 1).derot.x) -
                                  static_cast<double>(tb.at_back(n - 1).derot.x);
            const double s_mid = static_cast<double>(ta.at_back(mid).derot.x) -
                                 static_cast<double>(tb.at_back(mid).derot.x);
            // The same order along the row throughout, never nearer than the noise allows.
            if (s_then * sx <= 0 || s_mid * sx <= 0 || std::abs(s_then) < min_sx ||
                std::abs(s_mid) < min_sx)
                continue;
            const double t_now = ta.at_back(0).t_s, t_mid = ta.at_back(mid).t_s,
                         t_then = ta.at_back(n - 1).t_s;
            if (!(t_mid > t_then) || !(t_now > t_mid)) continue;
            loom_.push_back(std::log(sx / s_then) / (t_now - t_then));
            near_r1_.push_back(std::log(s_mid / s_then) / (t_mid - t_then));
            near_r2_.push_back(std::log(sx / s_mid) / (t_now - t_mid));
        }
        if (static_cast<int>(loom_.size()) < p_.loom_min_neighbours) continue;
        const double rate_then = median_inplace(loom_);
        const WindowFit& w = fits[a];
        const auto ri = static_cast<std::size_t>(region_of(ta.at_back(0).stab.x));
        count_rated(a, ri);
        track_score_[a] = rate_now(rate_then, w.lag);
        if (!(rate_then > 0)) continue;  // not nearing
        if (p_.near_foe_growth > 0 &&
            median_inplace(near_r2_) < p_.near_foe_growth * median_inplace(near_r1_)) {
            class_[a] = PointClass::Inconsistent;  // parting ever slower: not a surface neared
            continue;
        }
        class_[a] = outside_corridor(w.mx, w.my, rate_then, level, floor_down, 1, &lateral_m_[a])
                        ? PointClass::Outside
                        : PointClass::Hazard;
    }
}

void FlowClassifier::reject_ground() {
    // The points the fit reads: rated static ones, far enough below the horizon.
    auto below = [&](std::size_t i) {
        return (class_[i] == PointClass::Hazard || class_[i] == PointClass::Outside) &&
               ground_dh_[i] >= p_.ground_fit_min_dh_px && track_score_[i] > 0;
    };
    scratch_.clear();
    for (std::size_t i = 0; i < class_.size(); ++i)
        if (below(i)) scratch_.push_back(track_score_[i] / ground_dh_[i]);
    if (static_cast<int>(scratch_.size()) < p_.ground_fit_min_points) return;
    const auto q = static_cast<std::ptrdiff_t>(p_.ground_fit_quantile *
                                               static_cast<double>(scratch_.size() - 1));
    std::nth_element(scratch_.begin(), scratch_.begin() + q, scratch_.end());
    const double slope = scratch_[static_cast<std::size_t>(q)];
    const double k = slope * (1 + p_.ground_fit_margin);
    // A floor spans the view: points that fit it in at least two of the three regions. An
    // obstacle ahead over a floor too plain to track is the lowest envelope of its own rates,
    // and fits no line across the view.
    std::array<int, 3> fit{};
    const auto& tracks = tracker_.tracks();
    for (std::size_t i = 0; i < class_.size(); ++i)
        if (below(i) && track_score_[i] <= k * ground_dh_[i])
            ++fit[static_cast<std::size_t>(region_of(tracks[i].at_back(0).stab.x))];
    int regions = 0;
    for (int n : fit) regions += n >= 3 ? 1 : 0;
    if (regions < 2) return;
    for (std::size_t i = 0; i < class_.size(); ++i)
        if (class_[i] == PointClass::Hazard && ground_dh_[i] > 0 &&
            track_score_[i] <= k * ground_dh_[i])
            class_[i] = PointClass::Outside;
    // Without a speed, the floor's slope (V / (f h)) gives the points' places in units of the
    // height above it: across the path |dx| slope h / rate, above the camera -dh slope h / rate.
    // With an assumed height no higher than the real one, a point judged beside or above the
    // corridor is farther still.
    if (metric_ || !(p_.ground_height_m > 0)) return;
    for (std::size_t i = 0; i < class_.size(); ++i) {
        if (class_[i] != PointClass::Hazard || !(track_score_[i] > 0)) continue;
        const double per_px = slope * p_.ground_height_m / track_score_[i];  // m per px
        if (std::abs(ground_dx_[i]) * per_px > p_.corridor_half_width_m ||
            -ground_dh_[i] * per_px > p_.corridor_up_m)
            class_[i] = PointClass::Outside;
    }
}

bool FlowClassifier::fb_missed(const Trajectory& t, std::size_t n, double px) const {
    if (!(p_.fb_max_px > 0)) return false;
    for (std::size_t k = 0; k + 1 < n; ++k)
        if (!(static_cast<double>(t.at_back(k).fb_px) <= px)) return true;
    return false;
}

bool FlowClassifier::fb_unrated(const Trajectory& t, std::size_t n) const {
    return nav_moving_ && p_.fb_static && fb_missed(t, n, p_.fb_max_px);
}

double FlowClassifier::looming_rate(std::size_t a, bool moving_only, double lo, double hi,
                                    double radius) {
    // The median rate at which a's distances to its neighbours grow (1/TTC for a roughly
    // fronto-parallel patch: the trajectories' derot positions are free of the rotation). The
    // neighbours: moving points, or static ones whose own rate lies in [lo, hi] (the same
    // surface). NaN with fewer than loom_min_neighbours of them.
    const auto& tracks = tracker_.tracks();
    const auto win = static_cast<std::size_t>(std::max(2, p_.velocity_window));
    const double r2max = radius * radius;
    const double min2 = p_.loom_min_spread_px * p_.loom_min_spread_px;
    const Trajectory& ta = tracks[a];
    loom_.clear();
    // Flying forward, a moving object's points that LK could not track back (dragged along its
    // outline over the background streaming past) do not move with it. Not before a still
    // camera: there a hand opening as it reaches toward the lens misses too, and is all there is.
    const bool fb_out = moving_only && nav_moving_;
    if (fb_out && fb_missed(ta, std::min(win, ta.history_size()), p_.fb_max_px)) return kUnknown;
    const auto consider = [&](std::size_t b) {
        if (a == b) return;
        const Trajectory& tb = tracks[b];
        if (fb_out && fb_missed(tb, std::min(win, tb.history_size()), p_.fb_max_px)) return;
        const cv::Point2f d_now = ta.at_back(0).derot - tb.at_back(0).derot;
        const double n2 = static_cast<double>(d_now.dot(d_now));
        if (n2 > r2max || n2 < min2) return;
        const std::size_t n = std::min({win, ta.history_size(), tb.history_size()});
        if (n < 2) return;
        const TrackPoint& pa = ta.at_back(n - 1);
        const TrackPoint& pb = tb.at_back(n - 1);
        const cv::Point2f d_then = pa.derot - pb.derot;
        const double t2 = static_cast<double>(d_then.dot(d_then));
        const double dt = ta.at_back(0).t_s - pa.t_s;
        if (t2 < min2 || !(dt > 0)) return;
        // Two points of one approaching object move apart along the line joining them; a
        // pair whose separation turns more than it stretches is not on one rigid patch (a
        // point sliding along an occluding edge, a turning head).
        const cv::Point2f ds = d_now - d_then;
        const double along = static_cast<double>(ds.dot(d_then)) / std::sqrt(t2);
        const double across =
            std::abs(static_cast<double>(ds.x * d_then.y - ds.y * d_then.x)) / std::sqrt(t2);
        if (across > std::abs(along) + p_.flow_noise_px_s * dt) return;
        loom_.push_back(0.5 * std::log(n2 / t2) / dt);
    };
    if (moving_only) {
        for (std::size_t b : moving_idx_) consider(b);
    } else {
        // A lost track bears a point out only where it may count (fb_lost_px, classify).
        for (std::size_t b = 0; b < tracks.size(); ++b)
            if (class_[b] == PointClass::Hazard && track_score_[b] >= lo && track_score_[b] <= hi &&
                (b >= lost_.size() || !lost_[b] ||
                 keep_lost_[static_cast<std::size_t>(region_of(tracks[b].at_back(0).stab.x))]))
                consider(b);
    }
    if (static_cast<int>(loom_.size()) < p_.loom_min_neighbours) return kUnknown;
    return median_inplace(loom_);
}

double FlowClassifier::odometer_at(double t_s) const {
    // Linear between the samples (binary search: the samples' times rise); NaN outside them.
    const std::size_t n = odometer_.size();
    if (n < 2 || t_s < odometer_[0].t_s - 1e-6 || t_s > odometer_.back().t_s + 1e-6)
        return kUnknown;
    std::size_t lo = 1, hi = n - 1;  // the first sample at or after t_s, at least the second
    while (lo < hi) {
        const std::size_t mid = (lo + hi) / 2;
        if (odometer_[mid].t_s < t_s)
            lo = mid + 1;
        else
            hi = mid;
    }
    const Odometer& a = odometer_[lo - 1];
    const Odometer& b = odometer_[lo];
    const double w = std::clamp((t_s - a.t_s) / (b.t_s - a.t_s), 0.0, 1.0);
    return a.s_m + w * (b.s_m - a.s_m);
}

void FlowClassifier::check_history() {
    // A static point nears the camera at the drone's speed: its depth dt ago was its depth now
    // (speed / rate) plus the distance flown since, and it sat that much nearer the FOE. A point
    // walking outward (a person leaving the path) reads as a near static point by its rate, but
    // a near static point comes from close by the FOE only in its last moments: its past lies
    // far nearer the FOE than such a point's would. Judged by its looming, it is not
    // approaching.
    if (!(p_.history_check > 0)) return;
    // With a navdata velocity, only while it says the drone flies forward: hovering, the rates
    // are noise and the past says nothing.
    const bool have_v = !std::isnan(nav_speed_);
    if (have_v && !nav_moving_) return;
    const auto& tracks = tracker_.tracks();
    for (std::size_t i = 0; i < class_.size(); ++i) {
        if (class_[i] != PointClass::Hazard) continue;
        const Past& p = past_[i];
        const Trajectory& t = tracks[i];
        const double s_then = have_v ? odometer_at(p.t_s) : kUnknown;  // at the rate's time
        // Every kept past position at least history_min_s before the rate's time, newest first.
        bool moved = false, slow = false;
        for (std::size_t back = 0; back < t.history_size() && !moved; ++back) {
            const TrackPoint& q = t.at_back(back);
            const double dt = p.t_s - q.t_s;
            if (dt < p_.history_min_s) continue;
            // Depth then over depth now = 1 + rate * (distance flown / speed).
            const double flown = s_then - odometer_at(q.t_s);  // NaN when either is unknown
            const double dt_eff = std::isnan(flown) || !(nav_forward_mps_ > p_.min_speed_mps)
                                      ? dt
                                      : flown / nav_forward_mps_;
            const double predicted = p.a / (1.0 + p.rate * dt_eff);
            const double was = p.a + (static_cast<double>(q.derot.x) - p.derot_x) * p.ux +
                               (static_cast<double>(q.derot.y) - p.derot_y) * p.uy;
            moved = was < p_.history_check * predicted - p_.history_noise_px;
            // Covered a small share of the way a static point with its rate would have: it sat
            // nearly still, and its rate is a slip or a jump (an occluding edge dragged it).
            // Only with the distance flown known: a camera that sped up from rest sees its
            // static points sit still and then move too.
            if (p_.history_slow > 0 && !std::isnan(flown) &&
                p.a - predicted > 4 * p_.history_noise_px &&
                p.a - was < p_.history_slow * (p.a - predicted)) {
                slow = true;
                break;
            }
        }
        if (slow) {
            class_[i] = PointClass::Inconsistent;
        } else if (moved) {
            class_[i] = PointClass::Moving;
            track_score_[i] = kUnknown;
            moving_idx_.push_back(i);
        }
    }
}

void FlowClassifier::check_static_looming() {
    // A static point's rate about the FOE and the rate at which its distances to its neighbours
    // on the same surface grow are one and the same 1/TTC. Something moving across the view
    // away from the FOE (a person walking out of the path) has a radial flow too, read as a
    // near static point, but its points' distances grow only as fast as it really nears. A
    // point whose neighbours at a like rate (same surface) spread at less than
    // loom_consistency of its own rate is taken for a moving one, judged by its looming.
    // With too few such neighbours to tell, the point counts (a hand before a still camera: its
    // points cluster too closely to measure a spread; a plain pillar ahead shows a few specks),
    // except in the side regions while the navdata says the drone flies forward
    // (loom_confirm_sides): something there is in the corridor only when it is near (0.6 m off
    // the flight line is outside the centre band beyond about 4 m), so it spans enough of the
    // image for its points' spread to be measured, and a lone rate there (a slide along a
    // wall's foot, a point on a person walking off the path) has nothing to bear it out.
    if (!(p_.loom_consistency > 0)) return;
    const bool confirm_sides = p_.loom_confirm_sides && nav_moving_;
    const auto& tracks = tracker_.tracks();
    check_.clear();
    for (std::size_t i = 0; i < class_.size(); ++i) {
        if (class_[i] != PointClass::Hazard) continue;
        const double r = track_score_[i];
        double loom = looming_rate(i, false, 0.5 * r, 2.0 * r, p_.loom_radius_px);
        const Trajectory& ti = tracks[i];
        // Too young for check_history to see its past: its neighbours must bear it out there too.
        const bool young =
            p_.loom_confirm_young &&
            ti.at_back(0).t_s - ti.at_back(ti.history_size() - 1).t_s < p_.history_min_s;
        const bool confirm =
            confirm_sides && (young || region_of(ti.at_back(0).stab.x) != Region::Centre);
        // A near surface's points lie far apart: look farther for those that must confirm.
        if (std::isnan(loom) && confirm)
            loom = looming_rate(i, false, 0.5 * r, 2.0 * r, p_.confirm_radius_px);
        if (!std::isnan(loom) && loom < p_.loom_consistency * r)
            check_.push_back(i);  // moving
        else if (std::isnan(loom) && confirm)
            class_[i] = PointClass::Unrated;  // nothing bears it out
    }
    for (std::size_t i : check_) {
        class_[i] = PointClass::Moving;
        track_score_[i] = kUnknown;
        moving_idx_.push_back(i);
    }
}

FlowClassifier::Aperture FlowClassifier::aperture(const Trajectory& t, double rx, double ry) const {
    // The structure tensor is the raw image's; in undistorted pixels it is D^T G D, D the
    // distortion's Jacobian there (gradients are covectors).
    const cv::Point2f r0 = calib_.distort_point(t.undist);
    const cv::Point2f ex = calib_.distort_point(t.undist + cv::Point2f(1, 0)) - r0;
    const cv::Point2f ey = calib_.distort_point(t.undist + cv::Point2f(0, 1)) - r0;
    const cv::Matx22d d(static_cast<double>(ex.x), static_cast<double>(ey.x),
                        static_cast<double>(ex.y), static_cast<double>(ey.y));
    const auto a = static_cast<double>(t.structure[0]);
    const auto b = static_cast<double>(t.structure[1]);
    const auto c = static_cast<double>(t.structure[2]);
    const EdgeNormal e = edge_normal(d.t() * cv::Matx22d(a, b, b, c) * d, p_.aperture_edge_ratio);
    Aperture ap;
    if (!e.edge) return ap;
    ap.edge = true;
    ap.nx = e.nx;
    ap.ny = e.ny;
    ap.cos = e.nx * rx + e.ny * ry;
    return ap;
}

void FlowClassifier::rate_moving_points(const cv::Matx33d& level, double floor_down) {
    // A moving object approaching grows in the image: the distances between its points grow at
    // 1/TTC (for a roughly fronto-parallel patch), whatever the camera does. Median over
    // neighbours on the same object (moving points nearby), so one slipping point cannot decide.
    // Growing is not enough to hit: an object on a collision course keeps its bearing (its
    // derotated image position), one that will pass drifts across the image. Relative to the
    // camera a point at depth Z nearing at Z / TTC with derotated image velocity v (rad/s) is
    // v Z TTC off the camera when it reaches the camera's plane. Its depth is not measured; taken
    // as speed x TTC (an object crossing the path, or standing), it is too short for one coming
    // toward the drone, which then reads nearer the path than it will pass (so still counts),
    // and too long only for one receding ahead, slower than the drone and so late to matter.
    const bool test_path = p_.moving_corridor && metric_;
    const std::vector<WindowFit>* fits = test_path ? &window_fits() : nullptr;
    for (std::size_t a : moving_idx_) {
        const double rate = looming_rate(a, true, 0, 0, p_.loom_radius_px);
        if (std::isnan(rate)) continue;
        track_score_[a] = rate;
        double miss_lateral = kUnknown;  // where it crosses the camera's plane
        if (rate > 0 && fits != nullptr && (*fits)[a].ok) {
            const WindowFit& w = (*fits)[a];
            const double ttc = 1.0 / rate;
            const double z = cam_velocity_[2] * ttc;
            const cv::Vec3d miss(w.vx / calib_.fx * z * ttc, w.vy / calib_.fy * z * ttc, 0.0);
            if (outside_corridor(miss, level, floor_down, 1, 1, &miss_lateral)) {
                class_[a] = PointClass::Outside;
                continue;
            }
        }
        if (rate > 0) {
            const auto ri =
                static_cast<std::size_t>(region_of(tracker_.tracks()[a].at_back(0).stab.x));
            hazard_[ri].push_back(rate);
            hazard_lat_[ri].push_back(miss_lateral);
        }
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

std::string_view FlowClassifier::to_string(PointClass c) {
    switch (c) {
        case PointClass::Unrated:
            return "unrated";
        case PointClass::Inconsistent:
            return "inconsistent";
        case PointClass::Aperture:
            return "aperture";
        case PointClass::Outside:
            return "outside";
        case PointClass::Hazard:
            return "hazard";
        case PointClass::Moving:
            return "moving";
        case PointClass::Lost:
            return "lost";
    }
    return "unrated";
}

std::string_view FlowClassifier::point_kind(std::size_t i) const {
    return i < class_.size() ? to_string(class_[i]) : "unrated";
}

void FlowClassifier::add_overlay_points() {
    // Rings (the trajectories layer): corridor points coloured by 1/TTC, blue to red at
    // colour_max; points still being judged, and lost tracks that may not count, small and
    // blue; points placed outside the corridor or with inconsistent flow small and grey. Filled
    // dots (the centre band layer): the band's points. The white ring is the focus of expansion.
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
            case PointClass::Lost:
                o.points.push_back({tracks[i].raw, 3, blue_to_red(0), false});
                break;
            case PointClass::Moving:
                o.points.push_back({tracks[i].raw, 4, blue_to_red(s / p_.colour_max), true});
                break;
            case PointClass::Outside:
            case PointClass::Inconsistent:
            case PointClass::Aperture:
                o.points.push_back({tracks[i].raw, 2, kGrey, false});
                break;
        }
    }
    for (const Trajectory& t : tracks)
        if (region_of(t.at_back(0).stab.x) == Region::Centre)
            o.points.push_back({t.raw, 1.5f, kYellow, true});
    if (foe_source_ == FoeSource::Images || foe_source_ == FoeSource::Navdata)
        o.points.push_back({calib_.distort_point(foe_), 7, kWhite, false});
    // The outline channel's plain run through the FOE: coloured by its rate when it reads as a
    // near surface's outline, grey while it is only followed, with a tick at each end.
    const SilhouetteResult& run = silhouette_.last();
    if (p_.centre_silhouette && run.run) {
        const Rgb c = std::isnan(run.rate) ? kGrey : blue_to_red(run.rate / p_.colour_max);
        const cv::Point2f l(run.left, run.row), r(run.right, run.row);
        o.lines.push_back({l, r, c, 2});
        for (const cv::Point2f& e : {l, r})
            o.lines.push_back({e + cv::Point2f(0, -8), e + cv::Point2f(0, 8), c, 2});
    }
}

}  // namespace gs::vision
