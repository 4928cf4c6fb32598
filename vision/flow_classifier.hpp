#pragma once
// A better classifier behind the same interface ("flow"). It answers the thesis' own failures
// (§6.2.4, §8.2): the flow an attitude change causes is removed using navdata roll/pitch/yaw; each
// trajectory is judged by its expansion rate about the focus of expansion, an inverse
// time-to-contact (1/s) that does not depend on where in the image the point is; centre
// homography scales that are implausible are rejected; regions are scored with robust statistics
// (k-th largest rate on the sides, so a handful of points on an obstacle is enough; median over
// time in the centre), and a decision must hold for a few frames.

#include "vision/classifier.hpp"

namespace gs::vision {

struct FlowParams : TrackerParams {
    double centre_band_px = 80;           // same regions as the thesis
    int velocity_window = 10;             // frames for each trajectory's image velocity fit
    int min_track_length = 6;             // fewer points: no rate
    double min_foe_distance_px = 30;      // the rate is ill-conditioned near the FOE
    bool use_velocity_for_foe = true;     // place the FOE from navdata velocity when known
    double side_inv_ttc_threshold = 0.6;  // 1/s: unsafe when time to contact < ~1.7 s
    int side_min_support = 5;             // side score = k-th largest trajectory rate
    double centre_inv_ttc_threshold = 0.6;
    double homography_ransac_px = 2;
    int homography_min_points = 8;
    double min_inlier_ratio = 0.5;  // fewer inliers: reject the scale sample
    // Implausible centre scales (thesis fig. 6.15: single-sample spikes) are rejected: a rate
    // faster than max_inv_ttc, or one that jumps from the recent median by more than
    // max_rate_jump. A real approach grows the rate smoothly (d(1/TTC)/dt = 1/TTC^2 at constant
    // speed), so a jump that persists is accepted after max_rejections samples.
    double max_inv_ttc = 5;      // 1/s (TTC 0.2 s)
    double max_rate_jump = 1.0;  // 1/s between a sample and the recent median
    int max_rejections = 2;
    int centre_window = 7;          // centre score = median of the last n accepted rates
    double centre_max_age_s = 1.0;  // accepted rates older than this are forgotten
    int confirm_frames = 2;         // raw decision must hold this many frames
    double colour_max = 1.2;        // overlay: red at this rate (1/s)

    static const ParamTable<FlowParams>& table();
};

class FlowClassifier final : public TrackingClassifier {
public:
    explicit FlowClassifier(const CameraCalibration& calib, const FlowParams& p = FlowParams{});
    std::string_view name() const override { return "flow"; }
    const FlowParams& parameters() const { return p_; }

    std::vector<ParamInfo> params() const override { return FlowParams::table().list(p_); }
    [[nodiscard]] ParamStatus set_param(std::string_view name, double value) override;
    [[nodiscard]] bool get_param(std::string_view name, double& value) const override {
        return FlowParams::table().get(p_, name, value);
    }
    ParamMap params_to_map() const override { return FlowParams::table().to_map(p_); }
    [[nodiscard]] ParamMapErrors params_from_map(const ParamMap& m) override;

    // Focus of expansion used for the last frame (undistorted pixels).
    cv::Point2f focus_of_expansion() const { return foe_; }

private:
    const TrackerParams& tracker_params() const override { return p_; }
    bool wants_derotation() const override { return true; }
    double centre_band_px() const override { return p_.centre_band_px; }
    void classify(const FrameInput& in) override;
    void on_reset() override;
    void add_overlay_points() override;
    void classify_sides();
    void classify_centre(const FrameInput& in);
    void confirm(Region r, bool raw);
    double recent_median(double now_s);

    struct RateSample {
        double t_s;
        double rate;
    };

    FlowParams p_;
    cv::Point2f foe_{0, 0};
    cv::Matx33d derot_ = cv::Matx33d::eye();
    std::vector<double> ts_, xs_, ys_, side_rates_[3];
    std::vector<cv::Point2f> src_, dst_;
    std::vector<std::size_t> centre_tracks_;
    std::vector<std::uint8_t> inliers_;
    RingBuffer<RateSample> centre_rates_{64};
    std::vector<double> scratch_;
    std::array<int, 3> streak_{};
    int rejections_ = 0;
    std::size_t s_left_, s_left_thr_, s_right_, s_right_thr_, s_centre_, s_centre_thr_;
    std::size_t s_scale_raw_, s_rate_raw_, s_rejected_;
};

}  // namespace gs::vision
