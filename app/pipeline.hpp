#pragma once
// The obstacle pipeline: frames from any source (live link, virtual drone, dataset) through one
// classifier. The same code runs behind the window, `replay` and `eval`, so a flight gives the
// same decisions wherever it is played.

#include "drone/core/sample.hpp"
#include "drone/dataset/dataset.hpp"
#include "vision/classifier.hpp"
#include "vision/odometry.hpp"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

namespace gs::app {

// The classifier's input for one frame: the image header (no copy), capture time and the
// attitude and velocities at capture time.
vision::FrameInput to_frame_input(const FrameSample& s);
// The odometry's input for one bottom-camera frame captured at `t_ns` with `nav` (NavState at
// capture time): the altimeter as the distance to the floor, attitude and velocities.
vision::OdometryInput to_odometry_input(const NavState& nav, TimeNs t_ns, const cv::Mat& bottom);

// Consecutive frames further apart than this (capture times) leave a gap in the evidence (a link
// loss, a stalled video, frames missing from a recording): the classifier starts again after
// it, and the first frame after it has every region unknown (UnknownReason::Gap). The same
// limit makes live video stale (the session marks its regions UnknownReason::StaleVideo).
inline constexpr TimeNs kGapNs = ms_to_ns(500);

// Every region of `r` unknown for `why`: not valid, not unsafe (an unknown region never brakes
// and is never shown as clear).
void mark_unknown(vision::FrameResult& r, vision::UnknownReason why);

class ObstaclePipeline {
public:
    // Throws nothing: an unknown classifier name leaves the pipeline without one (ok() false).
    ObstaclePipeline(std::string classifier, const CameraCalibration& calibration);

    bool ok() const { return classifier_ != nullptr; }
    const std::string& classifier_name() const { return name_; }
    // Switches classifier (state reset). False for an unknown name (the current one stays).
    bool select(const std::string& name);
    void set_calibration(const CameraCalibration& calibration);
    // Forgets the history (a seek, a new source): the next frame is no gap.
    void reset();

    // Classifies one frame. After a gap (kGapNs) the classifier is reset first and the result's
    // regions are unknown (Gap).
    const vision::FrameResult& process(const FrameSample& s);
    std::uint64_t gaps() const { return gaps_; }  // gaps seen since construction
    vision::ObstacleClassifier& classifier() { return *classifier_; }
    const vision::ObstacleClassifier& classifier() const { return *classifier_; }

private:
    std::string name_;
    CameraCalibration calib_;
    std::unique_ptr<vision::ObstacleClassifier> classifier_;
    std::optional<TimeNs> last_t_ns_;  // capture time of the previous frame
    vision::FrameResult marked_;       // a gap frame's result (copied, regions unknown)
    std::uint64_t gaps_ = 0;
};

}  // namespace gs::app
