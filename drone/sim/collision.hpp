#pragma once
// The virtual drone as a body of its real size against the scene: every obstacle (clutter
// included), the four walls, the floor and the ceiling, tested each physics step. Pure geometry
// and a contact rule, no clock and no sockets; DroneCore calls it after each flight-model step.
//
// The body is the AR.Drone 2's hull as a yawed box: with the indoor hull 0.52 x 0.52 m and about
// 0.12 m tall (the outdoor hull 0.45 x 0.29 m). Its vertical extent starts at the flight model's
// altitude z (the height of the hull's underside; on the ground z = 0).
//
// A contact whose approach speed (the body's velocity into the surface) is above
// `crash_speed_mps` is a crash: a real AR.Drone whose propellers hit something cuts its motors
// (emergency, drone_state CUTOUT and MOTORS, docs/protocol.md section 3.2) and falls. Slower, it is
// a bump: the body is pushed out of the surface, its speed into it removed, and the bump counted.
// A contact lasting several steps is one event.

#include "drone/core/clock.hpp"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace gs::sim {

struct Scene;

struct BodyShape {
    double length_m = 0.52;  // along the nose
    double width_m = 0.52;
    double height_m = 0.12;
    static BodyShape indoor_hull() { return {}; }
    static BodyShape outdoor_hull() { return {0.45, 0.29, 0.12}; }
};

enum class ContactKind : std::uint8_t { Obstacle, Wall, Floor, Ceiling };
const char* to_string(ContactKind k);  // "obstacle", "wall", "floor", "ceiling"

// The deepest contact between the body and the scene at one pose.
struct Contact {
    ContactKind kind = ContactKind::Obstacle;
    std::size_t obstacle = 0;  // into Scene::obstacles when kind == Obstacle
    std::string what;          // obstacle id ("pillar"), "obstacle 3", "front wall", "floor"...
    double nx = 0, ny = 0, nz = 0;  // unit normal out of the surface, towards the body (world)
    double depth_m = 0;             // how far the body is inside
};

struct CollisionParams {
    BodyShape body;
    double crash_speed_mps = 0.3;  // approach speed at or above which a contact is a crash
};

// One contact event: a crash or a bump, at its first step.
struct CollisionEvent {
    TimeNs t_ns = 0;  // the drone's clock
    double t_s = 0;   // flight-model time
    bool crash = false;
    ContactKind kind = ContactKind::Obstacle;
    std::string what;
    double x_m = 0, y_m = 0, z_m = 0;  // body position (world frame, docs/dataset.md)
    double speed_mps = 0;              // horizontal and vertical speed magnitude at contact
    double approach_mps = 0;           // speed into the surface (along its normal)
};

// The scene's collision geometry (copied from it: the scene may go away).
class Collider {
public:
    explicit Collider(const Scene& scene, CollisionParams params = {});

    const CollisionParams& params() const { return params_; }
    // The deepest contact of the body at (x, y, z) with heading yaw_deg; nullopt when clear.
    // The floor counts only when z < 0 (the flight model keeps z >= 0 and lands on it).
    std::optional<Contact> contact(double x_m, double y_m, double z_m, double yaw_deg) const;
    // Horizontal clearance between the body and the nearest obstacle (and wall, with `walls`)
    // at the body's height (0 in contact): for evaluation.
    double clearance(double x_m, double y_m, double z_m, double yaw_deg, bool walls = true) const;

private:
    struct Shape {
        bool cylinder = false;
        double x = 0, y = 0, z0 = 0, z1 = 0;
        double hx = 0, hy = 0, radius = 0, yaw_rad = 0;
        std::string what;
    };
    CollisionParams params_;
    std::vector<Shape> shapes_;
    double x_min_ = 0, x_max_ = 0, y_min_ = 0, y_max_ = 0, height_ = 0;
};

}  // namespace gs::sim
