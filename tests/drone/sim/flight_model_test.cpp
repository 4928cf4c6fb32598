#include "drone/sim/flight_model.hpp"

#include <gtest/gtest.h>

#include <vector>

using namespace gs::sim;

namespace {
constexpr double kDt = 0.005;  // the virtual drone's 200 Hz step

// Runs `seconds` of steps with a fixed input, returning the ctrl majors seen in order
// (deduplicated).
std::vector<CtrlMajor> run(FlightModel& m, const FlightInput& in, double seconds) {
    std::vector<CtrlMajor> seen;
    const int n = static_cast<int>(seconds / kDt + 0.5);
    for (int i = 0; i < n; ++i) {
        m.step(in, kDt);
        if (seen.empty() || seen.back() != m.state().major) seen.push_back(m.state().major);
    }
    return seen;
}

FlightModel flying_model() {
    FlightModel m;
    FlightInput in;
    in.start = true;
    run(m, in, 5.0);
    return m;
}
}  // namespace

TEST(FlightModel, TakeOffGoesThroughTakeoffToHoverAtTheTakeoffHeight) {
    FlightModel m;
    EXPECT_EQ(m.state().major, CtrlMajor::Landed);
    FlightInput in;
    in.start = true;
    auto seen = run(m, in, 1.0);
    EXPECT_EQ(seen, (std::vector<CtrlMajor>{CtrlMajor::TakingOff}));
    EXPECT_TRUE(m.state().motors_on);
    // Spin-up (0.6 s) + 1 m at 0.45 m/s: hovering after ≈ 2.8 s, not before 2.5 s.
    seen = run(m, in, 1.5);
    EXPECT_EQ(m.state().major, CtrlMajor::TakingOff);
    seen = run(m, in, 1.5);
    EXPECT_EQ(m.state().major, CtrlMajor::Hovering);
    EXPECT_NEAR(m.state().z_m, 1.0, 0.05);
    EXPECT_EQ(m.state().ctrl_state(), 4u << 16);
}

TEST(FlightModel, FullForwardPitchFliesForwardAtTheConfiguredTilt) {
    FlightModel m = flying_model();
    const double x0 = m.state().x_m;
    FlightInput in;
    in.start = true;
    in.progressive = true;
    in.pitch = -1.0;  // nose down = forward
    run(m, in, 3.0);
    EXPECT_EQ(m.state().major, CtrlMajor::Flying);
    EXPECT_NEAR(m.state().pitch_deg, -12.0, 0.1);  // euler_angle_max 0.2094 rad
    EXPECT_GT(m.state().x_m - x0, 3.0);
    EXPECT_GT(m.state().vx_body_mps(), 1.5);
    EXPECT_NEAR(m.state().y_m, 0.0, 1e-9);
    EXPECT_NEAR(m.state().vy_body_mps(), 0.0, 1e-9);
}

TEST(FlightModel, LimitsScaleTheResponse) {
    FlightModel m = flying_model();
    FlightLimits l;
    l.euler_angle_max_rad = 0.1;
    l.control_vz_max_mm_s = 1000;
    l.control_yaw_rad_s = 1.0;
    m.set_limits(l);
    FlightInput in;
    in.start = true;
    in.progressive = true;
    in.roll = 1.0;  // bank right
    in.gaz = 0.5;
    in.yaw = -1.0;  // counter-clockwise
    run(m, in, 2.0);
    EXPECT_NEAR(m.state().roll_deg, 0.1 * 180 / 3.14159265, 0.05);
    EXPECT_NEAR(m.state().vz_mps, 0.5, 0.01);
    EXPECT_NEAR(m.state().yaw_rate_deg_s, -57.2958, 0.1);
    EXPECT_GT(m.state().vy_body_mps(), 0.3);  // banked right: moving right
}

TEST(FlightModel, InputsOutsideTheUnitRangeAreClamped) {
    FlightModel a = flying_model(), b = flying_model();
    FlightInput in;
    in.start = true;
    in.progressive = true;
    in.pitch = -7.0;
    run(a, in, 1.0);
    in.pitch = -1.0;
    run(b, in, 1.0);
    EXPECT_DOUBLE_EQ(a.state().x_m, b.state().x_m);
}

TEST(FlightModel, HoverBrakesToAStop) {
    FlightModel m = flying_model();
    FlightInput in;
    in.start = true;
    in.progressive = true;
    in.pitch = -1.0;
    run(m, in, 2.0);
    in.progressive = false;
    run(m, in, 6.0);
    EXPECT_EQ(m.state().major, CtrlMajor::Hovering);
    EXPECT_LT(std::abs(m.state().vx_body_mps()), 0.05);
}

TEST(FlightModel, LandingDescendsThenReportsLanded) {
    FlightModel m = flying_model();
    FlightInput in;  // start = false: land
    auto seen = run(m, in, 4.0);
    EXPECT_EQ(seen, (std::vector<CtrlMajor>{CtrlMajor::Landing, CtrlMajor::Landed}));
    EXPECT_EQ(m.state().z_m, 0.0);
    EXPECT_FALSE(m.state().motors_on);
}

TEST(FlightModel, LowBatteryRefusesTakeOffAndCriticalBatteryLands) {
    FlightModel m;
    m.set_battery(15);
    FlightInput in;
    in.start = true;
    run(m, in, 1.0);
    EXPECT_EQ(m.state().major, CtrlMajor::Landed);
    EXPECT_TRUE(m.state().battery_low);

    FlightModel f = flying_model();
    f.set_battery(4.0);
    run(f, in, 0.1);
    EXPECT_EQ(f.state().major, CtrlMajor::Landing);
}

TEST(FlightModel, EmergencyCutsTheMotorsAndIsClearedOnTheGround) {
    FlightModel m = flying_model();
    FlightInput in;
    in.start = true;
    in.emergency = true;
    run(m, in, 0.05);
    EXPECT_TRUE(m.state().emergency);
    EXPECT_FALSE(m.state().motors_on);
    in.emergency = false;
    in.start = false;
    run(m, in, 1.0);
    EXPECT_EQ(m.state().z_m, 0.0);  // it fell
    EXPECT_TRUE(m.state().emergency);
    // Holding bit 8 again (a new rising edge) clears it.
    in.emergency = true;
    run(m, in, 0.05);
    EXPECT_FALSE(m.state().emergency);
    // While in emergency, take-off is impossible; once cleared it works again.
    in.emergency = false;
    in.start = true;
    run(m, in, 0.2);
    EXPECT_EQ(m.state().major, CtrlMajor::TakingOff);
}

TEST(FlightModel, ComLostHoversWithTheLostComMinorState) {
    FlightModel m = flying_model();
    FlightInput in;
    in.start = true;
    in.progressive = true;
    in.pitch = -1;
    in.com_lost = true;
    run(m, in, 3.0);
    EXPECT_EQ(m.state().major, CtrlMajor::Hovering);
    EXPECT_EQ(m.state().minor, 8);
    EXPECT_LT(std::abs(m.state().vx_body_mps()), 0.1);
}

TEST(FlightModel, AltitudeStaysWithinTheConfiguredMaximum) {
    FlightModel m = flying_model();
    FlightInput in;
    in.start = true;
    in.progressive = true;
    in.gaz = 1;
    run(m, in, 10.0);
    EXPECT_NEAR(m.state().z_m, 3.0, 1e-9);
}

TEST(FlightModel, SameInputsGiveTheSameTrajectory) {
    FlightParams p;
    p.roll_wobble_deg = 3;
    p.wind_right_mps = 0.2;
    FlightModel a(p), b(p);
    FlightInput in;
    in.start = true;
    for (int i = 0; i < 2000; ++i) {
        in.progressive = i > 800;
        in.pitch = i > 800 ? -0.4 : 0;
        a.step(in, kDt);
        b.step(in, kDt);
    }
    EXPECT_EQ(a.state().x_m, b.state().x_m);
    EXPECT_EQ(a.state().y_m, b.state().y_m);
    EXPECT_EQ(a.state().roll_deg, b.state().roll_deg);
    EXPECT_GT(a.state().y_m, 0.05);  // the wind drifted it right
}
