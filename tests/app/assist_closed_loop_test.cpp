// Issue 16's done-when test, over real sockets: the virtual drone in the thesis' centre-pillar
// scene on a stepped clock, a DroneLink to it, the obstacle classifier on the link's decoded frames
// and the assist gate between a pilot who holds "forward" and the link's AT sender. With the
// assist off the drone crashes into the pillar (emergency, motors cut, the collision in the
// drone's ground truth); with it on, it stops short.

#include "app/assist_gate.hpp"
#include "app/pipeline.hpp"
#include "drone/core/camera_calibration.hpp"
#include "drone/link/drone_link.hpp"
#include "drone/sim/collision.hpp"
#include "drone/sim/loopback.hpp"
#include "drone/sim/scenarios.hpp"
#include "drone/sim/virtual_drone.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <thread>

namespace gs::app {
namespace {

using namespace std::chrono_literals;

struct PillarFlight {
    std::uint64_t collisions = 0;
    std::uint32_t drone_state = 0;  // the last navdata's, as the link received it
    sim::FlightState flight;
    double min_clearance_m = 1e9;
    double max_z_m = 0;
    std::uint64_t interventions = 0;
    std::vector<Intervention> log;
};

PillarFlight fly_at_the_pillar(bool assist_on) {
    PillarFlight res;
    FakeClock clock(0);
    auto scene = sim::resolve_scene("thesis_pillar_center");
    EXPECT_TRUE(scene);
    if (!scene) return res;
    const sim::Collider collider(*scene);
    sim::VirtualDroneOptions vo = sim::loopback_options(*scene);
    vo.clock = &clock;
    sim::VirtualDrone drone(std::move(vo));
    EXPECT_TRUE(drone.start());
    link::DroneLink link(sim::link_config(drone), clock);
    EXPECT_TRUE(link.start());
    auto frames = link.subscribe_frames(64);
    const auto deadline = std::chrono::steady_clock::now() + 10s;
    while (!drone.video_client_connected() && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(1ms);
    EXPECT_TRUE(drone.video_client_connected());

    ObstaclePipeline pipeline(std::string(vision::kDefaultClassifier),
                              builtin_calibration(CameraId::Front));
    AssistGate gate;
    gate.set_enabled(assist_on);
    bool takeoff_sent = false;
    std::optional<FlightCommand> sent;
    std::optional<TimeNs> crash_ns;
    TimeNs stopped_ns = -1;  // since when it has been stopped after a brake
    const FlightCommand forward{true, 0, -0.3f, 0, 0};  // ~1.1 m/s once up to speed
    for (int k = 0; k < 30 * 25; ++k) {
        const TimeNs t = static_cast<TimeNs>(k) * 1'000'000'000LL / 30;
        clock.set(t);
        EXPECT_TRUE(drone.wait_reached(t, 10s)) << "step " << k;
        // Every frame rendered up to this step, decoded by the link (waited for with a
        // deadline: the video crosses a real TCP connection).
        const std::uint32_t want = drone.last_frame_number();
        const auto fdeadline = std::chrono::steady_clock::now() + 3s;
        std::uint32_t got = 0;
        while (got < want && std::chrono::steady_clock::now() < fdeadline) {
            auto f = frames->pop_for(20ms);
            if (!f) continue;
            got = f->frame_number.value_or(got);
            const vision::FrameResult& r = pipeline.process(*f);
            // Aged from the frame's capture, as the window's path does (app/pilot_path.cpp).
            gate.on_decision(r, f->capture_ns != 0 ? f->capture_ns : t, true);
        }
        if (auto n = link.navdata().latest())
            gate.on_navdata(n->state, n->data.header.drone_state.fly());
        // Take off once the link has connected (its handshake runs on the stepped clock too).
        if (!takeoff_sent && link.state() == link::ConnectionState::Connected) {
            (void)link.submit(link::Takeoff{});
            takeoff_sent = true;
        }
        const sim::VirtualDroneStatus st = drone.status();
        res.max_z_m = std::max(res.max_z_m, st.flight.z_m);
        const bool up = st.flight.z_m > 0.9 && st.flight.flying();
        const FlightCommand pilot = up && t > 4'000'000'000LL ? forward : FlightCommand{};
        const AssistOutput out = gate.apply(pilot, clock.now_ns());
        if (!sent || !(*sent == out.command)) {
            if (out.command.progressive)
                (void)link.submit(link::Move{out.command.roll, out.command.pitch, out.command.gaz,
                                             out.command.yaw});
            else
                (void)link.submit(link::Hover{});
            sent = out.command;
        }
        if (st.flight.z_m > 0.2)
            res.min_clearance_m = std::min(
                res.min_clearance_m, collider.clearance(st.flight.x_m, st.flight.y_m, st.flight.z_m,
                                                        st.flight.yaw_deg, false));
        if (!crash_ns && st.counters.collisions > 0) crash_ns = t;
        if (crash_ns && t - *crash_ns > 1'500'000'000LL) break;
        // Stopped after a brake: 3 s more shows it stays stopped.
        if (gate.intervention_count() > 0 && std::abs(st.flight.vx_body_mps()) < 0.05) {
            if (stopped_ns < 0) stopped_ns = t;
            if (t - stopped_ns > 3'000'000'000LL) break;
        } else {
            stopped_ns = -1;
        }
    }
    const sim::VirtualDroneStatus st = drone.status();
    res.collisions = st.counters.collisions;
    res.flight = st.flight;
    if (auto n = link.navdata().latest()) res.drone_state = n->data.header.drone_state.raw;
    res.interventions = gate.intervention_count();
    res.log.assign(gate.interventions().begin(), gate.interventions().end());
    link.stop();
    drone.stop();
    return res;
}

TEST(AssistClosedLoop, WithoutTheAssistTheDroneCrashesIntoThePillar) {
    const PillarFlight f = fly_at_the_pillar(false);
    ASSERT_GT(f.max_z_m, 0.8) << "it never took off";
    EXPECT_EQ(f.collisions, 1u);
    const protocol::navdata::DroneState s{f.drone_state};
    EXPECT_TRUE(s.emergency());
    EXPECT_TRUE(s.cutout());
    EXPECT_FALSE(f.flight.motors_on);
    EXPECT_EQ(f.flight.z_m, 0.0);
    EXPECT_EQ(f.interventions, 0u);
}

TEST(AssistClosedLoop, WithTheAssistItStopsShortOfThePillar) {
    const PillarFlight f = fly_at_the_pillar(true);
    ASSERT_GT(f.max_z_m, 0.8) << "it never took off";
    EXPECT_EQ(f.collisions, 0u);
    EXPECT_TRUE(f.flight.flying());
    EXPECT_GT(f.min_clearance_m, 0.1);
    ASSERT_FALSE(f.log.empty());
    EXPECT_EQ(f.log.front().action, AssistAction::Braking);
    EXPECT_EQ(f.log.front().region, vision::Region::Centre);
    EXPECT_LT(f.log.front().before.pitch, 0.0f);  // the pilot's forward ...
    EXPECT_GT(f.log.front().after.pitch, 0.0f);   // ... sent as a nose-up brake
}

}  // namespace
}  // namespace gs::app
