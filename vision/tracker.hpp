#pragma once
// Shi-Tomasi corners tracked by pyramidal Lucas-Kanade into trajectories (thesis §3.2.3).
// "Move points, not images": tracking runs on the raw (distorted) grey image, optionally
// downscaled; only point coordinates are undistorted and roll-stabilised. Pyramids, point vectors
// and the detection mask are members reused every frame.

#include "drone/core/camera_calibration.hpp"
#include "drone/core/unknown.hpp"
#include "vision/ego_motion.hpp"
#include "vision/params.hpp"
#include "vision/stabilisation.hpp"

#include <opencv2/core.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace gs::vision {

struct TrackerParams {
    // Ego-motion from the tracked points (vision/ego_motion.hpp): the rotation between frames is
    // estimated from the images, on top of the navdata attitude change when there is one (which
    // then acts as a prior the images refine, and is rejected when they disagree), together with
    // the direction of translation (the focus of expansion). Off: the navdata rotation alone.
    bool ego_motion = true;
    double ego_noise_px = 0.35;         // tracking noise per point and frame (full-size px)
    double ego_huber_k = 2.0;           // robust weights (noise units)
    double ego_outlier_k = 4.0;         // a point this many noise units off the motion: moving
    int ego_min_points = 12;            // fewer points: no estimate
    double ego_translation_k = 2.5;     // a rotation alone within this many noise units: no
                                        // translation seen
    double ego_still_k = 0.5;           // without navdata, the median point within this many
                                        // noise units of a rotation: still (0 = off)
    double ego_prior_sigma_deg = 0.15;  // navdata attitude change uncertainty per frame
    double ego_prior_gate = 4.0;        // reject a navdata prior this many sigmas off the images
    double ego_image_floor_deg = 0.3;   // one frame's image rotation never better known than this
    double ego_max_rotation_deg = 10;   // a larger image correction per frame is not believed
    // Without navdata: a translation needs its FOE this well placed (else: still camera, moving
    // objects).
    double ego_reliable_foe_sigma_px = 80;
    double ego_prediction_sigma_deg = 0.5;  // without navdata: the last frame's rotation predicts
                                            // this one's to this (per axis)
    // The navdata rotation's error followed over frames (NavdataRateError): a rate bias and a
    // scale error. A MEMS gyro's scale error is a few per cent: a wider prior lets the images
    // teach the navdata a scale it does not have while the drone pitches into a forward
    // acceleration, when the floor's expansion and a pitch rate look alike (0.2 learnt -35 % on
    // the realism suite's take-offs and put the floor 0.3-0.4 m too high; README, Realism suite).
    double ego_bias_sigma_dps = 0.5;
    double ego_bias_tau_s = 10;
    double ego_latency_sigma_s = 0.05;  // RateErrorParams::latency_sigma_s (0: no lag allowed for)
    double ego_scale_sigma = 0.03;
    double ego_scale_walk = 0.01;
    // Without navdata roll, roll-stabilise with the roll the images measure (their rotation about
    // the optical axis, integrated and leaking back to level with this time constant: the drone
    // flies level on average, and an integrated rate drifts).
    bool image_roll = true;
    double image_roll_tau_s = 2.0;
    // Without a navdata rotation, start each LK search where the last frame's rotation (from the
    // images) moves the point: a camera that turns keeps turning.
    bool predict_rotation = true;
    // Rolling shutter: the sensor reads its rows out top to bottom over this time (the AR.Drone
    // 2 front camera: 25 ms), so while the camera turns each row sees it turned by the rate x
    // its delay. Each point's undistorted position is moved to where the camera's rotation puts
    // it at mid-frame (the rate: this frame's rotation prior, navdata or predicted, over the
    // frame interval). Uncorrected, a pitch that speeds up or slows down stretches the image
    // vertically from one frame to the next, and points read that as looming: the realism
    // closed loop's take-off brakes. 0: a global shutter (the tracker's default); -1 ("flow"'s
    // default): the camera's, from its calibration (CameraCalibration::readout_ms: the virtual
    // drone states 0 for its clean renders, the realism layer's readout for its own), and where
    // the calibration does not say, the AR.Drone 2 front camera's, kArDroneReadoutMs. The rate
    // is unrolled less readout_deadband_dps on each axis (a continuous deadband, no step where
    // a rate crosses it): in cruise the navdata's rate between frames is mostly its noise (2-13
    // deg/s at the 99th percentile on the realism suites), and unrolling by it shifts the rows
    // against each other by up to a pixel a frame; a pitch into forward flight (60-100 deg/s) is
    // unrolled nearly whole. Without a deadband, on the realism suites it cut three take-off brakes
    // of the closed loop but raised as many elsewhere (README, Realism suite).
    double readout_ms = 0;
    static constexpr double kArDroneReadoutMs = 25;
    double readout_deadband_dps = 0;
    int max_tracks = 150;               // speed: ~1 ms per frame with the settings below (bench)
    double quality_level = 0.01;        // goodFeaturesToTrack qualityLevel
    double min_corner_distance_px = 8;  // goodFeaturesToTrack minDistance (full-size px)
    double new_point_min_distance_px = 10;  // no new corner this close to a live trajectory
    int block_size = 3;                     // Shi-Tomasi window
    int lk_window_px = 11;                  // LK window (at tracking scale: 22 px at full size)
    int lk_levels = 2;                      // LK pyramid levels above the base
    int lk_iterations = 10;
    double lk_epsilon = 0.03;
    double lk_min_eig = 1e-4;  // LK drops points whose gradient matrix is weaker
    // Forward-backward check: each point is tracked back from where LK put it, and how far
    // that misses its start is kept with the point (TrackPoint::fb_px). The tracker only
    // measures; the flow classifier judges the miss against fb_max_px (0 = not measured).
    double fb_max_px = 0;
    double track_scale = 0.5;  // track on an image resized by this (measured: see bench)
    // Photometric compensation (a real camera does not keep the brightness LK assumes: its
    // auto-exposure steps, mains flicker bands the rows through the rolling shutter): the rows
    // are split into this many horizontal bands and each band's mean brightness is held to a
    // reference that follows the image slowly (time constant gain_tau_frames), interpolated
    // between band centres. A step of the whole image's or of a band's gain then reaches the
    // tracker spread over that many frames instead of at once. 0 = off.
    int gain_bands = 0;
    double gain_tau_frames = 30;
    // An exposure step (a real camera's auto-exposure making the whole image some 10-15 % brighter
    // or darker from one frame to the next) breaks the constant brightness LK assumes: on a
    // tiled floor points slip onto the next tile's corner and read as a near obstacle. A step is
    // the median of the log brightness ratios of an 8 x 6 grid of blocks to the last frame's,
    // when it is larger than step_gain_min and nearly every block (step_gain_share of them) went
    // the same way: a gain moves every block, a moving thing or the camera's own motion only
    // some, and not all one way. The last frame is then brought to this one's brightness for
    // this frame's search only: every other pair of frames is tracked as filmed (a compensation
    // that lasts, decaying over frames, drifts the brightness a little every frame, and on the
    // plain walls of the realism suite that read as motion and raised side alarms: README).
    // 0 = off; not with gain_bands or highpass_px, which change the brightness themselves.
    double step_gain_min = 0;
    double step_gain_share = 0.8;
    // Track on the image less its local mean over a box this wide (tracked-image px, odd; 0 =
    // off): brightness that varies slowly across the image (flicker bands rolling down the rows,
    // vignetting, a gain step's offset) leaves the texture LK follows, and moves no point.
    int highpass_px = 0;
    int detect_interval = 2;  // look for new corners every n-th frame (thesis: every frame)
    // Spread the trajectories over a grid of cols x rows cells (0 = off, the thesis): no cell
    // holds more than its share of max_tracks, the newest trajectories of a crowded cell give
    // way, and new corners go to cells below their share. Without it the strongest corners of a
    // far, slow background take every slot and keep them, and an obstacle gets none.
    int grid_cols = 0, grid_rows = 0;
    // The centre region (|stabilised x - width/2| <= centre_band_px: the classifiers' own,
    // thesis §3.2.4) decides a brake, and the grid's cells are shared with the sides: a far,
    // textured background beside a near, faintly textured obstacle (a concrete pillar filling
    // the centre) keeps those cells full with the strongest corners, and the obstacle gets no
    // trajectory. With centre_min_tracks > 0 the band is split into cells of about 40 x 60 px,
    // each holding its share of centre_min_tracks: a cell below its share is topped up with its
    // own strongest corners (as strong, relative to the image's strongest, as quality_level asks
    // of any: a plain surface's noise is no corner), and each cell's longest trajectories up to
    // its share are kept whatever their grid cell holds, outside max_tracks. 0 = off.
    double centre_band_px = 80;
    int centre_min_tracks = 0;
    double border_margin_px = 4;      // keep corners this far inside the stabilised image
    double mask_roll_step_deg = 0.5;  // recompute the detection mask when roll moves this much
    bool rotate_about_principal_point = false;  // thesis: rotates about the image centre
    // Sign of the stabilising rotation: +1 turns the points by +roll (clockwise on screen), which
    // undoes a right-side-down roll; -1 reproduces a naive getRotationMatrix2D(centre, roll).
    double roll_sign = 1.0;
};

// Registers the tracker's parameters ("track.*") in the table of a params struct derived from
// TrackerParams.
template <class P>
void describe_tracker_params(ParamTable<P>& t) {
    t.add("track.ego_motion", &P::ego_motion, 0, 1,
          "estimate the rotation and translation direction from the tracked points")
        .add("ego.noise_px", &P::ego_noise_px, 0.01, 10,
             "ego-motion: tracking noise per frame (px)")
        .add("ego.huber_k", &P::ego_huber_k, 0.5, 20,
             "ego-motion: robust weight threshold (noise units)")
        .add("ego.outlier_k", &P::ego_outlier_k, 1, 50,
             "ego-motion: a point this far off the motion is moving (noise units)")
        .add("ego.min_points", &P::ego_min_points, 4, 1000, "ego-motion: fewest points")
        .add("ego.translation_k", &P::ego_translation_k, 0.5, 50,
             "ego-motion: no translation seen while a rotation leaves less (noise units)")
        .add("ego.still_k", &P::ego_still_k, 0, 50,
             "ego-motion without navdata: still, whatever a few points do, while a rotation "
             "leaves the median point less (noise units; 0: off)")
        .add("ego.prior_sigma_deg", &P::ego_prior_sigma_deg, 0.001, 10,
             "ego-motion: navdata attitude change uncertainty per frame")
        .add("ego.prior_gate", &P::ego_prior_gate, 0.5, 100,
             "ego-motion: reject a navdata sample this many sigmas from the images")
        .add("ego.image_floor_deg", &P::ego_image_floor_deg, 0, 10,
             "ego-motion: one frame's image rotation is never taken as better known than this")
        .add("ego.max_rotation_deg", &P::ego_max_rotation_deg, 0.1, 90,
             "ego-motion: a larger image correction per frame is not believed")
        .add("ego.reliable_foe_sigma_px", &P::ego_reliable_foe_sigma_px, 1, 10000,
             "ego-motion without navdata: a translation needs its FOE placed this well")
        .add("ego.prediction_sigma_deg", &P::ego_prediction_sigma_deg, 0.01, 30,
             "ego-motion without navdata: the last rotation predicts this one's to this")
        .add("ego.bias_sigma_dps", &P::ego_bias_sigma_dps, 0, 100,
             "ego-motion: the navdata rotation rate's bias, standard deviation (deg/s)")
        .add("ego.bias_tau_s", &P::ego_bias_tau_s, 0.1, 1000,
             "ego-motion: ... and its correlation time (s)")
        .add("ego.latency_sigma_s", &P::ego_latency_sigma_s, 0, 1,
             "ego-motion: the most navdata lag behind the frames (measured against the images) "
             "allowed for at a change of rotation rate (s; 0: none)")
        .add("ego.scale_sigma", &P::ego_scale_sigma, 0, 2,
             "ego-motion: the navdata rotation's scale error, initial standard deviation")
        .add("ego.scale_walk", &P::ego_scale_walk, 0, 1,
             "ego-motion: ... and its drift per square-root second")
        .add("track.image_roll", &P::image_roll, 0, 1,
             "without navdata roll, stabilise with the roll the images measure")
        .add("track.image_roll_tau_s", &P::image_roll_tau_s, 0.1, 60,
             "image roll: time constant of the leak back to level")
        .add("track.predict_rotation", &P::predict_rotation, 0, 1,
             "without navdata rotation, start LK where the last frame's rotation moves points")
        .add("track.readout_ms", &P::readout_ms, -1, 100,
             "rolling shutter: row readout time, first row to last (0: global shutter, -1: the "
             "calibration's, else 25)")
        .add("track.readout_deadband_dps", &P::readout_deadband_dps, 0, 360,
             "rolling shutter: the rate is unrolled less this, per axis (deg/s)")
        .add("track.max_tracks", &P::max_tracks, 10, 2000, "most trajectories alive at once", true)
        .add("track.quality_level", &P::quality_level, 1e-4, 0.5,
             "Shi-Tomasi: corner strength relative to the strongest corner")
        .add("track.min_corner_distance_px", &P::min_corner_distance_px, 1, 100,
             "Shi-Tomasi: minimum distance between new corners")
        .add("track.new_point_min_distance_px", &P::new_point_min_distance_px, 0, 100,
             "no new corner this close to a live trajectory")
        .add("track.block_size", &P::block_size, 3, 15, "Shi-Tomasi window size")
        .add("track.lk_window_px", &P::lk_window_px, 5, 61, "Lucas-Kanade window size", true)
        .add("track.lk_levels", &P::lk_levels, 0, 6, "Lucas-Kanade pyramid levels", true)
        .add("track.lk_iterations", &P::lk_iterations, 1, 100, "Lucas-Kanade iterations per level")
        .add("track.lk_epsilon", &P::lk_epsilon, 1e-4, 1, "Lucas-Kanade convergence (px)")
        .add("track.fb_max_px", &P::fb_max_px, 0, 100,
             "forward-backward check: a point that, tracked back, missed its start by more than "
             "this (px) in its fit window is left out of a moving object's looming (and, with "
             "fb_static, not rated as static flying forward; 0: not measured)")
        .add("track.lk_min_eig", &P::lk_min_eig, 0, 0.1,
             "Lucas-Kanade: drop points with a weaker gradient matrix")
        .add("track.track_scale", &P::track_scale, 0.25, 1, "track on an image resized by this",
             true)
        .add("track.gain_bands", &P::gain_bands, 0, 64,
             "photometric compensation: bands of rows whose brightness is held steady (0 = off)")
        .add("track.gain_tau_frames", &P::gain_tau_frames, 1, 1000,
             "photometric compensation: frames over which a brightness change is let through")
        .add("track.step_gain_min", &P::step_gain_min, 0, 1,
             "exposure steps: a frame whose blocks all changed brightness by more than this "
             "(log ratio, median) is tracked from the last one brought to its brightness (0 = off)")
        .add("track.step_gain_share", &P::step_gain_share, 0.5, 1,
             "exposure steps: the share of blocks that must have changed the same way")
        .add("track.highpass_px", &P::highpass_px, 0, 99,
             "track on the image less its local mean over a box this wide (tracked-image px; "
             "0 = off)")
        .add("track.detect_interval", &P::detect_interval, 1, 30,
             "look for new corners every n-th frame")
        .add("track.grid_cols", &P::grid_cols, 0, 32,
             "spread trajectories over this many columns of cells (0 = off)")
        .add("track.grid_rows", &P::grid_rows, 0, 32, "... and this many rows (0 = off)")
        .add("track.centre_min_tracks", &P::centre_min_tracks, 0, 500,
             "keep at least this many trajectories in the centre band, whatever its grid cells "
             "hold (0 = off)")
        .add("track.border_margin_px", &P::border_margin_px, 0, 50,
             "keep corners this far inside the stabilised image", true)
        .add("track.mask_roll_step_deg", &P::mask_roll_step_deg, 0.05, 10,
             "recompute the detection mask when roll changes by this")
        .add("track.rotate_about_principal_point", &P::rotate_about_principal_point, 0, 1,
             "roll-stabilise about the principal point instead of the image centre", true)
        .add("track.roll_sign", &P::roll_sign, -1, 1,
             "+1 undoes a right-side-down roll; -1 rotates the other way; 0 disables", true);
}

struct TrackPoint {
    cv::Point2f stab;   // undistorted, roll-stabilised pixel (thesis image space)
    cv::Point2f derot;  // accumulated attitude-free position (see Trajectory)
    double t_s = 0;     // capture time, seconds
    // Forward-backward miss of the step into this point (full-size px; infinity when LK lost it
    // tracking back; 0 on a trajectory's first point or without the check, fb_max_px 0).
    float fb_px = 0;
};

// One tracked corner. `derot` integrates the frame-to-frame motion left after removing what the
// attitude change explains, so its slope is translation-only image velocity.
struct Trajectory {
    static constexpr std::size_t kHistory = 64;
    std::uint32_t id = 0;
    std::int64_t first_frame = 0;
    int length = 0;           // frames tracked so far (may exceed kHistory)
    cv::Point2f raw;          // newest position, raw image pixels (full size)
    cv::Point2f undist;       // newest position, undistorted pixels
    cv::Point2f undist_prev;  // the one before (== undist on the first frame)
    int moving_streak = 0;    // consecutive frames it did not follow the camera's motion
    // The image's structure tensor over the LK window at the newest position (sums of Ix^2,
    // Ix Iy, Iy^2; raw image axes): a corner constrains the flow in every direction, an edge only
    // across itself (its flow along the edge is LK's guess, and slides).
    cv::Vec3f structure{0, 0, 0};
    std::array<TrackPoint, kHistory> hist{};

    std::size_t history_size() const {
        return static_cast<std::size_t>(length) < kHistory ? static_cast<std::size_t>(length)
                                                           : kHistory;
    }
    // back = 0 is the newest point.
    const TrackPoint& at_back(std::size_t back) const {
        return hist[(static_cast<std::size_t>(length) - 1 - back) % kHistory];
    }
    void push(const TrackPoint& p) {
        hist[static_cast<std::size_t>(length) % kHistory] = p;
        ++length;
    }
};

struct TrackerTimings {
    double grey_ms = 0, pyramid_ms = 0, lk_ms = 0, geometry_ms = 0, detect_ms = 0;
};

class TrajectoryTracker {
public:
    TrajectoryTracker() = default;
    void configure(const CameraCalibration& calib, const TrackerParams& p);
    // New values for parameters that do not change sizes (TrackerParams marked without
    // resets_state): takes effect on the next update, keeps the trajectories (the navdata
    // rotation error filter starts again when its own parameters change).
    void set_params(const TrackerParams& p);
    void reset();

    // image: grey or BGR at the calibration's size. base_h maps the previous frame's undistorted
    // pixels to this frame's for the rotation known beforehand: the navdata attitude change when
    // prior.rotation says so, else identity (the images then predict it from the last frame's
    // rotation). With ego_motion on, the rotation is then estimated from the points (see
    // ego_motion.hpp) and trajectories' `derot` positions integrate what is left.
    void update(const cv::Mat& image, std::int64_t t_ns, double roll_deg, const cv::Matx33d& base_h,
                const EgoPrior& prior = {});
    // The rotation the images added to the known one in the last update() (camera axes, degrees;
    // 0 without an estimate) and the whole estimate.
    const cv::Vec3d& image_correction_deg() const { return correction_deg_; }
    const EgoMotion& ego() const { return ego_.last(); }
    // The camera's whole rotation from the last frame to this one (camera axes, radians): the
    // known one plus the images' correction.
    const cv::Vec3d& rotation_rad() const { return last_rotation_rad_; }
    // Roll used to stabilise the last frame (navdata's, or the images' when it had none).
    double roll_deg() const { return roll_used_deg_; }
    EgoMotionParams ego_params() const;
    RateErrorParams rate_error_params() const;

    const std::vector<Trajectory>& tracks() const { return tracks_; }
    // The last update()'s image in grey at full size (a header: the caller's image when it was
    // grey already, valid until the next update).
    const cv::Mat& grey() const { return grey_; }
    const CameraCalibration& calibration() const { return calib_; }
    const RollStabiliser& stabiliser() const { return stab_; }
    cv::Point2f centre() const { return centre_; }
    std::int64_t frame_index() const { return frame_; }
    // Exposure steps found so far (step_gain_min), and this frame's (its brightness over the last
    // one's; 1: none).
    int exposure_steps() const { return steps_found_; }
    double exposure_step() const { return std::exp(step_log_); }
    // The rolling shutter's readout in use (s): track.readout_ms, or the camera's (-1).
    double readout_s() const;
    int ended_last_frame() const { return ended_; }
    int added_last_frame() const { return added_; }
    const TrackerTimings& timings() const { return timings_; }

private:
    void set_roll(double roll_deg);
    cv::Point2f to_full(cv::Point2f p) const;
    cv::Point2f to_track(cv::Point2f p) const;
    void detect(double roll_deg);
    bool grid_on() const { return p_.grid_cols > 0 && p_.grid_rows > 0; }
    int cell_of(cv::Point2f raw) const;
    int cell_quota() const;
    bool in_centre_band(cv::Point2f stab) const;  // |stab.x - width/2| <= centre_band_px
    bool in_centre_band(const Trajectory& t) const;
    void mark_centre_reserve();
    void mask_live_tracks(cv::Mat& mask) const;
    void order_by_length();
    struct BandGrid {  // the centre band's cells (top_up_centre_band), full-size raw pixels
        double x0 = 0, cw = 1, ch = 1;
        int cols = 1, rows = 1, quota = 1;
        int cell(cv::Point2f raw) const;
    };
    BandGrid band_grid() const;
    void top_up_centre_band();
    void add_corners(bool centre_band_only);  // corners_ as new trajectories
    void balance_grid();
    void compensate_gain();
    // Finds an exposure step against the last frame (step_gain_min): step_log_.
    void find_step();
    void scale_previous_pyramid(double k);
    void own_grey_track(const cv::Mat& image);  // before changing grey_track_ in place
    // Moves undistorted points (rows from their raw positions) to mid-frame (readout_ms).
    void unroll_shutter(const std::vector<cv::Point2f>& raw, std::vector<cv::Point2f>& und) const;

    CameraCalibration calib_;
    TrackerParams p_;
    RollStabiliser stab_;
    cv::Point2f centre_;
    std::int64_t frame_ = 0;
    std::uint32_t next_id_ = 1;
    int ended_ = 0, added_ = 0;
    bool have_prev_ = false;
    double now_s_ = 0;

    cv::Mat grey_full_, grey_track_, grey_own_, local_mean_;
    cv::Mat grey_;  // header: grey_full_ or the caller's grey image
    std::vector<double> row_mean_, band_mean_, band_ref_, row_gain_;  // compensate_gain
    cv::Mat thumb_, thumb_prev_;                                      // find_step
    std::vector<float> step_ratio_;
    double step_log_ = 0;  // this frame's exposure step against the last one (log), 0: none
    int steps_found_ = 0;
    std::vector<cv::Mat> pyr_prev_, pyr_cur_;
    std::vector<Trajectory> tracks_;
    std::vector<cv::Point2f> prev_pts_, cur_pts_, raw_, und_;
    std::vector<std::uint8_t> status_, back_status_;
    std::vector<float> err_, back_err_, fb_px_;
    std::vector<cv::Point2f> back_pts_;
    std::vector<cv::Point2f> corners_;
    std::vector<cv::Point2f> pred_;
    std::vector<int> cell_count_;
    std::vector<std::size_t> order_;
    std::vector<std::uint8_t> drop_;
    std::vector<std::uint8_t> reserve_;  // per track: in the centre band's reserve
    int reserved_ = 0;
    cv::Mat band_mask_, eig_;  // top_up_centre_band
    struct BandCandidate {
        float eig;
        cv::Point2f at;  // tracked-image pixels
    };
    std::vector<BandCandidate> band_candidates_;
    std::vector<int> band_count_;
    EgoMotionEstimator ego_;
    cv::Vec3d last_rotation_rad_{0, 0, 0};  // whole camera rotation of the last frame
    cv::Vec3d shutter_rate_{0, 0, 0};       // this frame's rotation rate (rad/s), for readout_ms
    NavdataRateError nav_error_;            // the navdata rotation's error, followed over frames
    bool have_rotation_ = false;
    double image_roll_deg_ = 0;
    double roll_used_deg_ = 0;
    cv::Mat mask_base_, mask_;
    cv::Vec3d correction_deg_{0, 0, 0};
    double mask_roll_deg_ = kUnknown;
    TrackerTimings timings_;
};

}  // namespace gs::vision
