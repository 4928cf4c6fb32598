#pragma once
// Shi-Tomasi corners tracked by pyramidal Lucas-Kanade into trajectories (thesis §3.2.3).
// "Move points, not images": tracking runs on the raw (distorted) grey image, optionally
// downscaled; only point coordinates are undistorted and roll-stabilised. Pyramids, point vectors
// and the detection mask are members reused every frame.

#include "drone/core/camera_calibration.hpp"
#include "drone/core/unknown.hpp"
#include "vision/geometry.hpp"
#include "vision/params.hpp"

#include <opencv2/core.hpp>

#include <array>
#include <cstdint>
#include <vector>

namespace gs::vision {

struct TrackerParams {
    // Refinement of the navdata derotation from the tracked points (only with a focus of
    // expansion, i.e. for classifiers that derotate): what the attitude samples got wrong (noise,
    // latency against the video) shows as flow across the rays from the FOE, which a static scene
    // seen under pure translation never has.
    bool refine_rotation = true;
    double refine_huber_px = 1.0;  // robust weight: residuals above this count less
    double refine_max_deg = 3.0;   // a larger correction is not believed (left at 0)
    int refine_min_points = 12;
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
    double track_scale = 0.5;  // track on an image resized by this (measured: see bench)
    int detect_interval = 2;   // look for new corners every n-th frame (thesis: every frame)
    // Spread the trajectories over a grid of cols x rows cells (0 = off, the thesis): no cell
    // holds more than its share of max_tracks, the newest trajectories of a crowded cell give
    // way, and new corners go to cells below their share. Without it the strongest corners of a
    // far, slow background take every slot and keep them, and an obstacle gets none.
    int grid_cols = 0, grid_rows = 0;
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
    t.add("track.refine_rotation", &P::refine_rotation, 0, 1,
          "refine the navdata derotation from the tracked points (derotating classifiers)")
        .add("track.refine_huber_px", &P::refine_huber_px, 0.05, 20,
             "rotation refinement: robust weight threshold")
        .add("track.refine_max_deg", &P::refine_max_deg, 0, 30,
             "rotation refinement: largest correction believed per frame")
        .add("track.refine_min_points", &P::refine_min_points, 3, 1000,
             "rotation refinement: fewest points")
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
        .add("track.lk_min_eig", &P::lk_min_eig, 0, 0.1,
             "Lucas-Kanade: drop points with a weaker gradient matrix")
        .add("track.track_scale", &P::track_scale, 0.25, 1, "track on an image resized by this",
             true)
        .add("track.detect_interval", &P::detect_interval, 1, 30,
             "look for new corners every n-th frame")
        .add("track.grid_cols", &P::grid_cols, 0, 32,
             "spread trajectories over this many columns of cells (0 = off)")
        .add("track.grid_rows", &P::grid_rows, 0, 32, "... and this many rows (0 = off)")
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
    // resets_state): takes effect on the next update, keeps the trajectories.
    void set_params(const TrackerParams& p) { p_ = p; }
    void reset();

    // image: grey or BGR at the calibration's size. derot_h maps the previous frame's undistorted
    // pixels to this frame's for the attitude change alone (identity if unknown). With `foe` (the
    // focus of expansion, undistorted pixels) the attitude change is refined from the images:
    // see estimate_residual_rotation().
    void update(const cv::Mat& image, std::int64_t t_ns, double roll_deg,
                const cv::Matx33d& derot_h, const cv::Point2f* foe = nullptr);
    // The rotation the last update() added to derot_h (camera axes, degrees; 0 without refinement
    // or when too few points constrained it).
    const cv::Vec3d& residual_rotation_deg() const { return residual_deg_; }

    const std::vector<Trajectory>& tracks() const { return tracks_; }
    const CameraCalibration& calibration() const { return calib_; }
    const RollStabiliser& stabiliser() const { return stab_; }
    cv::Point2f centre() const { return centre_; }
    std::int64_t frame_index() const { return frame_; }
    int ended_last_frame() const { return ended_; }
    int added_last_frame() const { return added_; }
    const TrackerTimings& timings() const { return timings_; }

private:
    cv::Point2f to_full(cv::Point2f p) const;
    cv::Point2f to_track(cv::Point2f p) const;
    void detect(double roll_deg);
    bool grid_on() const { return p_.grid_cols > 0 && p_.grid_rows > 0; }
    int cell_of(cv::Point2f raw) const;
    int cell_quota() const;
    void balance_grid();

    CameraCalibration calib_;
    TrackerParams p_;
    RollStabiliser stab_;
    cv::Point2f centre_;
    std::int64_t frame_ = 0;
    std::uint32_t next_id_ = 1;
    int ended_ = 0, added_ = 0;
    bool have_prev_ = false;
    double now_s_ = 0;

    cv::Mat grey_full_, grey_track_;
    std::vector<cv::Mat> pyr_prev_, pyr_cur_;
    std::vector<Trajectory> tracks_;
    std::vector<cv::Point2f> prev_pts_, cur_pts_, raw_, und_;
    std::vector<std::uint8_t> status_;
    std::vector<float> err_;
    std::vector<cv::Point2f> corners_;
    std::vector<cv::Point2f> pred_;
    std::vector<int> cell_count_;
    std::vector<std::size_t> order_;
    std::vector<std::uint8_t> drop_;
    RotationFitScratch rot_scratch_;
    cv::Mat mask_base_, mask_;
    cv::Vec3d residual_deg_{0, 0, 0};
    double mask_roll_deg_ = kUnknown;
    TrackerTimings timings_;
};

}  // namespace gs::vision
