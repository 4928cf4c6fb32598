#pragma once
// Closed-loop evaluation of the collision-prevention assist (issue 16): one flight of the virtual
// drone in lock-step on one simulated clock, faster than real time and deterministic for a seed.
// Each 5 ms the drone's brain and flight model (DroneCore, its scene as a collision body) step;
// every 30 ms the ground station's AT datagram (REF + PCMD, as the link sends them) carries the
// pilot model's command through the assist; every 33 ms a frame is rendered through the AR.Drone
// 2 front camera model, encoded and decoded as H.264 and run through the obstacle classifier,
// whose decision reaches the assist after the video latency. The pilot model takes over from the
// take-off script and holds "forward" at the flight's speed (with the scene's heading wobble and
// drift) for the whole flight, as an inattentive pilot would: it never brakes by itself.
//
// The suite (`default_assist_suite`) is the issue's: an obstacle dead ahead (pillar, wall, doorway
// edge, person-sized box), obstacles passed close on each side, cluttered rooms with a target,
// open spaces with nothing to hit; each at every speed.

#include "app/assist.hpp"
#include "drone/core/expected.hpp"
#include "drone/sim/flight_model.hpp"
#include "drone/sim/realism.hpp"
#include "drone/sim/scene.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace gs::app {

struct AssistFlightSpec {
    std::string name;      // "pillar-ahead-1.0-s3"
    std::string kind;      // ahead, side, clutter, open
    std::string obstacle;  // what the flight is about: pillar, wall, doorway, person, none ...
    sim::Scene scene;      // start pose = where the drone takes off; target_id for obstacle flights
    double speed_mps = 1.0;
    double goal_m = 8.0;  // along the start heading: reached = completed
    double height_m = 1.0;
    double yaw_wobble_deg = 0, yaw_wobble_hz = 0.3;  // the pilot's heading wobble
    sim::FlightParams flight;                        // drift (wind) and roll wobble
    std::uint64_t seed = 1;                          // navdata noise
};

struct AssistEvalOptions {
    bool assist = true;
    AssistParams params;
    std::string classifier = "flow";
    std::vector<std::string> set;   // classifier parameters, key=value (checked by the caller)
    double video_latency_s = 0.12;  // capture to decision at the ground station (AR.Drone 2 Wi-Fi)
    double settle_s = 2.0;          // hover after take-off (frames flow to the classifier)
    double after_s = 4.0;           // the flight goes on this long past its nominal duration
    // A CSV of every AT cycle (time, position, speed, clearance, the regions the assist saw, its
    // action and command) for looking into one flight; empty: none.
    std::string trace_path;
    // The flight as a dataset (docs/dataset.md: video.h264, frames.csv with the navdata the
    // classifier was given and the ground-truth pose, flight.json), for `replay` to show what
    // the classifier saw; empty: none. The directory must not exist or be empty.
    std::string record_dir;
    // The camera, link and estimator as a real AR.Drone 2's (drone/sim/realism.hpp: what
    // `generate --realism` films): the classifier sees these frames and this navdata; the
    // people crossing are scenery (never hit). Default: none, a clean render.
    sim::RealismOptions realism;
};

struct AssistFlightResult {
    std::string name, kind, obstacle;
    double speed_mps = 0;
    bool assist = false;
    bool collided = false;  // a crash (motors cut)
    int bumps = 0;
    std::string hit;             // what it crashed into
    double hit_speed_mps = 0;    // speed into it
    bool completed = false;      // reached its goal
    bool braked = false;         // the assist braked at least once
    int interventions = 0;       // changes of action to braking, holding or limiting
    double min_clearance_m = 0;  // body to the nearest obstacle, over the flight (walls excluded)
    double brake_speed_mps = kUnknown;         // forward speed when the first brake began
    double stop_distance_m = kUnknown;         // travelled from that brake until stopped
    double first_brake_distance_m = kUnknown;  // clearance when it began
    // Ground truth when the first brake began: the distance straight ahead (along the heading, at
    // the drone's height) to the first surface, wall or obstacle, and the time to reach it at the
    // speed then. A brake with a surface nearer than the classifier's time-to-contact threshold
    // ahead (a room's far wall at 2 m/s) saw something real, even in an open space.
    double brake_ahead_m = kUnknown;
    double brake_ahead_ttc_s = kUnknown;
    double flight_s = 0;
    int frames = 0;
    int unknown_centre_frames = 0;  // frames whose centre decision was unknown
};

// Flies one flight. Errors: the renderer, the encoder or the classifier could not be made.
Expected<AssistFlightResult, std::string> fly_assist_flight(const AssistFlightSpec& spec,
                                                            const AssistEvalOptions& options);

// The suite's open flights fly kOpenGoalM; their room's far wall stands at least kOpenHorizonS at
// the flight's speed plus kOpenMarginM past that (4 s: over the flow classifier's 3.3 s threshold
// on time to contact, with its estimate's scatter), so nothing is to be flagged ahead of them.
inline constexpr double kOpenGoalM = 8.0;
inline constexpr double kOpenHorizonS = 4.0;
inline constexpr double kOpenMarginM = 1.0;

// The default suite at the given speeds, its scenes drawn from `seed`.
std::vector<AssistFlightSpec> default_assist_suite(const std::vector<double>& speeds,
                                                   std::uint64_t seed);
// A small suite (three flights: pillar ahead, pillar passed on the right, open space) for tests.
std::vector<AssistFlightSpec> smoke_assist_suite(const std::vector<double>& speeds,
                                                 std::uint64_t seed);

}  // namespace gs::app
