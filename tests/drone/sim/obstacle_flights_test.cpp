// The evaluation suite's scenes as flown (flown_scene): scenery is cleared from the path and
// from the flight line ahead of the flight's end, so that the target is the only obstacle a
// classifier can rightly flag and a flag elsewhere is a false alarm.

#include "drone/sim/obstacle_flights.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

namespace gs::sim {
namespace {

// The classifiers flag a region at 3.3 s to contact (inverse TTC threshold 0.3/s).
constexpr double kHorizonS = 1.0 / 0.3;

// How near scenery comes to the flight line ahead of `end` (along the start heading, as far as
// the flight covers at its speed within the classifiers' horizon), sampled every 5 cm.
double nearest_ahead(const Obstacle& o, const Scene& s, cv::Point2d end, double speed_mps) {
    const double yaw = s.start.yaw_deg * std::numbers::pi / 180;
    const cv::Point2d heading(std::cos(yaw), std::sin(yaw));
    double nearest = 1e9;
    for (double d = 0; d <= speed_mps * kHorizonS; d += 0.05) {
        const cv::Point2d q = end + d * heading;
        nearest = std::min(nearest, footprint_distance(o, q.x, q.y));
    }
    return nearest;
}

bool same(const Obstacle& a, const Obstacle& b) {
    return a.x_m == b.x_m && a.y_m == b.y_m && a.z_m == b.z_m && a.shape == b.shape;
}

TEST(ObstacleSuite, NoScenerySitsOnTheFlightLineAheadOfAFlightsEnd) {
    // A side pass flies 0.5-0.9 m beside the target's line, and the room's scenery is kept 1.6 m
    // from the target's line: on the far side it can stand 0.5 m from the drone's, in the
    // corridor, a few metres past where the recording ends. A classifier that flags it within
    // 3.3 s of contact is right, yet the flag counted as a wrong-side alarm (realism seed 2026's
    // cluttered_p1_R02: a box stack 0.45 m left of the line). The path that scenery is cleared
    // from now runs on ahead for what the flight covers in clear_ahead_s (4 s).
    const std::vector<ObstacleFlightInfo> suite = thesis_suite(2026);
    ASSERT_EQ(suite.size(), 82u);
    int before_near = 0, flights_before = 0, kept_clutter = 0, removed_far = 0;
    for (const ObstacleFlightInfo& f : suite) {
        if (!(f.params.clear_path_m > 0)) continue;
        ObstacleFlightInfo old = f;
        old.params.clear_ahead_s = 0;
        const auto was = flown_scene(old);
        const auto now = flown_scene(f);
        ASSERT_TRUE(was.has_value()) << f.name << ": " << was.error();
        ASSERT_TRUE(now.has_value()) << f.name << ": " << now.error();
        // Without the line ahead the path is the dry run's positions alone.
        ASSERT_FALSE(was->path.empty());
        const cv::Point2d end = was->path.back();
        const double clear = f.params.clear_path_m;
        bool near_before = false;
        for (const Obstacle& o : was->scene.obstacles) {
            if (!o.clutter) continue;
            const bool near = nearest_ahead(o, was->scene, end, f.params.speed_mps) < clear;
            near_before = near_before || near;
            bool kept = false;
            for (const Obstacle& k : now->scene.obstacles) kept = kept || same(o, k);
            if (kept) {
                ++kept_clutter;
                EXPECT_FALSE(near) << f.name << ": scenery left on the line ahead at (" << o.x_m
                                   << ", " << o.y_m << ")";
            } else if (!near) {
                ++removed_far;  // cleared by the line beyond the horizon (4 s, not 3.3)
            }
        }
        before_near += near_before ? 1 : 0;
        ++flights_before;
        // The target and the rest of the scene are what they were.
        EXPECT_EQ(now->target.has_value(), was->target.has_value()) << f.name;
        EXPECT_DOUBLE_EQ(now->scene.start.y_m, was->scene.start.y_m) << f.name;
    }
    std::printf(
        "%d of %d flights had scenery on the line ahead; %d pieces of scenery kept, %d cleared "
        "beyond the 3.3 s horizon\n",
        before_near, flights_before, kept_clutter, removed_far);
    EXPECT_GE(before_near, 1) << "the suite no longer shows what clear_ahead_s is for";
    EXPECT_GE(kept_clutter, 100) << "the rooms keep their scenery off the line";
}

}  // namespace
}  // namespace gs::sim
