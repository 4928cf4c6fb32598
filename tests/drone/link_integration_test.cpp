// The ground station's link against the virtual drone over real loopback sockets (ephemeral
// ports): bootstrap, configuration, flight, video, and the faults a Wi-Fi link suffers.
#include "drone/link/drone_link.hpp"
#include "drone/net.hpp"
#include "drone/sim/scenarios.hpp"
#include "drone/sim/virtual_drone.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <thread>

using namespace gs;
using namespace gs::link;
using namespace std::chrono_literals;

namespace {

// Waits (polling, bounded) until `pred` holds; returns how long it took, or nullopt on timeout.
std::optional<std::chrono::milliseconds> wait_for(const std::function<bool()>& pred,
                                                  std::chrono::milliseconds timeout) {
    const auto t0 = std::chrono::steady_clock::now();
    while (std::chrono::steady_clock::now() - t0 < timeout) {
        if (pred()) {
            return std::chrono::duration_cast<std::chrono::milliseconds>(
                std::chrono::steady_clock::now() - t0);
        }
        std::this_thread::sleep_for(5ms);
    }
    return std::nullopt;
}

struct Rig {
    std::unique_ptr<sim::VirtualDrone> drone;
    std::unique_ptr<DroneLink> link;

    explicit Rig(double battery = 100.0, bool video = true) {
        auto scene = sim::resolve_scene("thesis_pillar_center");
        EXPECT_TRUE(scene) << (scene ? "" : sim::to_string(scene.error()));
        sim::VirtualDroneOptions vo;
        vo.bind_address = "127.0.0.1";
        vo.at_port = vo.navdata_port = vo.video_port = vo.control_port = 0;
        vo.scene = *scene;
        vo.video = video;
        vo.core.battery_pct = battery;
        drone = std::make_unique<sim::VirtualDrone>(vo);
        auto s = drone->start();
        EXPECT_TRUE(s) << (s ? "" : s.error());
        LinkConfig lc;
        lc.drone_address = "127.0.0.1";
        lc.bind_address = "127.0.0.1";
        lc.at_port = drone->at_port();
        lc.navdata_port = drone->navdata_port();
        lc.video_port = drone->video_port();
        lc.control_port = drone->control_port();
        lc.video = video;
        link = std::make_unique<DroneLink>(lc);
        auto l = link->start();
        EXPECT_TRUE(l) << (l ? "" : l.error());
    }
    ~Rig() {
        link->stop();
        drone->stop();
    }
    bool connected() const { return link->state() == ConnectionState::Connected; }
    std::uint16_t major() const {
        auto n = link->navdata().latest();
        return n && n->data.demo ? n->data.demo->ctrl_state.major() : 0;
    }
};

}  // namespace

TEST(LinkIntegration, BootstrapsConfiguresTakesOffFliesForwardAndLands) {
    Rig rig;
    ASSERT_TRUE(wait_for([&] { return rig.connected(); }, 5s)) << rig.link->status().reason;
    EXPECT_EQ(rig.drone->status().counters.configs, 1u);  // general:navdata_demo
    EXPECT_TRUE(rig.link->status().machine.configs_sent >= 1);

    auto r = rig.link->execute(Takeoff{}, 1s);
    ASSERT_EQ(r.code, ResultCode::Sent) << r.reason;
    ASSERT_TRUE(wait_for([&] { return rig.major() == 4; }, 6s)) << "never hovering";
    const double x0 = rig.drone->ground_truth().pose.x_m;

    ASSERT_TRUE(rig.link->execute(Move{0, -0.5f, 0, 0}, 1s).ok());
    std::this_thread::sleep_for(3s);
    auto nav = rig.link->navdata().latest();
    ASSERT_TRUE(nav);
    EXPECT_EQ(nav->data.demo->ctrl_state.major(), 3);  // flying
    EXPECT_GT(nav->state.vx_mps, 0.5);
    EXPECT_NEAR(nav->state.pitch_deg, -6.0, 1.0);
    const double x1 = rig.drone->ground_truth().pose.x_m;
    EXPECT_GT(x1 - x0, 1.5);
    // The link's telemetry and the simulator's truth agree.
    EXPECT_NEAR(nav->state.altitude_m, rig.drone->ground_truth().pose.z_m, 0.1);

    ASSERT_TRUE(rig.link->execute(Land{}, 1s).ok());
    ASSERT_TRUE(wait_for([&] { return rig.major() == 2; }, 6s)) << "never landed";

    // Video: decoded frames at the display size, in order, without errors.
    auto frame = rig.link->video().latest();
    ASSERT_TRUE(frame);
    EXPECT_EQ(frame->image.cols, 640);
    EXPECT_EQ(frame->image.rows, 360);
    const auto st = rig.link->status();
    EXPECT_GT(st.video.decoded, 100u);
    EXPECT_EQ(st.video.decode_errors, 0u);
    EXPECT_EQ(st.video.resyncs, 0u);
    EXPECT_EQ(st.navdata.checksum_failures, 0u);
    EXPECT_EQ(st.machine.out_of_order, 0u);
    EXPECT_GT(st.at.counters.cycles, 200u);
}

TEST(LinkIntegration, WritesAreVerifiedAndIgnoredKeysReported) {
    Rig rig(100.0, false);
    ASSERT_TRUE(wait_for([&] { return rig.connected(); }, 5s));
    auto ok = rig.link->execute(SetConfig{"control:altitude_max", "2500", true}, 5s);
    EXPECT_EQ(ok.code, ResultCode::Sent) << ok.reason;
    auto ignored = rig.link->execute(SetConfig{"video:no_such_key", "1", true}, 5s);
    EXPECT_EQ(ignored.code, ResultCode::Rejected);
    EXPECT_NE(ignored.reason.find("no key video:no_such_key"), std::string::npos) << ignored.reason;
    auto cam = rig.link->execute(SwitchCamera{1}, 5s);
    EXPECT_EQ(cam.code, ResultCode::Sent) << cam.reason;
    auto bad = rig.link->execute(SetConfig{"general:ardrone_name", "a\"b", true}, 1s);
    EXPECT_EQ(bad.code, ResultCode::Rejected);
    auto cfg = rig.link->config().latest();
    ASSERT_TRUE(cfg);
    EXPECT_EQ(cfg->get("video:video_channel"), "1");
}

TEST(LinkIntegration, TakeOffIsRefusedBelowTwentyPercentBattery) {
    Rig rig(15.0, false);
    ASSERT_TRUE(wait_for([&] { return rig.connected(); }, 5s));
    ASSERT_TRUE(wait_for([&] { return rig.link->navdata().latest().has_value(); }, 2s));
    auto r = rig.link->execute(Takeoff{}, 1s);
    EXPECT_EQ(r.code, ResultCode::Rejected);
    EXPECT_NE(r.reason.find("battery 15 %"), std::string::npos) << r.reason;
}

TEST(LinkIntegration, ThirtyPercentNavdataLossKeepsTheLinkConnectedAndCountsGaps) {
    Rig rig(100.0, false);
    ASSERT_TRUE(wait_for([&] { return rig.connected(); }, 5s));
    sim::NavdataFaults f;
    f.loss = 0.3;
    rig.drone->inject(sim::FaultNavdata{f});
    bool always_connected = true;
    const auto t0 = std::chrono::steady_clock::now();
    while (std::chrono::steady_clock::now() - t0 < 4s) {
        always_connected &= rig.connected();
        std::this_thread::sleep_for(10ms);
    }
    EXPECT_TRUE(always_connected);
    // Stop the loss and let a few packets through so the last gap is closed, then compare.
    rig.drone->inject(sim::FaultNavdata{});
    std::this_thread::sleep_for(400ms);
    const auto gaps = rig.link->status().machine.sequence_gaps;
    const auto dropped = rig.drone->status().counters.navdata_dropped;
    EXPECT_GT(dropped, 10u);
    EXPECT_EQ(gaps, dropped);  // every packet the drone did not send is counted as a gap
}

TEST(LinkIntegration, ABlackoutIsLinkLostWithinHalfASecondAndRecoveredWithinOne) {
    Rig rig(100.0, false);
    ASSERT_TRUE(wait_for([&] { return rig.connected(); }, 5s));
    rig.drone->inject(sim::FaultBlackout{1000});
    auto lost = wait_for([&] { return rig.link->state() == ConnectionState::LinkLost; }, 2s);
    ASSERT_TRUE(lost);
    // 500 ms of silence plus at most one demo period (65 ms) and polling slack.
    EXPECT_LE(lost->count(), 500 + 65 + 100);
    EXPECT_GE(lost->count(), 400);
    // Navdata returns 1000 ms after the blackout started.
    auto back = wait_for([&] { return rig.connected(); }, 2s);
    ASSERT_TRUE(back);
    EXPECT_LE(lost->count() + back->count(), 1000 + 1000);
    EXPECT_EQ(rig.link->status().machine.link_losses, 1u);
}

TEST(LinkIntegration, AVideoResetMidFrameReconnectsAndResumesAtTheNextIdr) {
    Rig rig;
    ASSERT_TRUE(wait_for([&] { return rig.connected(); }, 5s));
    ASSERT_TRUE(wait_for([&] { return rig.link->status().video.decoded > 30; }, 5s));
    rig.drone->inject(sim::FaultVideoReset{});
    ASSERT_TRUE(wait_for([&] { return rig.link->status().video.disconnects >= 1; }, 3s));
    const auto before = rig.link->status().video.decoded;
    ASSERT_TRUE(wait_for([&] { return rig.link->status().video.decoded > before + 30; }, 5s));
    const auto st = rig.link->status();
    EXPECT_GE(st.video.connects, 2u);
    EXPECT_EQ(rig.drone->status().video_resets, 1u);
    EXPECT_EQ(st.video.decode_errors, 0u);
}

TEST(LinkIntegration, ADroneRebootMidFlightIsRecovered) {
    Rig rig(100.0, false);
    ASSERT_TRUE(wait_for([&] { return rig.connected(); }, 5s));
    ASSERT_TRUE(rig.link->execute(Takeoff{}, 1s).ok());
    ASSERT_TRUE(wait_for([&] { return rig.major() == 4; }, 6s));
    rig.drone->inject(sim::FaultReboot{});
    ASSERT_TRUE(wait_for([&] { return !rig.connected(); }, 2s));
    ASSERT_TRUE(wait_for([&] { return rig.connected(); }, 5s)) << rig.link->status().reason;
    EXPECT_EQ(rig.drone->status().counters.reboots, 1u);
    EXPECT_EQ(rig.drone->status().counters.configs, 2u);  // configured again after the reboot
    auto nav = rig.link->navdata().latest();
    ASSERT_TRUE(nav);
    EXPECT_LT(nav->seq, 200u);  // the new sequence is accepted
}

TEST(LinkIntegration, PacketsFromAnyOtherAddressAreDroppedAndCounted) {
    Rig rig(100.0, false);
    ASSERT_TRUE(wait_for([&] { return rig.connected(); }, 5s));
    auto intruder = net::UdpSocket::bind(net::Endpoint::loopback(0));
    ASSERT_TRUE(intruder);
    auto to = net::Endpoint::loopback(rig.link->navdata_local_port());
    for (int i = 0; i < 5; ++i) ASSERT_TRUE(intruder->send_to("spoofed navdata", to));
    ASSERT_TRUE(wait_for([&] { return rig.link->status().navdata.foreign_dropped == 5; }, 2s));
    EXPECT_TRUE(rig.connected());
}
