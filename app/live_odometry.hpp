#pragma once
// Visual odometry on the session's video while it comes from the bottom camera (issue 7): the
// thesis' single-camera mode (vision::VisualOdometry: bottom camera, navdata altitude as the
// distance to the floor), fed frame by frame on the session thread. Each processed frame fills
// an OdometryOutput: the sample's estimate and both integrated paths (eq. 6.2 from the visual
// estimate, and from the navdata velocities over the same samples) since the run started.
//
// A run starts at its first frame, at (0, 0) and the navdata heading of that frame, so the paths
// are in the navdata's yaw frame (x forward at yaw 0, y to its right) like the window's
// navdata-integrated flight path. It restarts on restart() (new source, seek, camera switch).
//
// The published paths are decimated to at most kMaxPathPoints (every path_stride-th sample plus
// the newest), so copying them into an output stays bounded however long the flight.

#include "drone/core/camera_calibration.hpp"
#include "drone/core/sample.hpp"
#include "vision/odometry.hpp"

#include <cstdint>
#include <memory>
#include <vector>

namespace gs::app {

struct OdometryOutput {
    bool active = false;            // this frame went through the odometry (bottom camera)
    std::uint64_t run = 0;          // changes whenever the odometry restarted
    vision::OdometrySample sample;  // this frame's estimate (index 0 of a run only primes)
    double distance_m = kUnknown;   // to the floor: the frame's navdata altitude
    std::vector<vision::PlanarPose> path, nav_path;  // decimated, oldest first, newest last
    int path_stride = 1;
    TimeNs start_t_ns = 0;  // capture time of the run's first frame
    std::int64_t samples = 0, invalid = 0, spike_zeroed = 0, rotation_gated = 0;
    double ms_mean = kUnknown;  // odometry time per sample, mean over the run
};

class LiveOdometry {
public:
    static constexpr std::size_t kMaxPathPoints = 1024;

    // The parameters used live: the thesis' defaults, except the spike bound. The thesis' 6 cm
    // per sample suits its hand-carried rig at 15 fps (0.9 m/s); a flying AR.Drone at 1 m/s
    // and 13 fps moves 8 cm per sample, which would be zeroed every sample. Live, a sample is a
    // spike above 25 cm (3.75 m/s at 15 fps, faster than the drone flies indoors).
    static vision::OdometryParams live_params();

    // `bottom`: the bottom camera's calibration (scaled to the frames when their size differs).
    explicit LiveOdometry(const CameraCalibration& bottom,
                          const vision::OdometryParams& params = live_params());
    ~LiveOdometry();

    void set_calibration(const CameraCalibration& bottom);  // restarts
    const CameraCalibration& calibration() const { return calib_; }
    // The next frame starts a new run.
    void restart();
    // One bottom-camera frame (its navdata at capture time gives the altitude and heading).
    // Fills `out`, reusing its vectors.
    void process(const FrameSample& f, OdometryOutput& out);

private:
    void push_path(const vision::PlanarPose& p, const vision::PlanarPose& nav);

    CameraCalibration calib_;
    vision::OdometryParams params_;
    std::unique_ptr<vision::VisualOdometry> vo_;
    int vo_width_ = 0, vo_height_ = 0;  // frame size the estimator was built for
    bool fresh_ = true;                 // the next frame starts a run
    std::uint64_t run_ = 0;
    TimeNs start_t_ns_ = 0;
    std::vector<vision::PlanarPose> path_, nav_path_;
    int stride_ = 1;
    std::int64_t samples_ = 0, invalid_ = 0, spikes_ = 0, gated_ = 0;
    double ms_sum_ = 0;
};

}  // namespace gs::app
