#pragma once
// Synthetic flights for the classifier tests: rendered frames under known camera motion.

#include "vision/classifier.hpp"
#include "vision/synthetic_scene.hpp"

#include <array>
#include <string>
#include <vector>

namespace gs::vision::test {

enum class Motion {
    SidePass,       // forward at 1 m/s past a wall 0.6 m to the right, far background
    NearPass,       // the same, the wall 0.45 m to the right (inside flow's 0.6 m corridor)
    Approach,       // forward at 1 m/s toward a fronto-parallel wall filling the view
    Roll,           // hovering, rolling +-10 degrees, far wall
    Yaw,            // hovering, yawing at 15 degrees/s, far wall
    WidePass,       // forward at 1 m/s past a wall 1.5 m to the right: beside the corridor
    Floor,          // forward at 1 m/s, 0.6 m above a textured floor, far wall
    Crossing,       // forward at 1 m/s, far wall; a person-sized board 7 m ahead walks off the path
                    // to the right at 1.3 m/s
    FloorObstacle,  // Floor, and a 1.2 m wide, 1.5 m tall board standing on it 5 m ahead
    FloorWidePass,  // Floor, and WidePass's wall 1.5 m to the right standing on it
    // From a hover 1.1 m above a textured floor, the pitch into forward flight an AR.Drone
    // flies: nose down to 11 degrees in 0.35 s, accelerating (drag 0.5/s) toward 1.1 m/s as
    // the nose comes back up at 4 degrees/s; far wall. The navdata's altitude is 1.1 m.
    TakeOff,
    TakeOffObstacle,  // TakeOff, and a 1.2 m wide, 1.6 m tall board on the floor 3.5 m ahead
};

struct FrameRecord {
    std::array<bool, 3> unsafe{};
    std::array<bool, 3> valid{};
    std::array<double, 3> score{};
    std::array<double, 3> edge_m{};  // RegionDecision::edge_m
    double distance_m = 0;           // to the wall ahead (Approach) / along the wall (SidePass)
    // The flow classifier's FOE source for the frame (FlowClassifier::FoeSource), -1 for others.
    int foe_source = -1;
    double foe_x = 0;  // ... and the FOE it used (undistorted px; with a source)
};

CameraCalibration synthetic_calibration();  // 640x360, 60 degree HFOV, no distortion

struct Flight {
    Motion motion;
    int frames;
    double fps = 25;
    bool navdata_velocity = true;    // give the classifier the velocity (the corridor needs it)
    bool navdata_altitude = true;    // ... and the height above the floor (Floor only)
    double navdata_yaw_scale = 1;    // navdata reports this share of the true yaw
    double navdata_vy_bias_mps = 0;  // added to the navdata's sideways velocity (a biased estimate)
    double navdata_lag_s = 0;        // TakeOff*: the navdata is this much older than the frame
    // The drone's pitch wobbling in cruise, a sine of this amplitude at 1 Hz (degrees; the
    // navdata reads it exactly)
    double pitch_wobble_deg = 0;
    std::vector<TexturedPlane> planes;
    int moving_plane = -1;  // this plane moves at plane_velocity (m/s, world axes)
    cv::Vec3d plane_velocity{0, 0, 0};
    CameraPose pose_at(int i) const;
    double distance_at(int i) const;
};
Flight make_flight(Motion m);

std::vector<FrameRecord> fly(const Flight& f, ObstacleClassifier& c);

// First frame index from which region r is unsafe in every later frame, -1 if never.
int first_unsafe(const std::vector<FrameRecord>& rec, Region r);
int count_unsafe(const std::vector<FrameRecord>& rec, Region r);

}  // namespace gs::vision::test
