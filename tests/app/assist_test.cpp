// The collision-prevention assist as a pure unit: braking, holding, releasing, side limits, what is
// never limited, unknown and stale evidence, override and off; and its braking against the
// drone's own hover on the virtual drone's flight model.

#include "app/assist.hpp"
#include "drone/sim/flight_model.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

namespace gs::app {
namespace {

FlightCommand forward(float pitch = -0.5f) {
    return {true, 0, pitch, 0, 0};
}

RegionEvidence unsafe(double ttc = kUnknown) {
    return {RegionState::Unsafe, 0.05, ttc};
}
RegionEvidence clear() {
    return {RegionState::Clear, 0.05, kUnknown};
}
// No evidence (too few points, too slow to judge), decided `age_s` ago (NaN: age not known).
RegionEvidence unknown(double age_s = 0.05) {
    return {RegionState::Unknown, age_s, kUnknown};
}

// Steps `in` every 30 ms from t = 0 until the assist brakes or 1 s has passed; the last output
// (and, when asked, every output on the way).
AssistOutput step_until_braking(Assist& a, AssistInput& in,
                                std::vector<AssistOutput>* seen = nullptr) {
    AssistOutput o = a.step(in);
    if (seen != nullptr) seen->push_back(o);
    for (double t = 0.03; t < 1.0 && o.action != AssistAction::Braking; t += 0.03) {
        in.t_s = t;
        o = a.step(in);
        if (seen != nullptr) seen->push_back(o);
    }
    return o;
}

AssistInput flying_forward(double vx, RegionEvidence centre) {
    AssistInput in;
    in.pilot = forward();
    in.regions = {clear(), centre, clear()};
    in.vx_mps = vx;
    in.vy_mps = 0;
    in.yaw_deg = 10;
    return in;
}

TEST(Assist, ClearPathPassesThePilotUnchanged) {
    Assist a;
    const AssistOutput o = a.step(flying_forward(1.0, clear()));
    EXPECT_EQ(o.command, forward());
    EXPECT_EQ(o.action, AssistAction::Watching);
    EXPECT_FALSE(o.intervened);
}

TEST(Assist, CentreUnsafeWhileMovingForwardBrakesThenHoldsUntilClear) {
    Assist a;
    // 0.8 s to contact at 1.5 m/s on a frame 50 ms old: 1.125 m, remembered at 0.84 m (ttc_trust).
    AssistInput in = flying_forward(1.5, unsafe(0.8));
    AssistOutput o = a.step(in);
    EXPECT_EQ(o.action, AssistAction::Braking);
    EXPECT_TRUE(o.intervened);
    EXPECT_TRUE(o.changed);
    EXPECT_EQ(o.region, vision::Region::Centre);
    EXPECT_EQ(o.reason, "BRAKING: obstacle ahead, contact in 0.8 s");
    EXPECT_TRUE(o.command.progressive);
    EXPECT_FLOAT_EQ(o.command.pitch, 1.0f);  // full nose-up

    in.t_s = 0.3;
    in.vx_mps = 0.6;
    o = a.step(in);
    EXPECT_EQ(o.action, AssistAction::Braking);
    EXPECT_FALSE(o.changed);
    // Still braking once the centre reads clear (a clear reading at speed is what the brake is
    // for): the line gives no time to contact, a clear region's is not the obstacle's.
    in.t_s = 0.4;
    in.regions[1] = {RegionState::Clear, 0.05, 9.1};
    o = a.step(in);
    EXPECT_EQ(o.action, AssistAction::Braking);
    EXPECT_EQ(o.reason, "BRAKING: obstacle ahead (centre now clear), until stopped");
    in.regions[1] = unsafe(0.8);

    in.t_s = 0.6;
    in.vx_mps = 0.2;  // slow: held from here, the creep taken out with a gentle nose-up
    o = a.step(in);
    EXPECT_EQ(o.action, AssistAction::Holding);
    EXPECT_TRUE(o.changed);
    EXPECT_TRUE(o.command.progressive);
    EXPECT_FLOAT_EQ(o.command.pitch, static_cast<float>(a.params().hold_gain * 0.2));

    // The centre turns unknown once the drone is stopped: still held (unknown is not clear).
    in.t_s = 1.0;
    in.vx_mps = 0.1;
    in.regions[1] = unknown(kUnknown);
    o = a.step(in);
    EXPECT_EQ(o.action, AssistAction::Holding);
    EXPECT_FLOAT_EQ(o.command.pitch, static_cast<float>(a.params().hold_gain * 0.1));
    EXPECT_NE(o.reason.find("until it is seen clear"), std::string::npos);
    // Under the creep speed: the drone's own hover.
    in.vx_mps = 0.03;
    o = a.step(in);
    EXPECT_FALSE(o.command.progressive);
    in.vx_mps = 0.1;

    // Clear for 1.6 s while creeping at 0.1 m/s: at that speed an obstacle over 0.33 m ahead
    // shows a time to contact over the classifier's 3.3 s, so "clear" proves nothing: held.
    in.regions[1] = clear();
    for (double t = 1.5; t <= 3.1; t += 0.1) {
        in.t_s = t;
        o = a.step(in);
    }
    EXPECT_EQ(o.action, AssistAction::Holding);
    // Backed away 2.25 m, then flown toward it at 0.8 m/s with the centre clear: the classifier
    // would have seen it (time to contact under 3.3 s) and did not: forgotten once it has read
    // clear for 0.7 s on frames flown at that speed, the first 0.35 s of flight toward it
    // (evidence_window_s, the classifier's fit window) proving nothing. (Backed away only 1.5 m,
    // the room to approach runs out first: braked again, and a clear reading while braking
    // counts for nothing.)
    double t = 3.1;
    for (int i = 0; i < 30; ++i) {
        in.t_s = t += 0.1;
        in.vx_mps = -0.75;
        a.step(in);
    }
    in.vx_mps = 0.8;
    for (int i = 0; i < 10; ++i) {
        in.t_s = t += 0.1;
        o = a.step(in);
        ASSERT_NE(o.reason, "watching") << "forgotten too early, at step " << i;
    }
    for (int i = 0; i < 3; ++i) {
        in.t_s = t += 0.1;
        o = a.step(in);
    }
    EXPECT_EQ(o.action, AssistAction::Watching);
    EXPECT_EQ(o.reason, "watching");
    EXPECT_EQ(o.command, forward());
}

TEST(Assist, ClearReadingsWhileBrakingDoNotForgetTheObstacle) {
    // Seed 7's clutter-target-2.0-57 in closed loop (realism on, the outline channel on): the
    // centre read unsafe for 4 frames 2.7 m from a plain target at 1.9 m/s, then clear all through
    // the brake (the target's few points and its outline lost as the view pitched up). Those
    // readings, made in the manoeuvre, forgot the target as the drone slowed through 0.18 m/s; the
    // pilot flew on into it. Readings made while braking no longer count as clear: held.
    // The trace's own rows (t, forward speed, centre, time to contact, age), step by step.
    constexpr RegionState C = RegionState::Clear, U = RegionState::Unsafe;
    struct Row {
        double t, vx;
        RegionState centre;
        double ttc, age;
    };
    const Row rows[] = {
        {6.505, 1.63337, C, kUnknown, 0.125},  {6.535, 1.65927, C, kUnknown, 0.155},
        {6.565, 1.68344, C, kUnknown, 0.15},   {6.595, 1.70569, C, kUnknown, 0.145},
        {6.625, 1.7263, C, kUnknown, 0.145},   {6.655, 1.74555, C, kUnknown, 0.14},
        {6.685, 1.76351, C, kUnknown, 0.135},  {6.715, 1.78026, C, kUnknown, 0.135},
        {6.745, 1.79599, C, kUnknown, 0.13},   {6.775, 1.81074, C, kUnknown, 0.125},
        {6.805, 1.82458, C, kUnknown, 0.125},  {6.835, 1.83745, C, kUnknown, 0.155},
        {6.865, 1.8492, C, kUnknown, 0.15},    {6.895, 1.85988, C, 2.88622, 0.145},
        {6.925, 1.87005, U, 2.1624, 0.145},    {6.955, 1.87938, U, 1.79746, 0.14},
        {6.985, 1.8745, U, 1.62914, 0.135},    {7.015, 1.85033, U, 1.61709, 0.135},
        {7.045, 1.81153, C, kUnknown, 0.13},   {7.075, 1.76164, C, kUnknown, 0.125},
        {7.105, 1.7034, C, kUnknown, 0.125},   {7.135, 1.63893, C, kUnknown, 0.155},
        {7.165, 1.56991, C, kUnknown, 0.15},   {7.195, 1.49763, C, kUnknown, 0.145},
        {7.225, 1.4231, C, kUnknown, 0.145},   {7.255, 1.34711, C, kUnknown, 0.14},
        {7.285, 1.27028, C, kUnknown, 0.135},  {7.315, 1.19308, C, kUnknown, 0.135},
        {7.345, 1.11588, C, kUnknown, 0.13},   {7.375, 1.03896, C, kUnknown, 0.125},
        {7.405, 0.96253, C, kUnknown, 0.125},  {7.435, 0.886755, C, kUnknown, 0.155},
        {7.465, 0.811758, C, kUnknown, 0.15},  {7.495, 0.737629, C, kUnknown, 0.145},
        {7.525, 0.664432, C, kUnknown, 0.145}, {7.555, 0.592217, C, kUnknown, 0.14},
        {7.585, 0.521014, C, 1.78561, 0.135},  {7.615, 0.450845, C, kUnknown, 0.135},
        {7.645, 0.381722, C, kUnknown, 0.13},  {7.675, 0.31365, C, 2.76388, 0.125},
        {7.705, 0.246628, C, kUnknown, 0.125}, {7.735, 0.180654, C, kUnknown, 0.155},
        {7.765, 0.132625, C, kUnknown, 0.15},  {7.795, 0.109147, C, 4.13082, 0.145},
        {7.825, 0.104343, C, kUnknown, 0.145}, {7.855, 0.113834, C, kUnknown, 0.14},
        {7.885, 0.134272, C, kUnknown, 0.135},
    };
    for (const bool count_while_braking : {false, true}) {
        SCOPED_TRACE(count_while_braking ? "the rule before" : "now");
        AssistParams p;
        p.clear_while_braking = count_while_braking;
        Assist a(p);
        AssistOutput o;
        bool braked = false;
        for (const Row& r : rows) {
            AssistInput in = flying_forward(r.vx, {r.centre, r.age, r.ttc});
            in.t_s = r.t;
            in.pilot = forward(-1.0f);
            o = a.step(in);
            braked = braked || o.action == AssistAction::Braking;
        }
        ASSERT_TRUE(braked);
        if (count_while_braking) {
            EXPECT_EQ(o.action, AssistAction::Watching) << o.reason;
        } else {
            EXPECT_EQ(o.action, AssistAction::Holding) << o.reason;
            EXPECT_TRUE(known(o.obstacle_m));
            EXPECT_FALSE(o.command.progressive && o.command.pitch < 0) << "no forward command";
        }
    }
}

TEST(Assist, AClearCentreWhileCreepingSlowerThanTheClassifierJudgesIsNoEvidence) {
    // Seed 11's ahead-pillar-0.6 in closed loop: stopped 0.15 m short of the pillar, the drone
    // crept toward it at about 0.2 m/s, which the flow classifier takes for hovering (its
    // min_speed_mps, 0.2): it read the centre clear, the assist forgot the pillar after 0.7 s
    // and let the pilot fly into it. A clear reading counts from evidence_min_mps (0.3 m/s).
    const auto last_action = [](double evidence_min_mps) {
        AssistParams p;
        p.evidence_min_mps = evidence_min_mps;
        Assist a(p);
        AssistInput in = flying_forward(1.5, unsafe(0.8));  // remembered 0.84 m ahead
        a.step(in);
        in.vx_mps = 0.2;
        in.regions[1] = clear();
        AssistOutput o;
        for (int i = 1; i <= 25; ++i) {  // 2.5 s, 0.5 m crept: in sight after 0.9 s
            in.t_s = 0.1 * i;
            o = a.step(in);
        }
        return o.action;
    };
    EXPECT_NE(last_action(0.3), AssistAction::Watching) << "forgot the obstacle it cannot see";
    EXPECT_EQ(last_action(0.0), AssistAction::Watching) << "the rule before: forgotten";
}

TEST(Assist, HeldAndStillMovingTowardTheObstacleItBrakesAgain) {
    AssistParams p;
    p.default_obstacle_m = 0.8;  // no time to contact: remembered closer than the gap
    Assist a(p);
    AssistInput in = flying_forward(1.0, unsafe());
    ASSERT_EQ(a.step(in).action, AssistAction::Braking);
    in.t_s = 0.5;
    in.vx_mps = 0.2;
    in.regions[1] = unknown(kUnknown);
    ASSERT_EQ(a.step(in).action, AssistAction::Holding);
    // A gust (or the hover's slow decay) carries it forward faster than rebrake_mps.
    in.t_s = 0.8;
    in.vx_mps = 0.5;
    const AssistOutput o = a.step(in);
    EXPECT_EQ(o.action, AssistAction::Braking);
    EXPECT_FLOAT_EQ(o.command.pitch, 1.0f);
}

TEST(Assist, AfterABrakeTheDroneIsHeldNoFartherThanTheGapFromWhereItStopped) {
    AssistParams p;
    p.confirm_s = 0;  // braking at the first reading (confirmation: the tests below)
    Assist a(p);
    // Unsafe with 3 s to contact at 1.2 m/s, on a frame 50 ms old: 3.54 m, remembered at 2.66 m.
    // But a time to contact at the classifier's threshold may come from an obstacle seen late
    // (much nearer): once stopped, it is remembered no farther than the gap ahead.
    AssistInput in = flying_forward(1.2, unsafe(3.0));
    ASSERT_EQ(a.step(in).action, AssistAction::Braking);
    in.t_s = 0.5;
    in.vx_mps = 0.1;
    in.regions[1] = unknown(kUnknown);
    AssistOutput o = a.step(in);
    EXPECT_EQ(o.action, AssistAction::Holding) << o.reason;
    EXPECT_NEAR(o.obstacle_m, a.params().hold_gap_m, 1e-9);
    EXPECT_TRUE(is_intervention(o.action));
    // Creeping on at 0.3 m/s for 10 s: 3 m more, under 1 m left: held, nose-up against the creep.
    for (int i = 1; i <= 100; ++i) {
        in.t_s = 0.5 + 0.1 * i;
        in.vx_mps = 0.3;
        o = a.step(in);
    }
    EXPECT_EQ(o.action, AssistAction::Holding);
    EXPECT_FLOAT_EQ(o.command.pitch, static_cast<float>(a.params().hold_gain * 0.3));
}

TEST(Assist, AnApproachingDroneIsStoppedWithItsStoppingDistanceBeforeTheGap) {
    // Held without a brake (stopped, the pilot pushing forward at an unsafe centre with no time
    // to contact): the obstacle is assumed default_obstacle_m ahead, here 3 m.
    AssistParams params;
    params.default_obstacle_m = 3.0;
    Assist a(params);
    const AssistParams& p = a.params();
    AssistInput in = flying_forward(0.0, unsafe());
    ASSERT_EQ(a.step(in).action, AssistAction::Holding);
    in.regions[1] = unknown(kUnknown);
    in.t_s = 0.1;
    ASSERT_EQ(a.step(in).action, AssistAction::Approaching);
    // Approaching at 0.8 m/s: it must brake while the stopping distance still fits in front of
    // the gap, not when the gap is reached.
    in.vx_mps = 0.8;
    const double stop = 0.8 * p.react_s + 0.8 * 0.8 / (2 * p.brake_decel_mps2);
    double left = 3.0, braked_at = -1;
    for (int i = 1; i <= 200 && braked_at < 0; ++i) {
        in.t_s = 0.1 + 0.03 * i;
        left -= 0.8 * 0.03;
        if (a.step(in).action == AssistAction::Braking) braked_at = left;
    }
    EXPECT_NEAR(braked_at, p.hold_gap_m + stop, 0.05);
}

TEST(Assist, YawClimbAndBackingAwayAreNeverLimited) {
    Assist a;
    AssistInput in = flying_forward(1.2, unsafe());
    in.pilot = {true, 0, -0.5f, 0.6f, -0.7f};
    AssistOutput o = a.step(in);
    ASSERT_EQ(o.action, AssistAction::Braking);
    EXPECT_FLOAT_EQ(o.command.gaz, 0.6f);
    EXPECT_FLOAT_EQ(o.command.yaw, -0.7f);
    in.vx_mps = 0.05;
    in.t_s = 1;
    o = a.step(in);
    ASSERT_EQ(o.action, AssistAction::Holding);
    EXPECT_TRUE(o.command.progressive);
    EXPECT_FLOAT_EQ(o.command.pitch, 0.0f);
    EXPECT_FLOAT_EQ(o.command.gaz, 0.6f);
    EXPECT_FLOAT_EQ(o.command.yaw, -0.7f);
    in.pilot = {true, 0, 0.4f, 0, 0};  // backing away
    o = a.step(in);
    EXPECT_EQ(o.command, in.pilot);
    EXPECT_FALSE(o.intervened);
}

TEST(Assist, TurningAwayReleasesTheHold) {
    AssistParams p;
    p.default_obstacle_m = 0.8;  // no time to contact: remembered closer than the gap
    Assist a(p);
    AssistInput in = flying_forward(0.0, unsafe());
    AssistOutput o = a.step(in);
    EXPECT_EQ(o.action, AssistAction::Holding);  // the pilot pushes forward while stopped
    in.yaw_deg = 40;  // turning, the centre still unsafe: held (and the heading followed)
    in.t_s = 1;
    EXPECT_EQ(a.step(in).action, AssistAction::Holding);
    in.regions[1] = unknown(kUnknown);
    in.yaw_deg = 70;  // 30 degrees further: not yet
    in.t_s = 2;
    EXPECT_EQ(a.step(in).action, AssistAction::Holding);
    in.yaw_deg = 95;  // 55 degrees from where the obstacle was last seen ahead
    in.t_s = 3;
    o = a.step(in);
    EXPECT_EQ(o.action, AssistAction::Watching);
    EXPECT_EQ(o.command, forward());
}

TEST(Assist, UnsafeSidesZeroOnlyTheRollTowardThem) {
    Assist a;
    AssistInput in = flying_forward(1.0, clear());
    in.regions[0] = unsafe(2.5);
    in.vy_mps = 0.6;  // already moving right, away from it, faster than the assist pushes
    in.pilot = {true, -0.4f, -0.3f, 0.1f, 0.2f};
    AssistOutput o = a.step(in);
    EXPECT_EQ(o.action, AssistAction::LimitLeft);
    EXPECT_EQ(o.region, vision::Region::Left);
    EXPECT_FLOAT_EQ(o.command.roll, 0.0f);
    EXPECT_FLOAT_EQ(o.command.pitch, -0.3f);  // forward is not the left's business
    EXPECT_FLOAT_EQ(o.command.gaz, 0.1f);
    EXPECT_FLOAT_EQ(o.command.yaw, 0.2f);
    EXPECT_EQ(o.reason, "LIMITING: obstacle left, no movement toward it, contact in 2.5 s");
    in.pilot.roll = 0.4f;  // away from it
    o = a.step(in);
    EXPECT_EQ(o.action, AssistAction::Watching);
    EXPECT_FLOAT_EQ(o.command.roll, 0.4f);

    Assist b;
    in.regions = {clear(), clear(), unsafe()};
    in.vy_mps = -0.6;
    in.pilot = {true, 0.5f, 0, 0, 0};
    o = b.step(in);
    EXPECT_EQ(o.action, AssistAction::LimitRight);
    EXPECT_FALSE(o.command.progressive);  // nothing left in the move: hover
}

TEST(Assist, AnUnsafeSideIsSteeredAwayFromUpToALateralSpeed) {
    Assist a;
    AssistInput in = flying_forward(1.0, clear());
    in.regions[0] = unsafe(2.0);
    AssistOutput o = a.step(in);
    EXPECT_EQ(o.action, AssistAction::SteerRight);
    EXPECT_EQ(o.region, vision::Region::Left);
    EXPECT_TRUE(o.intervened);
    EXPECT_FLOAT_EQ(o.command.roll, static_cast<float>(a.params().side_nudge));
    EXPECT_FLOAT_EQ(o.command.pitch, -0.5f);  // forward untouched: a pass, not a brake
    EXPECT_EQ(o.reason, "STEERING right: obstacle left, contact in 2.0 s");
    // A pilot already rolling away harder keeps their command.
    in.pilot.roll = 0.5f;
    o = a.step(in);
    EXPECT_FLOAT_EQ(o.command.roll, 0.5f);
    // Moving away fast enough: no more push, only the limit toward it.
    in.pilot.roll = 0;
    in.vy_mps = a.params().side_away_mps + 0.05;
    o = a.step(in);
    EXPECT_FLOAT_EQ(o.command.roll, 0.0f);
    // Both sides unsafe (a doorway): nothing is pushed either way.
    Assist b;
    in = flying_forward(1.0, clear());
    in.regions[0] = unsafe(2.0);
    in.regions[2] = unsafe(2.0);
    in.pilot.roll = 0;
    o = b.step(in);
    EXPECT_FLOAT_EQ(o.command.roll, 0.0f);
    // Not moving forward (hovering beside a wall): nothing is pushed.
    Assist c;
    in = flying_forward(0.0, clear());
    in.regions[2] = unsafe();
    o = c.step(in);
    EXPECT_FLOAT_EQ(o.command.roll, 0.0f);
}

TEST(AssistParams, EveryMemberIsNamedAndRangedAndOverridesApplyWhollyOrNotAtAll) {
    const auto& table = assist_param_table();
    // Every member is a double with an entry: a member added without one fails here.
    EXPECT_EQ(table.entries().size() * sizeof(double), sizeof(AssistParams));
    static const AssistParams defaults{};  // static: GCC 12 warns falsely on a local
    std::vector<std::string> names;
    for (const vision::ParamInfo& i : table.list(defaults)) {
        EXPECT_GE(i.value, i.min) << i.name;
        EXPECT_LE(i.value, i.max) << i.name;
        EXPECT_FALSE(i.description.empty()) << i.name;
        names.push_back(i.name);
    }
    std::sort(names.begin(), names.end());
    EXPECT_EQ(std::adjacent_find(names.begin(), names.end()), names.end()) << "a name twice";

    AssistParams p{};
    ASSERT_EQ(apply_assist_overrides(p, {"side_nudge=0", "hold_gap_m=0.6"}), std::nullopt);
    EXPECT_EQ(p.side_nudge, 0.0);
    EXPECT_EQ(p.hold_gap_m, 0.6);
    // One bad override anywhere: nothing is applied, and the error says which and why.
    AssistParams q{};
    auto e = apply_assist_overrides(q, {"side_nudge=0", "hold_gap_m=11"});
    ASSERT_TRUE(e);
    EXPECT_NE(e->find("hold_gap_m=11: value out of range (0..10)"), std::string::npos) << *e;
    EXPECT_EQ(q.side_nudge, defaults.side_nudge);
    e = apply_assist_overrides(q, {"hold_gap=1"});
    ASSERT_TRUE(e);
    EXPECT_NE(e->find("no parameter 'hold_gap' (ardrone-gs params --assist lists them)"),
              std::string::npos)
        << *e;
    EXPECT_TRUE(apply_assist_overrides(q, {"side_nudge"}));
    EXPECT_TRUE(apply_assist_overrides(q, {"side_nudge=abc"}));

    // The overrides reach the assist: with no side nudge an unsafe side is only limited.
    Assist a(p);
    AssistInput in = flying_forward(1.0, clear());
    in.regions[0] = unsafe(2.0);
    const AssistOutput o = a.step(in);
    EXPECT_FLOAT_EQ(o.command.roll, 0.0f);
    EXPECT_NE(o.action, AssistAction::SteerRight);
}

TEST(Assist, ASideObstacleIsSteeredAwayFromUntilAbreastAndLimitedUntilPast) {
    Assist a;
    AssistInput in = flying_forward(1.0, clear());
    in.regions[2] = unsafe(1.5);  // 1.5 m ahead on the right at 1 m/s
    a.step(in);
    // The pillar's alarm flickers off, and it leaves the camera's view as the drone comes
    // alongside: the region turns clear. The drone is still pushed away from it until it is
    // abreast of where it was seen (a few frames of steering move it a few centimetres), and a
    // pilot rolling back toward it is held off until the drone is past it.
    in.regions[2] = clear();
    in.pilot.roll = 0.3f;
    const double abreast = 1.5, until = abreast + a.params().side_pass_margin_m;
    double t = 0;
    for (; t < abreast - 0.1; t += 0.03) {
        in.t_s = t + 0.03;
        const AssistOutput o = a.step(in);
        ASSERT_FLOAT_EQ(o.command.roll, -static_cast<float>(a.params().side_nudge))
            << "at " << t << " s";
        ASSERT_EQ(o.action, AssistAction::SteerLeft);
        ASSERT_EQ(o.reason, "STEERING left: passing the obstacle seen right");
    }
    for (; t < abreast + 0.1; t += 0.03) {
        in.t_s = t + 0.03;
        a.step(in);
    }
    for (; t < until - 0.1; t += 0.03) {
        in.t_s = t + 0.03;
        const AssistOutput o = a.step(in);
        ASSERT_FLOAT_EQ(o.command.roll, 0.0f) << "at " << t << " s";
        ASSERT_EQ(o.action, AssistAction::LimitRight);
        ASSERT_EQ(o.reason, "LIMITING: passing the obstacle seen right, no movement toward it");
    }
    for (; t < until + 0.2; t += 0.03) {
        in.t_s = t + 0.03;
        a.step(in);
    }
    const AssistOutput o = a.step(in);
    EXPECT_FLOAT_EQ(o.command.roll, 0.3f);  // past it: the pilot's again
    EXPECT_EQ(o.action, AssistAction::Watching);
}

TEST(Assist, TheSideNudgeNeverPushesTowardASideWithoutEvidenceNorFartherThanItsShift) {
    // Seed 2027's open-none-1.5-47 (eval-assist, side_nudge 0.5): a one-frame right alarm while
    // braking, never flown past, kept the drone rolling left for seconds, toward a left side
    // that read unknown, into a box.
    Assist a;
    AssistInput in = flying_forward(1.0, clear());
    in.regions[2] = unsafe(1.5);
    in.regions[0] = unknown();
    in.pilot.roll = 0.3f;  // the pilot rolls toward the obstacle: that is zeroed, as always
    AssistOutput o = a.step(in);
    EXPECT_FLOAT_EQ(o.command.roll, 0.0f);  // nothing known to the left: not pushed there
    EXPECT_NE(o.action, AssistAction::SteerLeft);
    EXPECT_EQ(o.action, AssistAction::LimitRight);
    in.regions[0] = {RegionState::Stale, 0.9, kUnknown};
    in.t_s = 0.03;
    o = a.step(in);
    EXPECT_FLOAT_EQ(o.command.roll, 0.0f);  // stale is no evidence either
    // The left reads clear: pushed left, until the drone has moved side_shift_max_m away from
    // where the right last read unsafe (one frame's alarm here).
    Assist b;
    in = flying_forward(1.0, clear());
    in.regions[2] = unsafe(5.0);  // far enough ahead not to be abreast within the run
    in.vy_mps = -0.3;             // drifting left at 0.3 m/s, under side_away_mps
    in.pilot.roll = 0.3f;
    in.t_s = -0.03;
    o = b.step(in);
    EXPECT_EQ(o.action, AssistAction::SteerLeft);
    in.regions[2] = clear();
    // The push ends while the drift at 0.3 m/s can still be stopped within the shift.
    const AssistParams& p = b.params();
    const double drift = 0.3 * p.react_s + 0.3 * 0.3 / (2 * p.side_settle_decel_mps2);
    const double shift = p.side_shift_max_m - drift;
    double t = 0;
    for (; t < shift / 0.3 - 0.1; t += 0.03) {
        in.t_s = t;
        o = b.step(in);
        ASSERT_FLOAT_EQ(o.command.roll, -static_cast<float>(p.side_nudge)) << "at " << t << " s";
    }
    for (; t < shift / 0.3 + 0.1; t += 0.03) {
        in.t_s = t;
        o = b.step(in);
    }
    // Then the drift it left is rolled against (the pilot's roll toward the obstacle is still
    // zeroed: the counter-roll replaces it), ...
    EXPECT_FLOAT_EQ(o.command.roll, static_cast<float>(p.side_nudge));
    EXPECT_EQ(o.action, AssistAction::SteerRight);
    EXPECT_EQ(o.reason, "STEERING right: stopping the drift away from the obstacle seen right");
    // ... until it has stopped: still limited toward the obstacle, no more pushed.
    in.vy_mps = 0;
    in.t_s = t += 0.03;
    o = b.step(in);
    EXPECT_FLOAT_EQ(o.command.roll, 0.0f);
    EXPECT_EQ(o.action, AssistAction::LimitRight);
    // The right reads unsafe again: its obstacle is still in the corridor, pushed away anew.
    in.regions[2] = unsafe(4.0);
    in.t_s = t += 0.03;
    o = b.step(in);
    EXPECT_EQ(o.action, AssistAction::SteerLeft);
    EXPECT_FLOAT_EQ(o.command.roll, -static_cast<float>(p.side_nudge));
    in.regions[2] = clear();
    for (int k = 0; k < 3; ++k) {
        in.t_s = t += 0.03;
        o = b.step(in);
    }
    // Once the side reads clear and the drone is past it, a new alarm pushes again.
    in.regions[2] = clear();
    for (; t < 9.0; t += 0.03) {  // abreast 5.0 m after the last alarm, past 0.8 m later
        in.t_s = t;
        o = b.step(in);
    }
    EXPECT_EQ(o.action, AssistAction::Watching);
    EXPECT_FLOAT_EQ(o.command.roll, 0.3f);
    in.regions[2] = unsafe(2.0);
    in.t_s = t;
    o = b.step(in);
    EXPECT_EQ(o.action, AssistAction::SteerLeft);
}

// A level AR.Drone keeps its sideways speed: flown on a model with no drag at all (the worst
// case), the push away from a side obstacle and the counter-roll after it keep the drone within
// side_shift_max_m of where the alarm came, stop the drift, and give the roll back to the pilot.
// Seed 41's side-person-left-0.6-06 under --realism: one frame's false right alarm at take-off
// pushed the drone left for 0.7 s, and it coasted on to 1.05 m, across the line of the person it
// was yet to pass on the left.
TEST(Assist, ASidePushEndsWithinItsShiftAndStopsTheDriftItLeaves) {
    Assist a;
    const AssistParams& p = a.params();
    AssistInput in = flying_forward(0.6, clear());
    in.regions[2] = unsafe(0.8);        // one frame's alarm on the right
    const double accel_per_roll = 2.0;  // m/s^2 at full stick (12 degrees: g tan 12 = 2.1)
    const double lag_s = 0.15;          // the attitude's response to the stick
    double y = 0, vy = 0, roll_now = 0, widest = 0, t = 0;
    int settle_steps = 0, push_steps = 0, switches = 0;
    AssistAction last = AssistAction::Watching;
    for (; t < 8.0; t += 0.03) {
        in.t_s = t;
        in.vy_mps = vy;
        const AssistOutput o = a.step(in);
        in.regions[2] = clear();  // the alarm never comes back
        if (o.action != last) ++switches;
        last = o.action;
        if (o.action == AssistAction::SteerLeft) ++push_steps;
        if (o.action == AssistAction::SteerRight) {
            ++settle_steps;
            ASSERT_EQ(o.reason,
                      "STEERING right: stopping the drift away from the obstacle seen right");
        }
        roll_now += (static_cast<double>(o.command.roll) - roll_now) * 0.03 / lag_s;
        vy += accel_per_roll * roll_now * 0.03;
        y += vy * 0.03;
        widest = std::min(widest, y);
    }
    EXPECT_GT(push_steps, 5);    // it was pushed away
    EXPECT_GT(settle_steps, 5);  // and the drift rolled against
    EXPECT_GE(widest, -(p.side_shift_max_m + 0.05)) << "carried " << -widest << " m sideways";
    EXPECT_LT(std::abs(vy), p.side_settle_mps + 0.02);
    // One push, one counter-roll, then the limit toward the remembered obstacle: no alternating.
    EXPECT_LE(switches, 4);
    // Left alone, with the drift stopped, the drone is the pilot's again.
    in.vy_mps = 0;
    in.pilot.roll = 0.05f;
    in.t_s = t;
    EXPECT_FLOAT_EQ(a.step(in).command.roll, 0.05f);
}

TEST(Assist, APilotRollingOnAwayTakesTheCounterRollOver) {
    Assist a;
    AssistInput in = flying_forward(0.6, clear());
    in.regions[0] = unsafe(2.0);  // on the left: pushed right
    in.t_s = 0;
    EXPECT_EQ(a.step(in).action, AssistAction::SteerRight);
    in.regions[0] = clear();
    in.vy_mps = 0.8;  // drifting right too fast to stop within side_shift_max_m: push over
    in.t_s = 0.03;
    in.regions[0] = clear();
    AssistOutput o = a.step(in);
    EXPECT_EQ(o.action, AssistAction::SteerLeft);  // the counter-roll
    EXPECT_LT(o.command.roll, 0.0f);
    // The pilot rolls on right, away from the obstacle: the pilot's command.
    in.pilot.roll = 0.4f;
    in.t_s = 0.06;
    o = a.step(in);
    EXPECT_FLOAT_EQ(o.command.roll, 0.4f);
    EXPECT_NE(o.action, AssistAction::SteerLeft);
    // ... and it stays the pilot's when the stick comes back.
    in.pilot.roll = 0;
    in.t_s = 0.09;
    o = a.step(in);
    EXPECT_FLOAT_EQ(o.command.roll, 0.0f);
}

TEST(Assist, UnknownAndStaleEvidenceNeverBrakesAndSaysSo) {
    Assist a;
    AssistOutput o = a.step(flying_forward(1.5, unknown(kUnknown)));
    EXPECT_EQ(o.action, AssistAction::Watching);
    EXPECT_EQ(o.command, forward());
    EXPECT_EQ(o.reason, "centre unknown: no evidence, not braking");
    EXPECT_TRUE(o.unknown_ahead);
    EXPECT_EQ(o.centre, RegionState::Unknown);
    // An unsafe decision older than the staleness limit is no evidence either.
    o = a.step(flying_forward(1.5, {RegionState::Unsafe, 0.8, 1.0}));
    EXPECT_EQ(o.action, AssistAction::Watching);
    EXPECT_EQ(o.command, forward());
    EXPECT_EQ(o.reason, "centre stale: no evidence, not braking");
    EXPECT_TRUE(o.unknown_ahead);
    EXPECT_EQ(o.centre, RegionState::Stale);
    // Not flying forward: nothing to say about what is ahead.
    AssistInput still = flying_forward(0.0, unknown(kUnknown));
    still.pilot = FlightCommand{};
    EXPECT_FALSE(a.step(still).unknown_ahead);
}

TEST(Assist, AStoppedHeldDroneWithTheCentreClearProbesSlowlyAfterAWait) {
    // The probe's mechanics, with a blind gap under the stop's cap (0.75 m; the default is the
    // cap itself, under which nothing is probed: AStopTheCapPlacedIsNotProbedBlind).
    AssistParams p;
    p.probe_blind_gap_m = 0.75;
    // Braked for an obstacle placed 1.05 m ahead (0.75 x 1.4 s x 1 m/s, the frame 50 ms old) and
    // remembered 1.0 m ahead once stopped (hold_gap_m): no room to approach (the gap is 1 m),
    // room to probe (0.25 m plus the stopping distance, the blind gap being 0.75 m).
    Assist b(p);
    AssistInput in = flying_forward(1.0, unsafe(1.45));
    ASSERT_EQ(b.step(in).action, AssistAction::Braking);
    in.regions[1] = clear();
    in.vx_mps = 0.0;
    AssistOutput o;
    double t = 0.1;
    for (; t < 0.1 + p.probe_wait_s - 0.05; t += 0.03) {
        in.t_s = t;
        o = b.step(in);
        ASSERT_EQ(o.action, AssistAction::Holding) << "at " << t << " s: " << o.reason;
        ASSERT_FALSE(o.command.progressive && o.command.pitch < 0);
    }
    for (int i = 0; i < 4; ++i) {
        in.t_s = t += 0.03;
        o = b.step(in);
    }
    ASSERT_EQ(o.action, AssistAction::Probing) << o.reason;
    EXPECT_TRUE(o.intervened);
    EXPECT_FLOAT_EQ(o.command.pitch, static_cast<float>(-p.probe_pitch));  // -0.5 capped
    EXPECT_NEAR(o.obstacle_m, 1.0, 1e-9);
    // Faster than the probe speed (1.0 / 2.2 = 0.45 m/s): nose-up, not yet a brake.
    in.t_s = t += 0.03;
    in.vx_mps = 0.5;
    o = b.step(in);
    ASSERT_EQ(o.action, AssistAction::Probing) << o.reason;
    EXPECT_GT(o.command.pitch, 0.0f);
    // The centre reads unsafe while probing toward it: brake again.
    in.t_s = t += 0.03;
    in.vx_mps = 0.4;
    in.regions[1] = unsafe(2.0);
    EXPECT_EQ(b.step(in).action, AssistAction::Braking);
}

// The closed loop of the assist, the flight model and a classifier standing in for the real one,
// a pilot holding forward for the whole flight (as eval-assist's pilot does): what it did.
struct PilotRun {
    double x_end_m = 0;
    double min_gap_m = 1e9;  // to the obstacle's face, from the drone's centre
    int brakes = 0;
    bool probed = false;
    AssistAction last = AssistAction::Watching;
};

// `classify(t, x, vx)` gives the centre's evidence at time t for a drone at x moving at vx;
// `pilot(t, action)` the pilot's command, knowing what the assist last did.
template <class Classify, class Pilot>
PilotRun fly_with_pilot(Assist& a, double seconds, double obstacle_x, Classify classify,
                        Pilot pilot) {
    sim::FlightModel m;
    m.set_pose(0, 0, 1.0, 0);
    sim::FlightInput hover;
    hover.start = true;
    for (int i = 0; i < 200; ++i) m.step(hover, 0.005);  // airborne, hovering
    const double x0 = m.state().x_m;
    PilotRun r;
    FlightCommand cmd;
    AssistAction prev = AssistAction::Watching;
    for (int i = 0; i * 0.005 < seconds; ++i) {
        const double t = i * 0.005, x = m.state().x_m - x0, vx = m.state().vx_body_mps();
        r.min_gap_m = std::min(r.min_gap_m, obstacle_x - x);
        if (i % 6 == 0) {  // the AT beat, 30 ms
            AssistInput in;
            in.t_s = t;
            in.pilot = pilot(t, prev);
            in.regions = {clear(), classify(t, x, vx), clear()};
            in.vx_mps = vx;
            in.vy_mps = 0;
            in.yaw_deg = m.state().yaw_deg;
            const AssistOutput o = a.step(in);
            cmd = o.command;
            if (o.action == AssistAction::Braking && prev != AssistAction::Braking) ++r.brakes;
            r.probed = r.probed || o.action == AssistAction::Probing;
            if (std::getenv("ASSIST_TRACE") && o.action != prev)
                std::printf("%6.2f x %5.2f vx %5.2f %-8s %s\n", t, x, vx,
                            to_string(in.regions[1].state), o.reason.c_str());
            prev = r.last = o.action;
        }
        sim::FlightInput fi;
        fi.start = true;
        fi.progressive = cmd.progressive;
        fi.pitch = cmd.pitch;
        fi.roll = cmd.roll;
        m.step(fi, 0.005);
    }
    r.x_end_m = m.state().x_m - x0;
    return r;
}

template <class Classify>
PilotRun fly_with_pilot_forward(Assist& a, double seconds, double obstacle_x, Classify classify) {
    return fly_with_pilot(a, seconds, obstacle_x, classify,
                          [](double, AssistAction) { return forward(-0.4f); });
}

// The centre as the flow classifier reads it on the virtual drone: stopped (under 0.2 m/s) clear,
// since nothing approaches; slow (under 0.3 m/s, as on the suite) unknown, the direction of travel
// too uncertain to judge the centre; faster, unsafe when the time to contact is under 3.3 s, read
// 25 % long (a fit over past frames).
RegionEvidence flow_like(double vx, double true_ttc_s) {
    if (vx < 0.2) return clear();
    if (vx < 0.3) return unknown();
    return true_ttc_s < 3.3 ? unsafe(1.25 * true_ttc_s) : clear();
}

// A probing drone flown at 0.35 m/s with the centre reading `centre`, until it stops probing (or
// 3 s): the remaining distance of its last probing step, and its stopping distance at that speed.
struct ProbeEnd {
    double last_remaining_m = kUnknown;
    double stop_m = 0;
};
ProbeEnd probe_at_035(Assist& a, AssistInput& in, double& t, AssistOutput& o,
                      RegionEvidence centre) {
    in.vx_mps = 0.35;
    in.regions[1] = centre;
    ProbeEnd r;
    for (int i = 0; i < 100 && o.action == AssistAction::Probing; ++i) {
        in.t_s = t += 0.03;
        o = a.step(in);
        if (o.action == AssistAction::Probing) r.last_remaining_m = o.obstacle_m;
    }
    const AssistParams& p = a.params();
    r.stop_m = p.react_s * 0.35 + 0.35 * 0.35 / (2 * p.brake_decel_mps2);
    return r;
}

TEST(Assist, ABlindProbeKeepsTheWiderGapUntilTheCentreIsSeenClear) {
    // Two drones held 1.5 m short of a remembered obstacle (hold_gap_m 1.5 here) probe toward it
    // at 0.35 m/s: fast enough for the classifier, the obstacle within its time to contact. One's
    // centre reads unknown all the way (a near, plain surface: too few points): it stops probing
    // with probe_blind_gap_m plus its stopping distance left, for the obstacle may be nearer
    // than placed. The other's reads clear: once that is read on frames all flown at the probe's
    // speed (evidence_window_s) for probe_seen_s, it may come to probe_min_gap_m, and reads clear
    // long enough to forget the obstacle before that. (From the default 1.0 m it cannot: the
    // window and probe_seen_s take 0.23 m at 0.35 m/s, more than the 0.14 m of room it has.)
    AssistParams p;
    p.hold_gap_m = 1.5;
    p.probe_blind_gap_m = 0.75;  // the two gaps' rule, as it was made (the default is the cap)
    p.confirm_s = 0;             // braking at once
    ASSERT_GT(p.probe_blind_gap_m, p.probe_min_gap_m);
    for (const bool seen : {false, true}) {
        SCOPED_TRACE(seen ? "seen clear" : "blind");
        Assist a(p);
        AssistInput in = flying_forward(1.0, unsafe(2.2));
        ASSERT_EQ(a.step(in).action, AssistAction::Braking);
        in.regions[1] = clear();
        in.vx_mps = 0.0;
        AssistOutput o;
        double t = 0.1;
        for (; t < 0.1 + p.probe_wait_s + 0.1; t += 0.03) {
            in.t_s = t;
            o = a.step(in);
        }
        ASSERT_EQ(o.action, AssistAction::Probing) << o.reason;
        ASSERT_NEAR(o.obstacle_m, 1.5, 0.01);
        const ProbeEnd e = probe_at_035(a, in, t, o, seen ? clear() : unknown());
        const double last_probing_remaining = e.last_remaining_m, stop = e.stop_m;
        if (seen) {
            EXPECT_EQ(o.action, AssistAction::Watching) << o.reason;  // forgotten
            EXPECT_LT(last_probing_remaining, p.probe_blind_gap_m + stop) << "came nearer";
        } else {
            EXPECT_EQ(o.action, AssistAction::Holding) << o.reason;
            EXPECT_GE(o.obstacle_m, p.probe_blind_gap_m + stop - 0.011);
            EXPECT_LT(o.obstacle_m, p.probe_blind_gap_m + stop + 0.011);
            EXPECT_FALSE(o.command.progressive && o.command.pitch < 0) << "no forward command";
        }
    }
}

TEST(Assist, AClearFlickerRightAfterTheAlarmDoesNotGiveTheProbeTheNearerGap) {
    // Seed 11's ahead-pillar-0.6 in closed loop: braked at 0.6 m/s for a 2.2 s reading (the pillar
    // 0.6 m ahead, remembered 0.97 m), it read clear for 0.12 s right after, on frames flown at
    // speed before the brake, then unknown. Counted as the probe's proof of a clear way
    // (probe_seen_s 0.1), the blind probe that followed took the nearer gap and came within
    // 0.17 m. Either rule alone keeps probe_blind_gap_m: at probe_seen_s 0.3 a flicker that
    // short is not proof, and a clear reading made while braking counts for nothing.
    struct Case {
        double seen_s;
        bool clear_while_braking;
    };
    const AssistParams d;
    for (const Case c : {Case{0.1, true}, Case{d.probe_seen_s, true}, Case{0.1, false},
                         Case{d.probe_seen_s, d.clear_while_braking}}) {
        SCOPED_TRACE(testing::Message() << "probe_seen_s " << c.seen_s << ", clear_while_braking "
                                        << c.clear_while_braking);
        const double seen_s = c.seen_s;
        AssistParams p;
        p.probe_seen_s = seen_s;
        p.clear_while_braking = c.clear_while_braking;
        p.probe_blind_gap_m = 0.75;  // as then: a blind probe from the cap (now not probed)
        p.confirm_s = 0;             // braking at once
        Assist a(p);
        AssistInput in = flying_forward(0.6, clear());
        double t = 0;
        for (; t < 0.5; t += 0.03) {  // a speed history for the evidence window
            in.t_s = t;
            ASSERT_EQ(a.step(in).action, AssistAction::Watching);
        }
        in.t_s = t;
        in.regions[1] = unsafe(2.2);
        ASSERT_EQ(a.step(in).action, AssistAction::Braking);
        // The flicker while the brake bites, then nothing, then stopped (a stopped drone's
        // centre reads clear: nothing approaches).
        for (const double v : {0.55, 0.5, 0.45, 0.4, 0.3, 0.2, 0.1, 0.0}) {
            in.t_s = t += 0.03;
            in.vx_mps = v;
            in.regions[1] = v >= 0.4 ? clear() : unknown();
            a.step(in);
        }
        in.regions[1] = clear();
        AssistOutput o;
        for (const double t0 = t; t < t0 + p.probe_wait_s + 0.1; t += 0.03) {
            in.t_s = t;
            o = a.step(in);
        }
        ASSERT_EQ(o.action, AssistAction::Probing) << o.reason;
        // A blind probe at 0.35 m/s: the centre unknown all the way.
        const ProbeEnd e = probe_at_035(a, in, t, o, unknown());
        const double last_remaining = e.last_remaining_m, stop = e.stop_m;
        if (seen_s < 0.12 && c.clear_while_braking)
            EXPECT_LT(last_remaining, p.probe_blind_gap_m + stop - 0.1) << "the rule before";
        else
            EXPECT_GE(last_remaining, p.probe_blind_gap_m + stop - 0.011) << "came nearer";
    }
}

TEST(Assist, ASideAlarmBesideAnUnknownCentreIsTakenAsTheCentres) {
    // Seed 2027's clutter-target-0.6-10: a plain grey pillar ahead, its centre unknown (too few
    // tracked points), its left edge unsafe at 1.9-2.5 s to contact, at 0.6 m/s. Taken as the
    // centre's alarm: braked for and held, saying what it was. With the centre
    // read clear (a free way seen) or the rule off, the side rules alone: never a brake.
    struct Case {
        RegionEvidence centre;
        bool rule;
        bool brakes;
    };
    for (const Case c :
         {Case{unknown(), true, true}, Case{clear(), true, false}, Case{unknown(), false, false}}) {
        SCOPED_TRACE(testing::Message() << to_string(c.centre.state) << (c.rule ? "" : ", off"));
        AssistParams p;
        p.side_blocks_unknown_centre = c.rule;
        Assist a(p);
        AssistInput in = flying_forward(0.6, c.centre);
        in.regions[0] = unsafe(2.2);
        // 0.97 m ahead (ttc_trust): no time to confirm (confirm_gap_m), braked at once.
        AssistOutput o = step_until_braking(a, in);
        const bool braked = o.action == AssistAction::Braking;
        EXPECT_EQ(braked, c.brakes) << o.reason;
        if (!c.brakes) {
            EXPECT_NE(o.action, AssistAction::Holding) << o.reason;
            continue;
        }
        {
            // Hovering (not moving, the pilot not pushing forward), the same readings are no
            // action of the assist's, and are not logged as the side's.
            Assist h(p);
            AssistInput hover = in;
            hover.vx_mps = 0;
            hover.pilot = FlightCommand{};
            const AssistOutput w = h.step(hover);
            EXPECT_EQ(w.action, AssistAction::Watching) << w.reason;
            EXPECT_EQ(w.region, vision::Region::Centre);
        }
        EXPECT_EQ(o.reason, "BRAKING: obstacle left, nothing seen ahead, contact in 2.2 s");
        EXPECT_EQ(o.centre, RegionState::Unknown) << "the centre as read";
        EXPECT_EQ(o.region, vision::Region::Left) << "the region it acted for, as recorded";
        EXPECT_TRUE(o.changed);
        EXPECT_GT(o.command.pitch, 0.0f);
        // Stopped, the side gone, the centre still unknown: held, forward at zero, and logged
        // as the centre's hold once the side no longer reads unsafe.
        in.regions[0] = clear();
        in.vx_mps = 0;
        bool logged_centre_hold = false;
        for (double t = 1.0; t < 3.0; t += 0.03) {
            in.t_s = t;
            o = a.step(in);
            logged_centre_hold =
                logged_centre_hold || (o.changed && o.action == AssistAction::Holding &&
                                       o.region == vision::Region::Centre);
        }
        EXPECT_TRUE(logged_centre_hold);
        EXPECT_EQ(o.action, AssistAction::Holding) << o.reason;
        EXPECT_FALSE(o.command.progressive && o.command.pitch < 0);
    }
}

TEST(Assist, ASideObstacleReachingIntoThePathBrakesWhenNoPushClearsItInTime) {
    // Seed 41's ahead-doorway-right-1.5-35: a wall whose edge stood 0.2 m inside the path read
    // unsafe on the right only, 1.4 m before it, the centre clear, and the push away carried the
    // drone past it 0.23 m clear. With the edge placed (edge_m), a side whose obstacle the hull
    // (0.26 m) would pass nearer than 0.3 m, even after the push it can still make (at most
    // 0.5 m, 0.07 m in the 0.43 s that 0.9 s to contact leaves), is braked for as the centre's
    // alarm; with time to push, or the edge well beside, or not placed, or the rule off, the side
    // rules alone. The push counts only toward a side that reads clear. A side that reads so for
    // less than 0.25 s without a break (two frames' false alarm) is pushed from, never braked
    // for.
    struct Case {
        const char* what;
        double ttc_s, edge_m;
        RegionEvidence left;
        bool rule;
        bool brakes;
    };
    for (const Case c : {
             Case{"into the hull, 0.6 s away", 0.9, 0.05, clear(), true, true},
             Case{"beside the hull by 0.2 m, 0.6 s away", 0.9, 0.46, clear(), true, true},
             Case{"into the hull by 0.16 m, time to push", 3.0, 0.1, clear(), true, false},
             Case{"into the hull by 0.21 m: more than the push", 3.0, 0.05, clear(), true, true},
             Case{"beside the hull by 0.34 m", 0.9, 0.6, clear(), true, false},
             Case{"not placed", 0.9, kUnknown, clear(), true, false},
             Case{"rule off", 0.9, 0.05, clear(), false, false},
             Case{"near the hull, time to push", 3.0, 0.35, clear(), true, false},
             Case{"near the hull, no push (left unknown)", 3.0, 0.35, unknown(), true, true},
         }) {
        SCOPED_TRACE(c.what);
        AssistParams p;
        if (!c.rule) p.side_hull_half_m = 0;
        Assist a(p);
        AssistInput in = flying_forward(1.5, clear());
        in.regions[0] = c.left;
        in.regions[2] = RegionEvidence{RegionState::Unsafe, 0.05, c.ttc_s, c.edge_m};
        std::vector<AssistOutput> seen;
        AssistOutput o = step_until_braking(a, in, &seen);
        const bool braked = o.action == AssistAction::Braking;
        EXPECT_EQ(braked, c.brakes) << o.reason;
        if (!c.brakes) {
            EXPECT_NE(o.action, AssistAction::Holding) << o.reason;
            continue;
        }
        char contact[32];
        std::snprintf(contact, sizeof contact, "contact in %.1f s", c.ttc_s);
        EXPECT_EQ(o.reason,
                  std::string("BRAKING: obstacle right reaching into the path, ") + contact);
        EXPECT_EQ(o.region, vision::Region::Right) << "the region it acted for, as recorded";
        EXPECT_EQ(o.centre, RegionState::Clear) << "the centre as read";
        EXPECT_GT(o.command.pitch, 0.0f);
        // Only once the side has read unsafe for side_reach_confirm_s (0.25 s: pushed away
        // meanwhile where the left is clear); then, with no time to spare, at once, and with time,
        // confirmed first (said beside the push away while the other side reads clear).
        EXPECT_GE(in.t_s, 0.25 - 1e-9);
        EXPECT_NE(seen.front().action, AssistAction::Braking) << seen.front().reason;
        const bool confirmed = std::any_of(seen.begin(), seen.end(), [](const AssistOutput& x) {
            return x.pending ==
                   "CONFIRMING: right alarm reaching into the path, contact in 3.0 s, braking if "
                   "it holds";
        });
        EXPECT_EQ(confirmed, c.ttc_s > 1);
        if (c.ttc_s < 1) {
            EXPECT_LT(in.t_s, 0.25 + 0.031) << "braked once the side's time was up";
        }
        // The side no longer reads unsafe: still braking, and still saying what for.
        in.regions[2] = clear();
        in.t_s += 0.03;
        o = a.step(in);
        EXPECT_EQ(o.action, AssistAction::Braking) << o.reason;
        EXPECT_EQ(o.reason,
                  "BRAKING: obstacle right reaching into the path (centre now clear), until "
                  "stopped");
    }
    {
        // Two frames in the path, one clear, two again: never 0.25 s without a break.
        SCOPED_TRACE("flickering");
        Assist a;
        AssistInput in = flying_forward(1.5, clear());
        const RegionEvidence in_path{RegionState::Unsafe, 0.05, 0.9, 0.05};
        for (int k = 0; k < 30; ++k) {
            in.t_s = 0.03 * k;
            in.regions[2] = k % 3 == 2 ? clear() : in_path;
            const AssistOutput o = a.step(in);
            EXPECT_NE(o.action, AssistAction::Braking) << k << ": " << o.reason;
        }
    }
}

TEST(Assist, ASideAlarmStandingInForTheCentreIsNamedInEveryPhase) {
    // At 1.5 m/s a right side unsafe at 3 s to contact, the centre and the left unknown (nothing
    // to steer into, so the side rules do nothing): 3.4 m ahead (x 0.75), time to confirm
    // first; confirmed, braked; stopped with the side still unsafe, held. Every phase names the
    // side and says nothing was seen ahead, and is recorded as the right's; a change of phase
    // is a change (logged), the same phase again is not.
    Assist a;
    AssistInput in = flying_forward(1.5, unknown());
    in.regions[0] = unknown();
    in.regions[2] = unsafe(3.0);
    AssistOutput o = a.step(in);
    EXPECT_EQ(o.action, AssistAction::Confirming) << o.reason;
    EXPECT_EQ(o.reason,
              "CONFIRMING: right alarm, nothing seen ahead, contact in 3.0 s, braking "
              "if it holds");
    EXPECT_EQ(o.region, vision::Region::Right);
    EXPECT_EQ(o.centre, RegionState::Unknown);
    EXPECT_TRUE(o.changed);
    in.t_s = 0.03;
    o = a.step(in);
    EXPECT_EQ(o.action, AssistAction::Confirming) << o.reason;
    EXPECT_FALSE(o.changed) << "the same phase, the same region";
    double t = 0.03;
    while (o.action == AssistAction::Confirming && t < 1.0) {
        in.t_s = t += 0.03;
        o = a.step(in);
    }
    ASSERT_EQ(o.action, AssistAction::Braking) << o.reason;
    EXPECT_EQ(o.reason, "BRAKING: obstacle right, nothing seen ahead, contact in 3.0 s");
    EXPECT_EQ(o.region, vision::Region::Right);
    EXPECT_TRUE(o.changed);
    // Stopped; the side still unsafe (now 2.0 s), the centre unknown: held.
    in.regions[2] = unsafe(2.0);
    in.vx_mps = 0;
    for (int i = 0; i < 5; ++i) {
        in.t_s = t += 0.03;
        o = a.step(in);
    }
    EXPECT_EQ(o.action, AssistAction::Holding) << o.reason;
    EXPECT_EQ(
        o.reason,
        "HOLDING: obstacle right, nothing seen ahead, forward held at zero, contact in 2.0 s");
    EXPECT_EQ(o.region, vision::Region::Right);
}

TEST(Assist, ABrakePendingBehindASidesSteeringIsStillSaid) {
    // At 1.5 m/s the centre unsafe at 3 s to contact (a brake to confirm) and the left unsafe at
    // 2 s with the right clear (steered away from): the side's steering takes the action and
    // its line, acting now; the pending brake is still said, until it is confirmed (then the
    // brake's own line) or dropped (the centre clear: nothing pending).
    Assist a;
    AssistInput in = flying_forward(1.5, unsafe(3.0));
    in.regions[0] = unsafe(2.0);
    AssistOutput o = a.step(in);
    EXPECT_EQ(o.action, AssistAction::SteerRight) << o.reason;
    EXPECT_EQ(o.reason, "STEERING right: obstacle left, contact in 2.0 s");
    EXPECT_EQ(o.pending, "CONFIRMING: centre alarm, contact in 3.0 s, braking if it holds");
    // The centre alone: the same pending line is the action's.
    Assist b;
    o = b.step(flying_forward(1.5, unsafe(3.0)));
    EXPECT_EQ(o.action, AssistAction::Confirming);
    EXPECT_EQ(o.pending, o.reason);
    // Confirmed: braking, nothing pending.
    double t = 0;
    while (o.action != AssistAction::Braking && t < 1.0) {
        in.t_s = t += 0.03;
        o = a.step(in);
        if (o.action != AssistAction::Braking) {
            EXPECT_FALSE(o.pending.empty()) << o.reason;
        }
    }
    ASSERT_EQ(o.action, AssistAction::Braking) << o.reason;
    EXPECT_TRUE(o.pending.empty()) << o.pending;
    // Dropped: the centre reads clear long enough while the left stays unsafe.
    Assist c;
    in = flying_forward(1.5, unsafe(3.0));
    in.regions[0] = unsafe(2.0);
    o = c.step(in);
    ASSERT_FALSE(o.pending.empty());
    in.regions[1] = clear();
    for (t = 0; t < 1.0 && !o.pending.empty();) {
        in.t_s = t += 0.03;
        o = c.step(in);
    }
    EXPECT_TRUE(o.pending.empty()) << o.pending;
    EXPECT_EQ(o.action, AssistAction::SteerRight) << o.reason;
}

TEST(Assist, AStopTheCapPlacedIsNotProbedBlind) {
    // Seed 11's ahead-pillar-1.0 in closed loop: braked at 1.0 m/s for a reading of 2.2 s on a
    // frame 0.13 s old (placed 1.55 m ahead; the pillar truly stood 1.04 m ahead, its rates
    // read low), stopped 0.31 m on, remembered hold_gap_m (1.0 m) ahead where it stood 0.73 m.
    // The centre then reads clear (a stopped drone sees nothing approach), later unknown. With
    // the blind gap under the cap (0.75 m, the rule before) the drone probed into that metre and
    // came within 0.26 m of the pillar; with the default it is held, and says where the obstacle
    // is remembered.
    for (const double blind_gap : {0.75, AssistParams{}.probe_blind_gap_m}) {
        SCOPED_TRACE(blind_gap);
        AssistParams p;
        p.probe_blind_gap_m = blind_gap;
        p.confirm_s = 0;  // braking at once
        Assist a(p);
        AssistInput in = flying_forward(1.0, {RegionState::Unsafe, 0.13, 2.2});
        ASSERT_EQ(a.step(in).action, AssistAction::Braking);
        // The brake: 0.31 m flown while the speed falls to 0.
        double t = 0;
        for (const double v : {0.9, 0.75, 0.6, 0.45, 0.3, 0.2, 0.1, 0.0}) {
            in.t_s = t += 0.06;
            in.vx_mps = v;
            in.regions[1] = unknown(0.13);
            a.step(in);
        }
        bool probed = false, forward_sent = false;
        AssistOutput o;
        for (const double t0 = t; t < t0 + 6.0; t += 0.03) {
            in.t_s = t;
            in.regions[1] = t < t0 + 3.0 ? clear() : unknown(0.1);
            o = a.step(in);
            probed = probed || o.action == AssistAction::Probing;
            forward_sent = forward_sent || (o.command.progressive && o.command.pitch < 0);
        }
        EXPECT_NEAR(o.obstacle_m, 1.0, 0.01) << "capped at hold_gap_m ahead of the stop";
        if (blind_gap < p.hold_gap_m) {
            EXPECT_TRUE(probed) << "the rule before";
        } else {
            EXPECT_FALSE(probed);
            EXPECT_FALSE(forward_sent) << "no forward command while held";
            EXPECT_EQ(o.action, AssistAction::Holding) << o.reason;
            EXPECT_TRUE(o.intervened);
        }
    }
}

TEST(Assist, TheProbeBannerShowsBothBoundsOnlyWhereTheyDiffer) {
    // Braked at 1 m/s for readings that place the obstacle 2.2 m ahead (near bound: hold_gap_m
    // ahead of the stop) or 0.9 m ahead (the two bounds one place): the banner gives the range,
    // or one distance, never "1.0-1.0 m". (A blind gap under the cap, so that a probe starts.)
    AssistParams p;
    p.probe_blind_gap_m = 0.75;
    for (const double ttc : {3.0, 1.2}) {
        SCOPED_TRACE(ttc);
        Assist a(p);
        AssistInput in = flying_forward(1.0, unsafe(ttc));
        AssistOutput o = a.step(in);
        for (double t = 0.03; o.action != AssistAction::Braking && t < 0.5; t += 0.03) {
            in.t_s = t;
            o = a.step(in);  // confirmed, when there is time to
        }
        ASSERT_EQ(o.action, AssistAction::Braking);
        in.regions[1] = clear();
        in.vx_mps = 0.0;
        const double t0 = in.t_s;
        for (double t = t0 + 0.1; t < t0 + 1.5; t += 0.03) {
            in.t_s = t;
            o = a.step(in);
        }
        ASSERT_EQ(o.action, AssistAction::Probing) << o.reason;
        const std::string expect =
            ttc > 2 ? "remembered 1.0-2.2 m ahead" : "remembered 0.9 m ahead";
        EXPECT_NE(o.reason.find(expect), std::string::npos) << o.reason;
    }
}

TEST(Assist, AFalseAlarmFromHoverIsHeldUntilThePilotBacksOffAndFliesOnWithARunUp) {
    // Nothing ahead. The classifier flags the centre as the drone speeds up from hover, as on the
    // suite's open flights (runs of 1-20 AT cycles in the first metres), and reads as flow_like
    // does otherwise.
    struct Case {
        int run;      // AT cycles flagged
        double from;  // from this speed (m/s)
        double ttc;   // reading this time to contact (s)
    };
    // 4 cycles (0.09 s) is under confirm_s: never a brake. 14 (0.39 s) is confirmed: stopped, the
    // obstacle remembered about 1 m ahead (hold_gap_m), 1.2 m or 1.9 m at most (2.0 s or 3.1 s
    // at 0.8 m/s). A probe from a stop proves nothing within the room it has: every clear reading
    // it gets is made on frames flown while it sped up from hover (which the classifier, as
    // flow_like, reads clear), slower than the classifier sees 1 m at (evidence_window_s). So it
    // is not probed (the blind gap is the cap: AStopTheCapPlacedIsNotProbedBlind) and the drone
    // is held, saying so, until the pilot turns away, backs off or overrides. (With those readings
    // counted, the 2.0 s case was probed and forgotten: a probe fooled in the same way came within
    // 0.17 m of seed 11's pillar.) A pilot who backs off for 5 s (about 2 m) and flies on gives
    // the classifier the run-up it needs: forgotten on the way. (Backing off 3 s, about 1.2 m,
    // the room to approach ran out first: braked again at 1.2 m/s, and what is read while
    // braking counts for nothing: held.)
    const Case cases[] = {Case{4, 0.75, 3.1}, Case{14, 0.8, 2.0}, Case{14, 0.75, 3.1}};
    for (const Case c : cases) {
        for (const bool back_off : {false, true}) {
            SCOPED_TRACE(testing::Message() << c.run << " cycles from " << c.from << " m/s at "
                                            << c.ttc << " s" << (back_off ? ", backing off" : ""));
            Assist a;
            int flagged = 0;
            double held_since = -1, back_until = -1;
            const PilotRun r = fly_with_pilot(
                a, 25.0, 1e9,
                [&](double, double, double vx) {
                    if ((vx > c.from || flagged > 0) && flagged < c.run) {
                        ++flagged;
                        return unsafe(c.ttc);
                    }
                    return flow_like(vx, 1e9);
                },
                [&](double t, AssistAction last) {
                    if (back_off && back_until < 0) {
                        if (last != AssistAction::Holding)
                            held_since = -1;
                        else if (held_since < 0)
                            held_since = t;
                        else if (t - held_since >= 2.0)
                            back_until = t + 5.0;
                    }
                    return t < back_until ? forward(0.4f) : forward(-0.4f);
                });
            EXPECT_EQ(r.brakes > 0, c.run > 4);
            EXPECT_FALSE(r.probed);
            if (c.run <= 4 || back_off) {
                EXPECT_EQ(r.last, AssistAction::Watching) << "still held at the end";
                EXPECT_GT(r.x_end_m, 10.0);  // the flight went on
            } else {
                EXPECT_EQ(r.last, AssistAction::Holding);
                EXPECT_LT(r.x_end_m, 3.0);
            }
        }
    }
}

TEST(Assist, ACentreAlarmWithTimeToSpareIsConfirmedBeforeItBrakes) {
    // 3 s to contact at 1.0 m/s on a frame 50 ms old: 2.21 m ahead at ttc_trust; braking now
    // stops within 0.53 m (0.2 s reaction, 1.5 m/s^2), so the brake may wait 0.68 s and still
    // stop confirm_gap_m (1 m) short of it.
    Assist a;
    AssistInput in = flying_forward(1.0, unsafe(3.0));
    AssistOutput o = a.step(in);
    EXPECT_EQ(o.action, AssistAction::Confirming) << o.reason;
    EXPECT_EQ(o.command, forward()) << "confirming changes nothing the pilot sends";
    EXPECT_FALSE(o.intervened);
    EXPECT_FALSE(is_intervention(o.action));
    EXPECT_EQ(o.reason, "CONFIRMING: centre alarm, contact in 3.0 s, braking if it holds");
    // A one-frame alarm, then clear for confirm_clear_s: dropped, nothing braked.
    in.regions[1] = clear();
    for (double t = 0.03; t < 0.3; t += 0.03) {
        in.t_s = t;
        o = a.step(in);
        EXPECT_NE(o.action, AssistAction::Braking) << t;
    }
    EXPECT_EQ(o.action, AssistAction::Watching) << o.reason;
    // Another alarm after more than confirm_recall_s (1 s) is confirmed on its own: braked once
    // it has read unsafe for confirm_s (0.25 s), not before, even with a clear frame in between
    // (under confirm_clear_s).
    double braked_at = -1;
    for (int i = 0; i < 30 && braked_at < 0; ++i) {
        in.t_s = 1.5 + 0.03 * i;
        in.regions[1] = i == 3 ? clear() : unsafe(3.0);
        if (a.step(in).action == AssistAction::Braking) braked_at = in.t_s;
    }
    // Unsafe from 1.50 s, clear at 1.59 s, unsafe again: 0.25 s of unsafe readings by 1.80 s.
    EXPECT_NEAR(braked_at, 1.80, 0.031);
}

TEST(Assist, ACentreAlarmThatRecursWithinTheRecallOfOneDroppedBrakesAtOnce) {
    // A true obstacle flagged a frame at a time (seed 11's ahead-pillar-1.5: unsafe, 0.27 s
    // clear, unsafe, then clear until 0.6 s before contact): the first is dropped unconfirmed,
    // the second, within confirm_recall_s of it, brakes at once.
    Assist a;
    AssistInput in = flying_forward(1.5, unsafe(2.8));
    ASSERT_EQ(a.step(in).action, AssistAction::Confirming);
    in.regions[1] = clear();
    for (double t = 0.03; t < 0.3; t += 0.03) {
        in.t_s = t;
        ASSERT_NE(a.step(in).action, AssistAction::Braking) << t;
    }
    ASSERT_EQ(a.step(in).action, AssistAction::Watching) << "dropped";
    in.t_s = 0.9;
    in.regions[1] = unsafe(3.1);
    EXPECT_EQ(a.step(in).action, AssistAction::Braking);
    // Past the recall, an alarm is confirmed afresh.
    AssistParams p;
    p.confirm_recall_s = 0.5;
    Assist b(p);
    in.t_s = 0;
    in.regions[1] = unsafe(2.8);
    ASSERT_EQ(b.step(in).action, AssistAction::Confirming);
    in.regions[1] = clear();
    for (double t = 0.03; t < 0.3; t += 0.03) {
        in.t_s = t;
        (void)b.step(in);
    }
    in.t_s = 0.9;
    in.regions[1] = unsafe(3.1);
    EXPECT_EQ(b.step(in).action, AssistAction::Confirming);
}

TEST(Assist, ACentreAlarmWithNoTimeToSpareOrNoDistanceBrakesAtOnceAndItsDeadlineStands) {
    // Near (0.8 s at 1.5 m/s: the stop would come within a metre of it): at once.
    {
        Assist a;
        EXPECT_EQ(a.step(flying_forward(1.5, unsafe(0.8))).action, AssistAction::Braking);
    }
    // No time to contact, or no velocity: nothing places the obstacle, so nothing to wait for.
    {
        Assist a;
        EXPECT_EQ(a.step(flying_forward(1.0, unsafe())).action, AssistAction::Braking);
        Assist b;
        AssistInput in = flying_forward(kUnknown, unsafe(3.0));
        EXPECT_NE(b.step(in).action, AssistAction::Confirming);
    }
    // Confirmation off: at once, as before it existed.
    {
        AssistParams p;
        p.confirm_s = 0;
        Assist a(p);
        EXPECT_EQ(a.step(flying_forward(1.0, unsafe(3.0))).action, AssistAction::Braking);
    }
    // 1.5 s to contact at 2 m/s: 2.2 m ahead, a 1.7 m stop (0.4 m reaction, 1.33 m braking):
    // at once.
    {
        Assist a;
        EXPECT_EQ(a.step(flying_forward(2.0, unsafe(1.5))).action, AssistAction::Braking);
    }
    // One unsafe reading with time to spare, then the centre reads unknown (no evidence either
    // way): the brake comes at the deadline the reading set (0.68 s), for the obstacle it placed.
    Assist a;
    AssistInput in = flying_forward(1.0, unsafe(3.0));
    ASSERT_EQ(a.step(in).action, AssistAction::Confirming);
    in.regions[1] = unknown(kUnknown);
    double braked_at = -1;
    AssistOutput o;
    for (int i = 1; i < 40 && braked_at < 0; ++i) {
        in.t_s = 0.03 * i;
        o = a.step(in);
        if (o.action == AssistAction::Braking)
            braked_at = in.t_s;
        else
            EXPECT_EQ(o.action, AssistAction::Confirming) << in.t_s;
    }
    EXPECT_NEAR(braked_at, 0.69, 0.031);
    // Remembered where that reading placed it (2.21 m, less the 0.69 m flown since), not at the
    // default distance.
    EXPECT_NEAR(o.obstacle_m, 0.75 * (3.0 - 0.05 - 0.69) * 1.0, 0.02);
}

TEST(Assist, AFlickeringAlarmOfARealObstacleStillStopsTheDroneShortOfIt) {
    // An obstacle ahead whose alarm reads unsafe only every other AT cycle (points come and go),
    // clear in between: the unsafe time adds up across the clear cycles, and the deadline of each
    // reading stands, so the drone stops short of it.
    for (double obstacle : {3.0, 6.0}) {
        Assist a;
        int beat = 0;
        const PilotRun r =
            fly_with_pilot_forward(a, 20.0, obstacle, [&](double, double x, double vx) {
                const RegionEvidence e = flow_like(vx, vx > 0 ? (obstacle - x) / vx : 1e9);
                return ++beat % 2 == 0 && e.state == RegionState::Unsafe ? clear() : e;
            });
        EXPECT_GT(r.min_gap_m, 0.6) << obstacle << " m";
        EXPECT_GE(r.brakes, 1) << obstacle << " m";
    }
}

TEST(Assist, AProbeTowardARealObstacleBrakesAgainAndNeverReachesIt) {
    // An obstacle ahead, seen as flow_like sees it one decision (0.1 s) late.
    for (double obstacle : {1.8, 3.0, 6.0}) {
        Assist a;
        struct Seen {
            double t, x, vx;
        };
        std::vector<Seen> past;
        const PilotRun r =
            fly_with_pilot_forward(a, 30.0, obstacle, [&](double t, double x, double vx) {
                past.push_back({t, x, vx});
                std::size_t k = past.size() - 1;
                while (k > 0 && past[k].t > t - 0.1) --k;
                const Seen s = past[k];
                RegionEvidence e = flow_like(s.vx, s.vx > 0 ? (obstacle - s.x) / s.vx : 1e9);
                e.age_s = t - s.t;
                return e;
            });
        EXPECT_GT(r.min_gap_m, 0.3) << obstacle << " m";
        EXPECT_GE(r.brakes, 1) << obstacle << " m";
        EXPECT_NE(r.last, AssistAction::Watching) << obstacle << " m: forgotten a real obstacle";
    }
}

TEST(Assist, AnObstacleRememberedNearerThanItStandsIsForgottenOnlyOnceSeenClearWhereItMayBe) {
    // Seed 11's clutter-target-1.5: braked 2.6 m short of a plain target, the drone is held 1.0 m
    // ahead of where it stopped (hold_gap_m), a near bound, with the target farther. A probe
    // reading clear within sight of that near bound says nothing of the target, the target reads
    // unknown from 2.0 m (plain: too few tracked points), and the classifier's time to contact
    // is fitted over the last 0.3 s: while the drone speeds up it reads long by the speed gained
    // (and 25 % long besides, as flow_like). Judged at the near bound (sight_far_bound off), the
    // probe forgets the target and the pilot flies on into it through the unknown; judged at the
    // far bound, the near bound moves out only as far as each clear reading proves.
    const double target = 7.0;
    for (const bool far_bound : {false, true}) {
        SCOPED_TRACE(far_bound ? "far bound" : "near bound");
        AssistParams p;
        p.sight_far_bound = far_bound;
        // As when the rule was made: the probe's clear readings while it speeds up count, and
        // 0.1 s of them is proof enough for the nearer gap. (With today's evidence_window_s and
        // probe_seen_s the drone stays 2.97 m short with either bound.)
        p.evidence_window_s = 0;
        p.probe_seen_s = 0.1;
        p.probe_blind_gap_m = 0.75;  // (today's gap is the cap: not probed from it at all)
        Assist a(p);
        std::vector<std::pair<double, double>> speeds;  // (t, vx)
        const PilotRun r =
            fly_with_pilot_forward(a, 30.0, target, [&](double t, double x, double vx) {
                speeds.emplace_back(t, vx);
                std::size_t k = speeds.size() - 1;
                while (k > 0 && speeds[k].first > t - 0.3) --k;
                const double v_fit = speeds[k].second;  // the speed the fit saw
                const double ahead = target - x;
                if (vx >= 0.3 && ahead < 2.0) return unknown();
                return flow_like(vx, v_fit > 0.05 ? ahead / v_fit : 1e9);
            });
        EXPECT_GE(r.brakes, 1);
        EXPECT_TRUE(r.probed);
        // Near bound: forgotten, flown on at the pilot's speed and braked on a late alarm, 0.6 m
        // short. Far bound: a probe's creep only, 1.9 m short.
        std::printf("%s: came within %.2f m, %d brakes\n", far_bound ? "far bound" : "near bound",
                    r.min_gap_m, r.brakes);
        if (far_bound) {
            EXPECT_GT(r.min_gap_m, 1.5) << "flown into the unknown stretch";
        } else {
            EXPECT_LT(r.min_gap_m, 1.0) << "the old rule no longer shows what the bound is for";
        }
    }
}

}  // namespace
}  // namespace gs::app
