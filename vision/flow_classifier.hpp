#pragma once
// A better classifier behind the same interface ("flow"). It answers the thesis' own failures
// (§6.2.4, §8.2) with the geometry of the camera's motion:
//  - the camera's rotation between frames is removed: estimated from the tracked points
//    themselves (vision/ego_motion.hpp), with the navdata attitude change as a prior the images
//    refine (and reject when they disagree: a stale or biased sample), so footage without
//    navdata is derotated too; LK starts each search where the predicted rotation moves the point;
//  - the focus of expansion (FOE) comes from the derotated flow, fused with the navdata
//    velocity's direction when there is one, with its standard error;
//  - each trajectory is judged by its expansion rate about the FOE, an inverse time-to-contact
//    (1/s) that does not depend on where in the image the point is;
//  - with a speed (the navdata's, else an assumed one) the rate gives the point's depth
//    (Z = forward speed x TTC), hence where it is: only points inside the flight corridor
//    (beside the drone by less than corridor_half_width_m, above the floor, not far overhead) can
//    be obstacles, so the floor and side walls do not raise alarms however fast they stream by;
//  - a static point's rate also sets its past (check_history): a point that came from nearer
//    the focus of expansion than a static point with that rate could have (a person walking
//    off the path) is moving, and one that sat still far longer (dragged by an occluding edge)
//    is not rated;
//  - a point that Lucas-Kanade could not track back to where it came from (track.fb_max_px)
//    says nothing of a moving object's looming; optionally (fb_static), flying forward, nor of
//    a static point's rate: its flow may be a slip along a repeating pattern (a tiled floor).
//    That also drops a near surface seen at a grazing angle, whose patches LK follows less
//    exactly, so it is off by default (README, Realism suite);
//  - points that do not move with the scene (a hand, a person walking toward the drone) are
//    judged by their own looming: the rate at which the distances to their neighbours on the same
//    object grow, a time to contact that needs no FOE;
//  - a region is unknown, not clear, when there is no evidence: too few points, or neither a
//    usable velocity nor a reliable FOE (and the camera is not still), or most of the rated
//    points moving against the camera motion in use (max_moving_share: that motion is wrong);
//  - the centre can also read the expansion of the band's dominant plane from a derotated RANSAC
//    homography (off by default, see centre_homography);
//  - regions are scored with robust statistics (k-th largest rate), and a decision must hold for
//    a few frames.

#include "vision/classifier.hpp"
#include "vision/silhouette.hpp"

namespace gs::vision {

struct FlowParams : TrackerParams {
    FlowParams() {
        grid_cols = 4;  // trajectories spread over 4 x 3 cells: every part of the view is watched
        grid_rows = 3;
        // Measured for every point; misses keep points dragged along an outline (a person's)
        // out of a moving object's looming (fb_static).
        fb_max_px = 0.5;
        // track.gain_bands (photometric compensation) stays off: on the realism suite's seed-2026
        // open-space flights 32 bands cut the false alarms from 6 of 9 to 1 of 9, but on the
        // real clips (tests/app/real_clips_test.cpp) it misses two hand approaches and flags
        // quiet windows (a hand entering a band moves that band's mean, which the compensation
        // takes for a gain change). See README "Realism suite".
        // An exposure step is compensated, on the frames it happens only: 13 % darker in one
        // frame made the tiled floor's points slip a tile and brake the assist in open space.
        step_gain_min = 0.05;
        // The AR.Drone 2 front camera's rolling shutter, unrolled in manoeuvres only: a pitch
        // into forward flight stretches each frame more than the last and static points part
        // as if they loomed (the realism closed loop's take-off brakes), while in cruise the
        // navdata's rate is mostly its noise, and unrolling by it shifts the rows against each
        // other by up to a pixel a frame (tests/vision/tracker_test.cpp, TrackerShutter).
        readout_ms = -1;  // the camera's (its calibration's), else the AR.Drone 2's 25 ms
        readout_deadband_dps = 10;
    }
    int velocity_window = 10;          // frames for each trajectory's image velocity fit
    int min_track_length = 6;          // fewer points: no rate
    double min_foe_distance_px = 30;   // the rate is ill-conditioned near the FOE
    bool use_velocity_for_foe = true;  // place the FOE from navdata velocity when known
    double foe_sigma_k = 3;  // and keep this many standard errors of its place away from it
    // The aperture problem: a point whose smaller structure-tensor eigenvalue is below this share
    // of the larger lies on an edge, and only its flow across the edge is used (radial flow =
    // normal flow / cos of the angle between the edge's normal and the FOE ray); below
    // aperture_min_cos the edge runs too close to the ray for that, and the point is not rated.
    // The rate's noise grows as 1 / cos: 0.4 (the edge's normal up to 66 degrees from the ray,
    // 2.5 times the noise of a normal along it) since session 39, 0.5 before. An obstacle painted
    // in stripes shows mostly edges: on seed 23's hazard-striped pillar at 2.0 m/s one more edge
    // point rated makes the centre unsafe 2.5 m out instead of 0.84 m (README, Collision assist,
    // session 39).
    double aperture_edge_ratio = 0.2;
    double aperture_min_cos = 0.4;
    // Flow consistency: the tangential part of a point's derotated flow must stay below this
    // share of the radial part plus flow_noise_px_s, or the point is not a static one we approach.
    double max_tangential_ratio = 0.5;
    double flow_noise_px_s = 6;
    // The flight corridor (needs a speed; the floor also the altitude).
    bool corridor = true;
    double min_speed_mps = 0.2;          // slower: the depth is too uncertain to place points
    double corridor_half_width_m = 0.6;  // drone half-width (0.26 m with the hull) + margin
    // A point's offset from the flight line grows with the square of its distance from the FOE,
    // and the FOE is known to foe_sigma_px (a navdata velocity biased by a few cm/s moves it 20
    // px at 1.3 m/s): a static point is beside the corridor only when it is with the FOE this
    // many standard errors nearer it (0: the FOE as placed). Measured: README, Realism suite.
    double corridor_foe_k = 1;
    double floor_clearance_m = 0.3;  // lower than this above the floor: the floor
    double corridor_up_m = 1.0;      // higher than this above the camera: overhead
    // The floor from the flow itself (0 = off): flying parallel to the floor, a floor point's
    // rate grows in proportion to its distance below the horizon through the FOE (rate = V dh /
    // (f h)), and anything else seen at that row is nearer than the floor there, so rates
    // faster. The slope is the ground_fit_quantile of rate / dh over the rated points at least
    // ground_fit_min_dh_px below the horizon (ground_fit_min_points of them); a point at most
    // (1 + ground_fit_margin) times the floor's rate at its row is taken for the floor, when
    // at least three points of two regions fit it (a floor spans the view). Needs neither speed
    // nor altitude; used without the altitude only (with it, floor_clearance_m decides: in
    // closed loop the fit delayed the brake before a pillar, README).
    double ground_fit_margin = 0.6;
    bool ground_fit_always = false;  // with the altitude too (measured: README)
    // Without speed or altitude, the corridor from the floor fit's slope and this height above
    // the floor, a lower bound of the real one (0 = no corridor without a speed).
    double ground_height_m = 0.5;
    double ground_fit_quantile = 0.25;
    double ground_fit_min_dh_px = 20;
    int ground_fit_min_points = 8;
    // Without a navdata velocity the corridor can be placed with an assumed speed (footage whose
    // speed is roughly known; the AR.Drone's indoor flights: 0.5-1.5 m/s). 0, the default: no
    // corridor, every static point judged by its time to contact alone, which misses nothing
    // (a wrong speed misplaces every point across the path by the same factor).
    double assumed_speed_mps = 0;
    // The navdata velocity's direction is trusted to this (m/s across the path, a bias of a few
    // cm/s as an onboard estimator has), besides its sample-to-sample scatter.
    double velocity_bias_mps = 0.05;
    // The images' FOE is used when its standard error (averaged over velocity_window frames) is
    // below this; without it and without a velocity, a moving camera's regions are unknown.
    double max_foe_sigma_px = 40;
    double image_foe_floor_px = 8;  // the images' FOE is never taken as better known than this
    // Opt-in (0 = off): fused with the navdata's, the images' FOE counts as known no better than
    // this. Its error is mostly not the frame-to-frame scatter its standard error comes from but
    // a bias common to the frames: over a scene 10 m and more away a rotation error of a few
    // hundredths of a degree a frame, under what the images resolve, moves it tens of pixels
    // (the rotation-translation ambiguity). Over the virtual drone's tiled floor it sat 20-35 px
    // below the navdata's (and the true one) through a whole cruise, up to 60, while claiming
    // 13-23 px (a suspected cause, not verified: Lucas-Kanade reading the foreshortened floor's
    // vertical expansion short); fused as if that well known, it placed the FOE on the floor and
    // raised centre false alarms that braked the assist in open space. 40 (with
    // velocity_bias_mps 0.03) cuts those brakes on the clean closed loop, but with a real
    // camera's late, drifting navdata (the realism layer) the images' correction is worth more
    // and the centre's false alarms rise: off by default (README, Collision assist). Without a
    // navdata velocity, or with it rejected, the images' FOE keeps its own standard error.
    double fused_image_foe_floor_px = 0;
    // The same floor as a speed: fused with the navdata's, the images' FOE counts as known no
    // better than fx x image_foe_bias_mps / speed (0 = off). A rotation error under what the
    // images resolve moves their FOE by its flow over the translation's, so in proportion to
    // 1 / speed: in seed 11's open flight at 0.6 m/s the images' FOE sat 100 px below the true
    // one (from the ground truth) while claiming 8-30 px (README, Collision assist). Only the
    // fusion's weights and gate use it; the exclusion circle keeps the images' own error.
    double image_foe_bias_mps = 0.05;
    double foe_gate = 3;  // navdata FOE this many standard errors off: rejected
    // Where both the navdata and the images give an FOE, the points' own flows arbitrate: their
    // derotated velocities, fitted over velocity_window frames (the ones the rates come from),
    // run more or less radially from each candidate (misfit: the median share of the flow across
    // the ray, over static points at least min_foe_distance_px from it and flowing faster than
    // flow_noise_px_s). The images' own FOE is a median of per-frame estimates, each free to
    // trade a few hundredths of a degree of rotation for tens of pixels of FOE when the
    // translation's flow is small: in the clean closed loop's first metres it sat 90-120 px
    // below the navdata's while the points' fitted flows ran radially from the navdata's (misfit
    // 0.02-0.05 against 0.17-0.27), and floor points rated about it read a third of their time
    // to contact and ended inside the corridor. 0: the images decide beyond foe_gate, as before;
    // 1: beyond foe_gate, the navdata's unless the images' plainly fits
    // better (foe_overrule_ratio); 2 (default): also within it,
    // the navdata's replaces the fused FOE when its misfit is under foe_arbitrate_ratio of the
    // fused one's (under the realism layer's late, biased navdata the two are often close, and
    // taking the navdata's on any difference delayed centre detections: README).
    int foe_arbitrate = 2;
    double foe_arbitrate_ratio = 0.5;
    // Beyond foe_gate, the images' FOE replaces the navdata's only when its misfit is under this
    // share of the navdata's: under a real camera's noise (the realism suites) both misfits run
    // 0.2-0.45 and the images' was the smaller in half the frames where their FOE sat 170 px off
    // the true one, the navdata's 12; a wrong navdata velocity (0.35 m/s sideways, synthetic)
    // leaves the navdata's misfit 10-15 times the images'. 1: the smaller misfit, as before
    // (but the navdata's when there are too few points to tell).
    double foe_overrule_ratio = 0.2;
    // Fewer such points: within foe_gate the fused FOE, beyond it the navdata's.
    int foe_arbitrate_min_points = 12;
    double max_rotation_dps = 150;  // faster rotation: regions unknown (tracking unreliable)
    // Near the FOE (inside the circle above) a point's rate about it is not measured, yet an
    // obstacle dead ahead stands right there (with the FOE in its true place, a pillar at 0.6
    // m/s is inside the 3-sigma circle, 150 px, until it is 0.2 m away). Such a static point is
    // rated by how fast it parts from its neighbours in the same image row (within
    // near_foe_row_px, derotated): two points of one surface at one depth part at 1/TTC
    // whatever the FOE, and a row of the floor is one depth (a column is not). A point on a
    // row-like edge (its motion along the row not measured) is left out, and so is a pair whose
    // parting slows over the window (the median rate over its later half below near_foe_growth
    // times that over its first half): a surface neared at a steady speed parts ever faster,
    // while a moving outline dragging background points (a person crossing far ahead) parts
    // them at a steady pace. Placed in the corridor like any rated point. 0 = off.
    bool near_foe_rows = true;
    double near_foe_row_px = 10;
    double near_foe_growth = 1.0;
    // Moving objects: the looming rate of points that do not follow the camera's motion, from the
    // growth of their distances to neighbours within loom_radius_px (median over at least
    // loom_min_neighbours of them).
    bool looming = true;
    // A moving point counts only when its bearing's drift brings it into the flight corridor by
    // the time it arrives (rate_moving_points; needs a speed, else every approaching one counts).
    bool moving_corridor = true;
    double loom_radius_px = 90;
    int loom_min_neighbours = 3;
    double loom_min_spread_px = 8;
    // A static point's rate about the FOE must be borne out by its neighbours on the same
    // surface spreading apart at that rate: below this share of it, the point is moving
    // (check_static_looming). 0: off.
    double max_moving_share = 0.5;
    double loom_consistency = 0.5;
    // A point that must be borne out (loom_confirm_sides) and has too few such neighbours
    // within loom_radius_px looks this far: a near surface's points lie far apart.
    double confirm_radius_px = 200;
    // Flying forward (navdata), a side point counts only when its neighbours bear it out
    // (check_static_looming); elsewhere, or without them, it counts unconfirmed.
    bool loom_confirm_sides = true;
    // Flying forward, a centre point too young for the history check (history_min_s) must be
    // borne out by its neighbours too: nothing else tells a slipping young track from a near one.
    bool loom_confirm_young = true;
    // A static point's past is set by its rate: its depth then was its depth now plus the
    // distance flown since, so dt ago it sat 1 + rate * dt_eff times nearer the FOE (dt_eff: the
    // distance flown over the current speed; dt itself without a navdata speed). Each kept past
    // position at least history_min_s before the rate's time is compared with that
    // (check_history):
    //  - nearer the FOE than history_check of it, less history_noise_px: the point moved outward
    //    on its own (a person walking off the path, whose outward flow reads as a near static
    //    point's): it is moving, judged by its looming. 0: off;
    //  - having covered less than history_slow of the way such a point would have since (that
    //    way at least 4 noise widths): it sat nearly still, and its rate is a slip or a jump (a
    //    point an occluding edge dragged): not rated. 0: off.
    double history_check = 0.95;
    double history_min_s = 0.3;
    double history_noise_px = 1.5;
    double history_slow = 0.4;
    // With track.fb_max_px set (0.5 here): true, flying forward, a point that missed is not
    // rated as static; false, misses only keep points out of a moving object's looming. A
    // static miss also drops near surfaces LK follows less exactly (a wall seen at a grazing
    // angle, a plain target's specks as it nears: README, Realism suite).
    bool fb_static = false;
    // A step whose track-back missed by more than this (px) is a lost track, not a sub-pixel
    // slip: LK jumped to another patch (a plain, blurred person's clothes: 10-40 px). Flying
    // forward, while that step is in its fit window such a point rated as static may keep a
    // region's alarm going but neither raise one nor bear out another point's rate (it counts
    // only in a region that was unsafe last frame): a near surface streaming past at the end of
    // a close pass is matched less exactly too (its patch shears and grows between frames; its
    // track-backs miss by as much as its steps), and its alarm, raised while it was farther,
    // must hold. Needs track.fb_max_px; 0 = off.
    double fb_lost_px = 2;
    int moving_frames = 2;  // a point is moving after this many frames off the camera's motion
    double side_inv_ttc_threshold = 0.3;  // 1/s: unsafe when time to contact < 3.3 s
    int side_min_support = 4;             // region score = k-th largest point rate
    double centre_inv_ttc_threshold = 0.3;
    int centre_min_support = 4;
    // Centre homography channel: the thesis' centre method, derotated, read as the expansion rate
    // (scale - 1) / dt of the band's dominant plane, 1/TTC like the points; the centre score is
    // then the larger of the two. Off by default: on the evaluation suite it detected nothing the
    // corridor points missed, and with the camera pitched forward in flight the floor's plane
    // reads as expansion (open-space peaks 0.29/s against 0.20/s without it).
    bool centre_homography = false;
    // Centre outline channel (vision/silhouette.hpp): a plain surface on the flight line gives
    // the points nothing to track, but the plain run of pixels around the FOE widens at 1/TTC
    // when its ends are the surface's outline (they cover the texture beside them). The centre
    // score is then the largest of the channels. Its window is velocity_window. On by default
    // since session 38: in closed loop it brakes for seed 7's plain target at 2.0 m/s, which the
    // points never flag, and with the assist no longer forgetting an obstacle on what it reads
    // while braking, that flight stops 2.2 m short; offline it reads the centre earlier with no
    // open-space alarm added. It costs a brake in open space on one clean flight (seed 7's
    // open-none-1.0-31: a paler blotch on a far blotchy wall) and 0.07 ms a frame (README,
    // sessions 37 and 38).
    bool centre_silhouette = true;
    double silhouette_step_grey = 10;  // a brightness step this large ends the plain run
    double silhouette_own_px = 1.5;    // an end moved out over the texture beside it this far
    double homography_ransac_px = 2;
    int homography_min_points = 8;
    double min_inlier_ratio = 0.5;  // fewer inliers: reject the scale sample
    // Implausible centre scales are rejected: a rate faster than max_inv_ttc, or one that jumps
    // from the recent median by more than max_rate_jump. A real approach grows the rate smoothly
    // (d(1/TTC)/dt = 1/TTC^2 at constant speed), so a jump that persists is accepted after
    // max_rejections samples.
    double max_inv_ttc = 5;      // 1/s (TTC 0.2 s)
    double max_rate_jump = 1.0;  // 1/s between a sample and the recent median
    int max_rejections = 2;
    int centre_window = 7;          // homography rate = median of the last n accepted rates
    double centre_max_age_s = 1.0;  // accepted rates older than this are forgotten
    // The navdata's lag behind the frames is not known (the realism layer's 30 +- 10 ms, a real
    // link's own): a lag L misplaces each derotated point by f L w, w the rotation rate, and
    // while the rate changes the fitted flow is off by f L dw/dt, the same shift for every
    // point. Pitching into forward flight (about 11 degrees nose-down in a third of a second)
    // that reads as a third more looming on the floor ahead, which then seems nearer and higher
    // than it is and passes the floor test. So while the pitch rate changes faster than
    // lag_min_pitch_accel (cruise: under 0.25 rad/s^2 at the 99th percentile on the suites, its
    // noise; the pitch into forward flight: 1-7), the floor test places each static point below
    // the principal point as far as its radial flow less what this lag adds to it allows (none
    // where the lag takes flow away: the error has the sign of the rate's change). The floor
    // only, pitch only, in manoeuvres only, only what the lag adds: each wider allowance (above
    // too, for yaw, in cruise's noise, of either sign) took real obstacles' points off the path
    // in the closed loop (README, Realism suite, session 30).
    double lag_allowance_s = 0.05;     // s; negative: the navdata early; 0: off
    double lag_min_pitch_accel = 0.5;  // rad/s^2
    int confirm_frames = 2;            // raw decision must hold this many frames
    int side_confirm_frames = 4;  // ... a side region's in flight (0: confirm_frames; confirm())
    double colour_max = 1.0;      // overlay: red at this rate (1/s)

    static const ParamTable<FlowParams>& table();
};

class FlowClassifier final : public TrackingClassifier {
public:
    explicit FlowClassifier(const CameraCalibration& calib, const FlowParams& p = FlowParams{});
    std::string_view name() const override { return "flow"; }
    const FlowParams& parameters() const { return p_; }

    std::vector<ParamInfo> params() const override { return FlowParams::table().list(p_); }
    [[nodiscard]] ParamStatus set_param(std::string_view name, double value) override {
        return set_param_in(FlowParams::table(), p_, name, value);
    }
    [[nodiscard]] bool get_param(std::string_view name, double& value) const override {
        return FlowParams::table().get(p_, name, value);
    }
    ParamMap params_to_map() const override { return FlowParams::table().to_map(p_); }
    [[nodiscard]] ParamMapErrors params_from_map(const ParamMap& m) override {
        return params_from_map_in(FlowParams::table(), p_, m);
    }

    // Focus of expansion used for the last frame (undistorted pixels).
    cv::Point2f focus_of_expansion() const { return foe_; }
    // Whether the last frame placed points in metres (a speed known or assumed, and a FOE).
    bool corridor_active() const { return metric_; }
    // Where the last frame's FOE came from.
    enum class FoeSource : std::uint8_t { None, Images, Navdata, Still };
    FoeSource foe_source() const { return foe_source_; }
    // The last frame's ego-motion estimate from the tracked points.
    const EgoMotion& ego() const { return tracker_.ego(); }

    // What the last frame concluded about one trajectory (parallel to the tracker's tracks).
    enum class PointClass : std::uint8_t {
        Unrated,       // too short, too near the FOE, or receding
        Inconsistent,  // flow not radial from the FOE
        Aperture,      // on an edge that runs toward the FOE: its radial flow is not measured
        Outside,       // placed outside the corridor (beside it, floor, overhead)
        Hazard,        // counts toward its region's score
        Moving,        // does not move with the scene; rated by its looming (may count too)
        Lost,          // in the corridor, but a lost track (fb_lost_px) where it may not count
    };
    const std::vector<PointClass>& point_classes() const { return class_; }
    static std::string_view to_string(PointClass c);

private:
    const TrackerParams& tracker_params() const override { return p_; }
    bool wants_derotation() const override { return true; }
    std::string_view point_kind(std::size_t i) const override;
    double centre_band_px() const override { return p_.centre_band_px; }
    void prepare(const FrameInput& in, EgoPrior& prior) override;
    void classify(const FrameInput& in) override;
    void on_reset() override;
    void add_overlay_points() override;
    bool choose_foe(const FrameInput& in, UnknownReason& why);
    // The ego-motion estimate found this track off the camera's motion for moving_frames: a
    // moving object, not a static point of the scene.
    bool off_motion(const Trajectory& t) const {
        return p_.ego_motion && t.moving_streak >= p_.moving_frames;
    }
    // Median share of the fitted flows across their rays from `foe` (0 radial, 1 across); NaN
    // with fewer than foe_arbitrate_min_points usable points.
    double radial_misfit(const cv::Point2d& foe);
    void all_unknown(UnknownReason why);  // every region unknown for `why`, no alarm
    void rate_points(const cv::Matx33d& level, double floor_down);
    void rate_moving_points(const cv::Matx33d& level, double floor_down);
    // A rate fitted at the window's mean time, `lag` seconds ago, brought to now: the time to
    // contact is `lag` less than it was then (a receding or still point's rate as it was).
    static double rate_now(double rate_then, double lag) {
        if (!(rate_then > 0)) return rate_then;
        const double ttc_now = 1.0 / rate_then - lag;
        return ttc_now > 0.01 ? 1.0 / ttc_now : 100.0;
    }
    // The near-FOE points (near_foe_rows), after the others are rated.
    void rate_near_foe(const cv::Matx33d& level, double floor_down);
    // A point rated 1/TTC (then, at the fit window's mean time) at undistorted (mx, my): placed
    // beside the corridor, on the floor or overhead (metric_ only). `lateral`, when given, gets
    // its offset from the flight line (m, right positive; as placed, before the test's allowance
    // for the FOE's error) or NaN without a metric corridor.
    bool outside_corridor(double mx, double my, double rate_then, const cv::Matx33d& level,
                          double floor_down, double vertical_scale = 1,
                          double* lateral = nullptr) const;
    // The same for a point pc (m, camera frame): beside the flight line, floor or overhead.
    // `across` scales its offset from the flight line before the test.
    bool outside_corridor(const cv::Vec3d& pc, const cv::Matx33d& level, double floor_down,
                          double across = 1, double vertical_scale = 1,
                          double* lateral = nullptr) const;
    // How far region r's obstacle reaches across the flight line (RegionDecision::edge_m) from
    // its hazards this frame.
    double region_edge(Region r, double threshold, int k);
    void check_static_looming();
    void check_history();
    double odometer_at(double t_s) const;  // distance flown forward by then (m), NaN unknown
    bool fb_missed(const Trajectory& t, std::size_t n, double px) const;
    // Flying forward, this track's window holds a miss that keeps it from being rated static.
    bool fb_unrated(const Trajectory& t, std::size_t n) const;
    void reject_ground();
    double looming_rate(std::size_t a, bool moving_only, double lo, double hi, double radius);
    struct Aperture {
        bool edge = false;
        double nx = 0, ny = 0, cos = 1;  // edge normal (undistorted px), its cosine with the ray
    };
    Aperture aperture(const Trajectory& t, double rx, double ry) const;
    double homography_rate(const FrameInput& in);
    // The outline channel's rate this frame (updates it; NaN when off or not measured).
    double outline_rate(const FrameInput& in, bool foe_known);
    void confirm(Region r, bool raw);
    double recent_median(double now_s);

    struct RateSample {
        double t_s;
        double rate;
    };

    FlowParams p_;
    struct DirectionSample {
        cv::Vec3d dir;    // unit translation direction, camera axes
        double sigma_px;  // standard error of its FOE
    };
    cv::Point2f foe_{0, 0};
    FoeSource foe_source_ = FoeSource::None;
    cv::Vec3d cam_velocity_{0, 0, 0};  // camera frame (x right, y down, z forward), m/s
    RingBuffer<cv::Vec3d> level_velocity_{Trajectory::kHistory};  // navdata (forward, right, down)
    RingBuffer<DirectionSample> image_dirs_{Trajectory::kHistory};
    bool metric_ = false;
    bool nav_moving_ = false;      // the navdata velocity is known, forward and fast enough
    bool nav_slow_ = false;        // the navdata velocity is known and below min_speed_mps
    bool nav_starting_ = false;    // ... its window's mean below min_speed_mps, a sample above it
    bool nav_rejected_ = false;    // the images contradicted the navdata FOE this frame
    bool img_overruled_ = false;   // ... and the points' flows sided with the navdata
    double nav_speed_ = kUnknown;  // its magnitude (m/s), NaN without one
    double nav_forward_mps_ = kUnknown;  // its forward component (level frame, m/s)
    cv::Vec3d nav_dir_{0, 0, 1};
    double nav_sigma_px_ = 0;  // standard error of its FOE
    double foe_sigma_px_ = 0;  // standard error of the FOE used
    cv::Matx33d derot_ = cv::Matx33d::eye();
    std::vector<double> ts_, xs_, ys_, hazard_[3];
    // Per region, each hazard's offset from the flight line (m, right positive; NaN unknown), in
    // hazard_'s order; and per track, the offset its corridor test found.
    std::vector<double> hazard_lat_[3], lateral_m_, edge_scratch_;
    // Per track, its derotated image velocity fitted over the last velocity_window frames
    // (window_fits): the velocity at the window's mean time, `lag` seconds before the newest
    // frame, where it was then (m: undistorted; d: derotated), and the newest frame's time.
    struct WindowFit {
        bool ok = false;
        std::size_t n = 0;  // frames fitted
        double t0 = 0, lag = 0, vx = 0, vy = 0, mx = 0, my = 0, dx = 0, dy = 0;
    };
    // The navdata pitch rate of the last velocity_window frames (time s, rad/s about the
    // camera's x axis), and per fit length n its least-squares slope over the last n (rad/s^2):
    // a navdata late by L derotates a point wrong by fy L w, so a fit over n frames has its
    // vertical velocity off by fy L times that slope (lag_allowance_s).
    std::vector<double> pitch_t_, pitch_w_;  // frame time (s), pitch rate (rad/s), oldest first
    std::vector<double> pitch_slopes_;
    double rate_prev_t_ = kUnknown;  // the last frame with navdata (s)
    void note_nav_rate(const FrameInput& in);
    // The most a navdata lag of lag_allowance_s moves the fit of `w` along a direction whose
    // vertical component is `ay` (px/s).
    double lag_flow_px_s(const WindowFit& w, double ay) const;
    // The pitch rate's slope over the last n frames as the allowance takes it (rad/s^2, signed;
    // 0 under lag_min_pitch_accel, or with the allowance off).
    double lag_pitch_accel(std::size_t n) const;
    std::vector<WindowFit> fits_;
    bool fits_current_ = false;  // fits_ is this frame's
    // fits_ for this frame's tracks, computed on first use in a frame (a still frame, or one
    // with no FOE to choose between, needs none).
    const std::vector<WindowFit>& window_fits();
    // Per track, from the FOE in the level frame (px): below the horizon, and across.
    std::vector<double> ground_dh_, ground_dx_;
    // Per track, for check_history: the rate's reference time (s) and its rate then (1/s), the
    // point's distance from the FOE along the direction its flow is measured in (u) then (px),
    // and its translation-only (derot) position then.
    struct Past {
        double t_s, rate, a, ux, uy, derot_x, derot_y;
    };
    std::vector<Past> past_;
    // Distance flown forward (the navdata's forward velocity integrated, m) by capture time;
    // restarted after a frame without it.
    struct Odometer {
        double t_s, s_m, v_mps;  // time, distance so far, forward velocity then
    };
    RingBuffer<Odometer> odometer_{Trajectory::kHistory + 1};
    std::vector<int> rated_count_;
    // Per track: its fit window holds a lost step (fb_lost_px); per region, such points rated.
    std::vector<std::uint8_t> lost_;
    std::array<int, 3> lost_rated_{};
    std::array<bool, 3> keep_lost_{};  // per region: lost tracks count (unsafe last frame)
    void count_rated(std::size_t track, std::size_t region) {
        if (lost_[track])
            ++lost_rated_[region];
        else
            ++rated_count_[region];
    }
    std::vector<PointClass> class_;
    std::vector<cv::Point2f> src_, dst_;
    std::vector<std::uint8_t> inliers_;
    RingBuffer<RateSample> centre_rates_{64};
    std::vector<double> scratch_;
    std::array<int, 3> streak_{};
    int rejections_ = 0;
    std::size_t s_centre_sil_ = 0;
    SilhouetteCue silhouette_;
    std::size_t s_centre_points_, s_centre_hom_, s_scale_raw_, s_rate_raw_, s_rejected_, s_hazards_;
    std::size_t s_residual_yaw_, s_residual_pitch_, s_foe_sigma_, s_prior_rejected_, s_moving_;
    std::size_t s_image_yaw_, s_image_pitch_, s_lag_allowance_, s_exposure_step_;
    std::size_t s_foe_img_x_, s_foe_nav_x_, s_foe_x_, s_foe_img_y_, s_foe_nav_y_, s_foe_y_;
    std::vector<std::size_t> moving_idx_;
    std::vector<std::size_t> near_idx_;       // this frame's static points too near the FOE
    std::vector<std::uint8_t> row_measured_;  // per track: its motion along the row is measured
    std::vector<double> near_r1_, near_r2_;
    std::vector<double> loom_;
    std::vector<std::size_t> check_;
};

}  // namespace gs::vision
