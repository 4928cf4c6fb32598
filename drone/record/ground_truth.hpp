#pragma once
// What the recorder needs from a source that knows the truth (the virtual drone implements it):
// the scene's scenario for labels.json and, at any time, the drone's pose and where the scene's
// target obstacle lies relative to a pose. drone/record knows nothing else of the virtual drone.

#include "drone/core/clock.hpp"

#include <optional>
#include <string>
#include <vector>

namespace gs::record {

// The drone body's pose in the world frame of docs/dataset.md.
struct TruthPose {
    double x_m = 0, y_m = 0, z_m = 0;
    double roll_deg = 0, pitch_deg = 0, yaw_deg = 0;
};

struct TruthSample {
    TimeNs t_ns = 0;  // monotonic (the link's clock); 0: no sample yet
    TruthPose pose;
};

// The target obstacle seen from a pose: along the direction to its near face (negative once
// passed) and across it (right positive).
struct TargetOffset {
    double distance_m = 0;
    double lateral_m = 0;
};

// labels.json's description of the flight.
struct TruthScene {
    std::string scenario;  // "left", "right", "center", "none" (see scenario_of)
    std::string name;
    std::string target_id;  // empty: no target obstacle
    std::string description;
};

// A contact of the drone's body with the scene (collisions.csv, docs/dataset.md).
struct TruthCollision {
    TimeNs t_ns = 0;     // monotonic (the link's clock)
    bool crash = false;  // motors cut; false: a gentle bump
    std::string kind;    // "obstacle", "wall", "ceiling", "floor"
    std::string what;    // the obstacle's id or "obstacle N", "front wall" ...
    TruthPose pose;      // where the body was
    double speed_mps = 0;
    double approach_mps = 0;  // speed into the surface
};

class GroundTruthSource {
public:
    virtual ~GroundTruthSource() = default;
    virtual TruthScene truth_scene() const = 0;
    // The newest pose (called from the recorder's thread).
    virtual TruthSample truth_sample() const = 0;
    // The scene's target relative to pose `p`; nullopt when the scene has none.
    virtual std::optional<TargetOffset> target_offset(const TruthPose& p) const = 0;
    // Every contact so far, oldest first; a source that cannot collide has none.
    virtual std::vector<TruthCollision> truth_collisions() const { return {}; }
};

}  // namespace gs::record
