#pragma once
// The outline cue for plain obstacles (issue 16): a surface with no texture gives a point tracker
// nothing to follow, but its outline still looms. On a strip of rows through the focus of
// expansion (the flight line), the plain run of pixels around the FOE column ends at two steps
// in brightness; while the drone approaches the surface those steps move apart, and the run's
// width grows as 1/Z, so d ln(width) / dt = v / Z = 1 / time to contact. A uniform image shift
// (yaw) moves both ends alike and leaves the width alone.
//
// The run is an obstacle only when its ends are the outline of a near surface. A far plain wall
// seen through a gap between two near posts widens just the same, but its ends belong to the
// posts. Each end is judged by what the texture just outside it does:
//  - a near surface's outline covers the farther background beside it: the end moves outward
//    over that texture ("covers");
//  - an end that belongs to its outside (a post's edge) or lies on the same surface (a mark on
//    a wall) moves with it;
//  - an end the outside texture slides over is behind something nearer: not an outline.
// With the camera's rotation taken off (the tracker's estimate), a run that is one surface on
// the flight line only expands about the FOE: both ends' motions agree with its width's growth.
// The cue reads the run's width rate (less twice its standard error: an end wavering between two
// steps scatters it) when:
//  - every end whose outside has texture covers it, and at least one does (an end with a plain
//    outside says nothing either way);
//  - the run's motion, rotation aside, is one expansion about the FOE (a run from a near post's
//    edge to a far step widens as fast, but its ends do not part about the FOE).
// A gap between textured posts (both ends move with the posts) and marks on a wall (the same)
// are left to the points. A run with only one near end is not read either: the near surface
// inside that end cannot be told from a near object beside the run whose texture is misread.
//
// Pure: grey images and times in, a rate out. No allocation per frame once the sizes are met.

#include "drone/core/camera_calibration.hpp"

#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

namespace gs::vision {

struct SilhouetteParams {
    int strip_rows = 21;       // rows per strip, combined by their median (small specks drop out)
    int search_px = 200;       // how far from the FOE column the run's ends are looked for (px)
    double step_grey = 10;     // a brightness step this large (grey levels) ends the plain run ...
    int step_px = 6;           // ... measured between the means of this many px either side
    double min_width_px = 24;  // narrower runs are not measured
    int max_jump_px = 24;      // an end further than this from its last position: a new run
    double max_width_step = 0.12;  // ... or its width changed by more than this share (+1.5 px)
    int row_step_px = 1;           // the strip moves toward the FOE's row by at most this a frame
    int window = 10;               // frames in the width's fit
    int min_frames = 6;            // fewest frames in the fit for a rate
    double rate_k_se = 2;    // the width's rate read is its fit less this many standard errors
    int outside_px = 24;     // the texture read just outside each end ...
    int outside_gap_px = 4;  // ... this far from it
    double outside_min_std = 2.5;  // grey std below which the outside has no texture to read
    double outside_min_ncc = 0.8;  // weaker matches of the outside texture are not used
    int own_frames = 15;           // an end's motion over its outside is read over this many frames
    float own_path_px = 10;        // ... or fewer, once the end moved this far
    int own_search_px = 6;         // ... searched this far beyond the end's own path either way
    double own_min_px = 1.5;       // an end covers its outside: it moved outward over it this far
    // One surface: the run's motion less the camera's rotation and its expansion about the FOE
    // (a shift both ends share) stays within this over the fit's window (px).
    double shift_max_px = 5;
    // An end's motion between frames, rotation aside, beyond noise + max_end_rate * (its
    // distance from the FOE + foe_error_px) * dt is a jump to another step: a new run.
    double end_noise_px = 2;
    double max_end_rate = 1.5;  // 1/s
    double foe_error_px = 20;
};

struct SilhouetteResult {
    bool run = false;           // a plain run around the FOE column with two ends this frame
    float row = 0;              // the strip's centre row (raw pixels)
    float left = 0, right = 0;  // the run's ends (raw pixels)
    double width_px = 0;        // undistorted
    int frames = 0;             // frames the run has been followed (the fit's window at most)
    // Each end's outward motion over the texture beside it over its last own_path_px of path or
    // own_frames (px; NaN: plain or ambiguous; about 0: the texture moves with it).
    double own_left = kUnknown, own_right = kUnknown;
    double width_rate = kUnknown;     // d ln(width)/dt (1/s) once followed min_frames
    double width_rate_se = kUnknown;  // its standard error (1/s)
    double shift_px = kUnknown;       // the run's motion not explained by rotation and expansion
    bool one_surface = false;         // the ends are one near surface's outline (see above)
    double rate = kUnknown;           // the cue (1/s; NaN: nothing measured)
};

class SilhouetteCue {
public:
    SilhouetteCue() = default;
    // New values take effect on the next update (the run followed so far is kept).
    void set_params(const SilhouetteParams& p);
    void reset();

    // grey: the raw (distorted) 8-bit image; foe: the focus of expansion (undistorted pixels);
    // rotation: the camera's rotation since the last frame as a homography of undistorted pixels
    // (last frame's -> this one's).
    const SilhouetteResult& update(const cv::Mat& grey, const CameraCalibration& calib,
                                   cv::Point2f foe, const cv::Matx33d& rotation, double t_s);
    // No FOE this frame: the run is lost.
    void lose();
    const SilhouetteResult& last() const { return r_; }

private:
    struct Sample {
        double t_s;
        double log_w;
        double d_left, d_right;  // the ends' motion less the rotation (undistorted px; NaN: first)
        double a_left, a_right;  // the ends' distance from the FOE (undistorted px, signed)
        double width;            // undistorted px
        float left, right;       // raw px
        cv::Point2f left_u, right_u;  // undistorted
        int row;                      // the strip's centre row (raw px)
        int x0;                       // image column of its profile's index 0
        std::size_t slot;             // its profile in pool_
    };
    bool read_profile(const cv::Mat& grey, int row, int centre_col);
    bool find_run(int c0, double& left, double& right) const;
    double step_at(int i) const;                  // profile index
    double locate_end(int found, int dir) const;  // the end near step index found (dir: outward)
    // How far the end at image column `end` (dir: its outside's side) moved outward over the
    // texture beside it since sample `base`, the end having spread from the FOE by `growth`
    // since (px; NaN when that texture is plain or ambiguous).
    double outside_cover(double end, int dir, const Sample& base, double growth);
    void finish();
    std::size_t capacity() const;

    SilhouetteParams p_;
    SilhouetteResult r_;
    std::vector<std::uint8_t> column_;              // one column's strip values
    std::vector<float> median_, profile_, prefix_;  // per column of the strip
    std::vector<std::vector<float>> pool_;          // the followed samples' profiles
    std::size_t next_slot_ = 0;
    int x0_ = 0;                // image column of profile index 0
    std::vector<Sample> hist_;  // the followed run, oldest first, at most capacity() - 1
    std::vector<double> ts_, ys_, scores_, stretched_;
};

}  // namespace gs::vision
