// The ground station's link against the virtual drone over real loopback sockets (ephemeral
// ports): bootstrap, configuration, flight, video, and the faults a Wi-Fi link suffers.
#include "drone/dataset/align.hpp"
#include "drone/link/drone_link.hpp"
#include "drone/protocol/pave.hpp"
#include "drone/sim/loopback.hpp"
#include "drone/sim/scenarios.hpp"
#include "drone/sim/virtual_drone.hpp"
#include "drone/transport/net.hpp"
#include "support/wait.hpp"

#include "support/state_bits.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <map>
#include <regex>
#include <thread>

using namespace gs;
using namespace gs::protocol;
using namespace gs::link;
using namespace std::chrono_literals;

namespace {

using test::wait_until;

struct Rig {
    std::unique_ptr<sim::VirtualDrone> drone;
    std::unique_ptr<DroneLink> link;

    explicit Rig(double battery = 100.0, bool video = true, bool autopilot = false) {
        auto scene = sim::resolve_scene("thesis_pillar_center");
        EXPECT_TRUE(scene) << (scene ? "" : sim::to_string(scene.error()));
        sim::VirtualDroneOptions vo = sim::loopback_options(*scene);
        vo.video = video;
        vo.core.battery_pct = battery;
        vo.autopilot = autopilot;
        drone = std::make_unique<sim::VirtualDrone>(vo);
        auto s = drone->start();
        EXPECT_TRUE(s) << (s ? "" : s.error().message);
        LinkConfig lc = sim::link_config(*drone);
        lc.video = video;
        link = std::make_unique<DroneLink>(lc);
        auto l = link->start();
        EXPECT_TRUE(l) << (l ? "" : l.error().message);
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
    // The simulator's truth, not the link's view of it.
    bool drone_flying() const { return drone->status().flight.flying(); }
    std::uint32_t drone_bits() const { return drone->status().drone_state; }
    // Watches the drone while the link sends `cycles` more AT cycles (about 30 ms each, more on
    // a slow machine: the watch is counted in what the link did, not in time): true when it
    // never flew (motors, FLY bit or height).
    bool stays_on_the_ground(std::uint64_t cycles) const {
        const auto until = link->status().at.counters.cycles + cycles;
        bool ground = true;
        const bool done = wait_until(
                              [&] {
                                  const auto st = drone->status();
                                  ground &= !st.flight.flying() && !st.flight.motors_on &&
                                            st.flight.z_m == 0.0 && !(st.drone_state & test::kFly);
                                  return link->status().at.counters.cycles >= until;
                              },
                              30s)
                              .has_value();
        return ground && done;
    }
    // Waits until the link accepted `n` more navdata packets (so whatever the drone sent before
    // has been received and judged).
    bool accepts_more(std::uint64_t n) const {
        const auto until = link->status().navdata.accepted + n;
        return wait_until([&] { return link->status().navdata.accepted >= until; }, 10s)
            .has_value();
    }
};

}  // namespace

TEST(LinkIntegration, BootstrapsConfiguresTakesOffFliesForwardAndLands) {
    Rig rig;
    ASSERT_TRUE(wait_until([&] { return rig.connected(); }, 5s)) << rig.link->status().reason;
    // general:navdata_demo FALSE and general:navdata_options (full navdata, issue 17 item 5)
    EXPECT_EQ(rig.drone->status().counters.configs, 2u);
    EXPECT_TRUE(rig.link->status().machine.configs_sent >= 1);

    auto r = rig.link->execute(Takeoff{}, 1s);
    ASSERT_EQ(r.code, ResultCode::Sent) << r.reason;
    ASSERT_TRUE(wait_until([&] { return rig.major() == 4; }, 6s)) << "never hovering";
    const double x0 = rig.drone->ground_truth().pose.x_m;

    ASSERT_TRUE(rig.link->execute(Move{0, -0.5f, 0, 0}, 1s).ok());
    // Flying forward: 1.5 m covered (about 2 s at the virtual drone's speed).
    ASSERT_TRUE(wait_until([&] { return rig.drone->ground_truth().pose.x_m - x0 > 1.5; }, 20s));
    ASSERT_TRUE(wait_until(
        [&] {
            auto n = rig.link->navdata().latest();
            return n && n->state.vx_mps > 0.5;
        },
        5s));
    auto nav = rig.link->navdata().latest();
    ASSERT_TRUE(nav);
    EXPECT_EQ(nav->data.demo->ctrl_state.major(), 3);  // flying
    EXPECT_NEAR(nav->state.pitch_deg, -6.0, 1.0);
    // The link's telemetry and the simulator's truth agree.
    EXPECT_NEAR(nav->state.altitude_m, rig.drone->ground_truth().pose.z_m, 0.1);

    ASSERT_TRUE(rig.link->execute(Land{}, 1s).ok());
    ASSERT_TRUE(wait_until([&] { return rig.major() == 2; }, 6s)) << "never landed";

    // Video: decoded frames at the display size, in order, without errors.
    auto frame = rig.link->video().latest();
    ASSERT_TRUE(frame);
    EXPECT_EQ(frame->image.cols, 640);
    EXPECT_EQ(frame->image.rows, 360);
    // Every frame the drone sent was decoded (none missed, whatever the machine's speed; the
    // one in flight at the end aside), the stream start's P-frames aside.
    const auto st = rig.link->status();
    const auto sent = rig.drone->status().video_frames_sent;
    EXPECT_GT(st.video.decoded, 10u);
    EXPECT_GE(st.video.decoded + st.video.idr_waits + 2, sent);
    EXPECT_EQ(st.video.decode_errors, 0u);
    EXPECT_EQ(st.video.resyncs, 0u);
    EXPECT_EQ(st.navdata.checksum_failures, 0u);
    EXPECT_EQ(st.machine.out_of_order, 0u);
    EXPECT_GT(st.at.counters.cycles, 200u);
}

TEST(LinkIntegration, WritesAreVerifiedAndIgnoredKeysReported) {
    Rig rig(100.0, false);
    ASSERT_TRUE(wait_until([&] { return rig.connected(); }, 5s));
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
    ASSERT_TRUE(wait_until([&] { return rig.connected(); }, 5s));
    ASSERT_TRUE(wait_until([&] { return rig.link->navdata().latest().has_value(); }, 2s));
    auto r = rig.link->execute(Takeoff{}, 1s);
    EXPECT_EQ(r.code, ResultCode::Rejected);
    EXPECT_NE(r.reason.find("battery 15 %"), std::string::npos) << r.reason;
}

TEST(LinkIntegration, ThirtyPercentNavdataLossKeepsTheLinkConnectedAndCountsGaps) {
    Rig rig(100.0, false);
    ASSERT_TRUE(wait_until([&] { return rig.connected(); }, 5s));
    sim::NavdataFaults f;
    f.loss = 0.3;
    rig.drone->inject(sim::FaultNavdata{f});
    // Connected all the while the drone loses 200 packets (about 3 s of 200 Hz navdata).
    bool always_connected = true;
    ASSERT_TRUE(wait_until(
        [&] {
            always_connected &= rig.connected();
            return rig.drone->status().counters.navdata_dropped >= 200;
        },
        30s));
    EXPECT_TRUE(always_connected);
    // Stop the loss and let packets through so the last gap is closed, then compare.
    rig.drone->inject(sim::FaultNavdata{});
    ASSERT_TRUE(wait_until([&] { return rig.drone->status().counters.navdata_sent > 0; }, 1s));
    const auto sent = rig.drone->status().counters.navdata_sent;
    ASSERT_TRUE(
        wait_until([&] { return rig.drone->status().counters.navdata_sent > sent + 20; }, 5s));
    ASSERT_TRUE(rig.accepts_more(10));
    const auto gaps = rig.link->status().machine.sequence_gaps;
    const auto dropped = rig.drone->status().counters.navdata_dropped;
    EXPECT_GT(dropped, 10u);
    const auto m = rig.link->status().machine;
    // Every packet the drone did not send is counted as a gap, through watchdog events too.
    EXPECT_EQ(gaps, dropped) << "watchdog events " << m.com_watchdog_events << ", sequence resets "
                             << m.sequence_resets << ", link losses " << m.link_losses;
}

TEST(LinkIntegration, ABlackoutIsLinkLostWithinHalfASecondAndRecoveredWithinOne) {
    Rig rig(100.0, false);
    ASSERT_TRUE(wait_until([&] { return rig.connected(); }, 5s));
    rig.drone->inject(sim::FaultBlackout{1000});
    auto lost = wait_until([&] { return rig.link->state() == ConnectionState::LinkLost; }, 2s);
    ASSERT_TRUE(lost);
    // 500 ms of silence plus at most one demo period (65 ms) and polling slack.
    EXPECT_LE(lost->count(), 500 + 65 + 100);
    EXPECT_GE(lost->count(), 400);
    // Navdata returns 1000 ms after the blackout started.
    auto back = wait_until([&] { return rig.connected(); }, 2s);
    ASSERT_TRUE(back);
    EXPECT_LE(lost->count() + back->count(), 1000 + 1000);
    EXPECT_EQ(rig.link->status().machine.link_losses, 1u);
}

TEST(LinkIntegration, FramesCapturedInANavdataBlackoutHaveUnknownNavdataNotTheLastSample) {
    // Video goes on through a navdata blackout: those frames' attitude and velocity are unknown
    // (the classifier judges them from the images), never the last sample relabelled with a
    // time seconds later; frames after it have navdata again.
    Rig rig;
    ASSERT_TRUE(wait_until([&] { return rig.connected(); }, 5s));
    ASSERT_TRUE(wait_until([&] { return rig.link->status().video.decoded > 5; }, 20s));
    auto frames = rig.link->subscribe_frames(512);
    rig.drone->inject(sim::FaultBlackout{2000});
    ASSERT_TRUE(wait_until([&] { return rig.link->status().video.nav_missing >= 10; }, 10s));
    ASSERT_TRUE(wait_until([&] { return rig.connected(); }, 10s));
    const auto after = rig.link->status().video.decoded;
    ASSERT_TRUE(wait_until([&] { return rig.link->status().video.decoded > after + 10; }, 10s));
    rig.link->unsubscribe(frames.get());
    int unknown = 0, known_after = 0;
    bool seen_unknown = false;
    while (auto f = frames->try_pop()) {
        EXPECT_EQ(f->nav.t_ns, f->t_ns);
        if (std::isnan(f->nav.roll_deg)) {
            ++unknown;
            seen_unknown = true;
            EXPECT_TRUE(std::isnan(f->nav.vx_mps) && std::isnan(f->nav.altitude_m));
        } else if (seen_unknown) {
            ++known_after;
        }
    }
    EXPECT_GE(unknown, 10);
    EXPECT_GE(known_after, 5);
}

TEST(LinkIntegration, AVideoResetMidFrameReconnectsAndResumesAtTheNextIdr) {
    Rig rig;
    ASSERT_TRUE(wait_until([&] { return rig.connected(); }, 5s));
    ASSERT_TRUE(wait_until([&] { return rig.link->status().video.decoded > 5; }, 20s));
    const auto waits_before = rig.link->status().video.idr_waits;
    // Cut inside an IDR frame: the new connection starts with P-frames of the same GOP.
    rig.drone->inject(sim::FaultVideoReset{true});
    ASSERT_TRUE(wait_until([&] { return rig.link->status().video.disconnects >= 1; }, 10s));
    const auto before = rig.link->status().video.decoded;
    ASSERT_TRUE(wait_until([&] { return rig.link->status().video.decoded > before + 5; }, 30s));
    const auto st = rig.link->status();
    EXPECT_GE(st.video.connects, 2u);
    EXPECT_EQ(rig.drone->status().video_resets, 1u);
    EXPECT_EQ(st.video.decode_errors, 0u);
    // The decoder skipped the P-frames it had no reference for, then resumed at the IDR.
    EXPECT_GT(st.video.idr_waits, waits_before);
}

TEST(LinkIntegration, VideoFramesCarryThePaveFrameNumberAndTimestampTheDroneSent) {
    Rig rig;
    auto raw = rig.link->subscribe_raw(4096);
    auto frames = rig.link->subscribe_frames(256);
    auto units = rig.link->subscribe_access_units(256);
    ASSERT_TRUE(wait_until([&] { return rig.link->status().video.decoded > 20; }, 8s));
    rig.link->unsubscribe(raw.get());
    rig.link->unsubscribe(frames.get());
    rig.link->unsubscribe(units.get());
    // What went over the wire, cut into frames by an independent framer.
    PaveFramer framer;
    std::map<std::uint32_t, std::uint32_t> sent_ms;  // frame_number -> PaVE timestamp
    while (auto e = raw->try_pop()) {
        if (e->kind != RawEvent::Kind::Video) continue;
        framer.push(e->bytes);
        while (auto ev = framer.next()) {
            if (auto* f = std::get_if<PaveFrame>(&*ev)) {
                sent_ms[f->header.frame_number] = f->header.timestamp;
            }
        }
    }
    ASSERT_GT(sent_ms.size(), 20u);
    int checked = 0;
    std::optional<std::uint32_t> prev_ms;
    while (auto fs = frames->try_pop()) {
        ASSERT_TRUE(fs->frame_number);
        ASSERT_TRUE(fs->pave_timestamp_ms);
        auto it = sent_ms.find(*fs->frame_number);
        if (it == sent_ms.end()) continue;  // its bytes came before the raw subscription
        EXPECT_EQ(*fs->pave_timestamp_ms, it->second) << "frame " << *fs->frame_number;
        if (prev_ms) {
            EXPECT_GT(*fs->pave_timestamp_ms, *prev_ms);
        }
        prev_ms = fs->pave_timestamp_ms;
        ++checked;
    }
    EXPECT_GT(checked, 15);
    int units_checked = 0;
    while (auto au = units->try_pop()) {
        auto it = sent_ms.find(au->frame_number);
        if (it == sent_ms.end()) continue;
        ASSERT_TRUE(au->pave_timestamp_ms);
        EXPECT_EQ(*au->pave_timestamp_ms, it->second);
        ++units_checked;
    }
    EXPECT_GT(units_checked, 15);
}

namespace {
// A navdata and AT link (no video, no control) to a loopback socket that never answers.
LinkConfig unanswered_link(const transport::UdpSocket& quiet) {
    LinkConfig lc;
    lc.drone_address = "127.0.0.1";
    lc.bind_address = "127.0.0.1";
    lc.at_port = lc.navdata_port = quiet.local_endpoint()->port;
    lc.video = false;
    lc.control = false;
    return lc;
}
}  // namespace

TEST(LinkIntegration, AStartedLinkSaysBootstrappingFromTheMomentStartReturns) {
    // Nobody answers on these ports: the link must say it is connecting (bootstrapping) from the
    // first status read after start(), never "Disconnected" before its AT thread has run (the
    // window showed NO SOURCE for a frame while connecting, a CI failure of CockpitLive).
    auto quiet = transport::UdpSocket::bind(transport::Endpoint::loopback(0));
    ASSERT_TRUE(quiet);
    DroneLink link(unanswered_link(*quiet));
    EXPECT_EQ(link.status().state, ConnectionState::Disconnected);
    ASSERT_TRUE(link.start());
    EXPECT_EQ(link.state(), ConnectionState::Bootstrapping);
    const LinkStatus st = link.status();
    EXPECT_EQ(st.state, ConnectionState::Bootstrapping) << st.reason;
    EXPECT_NE(st.reason.find("waking navdata up"), std::string::npos) << st.reason;
    link.stop();
    EXPECT_EQ(link.state(), ConnectionState::Disconnected);
}

TEST(LinkIntegration, TheAtStreamsAgeIsTheTimeSinceItsLastCycle) {
    // The window's link health shows each stream's age; for AT it showed the last gap between two
    // cycles, which a stalled sender keeps for ever ("30 ms" with nothing sent). It is the time
    // since the last cycle: unknown before the first, small while the sender runs, growing once
    // it has stopped.
    auto quiet = transport::UdpSocket::bind(transport::Endpoint::loopback(0));
    ASSERT_TRUE(quiet);
    DroneLink link(unanswered_link(*quiet));
    EXPECT_EQ(link.status().at.last_cycle_ns, 0);
    ASSERT_TRUE(link.start());
    ASSERT_TRUE(wait_until([&] { return link.status().at.counters.datagrams >= 5; }, 10s));
    LinkStatus st = link.status();
    ASSERT_GT(st.at.last_cycle_ns, 0);
    EXPECT_LE(st.at.last_cycle_ns, st.now_ns);
    link.stop();
    const TimeNs last = link.status().at.last_cycle_ns;
    ASSERT_TRUE(wait_until([&] { return link.status().now_ns - last > 200'000'000; }, 10s));
    st = link.status();
    EXPECT_EQ(st.at.last_cycle_ns, last);  // nothing sent since: the age grows
    EXPECT_GT(st.now_ns - st.at.last_cycle_ns, 200'000'000);
}

TEST(LinkIntegration, PaveFramesInAnotherCodecAreCountedNotDecoded) {
    // A crafted stream on a loopback video port: MPEG-4 frames (what 5555 carries in the record
    // codec modes, docs/protocol.md §4.5) between two ends of nothing else.
    auto listener = transport::TcpListener::listen(transport::Endpoint::loopback(0));
    ASSERT_TRUE(listener);
    auto quiet = transport::UdpSocket::bind(transport::Endpoint::loopback(0));  // a navdata/AT sink
    ASSERT_TRUE(quiet);
    LinkConfig lc;
    lc.drone_address = "127.0.0.1";
    lc.bind_address = "127.0.0.1";
    lc.at_port = lc.navdata_port = quiet->local_endpoint()->port;
    lc.video_port = listener->local_endpoint()->port;
    lc.control = false;
    DroneLink link(lc);
    ASSERT_TRUE(link.start());
    auto client = listener->accept(transport::Millis{2000});
    ASSERT_TRUE(client);
    std::vector<std::uint8_t> stream;
    for (std::uint32_t n = 1; n <= 5; ++n) {
        PaveHeader h;
        h.video_codec = n == 3 ? PaveCodec::Vlib : PaveCodec::Mpeg4Visual;
        h.payload_size = 100;
        h.display_width = 640;
        h.display_height = 360;
        h.frame_number = n;
        h.timestamp = 33 * n;
        h.frame_type = PaveFrameType::P;
        const std::size_t at = stream.size();
        stream.resize(at + h.header_size + h.payload_size, 0x55);
        ASSERT_TRUE(write_pave_header(h, std::span<std::uint8_t>(stream).subspan(at)));
    }
    ASSERT_TRUE(client->write_all(std::span<const std::uint8_t>(stream), transport::Millis{1000}));
    ASSERT_TRUE(wait_until([&] { return link.status().video.unsupported_codec_frames == 5; }, 2s))
        << link.status().video.unsupported_codec_frames;
    const auto st = link.status().video;
    EXPECT_EQ(st.pave_frames, 5u);
    EXPECT_EQ(st.decoded, 0u);
    EXPECT_EQ(st.decode_errors, 0u);
    EXPECT_NE(st.last_error.find("frame 5"), std::string::npos) << st.last_error;
    link.stop();
}

TEST(LinkIntegration, ADroneRebootMidFlightIsRecoveredAndTheDroneStaysOnTheGround) {
    Rig rig(100.0, false);
    ASSERT_TRUE(wait_until([&] { return rig.connected(); }, 5s));
    ASSERT_TRUE(rig.link->execute(Takeoff{}, 1s).ok());
    ASSERT_TRUE(wait_until([&] { return rig.drone->ground_truth().pose.z_m > 0.5; }, 6s));
    rig.drone->inject(sim::FaultReboot{1000});
    ASSERT_TRUE(wait_until([&] { return !rig.connected(); }, 2s));
    // Until the link noticed, its take-off bit went to a drone still booting (deaf); then the
    // link sends hover alone (no REF) until navdata returns and shows the restart.
    bool flew = false;
    ASSERT_TRUE(wait_until(
        [&] {
            flew |= rig.drone_flying();
            return rig.connected();
        },
        5s))
        << rig.link->status().reason;
    EXPECT_FALSE(flew);
    EXPECT_EQ(rig.drone->status().counters.reboots, 1u);
    EXPECT_EQ(rig.drone->status().counters.configs, 4u);  // configured again after the reboot
    auto nav = rig.link->navdata().latest();
    ASSERT_TRUE(nav);
    EXPECT_LT(nav->seq, 200u);  // the new sequence is accepted
    // No stale take-off: the pilot has to press Take off again.
    EXPECT_TRUE(rig.stays_on_the_ground(50));
    const auto st = rig.link->status();
    EXPECT_EQ(st.at.intent, FlyIntent::Land);
    EXPECT_EQ(st.machine.drone_restarts, 1u);
    ASSERT_TRUE(rig.link->execute(Takeoff{}, 1s).ok());
    EXPECT_TRUE(wait_until([&] { return rig.drone_flying(); }, 2s));
}

TEST(LinkIntegration, CuttingTheMotorsThenResettingTheEmergencyDoesNotTakeOffAgain) {
    Rig rig(100.0, false);
    ASSERT_TRUE(wait_until([&] { return rig.connected(); }, 5s));
    ASSERT_TRUE(rig.link->execute(Takeoff{}, 1s).ok());
    ASSERT_TRUE(wait_until([&] { return rig.drone->ground_truth().pose.z_m > 0.3; }, 4s));
    ASSERT_TRUE(rig.link->execute(Emergency{}, 1s).ok());  // cut the motors
    ASSERT_TRUE(wait_until([&] { return (rig.drone_bits() & test::kEmergency) != 0; }, 2s));
    ASSERT_TRUE(wait_until([&] { return rig.drone->ground_truth().pose.z_m == 0.0; }, 2s));
    // The link must see the emergency before it can ask to leave it.
    ASSERT_TRUE(wait_until(
        [&] {
            auto n = rig.link->navdata().latest();
            return n && (n->data.header.drone_state.raw & test::kEmergency);
        },
        1s));
    ASSERT_TRUE(rig.link->execute(Emergency{}, 1s).ok());  // reset it
    ASSERT_TRUE(wait_until([&] { return (rig.drone_bits() & test::kEmergency) == 0; }, 2s));
    EXPECT_TRUE(rig.stays_on_the_ground(50));
    EXPECT_EQ(rig.link->status().at.intent, FlyIntent::Land);
}

TEST(LinkIntegration, TheLinkAdoptsAnAutopilotedFlightAndLandLandsIt) {
    Rig rig(100.0, false, true);
    ASSERT_TRUE(wait_until([&] { return rig.connected(); }, 5s));
    // Connected to a drone already flying: it keeps flying (REF carries the take-off bit).
    ASSERT_TRUE(wait_until([&] { return rig.link->status().at.intent == FlyIntent::Fly; }, 1s));
    EXPECT_EQ(rig.link->status().at.counters.flying_adopted, 1u);
    // The autopilot climbs to its 1 m and holds it.
    ASSERT_TRUE(
        wait_until([&] { return std::abs(rig.drone->status().flight.z_m - 1.0) < 0.1; }, 10s));
    auto st = rig.drone->status();
    EXPECT_TRUE(st.autopilot_active);
    EXPECT_TRUE(st.flight.flying());
    EXPECT_NEAR(st.flight.z_m, 1.0, 0.1);
    // The pilot wins: Land clears the take-off bit and the autopilot yields.
    ASSERT_TRUE(rig.link->execute(Land{}, 1s).ok());
    ASSERT_TRUE(wait_until([&] { return rig.major() == 2; }, 5s)) << "never landed";
    // Landed is reported as the drone touches down (200 Hz navdata sees it within 5 ms).
    ASSERT_TRUE(wait_until([&] { return rig.drone->status().flight.z_m == 0.0; }, 2s));
    st = rig.drone->status();
    EXPECT_FALSE(st.autopilot_active);
    EXPECT_EQ(st.counters.autopilot_yields, 1u);
}

TEST(LinkIntegration, FlightAnimationsGoAsConfigAndLedAnimationsAsAtLed) {
    // docs/protocol.md §2.4/§2.9: firmware 2 takes flight animations as CONFIG control:flight_anim
    // (SDK 2.0 no longer sends AT*ANIM); AT*LED is what SDK 2.0 still emits for the LEDs.
    Rig rig(100.0, false);
    ASSERT_TRUE(wait_until([&] { return rig.connected(); }, 5s));
    auto raw = rig.link->subscribe_raw(4096);
    auto r = rig.link->execute(Anim{8, 2000}, 3s);
    EXPECT_EQ(r.code, ResultCode::Sent) << r.reason;  // after the drone's ACK
    auto led = rig.link->execute(Led{1, 3.0f, 3}, 1s);
    EXPECT_EQ(led.code, ResultCode::Sent) << led.reason;
    ASSERT_TRUE(wait_until([&] { return rig.drone->status().counters.leds == 1; }, 1s));
    EXPECT_EQ(rig.drone->status().counters.anims, 1u);
    auto bad = rig.link->execute(Anim{20, 1000}, 1s);
    EXPECT_EQ(bad.code, ResultCode::Rejected);
    EXPECT_NE(bad.reason.find("0..19"), std::string::npos) << bad.reason;
    EXPECT_EQ(rig.link->execute(Anim{3, 0}, 1s).code, ResultCode::Rejected);
    rig.link->unsubscribe(raw.get());

    // The datagrams as they went out: CONFIG_IDS immediately before the CONFIG, in one
    // datagram, with consecutive sequence numbers; the LED with the float sent as its bits.
    const std::regex anim_re(
        "AT\\*CONFIG_IDS=(\\d+),\"[0-9a-f]{8}\",\"[0-9a-f]{8}\",\"[0-9a-f]{8}\"\r"
        "AT\\*CONFIG=(\\d+),\"control:flight_anim\",\"8,2000\"\r");
    const std::regex led_re("AT\\*LED=\\d+,1,1077936128,3\r");
    int anims = 0, leds = 0, old_style = 0;
    while (auto e = raw->try_pop()) {
        if (e->kind != RawEvent::Kind::At) continue;
        const std::string text(e->bytes.begin(), e->bytes.end());
        std::smatch m;
        if (std::regex_search(text, m, anim_re)) {
            ++anims;
            EXPECT_EQ(std::stoul(m[2].str()), std::stoul(m[1].str()) + 1) << text;
        }
        if (std::regex_search(text, led_re)) ++leds;
        if (text.find("AT*ANIM=") != std::string::npos) ++old_style;
    }
    EXPECT_GE(anims, 1);  // resent only if the ACK did not come
    EXPECT_EQ(leds, 1);   // a one-shot: exactly once
    EXPECT_EQ(old_style, 0);
    auto cfg = rig.link->execute(SetConfig{"control:flight_anim", "8,2000", true}, 3s);
    EXPECT_EQ(cfg.code, ResultCode::Sent) << cfg.reason;  // the drone holds "8,2000"
}

TEST(LinkIntegration, CorruptChecksumsAreCountedAndDropped) {
    Rig rig(100.0, false);
    ASSERT_TRUE(wait_until([&] { return rig.connected(); }, 5s));
    const auto before = rig.link->status();
    sim::NavdataFaults f;
    f.corrupt_checksum = 0.4;
    rig.drone->inject(sim::FaultNavdata{f});
    ASSERT_TRUE(
        wait_until([&] { return rig.drone->status().counters.navdata_corrupted >= 4; }, 3s));
    rig.drone->inject(sim::FaultNavdata{});
    ASSERT_TRUE(rig.accepts_more(20));  // whatever was faulty has come and been judged
    const auto corrupted = rig.drone->status().counters.navdata_corrupted;
    const auto st = rig.link->status();
    EXPECT_EQ(st.navdata.checksum_failures, corrupted);  // every one, and only those
    // Each dropped packet leaves a hole in the sequence the next good one shows; nothing else.
    EXPECT_EQ(st.machine.sequence_gaps - before.machine.sequence_gaps, corrupted);
    EXPECT_EQ(st.machine.out_of_order, before.machine.out_of_order);
    EXPECT_EQ(st.navdata.foreign_dropped, 0u);
    EXPECT_EQ(st.navdata.parse_errors, 0u);
    EXPECT_NE(st.navdata.last_error.find("checksum"), std::string::npos) << st.navdata.last_error;
    EXPECT_TRUE(rig.connected());
}

TEST(LinkIntegration, ReorderedAndDuplicatedNavdataIsDroppedAsOutOfOrder) {
    Rig rig(100.0, false);
    ASSERT_TRUE(wait_until([&] { return rig.connected(); }, 5s));
    const auto gaps_before = rig.link->status().machine.sequence_gaps;
    sim::NavdataFaults f;
    f.reorder = 0.3;
    f.duplicate = 0.3;
    rig.drone->inject(sim::FaultNavdata{f});
    ASSERT_TRUE(wait_until(
        [&] {
            const auto c = rig.drone->status().counters;
            return c.navdata_reordered >= 3 && c.navdata_duplicated >= 3;
        },
        3s));
    rig.drone->inject(sim::FaultNavdata{});
    ASSERT_TRUE(rig.accepts_more(20));  // whatever was faulty has come and been judged
    const auto c = rig.drone->status().counters;
    const auto st = rig.link->status();
    // A held-back packet arrives after a newer one, a duplicate after itself: both are dropped.
    EXPECT_EQ(st.machine.out_of_order, c.navdata_reordered + c.navdata_duplicated);
    // A held-back packet is first seen as a one-packet gap by its successor.
    EXPECT_EQ(st.machine.sequence_gaps - gaps_before, c.navdata_reordered);
    EXPECT_EQ(c.navdata_dropped, 0u);
    EXPECT_EQ(st.navdata.checksum_failures, 0u);
    EXPECT_EQ(st.navdata.foreign_dropped, 0u);
    EXPECT_TRUE(rig.connected());
}

TEST(LinkIntegration, PacketsFromAnyOtherAddressAreDroppedAndCounted) {
    Rig rig(100.0, false);
    ASSERT_TRUE(wait_until([&] { return rig.connected(); }, 5s));
    auto intruder = transport::UdpSocket::bind(transport::Endpoint::loopback(0));
    ASSERT_TRUE(intruder);
    auto to = transport::Endpoint::loopback(rig.link->navdata_local_port());
    for (int i = 0; i < 5; ++i) ASSERT_TRUE(intruder->send_to("spoofed navdata", to));
    ASSERT_TRUE(wait_until([&] { return rig.link->status().navdata.foreign_dropped == 5; }, 2s));
    ASSERT_TRUE(rig.accepts_more(20));  // and the drone's packets after them: none dropped
    const auto st = rig.link->status();
    EXPECT_EQ(st.navdata.foreign_dropped, 5u);  // those five, and the drone's packets none
    EXPECT_EQ(st.navdata.checksum_failures, 0u);
    EXPECT_EQ(st.navdata.parse_errors, 0u);
    EXPECT_EQ(st.machine.out_of_order, 0u);
    EXPECT_EQ(st.machine.sequence_gaps, 0u);
    EXPECT_TRUE(rig.connected());
}

TEST(LinkIntegration, DatagramsSentToTheAtSocketAreDrainedCountedAndDropped) {
    // Issue 14 point 10: the drone never writes to the AT socket; before, whatever did piled up
    // in the kernel buffer (125 KB after 40 datagrams).
    Rig rig(100.0, false);
    ASSERT_TRUE(wait_until([&] { return rig.connected(); }, 5s));
    auto intruder = transport::UdpSocket::bind(transport::Endpoint::loopback(0));
    ASSERT_TRUE(intruder);
    ASSERT_NE(rig.link->at_local_port(), 0);
    const auto to = transport::Endpoint::loopback(rig.link->at_local_port());
    const std::string junk(1000, 'x');
    for (int i = 0; i < 40; ++i) ASSERT_TRUE(intruder->send_to(junk, to));
    ASSERT_TRUE(wait_until([&] { return rig.link->status().at.foreign_datagrams == 40; }, 3s))
        << rig.link->status().at.foreign_datagrams;
    const auto st = rig.link->status();
    EXPECT_EQ(st.at.foreign_bytes, 40u * 1000u);
    EXPECT_EQ(st.at.send_errors, 0u);
    EXPECT_TRUE(rig.connected());
}

TEST(LinkIntegration, ARebootCutsVideoRefusesItWhileBootingAndVideoComesBackAfter) {
    // Issue 14 point 11: a real drone's video and configuration connections die with it and its
    // ports refuse connections until it is back up; the link must recover video by itself.
    Rig rig;
    ASSERT_TRUE(wait_until([&] { return rig.connected(); }, 5s));
    ASSERT_TRUE(wait_until([&] { return rig.link->status().video.decoded > 5; }, 5s));
    ASSERT_TRUE(wait_until([&] { return rig.link->status().control_connected; }, 5s));
    const auto disconnects = rig.link->status().video.disconnects;
    rig.drone->inject(sim::FaultReboot{2000});
    ASSERT_TRUE(wait_until([&] { return rig.link->status().video.disconnects > disconnects; }, 2s))
        << "the reboot did not cut the video connection";
    ASSERT_TRUE(wait_until([&] { return rig.drone->status().reboot_closes >= 2; }, 2s))
        << "video and control connections: " << rig.drone->status().reboot_closes;
    // Early in the 2 s boot: both ports refuse a connection.
    ASSERT_TRUE(rig.drone->status().booting);
    auto video = transport::TcpStream::connect(
        transport::Endpoint::loopback(rig.drone->video_port()), transport::Millis{300});
    EXPECT_FALSE(video) << "video port accepted a connection while the drone boots";
    auto control = transport::TcpStream::connect(
        transport::Endpoint::loopback(rig.drone->control_port()), transport::Millis{300});
    EXPECT_FALSE(control) << "control port accepted a connection while the drone boots";
    EXPECT_TRUE(rig.drone->status().booting);
    // Once up, the link reconnects and decodes again (from the next IDR).
    const auto decoded = rig.link->status().video.decoded;
    ASSERT_TRUE(wait_until([&] { return rig.link->status().video.decoded > decoded + 10; }, 8s))
        << rig.link->status().video.last_error;
    EXPECT_TRUE(wait_until([&] { return rig.link->status().control_connected; }, 3s));
    EXPECT_FALSE(rig.drone->status().booting);
    EXPECT_GE(rig.link->status().video.connects, 2u);
}

TEST(LinkIntegration, NavdataRunsAtTwoHundredHertzAndFramesCarryTheAttitudeAtTheirCapture) {
    // Issue 17 item 5 / issue 15 item 3: full navdata by default, and every live frame's state
    // is the accepted navdata interpolated at the frame's capture time, as a recording does
    // (drone/core/nav_timeline.hpp), not the newest sample relabelled.
    Rig rig;
    auto navs = rig.link->subscribe_navdata(4096);
    auto frames = rig.link->subscribe_frames(256);
    ASSERT_TRUE(wait_until([&] { return rig.connected(); }, 5s));
    ASSERT_TRUE(rig.link->execute(Takeoff{}, 1s).ok());  // attitude that changes
    ASSERT_TRUE(wait_until([&] { return rig.link->status().video.decoded > 60; }, 30s));
    ASSERT_TRUE(wait_until([&] { return rig.link->status().navdata.rate_hz > 150; }, 3s))
        << rig.link->status().navdata.rate_hz << " Hz";
    EXPECT_FALSE(rig.drone_bits() & test::kDemo) << "the drone stayed in demo mode";
    rig.link->unsubscribe(navs.get());
    rig.link->unsubscribe(frames.get());
    NavTimeline accepted(1 << 14);
    std::vector<link::NavSample> samples;
    while (auto n = navs->try_pop()) {
        accepted.push(n->state);
        samples.push_back(*n);
    }
    int checked = 0;
    while (auto f = frames->try_pop()) {
        // Only frames whose capture the link could bracket: the sample after the capture time
        // had arrived (5 ms) before the frame's last byte. The others took the newest sample.
        auto after = std::find_if(samples.begin(), samples.end(), [&](const link::NavSample& n) {
            return n.state.t_ns >= f->t_ns;
        });
        if (after == samples.end() || after == samples.begin() ||
            after->recv_ns + ms_to_ns(5) > f->recv_ns)
            continue;
        const NavState want = accepted.state_at(f->t_ns);
        ASSERT_EQ(f->nav.t_ns, f->t_ns);
        if (std::isnan(want.roll_deg)) continue;
        EXPECT_DOUBLE_EQ(f->nav.roll_deg, want.roll_deg) << "frame " << f->index;
        EXPECT_DOUBLE_EQ(f->nav.pitch_deg, want.pitch_deg) << "frame " << f->index;
        EXPECT_DOUBLE_EQ(f->nav.altitude_m, want.altitude_m) << "frame " << f->index;
        ++checked;
    }
    EXPECT_GT(checked, 10);
    const auto st = rig.link->status().video;
    EXPECT_GT(st.nav_interpolated, 0u);
    // Every byte counted, per stream.
    const auto ls = rig.link->status();
    EXPECT_GT(ls.navdata.bytes, ls.navdata.accepted * 24);
    EXPECT_GT(ls.at.bytes_sent, ls.at.counters.datagrams * 10);
    EXPECT_GT(ls.video.bytes, ls.video.decoded * 64);  // a 64-byte PaVE header and a payload each
}
