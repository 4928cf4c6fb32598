#pragma once
// The simulated world: an indoor room (floor, walls, ceiling), obstacles (box and cylinder
// pillars, clutter), lighting, a start pose and an optional autopilot script. Loaded from JSON in
// assets/scenes/ or generated from a seed for evaluation; ground-truth queries for labels.csv.
//
// World frame (docs/dataset.md): x forward along the initial heading, y right, z up, metres; yaw
// clockwise seen from above, roll positive = right side down, pitch positive = nose up.

#include "drone/core/expected.hpp"
#include "drone/sim/asset_error.hpp"
#include "drone/sim/texture.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace gs::sim {

struct Pose {
    double x_m = 0, y_m = 0, z_m = 0;
    double roll_deg = 0, pitch_deg = 0, yaw_deg = 0;
};

struct Room {
    double x_min_m = -2, x_max_m = 20;  // back and front walls
    double y_min_m = -6, y_max_m = 6;   // left and right walls
    double height_m = 3.5;
    TextureSpec floor, ceiling, wall_front, wall_back, wall_left, wall_right;
};

enum class ObstacleShape { Box, Cylinder };

struct Obstacle {
    std::string id;  // optional name ("pillar"); the scenario's target refers to it
    ObstacleShape shape = ObstacleShape::Box;
    double x_m = 0, y_m = 0;                // footprint centre
    double z_m = 0;                         // base height
    double size_x_m = 0.5, size_y_m = 0.5;  // box footprint (before yaw)
    double radius_m = 0.25;                 // cylinder
    double height_m = 1.0;
    double yaw_deg = 0;  // box rotation, clockwise seen from above
    int sides = 16;      // cylinder facets
    TextureSpec texture;
    bool clutter = false;  // scenery, not an obstacle a flight is scored against
};

struct Lighting {
    double gain = 1.0;       // overall brightness
    double ambient = 0.6;    // share of light independent of the surface direction
    double vignette = 0.35;  // brightness loss at the image corners (0 = none)
};

// One segment of a scripted flight: body-frame velocity held for a duration.
struct AutopilotStep {
    std::string action = "move";  // "takeoff", "hover", "move", "land"
    double duration_s = 0;
    double vx_mps = 0, vy_mps = 0, vz_mps = 0, yaw_rate_dps = 0;
};

struct Scene {
    std::string name;
    std::string description;
    std::string source_file;  // where it was loaded from; empty when generated
    Room room;
    std::vector<Obstacle> obstacles;
    Lighting lighting;
    Pose start;                     // drone start pose (camera position)
    std::string scenario = "none";  // docs/dataset.md labels.json: left, right, center, none
    std::string target_id;          // obstacle the flight approaches (labels.csv), empty for none
    std::vector<AutopilotStep> autopilot;
};

// Loads a scene JSON (see assets/scenes/README.md). Errors name the file and the JSON key.
[[nodiscard]] Expected<Scene, AssetError> load_scene(const std::string& path);

// Parameters of the seeded random scene generator (evaluation flights).
struct GeneratorParams {
    std::string scenario = "center";  // left, right, center, none
    double start_distance_m = 7.0;    // start to the target's near face
    double lateral_offset_m = 0.5;    // target centre from the flight line (left/right)
    double clutter_density = 0.5;     // 0 = empty room ... 1 = crowded edges
    double texture_richness = 1.0;    // 0 = plain, hard-to-track walls ... 1 = rich textures
    double light_gain = 1.0;          // multiplied with a random 0.8..1.2
    double start_height_m = 1.0;
};

// A random room, target obstacle and clutter, deterministic for (params, seed). Clutter keeps
// out of the flight corridor so the only obstacle on the path is the target.
Scene generate_scene(const GeneratorParams& params, std::uint64_t seed);

// ---- Ground truth -------------------------------------------------------------------------

struct ObstacleHit {
    std::size_t index = 0;  // into Scene::obstacles
    double distance_m = 0;  // along the direction to the obstacle's near face (negative: passed)
    double lateral_m = 0;   // obstacle centre across the direction, right positive
};

// Where obstacle `index` is relative to a horizontal line from (x, y) heading heading_deg.
ObstacleHit obstacle_relative(const Scene& s, std::size_t index, double x_m, double y_m,
                              double heading_deg);

// The nearest obstacle (clutter included) whose footprint overlaps the corridor
// |lateral| <= half_width_m ahead of (x, y), by near-face distance >= 0.
std::optional<ObstacleHit> obstacle_ahead(const Scene& s, double x_m, double y_m,
                                          double heading_deg, double half_width_m,
                                          double max_range_m = 1e9);

// Horizontal distance from (x, y) to the obstacle's footprint (0 inside it).
double footprint_distance(const Obstacle& o, double x_m, double y_m);

// Index of the obstacle with id, if any.
std::optional<std::size_t> find_obstacle(const Scene& s, const std::string& id);

// Distance along a 3-D ray (world frame, direction need not be unit) to the first surface:
// obstacles, walls, floor or ceiling. nullopt if nothing is hit (origin outside the room).
std::optional<double> ray_distance(const Scene& s, double ox, double oy, double oz, double dx,
                                   double dy, double dz);

}  // namespace gs::sim
