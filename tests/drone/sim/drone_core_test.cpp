#include "drone/sim/drone_core.hpp"
#include "drone/protocol/at.hpp"
#include "drone/protocol/navdata.hpp"

#include "support/state_bits.hpp"

#include <gtest/gtest.h>

#include <functional>

using namespace gs;
using namespace gs::sim;

namespace {
using namespace gs::test;

transport::Endpoint client(std::uint16_t port = 40000) {
    return *transport::Endpoint::parse("127.0.0.1:" + std::to_string(port));
}

std::span<const std::uint8_t> bytes(const std::string& s) {
    return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

// A scripted ground station: keeps the AT stream alive every 30 ms and collects navdata.
struct Station {
    DroneCore core;
    TimeNs now = ms_to_ns(1000);
    at::SeqCounter seq;
    bool fly = false, emergency = false;
    at::Pcmd pcmd;
    // Extra commands for the next datagram, numbered when sent (after REF and PCMD).
    std::vector<std::function<std::string(at::SeqCounter&)>> extra;
    std::vector<OutDatagram> out;
    std::vector<protocol::navdata::Navdata> received;
    bool keepalive = true;

    explicit Station(DroneCoreOptions o = {}) : core(std::move(o)) { core.advance(now, out); }

    void send_now() {
        std::string d = at::ref(seq.next(), at::ref_input(fly, emergency));
        d += pcmd.flags ? at::pcmd(seq.next(), pcmd.flags, pcmd.roll, pcmd.pitch,
                                             pcmd.gaz, pcmd.yaw)
                        : at::hover(seq.next());
        for (auto& e : extra) d += e(seq);
        extra.clear();
        core.on_at(bytes(d), client(), now);
    }
    void run(int ms) {
        for (int t = 0; t < ms; t += 5) {
            now += ms_to_ns(5);
            if (keepalive && (t % 30) == 0) send_now();
            out.clear();
            core.advance(now, out);
            for (auto& d : out) {
                EXPECT_EQ(d.to, client());
                auto nd = protocol::navdata::parse_navdata(d.bytes);
                if (nd) received.push_back(std::move(*nd));
            }
        }
    }
    void config(const std::string& key, const std::string& value) {
        extra.push_back([](at::SeqCounter& sq) {
            return *at::config_ids(sq.next(), "00000000", "00000000", "00000000");
        });
        extra.push_back([key, value](at::SeqCounter& sq) {
            return *at::config(sq.next(), key, value);
        });
    }
    std::uint32_t last_state() const {
        if (received.empty()) {
            ADD_FAILURE() << "no navdata received";
            return 0;
        }
        return received.back().header.drone_state.raw;
    }
    void wake() { core.on_navdata_trigger(client(), now); }
    void configure_demo() {
        wake();
        config("general:navdata_demo", "TRUE");
        run(100);
        ASSERT_TRUE(last_state() & kAck);
        extra.push_back([](at::SeqCounter& sq) {
            return at::ctrl(sq.next(), at::CtrlMode::Ack);
        });
        run(100);
        ASSERT_FALSE(last_state() & kAck);
    }
};
}  // namespace

TEST(DroneCore, SendsNothingUntilWokenThenBootstrapPacketsToTheWakerAt15Hz) {
    Station s;
    s.run(500);
    EXPECT_TRUE(s.received.empty());
    s.wake();
    s.run(1000);
    ASSERT_GE(s.received.size(), 14u);
    ASSERT_LE(s.received.size(), 16u);
    for (const auto& nd : s.received) {
        EXPECT_TRUE(nd.header.drone_state.raw & kBootstrap);
        EXPECT_FALSE(nd.demo.has_value());
        EXPECT_EQ(nd.options.size(), 1u);  // only the checksum
    }
    EXPECT_EQ(s.received.front().header.sequence + s.received.size() - 1,
              s.received.back().header.sequence);
}

TEST(DroneCore, DemoConfigurationAcksThenSendsDemoNavdataMatchingTheFlight) {
    Station s;
    s.configure_demo();
    s.received.clear();
    s.run(1000);
    ASSERT_GE(s.received.size(), 14u);
    const auto& nd = s.received.back();
    EXPECT_TRUE(nd.header.drone_state.raw & kDemo);
    EXPECT_FALSE(nd.header.drone_state.raw & kBootstrap);
    ASSERT_TRUE(nd.demo);
    ASSERT_TRUE(nd.vision_detect);
    EXPECT_EQ(nd.demo->ctrl_state.major(), 2);  // landed
    EXPECT_EQ(nd.demo->vbat_flying_percentage, 100u);
    EXPECT_EQ(s.core.config().get("general:navdata_demo"), "TRUE");
}

TEST(DroneCore, FullModeSendsTheRequestedOptionsAt200Hz) {
    Station s;
    s.wake();
    s.config("general:navdata_demo", "FALSE");
    s.run(50);
    s.extra.push_back([](at::SeqCounter& sq) {
        return at::ctrl(sq.next(), at::CtrlMode::Ack);
    });
    s.config("general:navdata_options",
             std::to_string((1 << 0) | (1 << 1) | (1 << 10) | (1 << 19)));
    s.run(50);
    s.extra.push_back([](at::SeqCounter& sq) {
        return at::ctrl(sq.next(), at::CtrlMode::Ack);
    });
    s.run(50);
    s.received.clear();
    s.run(1000);
    EXPECT_NEAR(static_cast<double>(s.received.size()), 200.0, 2.0);
    const auto& nd = s.received.back();
    EXPECT_FALSE(nd.header.drone_state.raw & kDemo);
    EXPECT_TRUE(nd.demo && nd.time && nd.altitude && nd.video_stream);
    EXPECT_FALSE(nd.vision_detect.has_value());
    EXPECT_FALSE(nd.magneto.has_value());
}

TEST(DroneCore, TakesOffFliesForwardAndReportsItInNavdata) {
    Station s;
    s.configure_demo();
    s.fly = true;
    s.run(4000);
    ASSERT_TRUE(s.last_state() & kFly);
    EXPECT_EQ(s.received.back().demo->ctrl_state.major(), 4);  // hovering
    EXPECT_NEAR(s.received.back().demo->altitude_mm, 1000, 60);
    s.pcmd = {at::kPcmdProgressive, 0, -0.5f, 0, 0};
    s.run(3000);
    const auto& d = *s.received.back().demo;
    EXPECT_EQ(d.ctrl_state.major(), 3);     // flying
    EXPECT_NEAR(d.theta_mdeg, -6000, 200);  // half of 12 degrees, nose down
    EXPECT_GT(d.vx_mm_s, 500);
    EXPECT_GT(s.core.flight().x_m, 1.5);
    s.pcmd = {};
    s.fly = false;
    s.run(4000);
    EXPECT_EQ(s.received.back().demo->ctrl_state.major(), 2);
    EXPECT_FALSE(s.last_state() & kFly);
}

TEST(DroneCore, CommandsWithOldSequenceNumbersAreIgnoredUntilTheCounterResets) {
    Station s;
    s.configure_demo();
    s.keepalive = false;
    const transport::Endpoint c = client();
    s.core.on_at(bytes(at::ref(1000, at::ref_input(false, false))), c, s.now);
    s.core.on_at(bytes(at::ref(999, at::ref_input(true, false))), c,
                 s.now);  // stale: ignored
    s.run(10);
    EXPECT_FALSE(s.core.flight().user_start);
    EXPECT_EQ(s.core.counters().at_rejected_seq, 1u);
    s.core.on_at(bytes(at::ref(1, at::ref_input(true, false))), c,
                 s.now);  // 1 restarts
    s.run(10);
    EXPECT_TRUE(s.core.flight().user_start);
}

TEST(DroneCore, SilenceRaisesTheWatchdogBitUntilComwdg) {
    Station s;
    s.configure_demo();
    s.fly = true;
    s.run(4000);
    s.pcmd = {at::kPcmdProgressive, 0, -1.0f, 0, 0};
    s.run(500);
    s.keepalive = false;
    s.run(300);
    EXPECT_TRUE(s.last_state() & kComWdg);
    EXPECT_FALSE(s.last_state() & kComLost);  // 300 ms is not a lost link
    EXPECT_EQ(s.core.counters().watchdog_events, 1u);
    s.keepalive = true;
    s.run(1000);  // commands flow again and are obeyed; the bit stays until AT*COMWDG
    EXPECT_TRUE(s.last_state() & kComWdg);
    EXPECT_GT(s.core.flight().vx_body_mps(), 1.0);
    s.extra.push_back([](at::SeqCounter& sq) { return at::comwdg(sq.next()); });
    s.run(200);
    EXPECT_FALSE(s.last_state() & kComWdg);
}

TEST(DroneCore, TwoSecondsWithoutCommandsIsComLostHover) {
    Station s;
    s.configure_demo();
    s.fly = true;
    s.run(4000);
    s.keepalive = false;
    s.run(2200);
    EXPECT_TRUE(s.last_state() & kComLost);
    EXPECT_EQ(s.received.back().demo->ctrl_state.major(), 4);
    EXPECT_EQ(s.received.back().demo->ctrl_state.minor(), 8);  // LOST_COM
}

TEST(DroneCore, ConfigDumpOnRequestAndUnknownKeysAreAckedButIgnored) {
    Station s;
    s.configure_demo();
    s.config("control:altitude_max", "2500");
    s.config("video:no_such_key", "1");
    s.extra.push_back([](at::SeqCounter& sq) {
        return at::ctrl(sq.next(), at::CtrlMode::CfgGet);
    });
    s.run(60);
    auto dump = s.core.take_config_dump();
    ASSERT_TRUE(dump);
    EXPECT_EQ(dump->back(), '\0');
    auto parsed = protocol::parse_config_dump(*dump);
    ASSERT_TRUE(parsed);
    EXPECT_EQ(parsed->get("control:altitude_max"), "2500");
    EXPECT_EQ(parsed->get("general:navdata_demo"), "TRUE");
    EXPECT_FALSE(parsed->contains("video:no_such_key"));
    EXPECT_EQ(s.core.counters().configs_unknown, 1u);
    EXPECT_FALSE(s.core.take_config_dump());  // handed out once
}

TEST(DroneCore, EmergencyCutsTheMotorsAndShowsInTheState) {
    Station s;
    s.configure_demo();
    s.fly = true;
    s.run(4000);
    s.emergency = true;
    s.run(100);
    EXPECT_TRUE(s.last_state() & kEmergency);
    EXPECT_FALSE(s.core.flight().motors_on);
}

TEST(DroneCore, LowBatteryIsReportedAndTakeOffRefused) {
    DroneCoreOptions o;
    o.battery_pct = 15;
    Station s(o);
    s.configure_demo();
    s.fly = true;
    s.run(2000);
    EXPECT_TRUE(s.last_state() & kVbatLow);
    EXPECT_FALSE(s.last_state() & kFly);
}

TEST(DroneCore, FaultsAreSeededAndCounted) {
    auto run_with = [](NavdataFaults f, std::uint64_t seed) {
        DroneCoreOptions o;
        o.seed = seed;
        Station s(o);
        s.configure_demo();
        s.core.set_faults(f);
        s.received.clear();
        s.run(10000);
        return std::make_pair(s.received.size(), s.core.counters());
    };
    NavdataFaults loss;
    loss.loss = 0.3;
    auto [n1, c1] = run_with(loss, 7);
    auto [n2, c2] = run_with(loss, 7);
    EXPECT_EQ(n1, n2);  // same seed, same run
    const double sent_plus_lost = static_cast<double>(c1.navdata_sent + c1.navdata_dropped);
    EXPECT_NEAR(static_cast<double>(c1.navdata_dropped) / sent_plus_lost, 0.3, 0.06);

    NavdataFaults corrupt;
    corrupt.corrupt_checksum = 1.0;
    auto [n3, c3] = run_with(corrupt, 1);
    EXPECT_EQ(n3, 0u);  // every packet fails its checksum
    EXPECT_GT(c3.navdata_corrupted, 100u);
}

TEST(DroneCore, ARebootStartsSequencesAgainInBootstrapAndForgetsTheClient) {
    Station s;
    s.configure_demo();
    s.core.reboot(s.now);
    s.received.clear();
    s.run(300);
    EXPECT_TRUE(s.received.empty());  // must be woken again
    s.wake();
    s.run(300);
    ASSERT_FALSE(s.received.empty());
    EXPECT_EQ(s.received.front().header.sequence, 1u);
    EXPECT_TRUE(s.last_state() & kBootstrap);
    EXPECT_EQ(s.core.config().get("general:navdata_demo"), "FALSE");
}

TEST(DroneCore, TheAutopilotFliesTheScriptedSegment) {
    DroneCoreOptions o;
    o.autopilot_enabled = true;
    o.autopilot = {
        {"takeoff", 0, 0, 0, 0, 0}, {"move", 7.0, 1.0, 0, 0, 0}, {"hover", 1.0, 0, 0, 0, 0}};
    Station s(o);
    s.keepalive = false;  // no ground station: the script flies on its own
    s.run(3500);
    EXPECT_TRUE(s.core.flight().flying());
    EXPECT_NEAR(s.core.flight().z_m, 1.0, 0.1);
    s.run(3000);
    EXPECT_EQ(s.core.flight().major, CtrlMajor::Flying);
    EXPECT_NEAR(s.core.flight().vx_body_mps(), 1.0, 0.05);
    s.run(6000);
    EXPECT_TRUE(s.core.autopilot_done());
    EXPECT_EQ(s.core.flight().major, CtrlMajor::Hovering);
    EXPECT_NEAR(s.core.flight().x_m, 7.0, 0.7);
    EXPECT_NEAR(s.core.flight().y_m, 0.0, 0.01);
}

namespace {
// Starts hovering at 1 m, hovers half a second, then flies forward at 1 m/s for ten seconds.
DroneCoreOptions scripted_flight() {
    DroneCoreOptions o;
    o.start.z_m = 1.0;
    o.autopilot_enabled = true;
    o.autopilot = {{"hover", 0.5, 0, 0, 0, 0}, {"move", 10.0, 1.0, 0, 0, 0}};
    return o;
}
}  // namespace

TEST(DroneCore, TheAutopilotIgnoresAClientThatOnlyKeepsTheLinkAlive) {
    // A ground station that adopted the flying state (REF take-off bit set, PCMD hover), and one
    // that never set the bit: neither asks for anything, so the script flies on.
    for (bool fly : {true, false}) {
        Station s(scripted_flight());
        s.configure_demo();
        s.fly = fly;
        s.run(3000);
        EXPECT_TRUE(s.core.autopilot_active()) << fly;
        EXPECT_EQ(s.core.counters().autopilot_yields, 0u);
        EXPECT_NEAR(s.core.flight().vx_body_mps(), 1.0, 0.1) << fly;
        EXPECT_NEAR(s.core.flight().z_m, 1.0, 0.05) << fly;
    }
}

TEST(DroneCore, AManualMoveMakesTheAutopilotYieldForGood) {
    Station s(scripted_flight());
    s.configure_demo();
    s.fly = true;
    s.run(2000);
    ASSERT_GT(s.core.flight().vx_body_mps(), 0.5);             // the script flies forward
    s.pcmd = {at::kPcmdProgressive, 0.5f, 0, 0, 0};  // the pilot banks right
    s.run(2000);
    EXPECT_FALSE(s.core.autopilot_active());
    EXPECT_EQ(s.core.autopilot_yield_reason(), "manual move");
    EXPECT_EQ(s.core.counters().autopilot_yields, 1u);
    EXPECT_GT(s.core.flight().vy_body_mps(), 0.5);  // the pilot's move, not the script's
    EXPECT_LT(s.core.flight().vx_body_mps(), 0.5);  // no longer driven: drag slows it
    // The pilot lets go: the drone hovers, the script does not come back.
    s.pcmd = {};
    s.run(3000);
    EXPECT_FALSE(s.core.autopilot_active());
    EXPECT_EQ(s.core.flight().major, CtrlMajor::Hovering);
    EXPECT_NEAR(s.core.flight().vx_body_mps(), 0.0, 0.1);
}

TEST(DroneCore, AFlightAnimationOrACalibrationMakesTheAutopilotYield) {
    // A client that only keeps the link alive (hover PCMD, take-off bit adopted) and LED
    // animations leave the script alone; a flight animation or a calibration is the pilot's.
    {
        Station s(scripted_flight());
        s.configure_demo();
        s.fly = true;
        s.run(1000);
        s.extra.push_back(
            [](at::SeqCounter& sq) { return at::led(sq.next(), 1, 2.0f, 1); });
        s.run(300);
        EXPECT_TRUE(s.core.autopilot_active());
        s.config("control:flight_anim", "8,2000");
        s.run(100);
        EXPECT_FALSE(s.core.autopilot_active());
        EXPECT_EQ(s.core.autopilot_yield_reason(), "animation");
        EXPECT_EQ(s.core.counters().anims, 1u);
        EXPECT_EQ(s.core.counters().autopilot_yields, 1u);
    }
    {
        Station s(scripted_flight());
        s.configure_demo();
        s.fly = true;
        s.run(1000);
        s.extra.push_back(
            [](at::SeqCounter& sq) { return at::anim(sq.next(), 3, 1000); });
        s.run(100);
        EXPECT_EQ(s.core.autopilot_yield_reason(), "animation");
    }
    {
        Station s(scripted_flight());
        s.configure_demo();
        s.fly = true;
        s.run(1000);
        s.extra.push_back(
            [](at::SeqCounter& sq) { return at::calib(sq.next()); });
        s.run(100);
        EXPECT_FALSE(s.core.autopilot_active());
        EXPECT_EQ(s.core.autopilot_yield_reason(), "calibration");
        EXPECT_EQ(s.core.counters().calibrations, 1u);
    }
}

TEST(DroneCore, TheTakeOffBitGoingFromSetToClearLandsTheAutopilotedDrone) {
    Station s(scripted_flight());
    s.configure_demo();
    s.fly = true;
    s.run(1000);
    s.fly = false;  // Land
    s.run(100);
    EXPECT_FALSE(s.core.autopilot_active());
    EXPECT_EQ(s.core.autopilot_yield_reason(), "land");
    s.run(3000);
    EXPECT_EQ(s.core.flight().major, CtrlMajor::Landed);
    EXPECT_FALSE(s.last_state() & kFly);
    s.run(2000);  // and it stays there
    EXPECT_EQ(s.core.flight().z_m, 0.0);
}

TEST(DroneCore, AnEmergencyEndsTheAutopilotAndTheResetLeavesTheDroneOnTheGround) {
    Station s(scripted_flight());
    s.configure_demo();
    s.run(1000);
    s.emergency = true;
    s.run(100);
    s.emergency = false;
    s.run(1000);  // fallen
    EXPECT_FALSE(s.core.autopilot_active());
    EXPECT_EQ(s.core.autopilot_yield_reason(), "emergency");
    EXPECT_TRUE(s.last_state() & kEmergency);
    s.emergency = true;  // reset
    s.run(100);
    s.emergency = false;
    s.run(2000);
    EXPECT_FALSE(s.last_state() & kEmergency);
    EXPECT_FALSE(s.last_state() & kFly);
    EXPECT_EQ(s.core.flight().z_m, 0.0);
}

TEST(DroneCore, ARebootEndsTheAutopilotAndTheDroneIsDeafWhileBooting) {
    Station s(scripted_flight());
    s.configure_demo();
    s.fly = true;
    s.run(1000);
    s.core.reboot(s.now, ms_to_ns(500));
    const auto at_before = s.core.counters().at_datagrams;
    s.run(400);  // the take-off bit keeps coming: nobody is listening yet
    EXPECT_GT(s.core.counters().at_while_booting, 10u);
    EXPECT_EQ(s.core.counters().at_datagrams, at_before);
    s.wake();  // ignored too
    s.fly = false;
    s.run(600);
    EXPECT_FALSE(s.core.navdata_client());
    EXPECT_FALSE(s.core.autopilot_active());
    EXPECT_FALSE(s.core.flight().flying());
    EXPECT_GT(s.core.counters().at_datagrams, at_before);  // booted: listening again
}
