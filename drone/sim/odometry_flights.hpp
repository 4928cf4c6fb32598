#pragma once
// Flights for the visual-odometry tests of the thesis (§5.1.2): hover, translation,
// translation + rotation and rotation, as a hand-held two-camera plate would fly them at 15 fps
// in a motion-capture room (§5.1.1): a bottom camera over a taped floor, an upward camera under a
// taped ceiling, each with an ultrasonic distance sensor (1 cm resolution, 10 Hz, noise), exact
// ground-truth poses, and AR.Drone-like navdata (attitude, drifting yaw, noisy velocities).
// Deterministic for (params, seed).
//
// Written as a docs/dataset.md bottom-camera dataset (flight.json, frames/, frames.csv with gt_*
// and altitude_m = the bottom distance sensor) plus the two-camera extras read by `ardrone-gs
// odometry`: top/ (one image per frame), top.json (its calibration) and distances.csv
// (frame,bottom_m,top_m).

#include "drone/core/camera_calibration.hpp"
#include "drone/dataset/dataset.hpp"
#include "drone/sim/scene.hpp"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace gs::sim {

enum class OdometryTest { Hover, Translation, TranslationRotation, Rotation };
std::string to_string(OdometryTest t);
std::optional<OdometryTest> odometry_test_from_string(const std::string& s);

struct OdometryFlightParams {
    OdometryTest test = OdometryTest::Translation;
    double fps = 15;           // the thesis' recording rate
    double duration_s = 0;     // 0: the test's own (60 s hover/rotation, the path's length)
    double height_m = 1.2;     // bottom camera above the floor
    double ceiling_m = 4.2;    // room height: the top camera is 3 m below the ceiling
    double speed_mps = 0.25;   // along the path
    double yaw_rate_dps = 30;  // turns of the translation + rotation path
    bool top_camera = true;
    // Hand-held wobble: smooth random motion (sums of sines, 0.1-1 Hz) added to the path.
    double wobble_xy_m = 0.004;
    double wobble_z_m = 0.004;
    double wobble_tilt_deg = 0.4;  // roll and pitch
    double wobble_yaw_deg = 0.3;
    // Distance sensors (Maxbotix MB1320: 1 cm resolution, 10 Hz).
    double distance_noise_m = 0.004;
    double distance_resolution_m = 0.01;
    double distance_rate_hz = 10;
    // The top frame is captured this much later than the bottom one (the thesis' webcams were
    // not synchronised); 0 = synchronised.
    double top_delay_s = 0;
    // Navdata model. Roll and pitch as an onboard estimator reports them: white noise plus a
    // bias per axis that starts at nav_attitude_bias_deg (its sign from the seed) and drifts as
    // a random walk of nav_attitude_bias_walk_dps per square-root second.
    double nav_attitude_noise_deg = 0.05;
    double nav_attitude_bias_deg = 0;
    double nav_attitude_bias_walk_dps = 0;
    double nav_yaw_drift_dps = 0.02;
    double nav_velocity_noise_mps = 0.02;
    int jpeg_quality = 95;  // frames are stored as JPEG (the size of PNGs at 15 fps x 60 s)
};

// One sample of the flight: the true poses of both cameras and what the sensors read.
struct OdometryFlightSample {
    double t_s = 0;
    Pose bottom;                   // bottom camera (= the plate's reference point)
    Pose top;                      // top camera at its capture time
    double bottom_distance_m = 0;  // distance sensors as read
    double top_distance_m = 0;
    NavState nav;  // attitude, yaw with drift, body velocities with noise; altitude = bottom
};

// The flight's samples (no rendering). The first pose is at the world origin, heading 0.
std::vector<OdometryFlightSample> odometry_flight_samples(const OdometryFlightParams& p,
                                                          std::uint64_t seed);

// Room with taped floor and ceiling (thesis fig. 5.6) and nothing else in view.
Scene odometry_scene(const OdometryFlightParams& p, std::uint64_t seed);

struct OdometryFlightSummary {
    int frames = 0;
    double duration_s = 0;
    double path_length_m = 0;
    double render_ms = 0;  // total
    double write_ms = 0;
};

// Renders and writes the flight to `dir` (created; must not exist or be empty).
[[nodiscard]] Expected<OdometryFlightSummary, std::string> write_odometry_flight(
    const std::filesystem::path& dir, const OdometryFlightParams& p, std::uint64_t seed);

// The two-camera extras of a dataset directory, when present.
struct TwoCameraExtras {
    std::vector<std::filesystem::path> top_images;         // top/NNNNNN.{png,jpg}, frame order
    std::optional<gs::CameraCalibration> top_calibration;  // top.json
    std::vector<double> bottom_m, top_m;  // distances.csv per frame (NaN where empty)
};
[[nodiscard]] Expected<TwoCameraExtras, std::string> read_two_camera_extras(
    const std::filesystem::path& dir, std::int64_t frames);

}  // namespace gs::sim
