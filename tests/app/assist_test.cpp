// The collision-prevention assist as a pure unit: braking, holding, releasing, side limits, what is
// never limited, unknown and stale evidence, override and off; and its braking against the
// drone's own hover on the virtual drone's flight model.

#include "app/assist.hpp"
#include "drone/sim/flight_model.hpp"

#include <gtest/gtest.h>

#include <cmath>

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
    in.regions[1] = {RegionState::Unknown, kUnknown, kUnknown};
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
    // Backed away 1.5 m, then flown toward it at 0.8 m/s with the centre clear: the classifier
    // would have seen it (time to contact under 3.3 s) and did not: forgotten after 0.7 s.
    double t = 3.1;
    for (int i = 0; i < 20; ++i) {
        in.t_s = t += 0.1;
        in.vx_mps = -0.75;
        a.step(in);
    }
    in.vx_mps = 0.8;
    for (int i = 0; i < 6; ++i) {
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

TEST(Assist, HeldAndStillMovingTowardTheObstacleItBrakesAgain) {
    AssistParams p;
    p.default_obstacle_m = 0.8;  // no time to contact: remembered closer than the gap
    Assist a(p);
    AssistInput in = flying_forward(1.0, unsafe());
    ASSERT_EQ(a.step(in).action, AssistAction::Braking);
    in.t_s = 0.5;
    in.vx_mps = 0.2;
    in.regions[1] = {RegionState::Unknown, kUnknown, kUnknown};
    ASSERT_EQ(a.step(in).action, AssistAction::Holding);
    // A gust (or the hover's slow decay) carries it forward faster than rebrake_mps.
    in.t_s = 0.8;
    in.vx_mps = 0.5;
    const AssistOutput o = a.step(in);
    EXPECT_EQ(o.action, AssistAction::Braking);
    EXPECT_FLOAT_EQ(o.command.pitch, 1.0f);
}

TEST(Assist, AfterABrakeItLetsTheDroneOnlyUpToAGapBeforeTheRememberedObstacle) {
    Assist a;
    // Unsafe with 3 s to contact at 1.2 m/s, on a frame 50 ms old: 3.54 m, remembered at 2.66 m.
    AssistInput in = flying_forward(1.2, unsafe(3.0));
    ASSERT_EQ(a.step(in).action, AssistAction::Braking);
    in.t_s = 0.5;
    in.vx_mps = 0.1;
    in.regions[1] = {RegionState::Unknown, kUnknown, kUnknown};
    AssistOutput o = a.step(in);
    EXPECT_EQ(o.action, AssistAction::Watching);  // 2.66 m - travelled: room to go on
    EXPECT_EQ(o.command, forward());
    EXPECT_NE(o.reason.find("APPROACHING: obstacle remembered"), std::string::npos) << o.reason;
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
    Assist a;
    const AssistParams& p = a.params();
    AssistInput in = flying_forward(1.0, unsafe(4.05));  // 4 m ahead (frame 50 ms old) ...
    ASSERT_EQ(a.step(in).action, AssistAction::Braking);
    in.regions[1] = {RegionState::Unknown, kUnknown, kUnknown};
    in.t_s = 0.1;
    in.vx_mps = 0.0;  // ... remembered at 3 m (ttc_trust); stopped at once
    ASSERT_EQ(a.step(in).action, AssistAction::Watching);
    // Approaching at 0.8 m/s: it must brake while the stopping distance still fits in front of
    // the gap, not when the gap is reached.
    in.vx_mps = 0.8;
    const double stop = 0.8 * p.react_s + 0.8 * 0.8 / (2 * p.brake_decel_mps2);
    double left = p.ttc_trust * 4.0, braked_at = -1;
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
    in.regions[1] = {RegionState::Unknown, kUnknown, kUnknown};
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

TEST(Assist, TheLimitTowardASideLastsUntilTheDroneIsPastWhatItSaw) {
    Assist a;
    AssistInput in = flying_forward(1.0, clear());
    in.regions[2] = unsafe(1.5);  // 1.5 m ahead on the right at 1 m/s
    a.step(in);
    // The pillar leaves the camera's view as the drone comes alongside: the region turns clear,
    // but a pilot rolling back toward it is still held off until the drone is past it.
    in.regions[2] = clear();
    in.pilot.roll = 0.3f;
    double t = 0;
    const double until = 1.5 + a.params().side_pass_margin_m;
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

TEST(Assist, UnknownAndStaleEvidenceNeverBrakesAndSaysSo) {
    Assist a;
    AssistOutput o = a.step(flying_forward(1.5, {RegionState::Unknown, kUnknown, kUnknown}));
    EXPECT_EQ(o.action, AssistAction::Watching);
    EXPECT_EQ(o.command, forward());
    EXPECT_EQ(o.reason, "centre unknown: no evidence, not braking");
    // An unsafe decision older than the staleness limit is no evidence either.
    o = a.step(flying_forward(1.5, {RegionState::Unsafe, 0.8, 1.0}));
    EXPECT_EQ(o.action, AssistAction::Watching);
    EXPECT_EQ(o.command, forward());
    EXPECT_EQ(o.reason, "centre stale: no evidence, not braking");
}

TEST(Assist, OverrideOffAndGroundPassThrough) {
    Assist a;
    AssistInput in = flying_forward(1.5, unsafe());
    in.override = true;
    AssistOutput o = a.step(in);
    EXPECT_EQ(o.action, AssistAction::Override);
    EXPECT_EQ(o.command, forward());
    in.override = false;
    in.enabled = false;
    o = a.step(in);
    EXPECT_EQ(o.action, AssistAction::Off);
    EXPECT_EQ(o.command, forward());
    in.enabled = true;
    in.flying = false;
    EXPECT_EQ(a.step(in).command, forward());
    // Back on and flying: it brakes at once.
    in.flying = true;
    EXPECT_EQ(a.step(in).action, AssistAction::Braking);
}

TEST(Assist, WithoutNavdataVelocityItHoversRatherThanGuessing) {
    Assist a;
    AssistInput in = flying_forward(kUnknown, unsafe());
    const AssistOutput o = a.step(in);
    EXPECT_EQ(o.action, AssistAction::Holding);
    EXPECT_EQ(o.command, FlightCommand{});  // hover: the drone's own velocity loop stops it
}

TEST(Assist, BrakingNeverLastsLongerThanItsLimit) {
    Assist a;
    AssistInput in = flying_forward(2.0, unsafe());
    EXPECT_EQ(a.step(in).action, AssistAction::Braking);
    in.t_s = 2.5;  // a velocity that never drops (a broken estimate): hover after max_brake_s
    EXPECT_EQ(a.step(in).action, AssistAction::Holding);
}

// On the virtual drone's flight model: from each of the thesis' speeds, the assist's brake (full
// nose-up, then hover) stops at least as short as the drone's own hover, and within the thesis'
// measured stopping distance of the AR.Drone (under 0.7 m up to 2 m/s) plus the attitude lag.
double stopping_distance(double v0, bool assist) {
    sim::FlightModel m;
    m.set_pose(0, 0, 1.0, 0);
    sim::FlightInput in;
    in.start = true;
    in.progressive = true;
    // Reach v0 with the tilt that holds it.
    const double tilt = std::atan(0.55 * v0 / 9.81) * 180 / M_PI;
    in.pitch = -tilt / (m.limits().euler_angle_max_rad * 180 / M_PI);
    for (int i = 0; i < 2000 && m.state().vx_body_mps() < v0; ++i) {
        sim::FlightInput boost = in;
        boost.pitch = -1;
        m.step(boost, 0.005);
    }
    for (int i = 0; i < 400; ++i) m.step(in, 0.005);  // settle at v0
    const double x0 = m.state().x_m;
    Assist a;
    AssistInput ai;
    ai.pilot = {true, 0, static_cast<float>(in.pitch), 0, 0};
    ai.regions = {clear(), unsafe(), clear()};
    for (int i = 0; i < 1000; ++i) {
        ai.t_s = i * 0.005;
        ai.vx_mps = m.state().vx_body_mps();
        ai.yaw_deg = m.state().yaw_deg;
        sim::FlightInput cmd;
        cmd.start = true;
        if (assist) {
            const FlightCommand c = a.step(ai).command;
            cmd.progressive = c.progressive;
            cmd.pitch = c.pitch;
        }  // else: hover
        m.step(cmd, 0.005);
    }
    return m.state().x_m - x0;
}

TEST(Assist, BrakingStopsNoLongerThanHoverOnTheFlightModel) {
    for (double v : {0.6, 1.0, 1.5, 2.0}) {
        const double hover = stopping_distance(v, false);
        const double brake = stopping_distance(v, true);
        EXPECT_LE(brake, hover + 1e-3) << v << " m/s";
        EXPECT_LT(brake, 0.7 + 0.3 * v) << v << " m/s";
        EXPECT_GT(brake, 0.05) << v << " m/s";
    }
}

}  // namespace
}  // namespace gs::app
