#pragma once
// Ego-motion between two frames from the tracked points themselves, with the navdata as a prior
// when there is one: the camera's rotation, and the direction of its translation (the focus of
// expansion, FOE) with its uncertainty.
//
// Model (small motion, normalised coordinates x = (u - cx) / fx ...): a static point's image
// moves by the rotation's flow J(x) w plus a translational flow parallel to the ray from the FOE,
// (x t_z - t_xy) / Z. What crosses those rays is rotation; so, for a translation direction t,
// every point gives one linear equation in w (its flow across its ray), and for a rotation w,
// one linear equation in t (the derotated flow is parallel to its ray: t . (g_y, -g_x,
// g_x y - g_y x) = 0, the differential epipolar constraint, which also holds for an FOE at
// infinity). The two are solved in turn with robust weights. A point on a moving object (a hand,
// a person walking) does not follow the model and ends up with a large residual: it is reported
// as an outlier, not allowed to move the estimate.
//
// Model selection: when a pure rotation explains the flow to within the tracking noise, no
// translation is seen (the camera is still, or everything static is too far away to approach
// soon): Translation::None. Otherwise the FOE is estimated (Translation::Known) with a standard
// error from the fit's information matrix; a sideways motion puts it far outside the image with a
// large error, and the caller decides what is reliable.
//
// Priors and their checks: the navdata attitude change (a rotation with sigma per axis) and the
// navdata velocity (a translation direction with sigma). The images refine them; a prior that
// disagrees with what the images say by more than `prior_gate` standard errors (a stale sample,
// a bias, a sample from the wrong instant) is rejected for this frame and counted.
//
// Pure computation over spans; scratch vectors are members reused every call (no per-frame
// allocation once warm).

#include "drone/core/camera_calibration.hpp"
#include "drone/core/unknown.hpp"

#include <opencv2/core.hpp>

#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace gs::vision {

struct EgoMotionParams {
    double noise_px = 0.35;      // tracking noise per point and frame (full-size pixels)
    double huber_k = 2.0;        // robust weights: residuals above k noise count less ...
    double outlier_k = 4.0;      // ... and above this many (after the fit) are outliers
    int min_points = 12;         // fewer: no estimate
    double translation_k = 2.5;  // no translation when pure rotation leaves a median
                                 // residual below this many noise_px
    // Without navdata, still whatever the few other points do when pure rotation leaves the
    // median point below this many noise_px: the scene's majority does not move, so what does
    // moves by itself (0 = off: the few points must be few, as above).
    double still_k = 0.5;
    double prior_gate = 4.0;       // reject a prior this many standard errors from the images
    double image_floor_deg = 0.3;  // one frame's image rotation never better known than this
    double max_rotation_deg = 10;  // a larger rotation between two frames is not believed
    // Without navdata, a translation is taken only with its FOE in front of the camera and
    // placed to this standard error (else: a still camera and moving objects).
    double reliable_foe_sigma_px = 80;
    int iterations = 6;
};

struct EgoPrior {
    bool rotation = false;             // the points were already moved by a navdata rotation (pred)
    double rotation_sigma_deg = 0.15;  // its uncertainty per axis
    // Navdata translation direction (camera axes, unit); NaN = none.
    cv::Vec3d translation{kUnknown, 0, 0};
    double translation_sigma_rad = 0.05;
};

struct EgoMotion {
    enum class Translation : std::uint8_t {
        Unknown,  // too few points, or nothing fits
        None,     // a rotation explains the flow: nothing static approaches
        Known,    // translating; direction and FOE below
    };
    bool valid = false;                 // an estimate was made (enough points, plausible)
    cv::Vec3d correction_rad{0, 0, 0};  // rotation the images add to the prior's (camera axes)
    bool prior_rotation_used = false;   // the navdata rotation was given and accepted
    bool prior_rotation_rejected = false;
    // With a navdata rotation: what the images alone say of its error this frame, and the
    // variance of that per axis (never below image_floor_deg squared). A caller that follows
    // the error over frames (it is mostly slow: latency, a bias) uses these.
    cv::Vec3d image_rad{0, 0, 0};
    cv::Vec3d image_var{0, 0, 0};
    bool prior_translation_rejected = false;
    Translation translation = Translation::Unknown;
    cv::Vec3d direction{0, 0, 0};  // unit translation direction, camera axes (z forward), Known
    cv::Point2f foe{std::numeric_limits<float>::quiet_NaN(),
                    std::numeric_limits<float>::quiet_NaN()};  // undistorted px; NaN: none
    double foe_sigma_px = std::numeric_limits<double>::infinity();
    double translation_px = 0;  // median derotated flow magnitude (px per frame)
    double residual_px = 0;     // median residual of the chosen model (px)
    int points = 0, outliers = 0;
};

class EgoMotionEstimator {
public:
    // pred: last frame's undistorted points moved by the prior rotation (or unmoved without one);
    // cur: where they were tracked to (undistorted). quality (optional, parallel): how well each
    // point's position is determined, the smaller eigenvalue of its LK gradient matrix: a corner
    // on a foreshortened wall is nearly an edge, and its flow along the edge is uncertain (and
    // underestimated), so it counts less. After the call outlier(i) tells whether point i does
    // not follow the estimated motion.
    const EgoMotion& estimate(const CameraCalibration& calib, std::span<const cv::Point2f> pred,
                              std::span<const cv::Point2f> cur, const EgoPrior& prior,
                              const EgoMotionParams& p, std::span<const float> quality = {});
    const EgoMotion& last() const { return m_; }
    // The caller applies a different rotation than estimated (a temporal median of the
    // corrections): the direction, FOE and outliers again for that rotation.
    const EgoMotion& refine(const CameraCalibration& calib, const cv::Vec3d& w_applied);
    bool outlier(std::size_t i) const { return i < outlier_.size() && outlier_[i] != 0; }

private:
    struct Pt {
        double x, y;     // normalised position (at pred)
        double rx, ry;   // cur - pred, normalised
        double j[2][3];  // rotation Jacobian at (x, y)
        double s;        // 1 / its noise relative to the others' (tracking quality)
    };
    double fit_rotation_only(const cv::Vec3d& start, cv::Vec3d& w, double sigma_n);
    bool fit_translation(const EgoPrior& prior, bool fix_w, double sigma_n,
                         const EgoMotionParams& p, cv::Vec3d& w, cv::Vec3d& t, cv::Matx33d& info_t,
                         cv::Matx33d& info_w, cv::Vec3d& b_w);
    double rotation_cost(const cv::Vec3d& w, double sigma_n) const;
    cv::Matx<double, 5, 5> joint_information(const cv::Vec3d& t, const cv::Vec3d& w, double sigma_n,
                                             cv::Vec3d& e1, cv::Vec3d& e2) const;
    void describe_translation(const CameraCalibration& calib, const cv::Vec3d& w,
                              const cv::Vec3d& t, const cv::Matx<double, 5, 5>& info,
                              const cv::Vec3d& e1, const cv::Vec3d& e2);
    cv::Vec3d fuse_rotation(const EgoMotionParams& p, const cv::Matx33d& cov_img,
                            const cv::Vec3d& w_img, double sp);
    void finish_still(const EgoPrior& prior, const EgoMotionParams& p, double sigma_n, double f,
                      const cv::Vec3d& w_rot, double med_rot);
    bool finish_translating(const CameraCalibration& calib, const EgoPrior& prior,
                            const EgoMotionParams& p, double sigma_n, double f,
                            const cv::Vec3d& w_rot, int rotation_outliers, bool was_translating);

    struct Call {
        EgoPrior prior;
        EgoMotionParams p;
        double sigma_n = 1, f = 1, s2 = 1;
    };
    EgoMotion m_;
    Call last_;
    int known_run_ = 0;  // consecutive frames before this one with a translation
    std::vector<Pt> pts_;
    std::vector<double> wt_, res_, res_rot_, scratch_;
    std::vector<std::uint8_t> outlier_;
};

// The navdata rotation's error over frames, per camera axis, as an IMU's errors are: a rate
// bias b (a Gauss-Markov process: standard deviation, correlation time) plus a scale error s
// (starting within a standard deviation, drifting by a walk per square-root second), so that the
// navdata rate w reads b + s w too much. Each frame the images measure that error (EgoMotion's
// image_rad over the frame time, with image_var); a Kalman filter on [b, s] per axis follows it.
// A bias is a fraction of a degree per second, so a steady disagreement while the drone flies
// straight (a close obstacle on one side pulls the image rotation) barely moves it; a scale
// error shows while turning, and is learnt then.
struct RateErrorParams {
    double bias_sigma_dps = 0.5;
    double bias_tau_s = 10;
    double scale_sigma = 0.03;  // a MEMS gyro's (TrackerParams::ego_scale_sigma)
    double scale_walk = 0.01;
    // The navdata's lag behind the frame's capture is not known (a real link's differs from a
    // simulator's), and no slow error models it: a sample late by L is off by L times the
    // change of rate, a fast error while the drone manoeuvres. The lag is measured: the shift
    // (in frames, -1 to 2) at which the navdata's rotations best match the images' over the
    // last lag_tau_s, once that shift beats none by lag_min_gain of the mismatch. Each frame
    // the lag found, times lag_k and at most latency_sigma_s, is then allowed for as a passing
    // error of that size times the navdata's change of rate, which this frame's images measure
    // (latency_sigma_s 0: not allowed for).
    double latency_sigma_s = 0.05;
    double lag_tau_s = 5;
    double lag_min_gain = 0.1;
    double lag_k = 1.5;
    bool operator==(const RateErrorParams&) const = default;
};

class NavdataRateError {
public:
    explicit NavdataRateError(const RateErrorParams& p = {}) { reset(p); }
    void reset(const RateErrorParams& p);
    // New parameters: the filter starts again from their priors (what it learnt under others
    // is dropped); the same ones change nothing.
    void set_params(const RateErrorParams& p) {
        if (!(p == p_)) reset(p);
    }
    // nav_rot: the navdata rotation over the frame (rad, camera axes); dt: the frame time (s).
    // Returns the rotation to add to the navdata's for this frame (rad), after the update.
    cv::Vec3d update(const cv::Vec3d& image_rad, const cv::Vec3d& image_var,
                     const cv::Vec3d& nav_rot, double dt);
    double bias_rad_s(int axis) const { return axes_[static_cast<std::size_t>(axis)].x[0]; }
    double scale(int axis) const { return axes_[static_cast<std::size_t>(axis)].x[1]; }
    // The navdata's lag behind the images found so far (s; 0 until one is found).
    double lag_s() const { return lag_s_; }

private:
    struct Axis {
        cv::Vec2d x{0, 0};
        cv::Matx22d p = cv::Matx22d::zeros();
        double last_rate = kUnknown;  // the navdata rate of the last update (rad/s)
    };
    void measure_lag(const cv::Vec3d& image_rad, const cv::Vec3d& nav_rot, double dt);
    RateErrorParams p_;
    std::array<Axis, 3> axes_{};
    // The last four frames' navdata rotations and the images' (navdata + image_rad), newest
    // last, and the decaying mismatch of the images' with the navdata's shifted by -1..2 frames.
    std::array<cv::Vec3d, 4> nav_hist_{};
    std::array<cv::Vec3d, 4> img_hist_{};
    int hist_n_ = 0;
    std::array<double, 4> mismatch_{};
    double lag_s_ = 0;
};

}  // namespace gs::vision
