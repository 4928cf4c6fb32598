// The virtual drone on a clock its owner steps (issue 13, point 13): stepped 1/30 s at a time, it
// flies, sends navdata and renders video by that clock alone, so a fast and a slow machine see the
// same flight. The offscreen window relies on it (tests/ui/cockpit_lockstep_test.cpp).
#include "drone/core/clock.hpp"
#include "drone/link/drone_link.hpp"
#include "drone/sim/loopback.hpp"
#include "drone/sim/scenarios.hpp"
#include "drone/sim/virtual_drone.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

namespace gs::test {
namespace {

using namespace std::chrono_literals;

struct Step {
    sim::FlightState flight;
    std::uint64_t frames_sent = 0;
};

// Flies the scene's scripted pass lock-stepped for `steps` window frames with a link on the same
// clock; `slow` makes each step take real time as a loaded machine would.
std::vector<Step> lockstepped_flight(int steps, bool slow) {
    FakeClock clock(0);
    auto scene = sim::resolve_scene("thesis_pillar_left");
    EXPECT_TRUE(scene);
    if (!scene) return {};
    sim::VirtualDroneOptions vo = sim::loopback_options(std::move(*scene));
    vo.autopilot = true;
    vo.clock = &clock;
    sim::VirtualDrone drone(std::move(vo));
    EXPECT_TRUE(drone.start());
    link::DroneLink link(sim::link_config(drone), clock);
    EXPECT_TRUE(link.start());
    // The video connection comes first (real time), then the flight (simulated time).
    const auto deadline = std::chrono::steady_clock::now() + 10s;
    while (!drone.video_client_connected() && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(1ms);
    EXPECT_TRUE(drone.video_client_connected());
    std::vector<Step> out;
    for (int k = 0; k < steps; ++k) {
        const TimeNs t = static_cast<TimeNs>(k) * 1'000'000'000LL / 30;
        clock.set(t);
        EXPECT_TRUE(drone.wait_reached(t, 10s)) << "step " << k;
        // A slow machine: the window takes 40 ms of real time to draw this frame.
        if (slow) std::this_thread::sleep_for(40ms);
        // The physics has run to t: the status the drone publishes (every 20 ms of its clock) is
        // of this step.
        const auto st_deadline = std::chrono::steady_clock::now() + 5s;
        while (std::abs(drone.status().flight.t_s - static_cast<double>(t) * 1e-9) > 0.021 &&
               std::chrono::steady_clock::now() < st_deadline)
            std::this_thread::sleep_for(200us);
        out.push_back({drone.status().flight, drone.video_frames_sent()});
    }
    link.stop();
    drone.stop();
    return out;
}

TEST(Lockstep, TheVirtualDroneFliesTheSameOnAFastAndASlowMachine) {
    const std::vector<Step> fast = lockstepped_flight(60, false);
    const std::vector<Step> slow = lockstepped_flight(60, true);
    ASSERT_EQ(fast.size(), 60u);
    ASSERT_EQ(slow.size(), 60u);
    for (std::size_t k = 0; k < fast.size(); ++k) {
        // Simulated time is the step's, whatever the real time it took.
        EXPECT_NEAR(fast[k].flight.t_s, static_cast<double>(k) / 30.0, 0.0051) << k;
        EXPECT_EQ(fast[k].flight.t_s, slow[k].flight.t_s) << k;
        EXPECT_EQ(fast[k].flight.z_m, slow[k].flight.z_m) << k;
        EXPECT_EQ(fast[k].flight.x_m, slow[k].flight.x_m) << k;
        EXPECT_EQ(fast[k].flight.yaw_deg, slow[k].flight.yaw_deg) << k;
        // One video frame per 1/30 s of flight, the same number by each step.
        EXPECT_EQ(fast[k].frames_sent, slow[k].frames_sent) << k;
        EXPECT_EQ(fast[k].frames_sent, static_cast<std::uint64_t>(k + 1)) << k;
    }
    // It flew: the scripted take-off lifted it within the two seconds.
    EXPECT_GT(fast.back().flight.z_m, 0.3);
}

}  // namespace
}  // namespace gs::test
