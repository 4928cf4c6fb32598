// The closed-loop suite's geometry (app/assist_eval.cpp): what each kind of flight promises about
// its room holds for every seed and speed, so a score counts what the assist did, not what the
// scene happened to hold.

#include "app/assist.hpp"
#include "app/assist_eval.hpp"
#include "drone/sim/scene.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>

namespace gs::app {
namespace {

const std::vector<double> kSpeeds{0.6, 1.0, 1.5, 2.0};

// An open flight has nothing to hit on its path, nor anything the classifier would rightly flag
// when it reaches its goal still flying at its speed: the far wall lies beyond the classifier's
// time-to-contact threshold (AssistParams::detect_ttc_s, the flow classifier's 3.3 s) at that
// speed, and no obstacle (clutter included) is in the corridor up to that wall. A 2 m/s flight
// used to end 4 m from a 12 m room's far wall: its brake was counted as a nuisance.
TEST(AssistSuite, OpenFlightsHaveNothingToFlagAheadUpToAndPastTheirGoal) {
    const double detect_ttc_s = AssistParams{}.detect_ttc_s;
    for (std::uint64_t seed : {2027ULL, 7ULL, 11ULL, 1ULL, 123456ULL}) {
        const auto suite = default_assist_suite(kSpeeds, seed);
        int open = 0;
        for (const auto& f : suite) {
            if (f.kind != "open") continue;
            ++open;
            SCOPED_TRACE(f.name + " seed " + std::to_string(seed));
            const sim::Scene& s = f.scene;
            EXPECT_EQ(f.goal_m, kOpenGoalM);
            const double goal_x = s.start.x_m + f.goal_m;
            const double past_goal_m = s.room.x_max_m - goal_x;
            EXPECT_GE(past_goal_m, kOpenHorizonS * f.speed_mps + kOpenMarginM - 1e-9);
            EXPECT_GT(past_goal_m, detect_ttc_s * f.speed_mps + 0.5);
            // Nothing within 1 m of the flight line (the hull's half-width, 0.26 m, and the flow
            // classifier's 0.6 m corridor) from the start to the far wall.
            const auto hit = sim::obstacle_ahead(s, s.start.x_m, s.start.y_m, 0.0, 1.0);
            EXPECT_FALSE(hit.has_value()) << "an obstacle at " << hit->distance_m << " m";
        }
        EXPECT_EQ(open, 5 * static_cast<int>(kSpeeds.size()));
        EXPECT_GE(suite.size(), 60U);
    }
}

}  // namespace
}  // namespace gs::app
