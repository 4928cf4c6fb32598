#include "drone/link/link_state.hpp"

#include "support/state_bits.hpp"

#include <gtest/gtest.h>

using namespace gs;
using namespace gs::protocol;
using namespace gs::link;

namespace {
using namespace gs::test;
// docs/protocol.md §7.4, a real bootstrap packet.
constexpr std::uint32_t kBootstrapState = 0x4F800C10;

// Drives a state machine with a fake time line and a scripted drone.
struct Harness {
    LinkStateMachine sm;
    TimeNs now = ms_to_ns(1000);
    std::uint32_t seq = 100;
    LinkActions out;

    // Demo mode unless told: most tests here are about the machine, not the navdata mode.
    static LinkSetup demo() {
        LinkSetup s;
        s.navdata_demo = true;
        return s;
    }
    explicit Harness(LinkSetup s = demo()) : sm(std::move(s)) {}
    void start() {
        out.clear();
        sm.start(now, out);
    }
    bool nav(std::uint32_t state, std::uint32_t sequence) {
        out.clear();
        bool ok = sm.on_navdata({state, sequence}, now, out);
        LinkActions t;
        sm.tick(now, t);
        merge(t);
        return ok;
    }
    bool nav(std::uint32_t state) { return nav(state, ++seq); }
    void tick_for(int ms, int step_ms = 5) {
        out.clear();
        for (int i = 0; i < ms; i += step_ms) {
            now += ms_to_ns(step_ms);
            LinkActions t;
            sm.tick(now, t);
            merge(t);
        }
    }
    void advance(int ms) { now += ms_to_ns(ms); }
    void merge(const LinkActions& t) {
        out.send_trigger |= t.send_trigger;
        out.send_ctrl_ack |= t.send_ctrl_ack;
        out.send_ctrl_get_config |= t.send_ctrl_get_config;
        out.configs.insert(out.configs.end(), t.configs.begin(), t.configs.end());
        out.done.insert(out.done.end(), t.done.begin(), t.done.end());
        out.link_lost |= t.link_lost;
        out.link_restored |= t.link_restored;
        out.drone_restarted |= t.drone_restarted;
        if (t.connected) out.connected = t.connected;
    }
    // The drone's side of one CONFIG exchange: ACK up, then cleared on CTRL 5.
    void ack_config(std::uint32_t base) {
        advance(10);
        nav(base | kAck);
        ASSERT_TRUE(out.send_ctrl_ack);
        advance(10);
        nav(base);
    }
    void connect_demo() {
        start();
        advance(20);
        nav(kBootstrapState, 1);
        ASSERT_EQ(sm.state(), ConnectionState::Configuring);
        ASSERT_EQ(out.configs.size(), 1u);
        ack_config(kThreads | kDemo);
        ASSERT_EQ(sm.state(), ConnectionState::Connected) << sm.state_reason();
    }
};
}  // namespace

TEST(LinkState, BootstrapSendsTheWakeUpAndResendsItOnSilence) {
    Harness h;
    EXPECT_EQ(h.sm.state(), ConnectionState::Disconnected);
    h.start();
    EXPECT_TRUE(h.out.send_trigger);
    EXPECT_EQ(h.sm.state(), ConnectionState::Bootstrapping);
    h.tick_for(95);
    EXPECT_FALSE(h.out.send_trigger);
    h.tick_for(10);
    EXPECT_TRUE(h.out.send_trigger);
    h.tick_for(1000);
    EXPECT_EQ(h.sm.counters().triggers_sent, 12u);
    EXPECT_EQ(h.sm.state(), ConnectionState::Bootstrapping);
    EXPECT_NE(h.sm.state_reason().find("wake-ups sent"), std::string::npos);
}

TEST(LinkState, ConfiguresDemoModeWithTheAckHandshakeThenConnects) {
    Harness h;
    h.start();
    h.advance(20);
    EXPECT_TRUE(h.nav(kBootstrapState, 1));
    EXPECT_EQ(h.sm.state(), ConnectionState::Configuring);
    ASSERT_EQ(h.out.configs.size(), 1u);
    EXPECT_EQ(h.out.configs[0].first, "general:navdata_demo");
    EXPECT_EQ(h.out.configs[0].second, "TRUE");
    // While the ACK is not raised, nothing else is sent and the state waits.
    h.advance(30);
    h.nav(kBootstrapState);
    EXPECT_TRUE(h.out.configs.empty());
    EXPECT_FALSE(h.out.send_ctrl_ack);
    // ACK raised: CTRL 5 sent and repeated every 50 ms while the bit stays up.
    h.advance(10);
    h.nav(kBootstrapState | kAck);
    EXPECT_TRUE(h.out.send_ctrl_ack);
    h.advance(20);
    h.nav(kBootstrapState | kAck);
    EXPECT_FALSE(h.out.send_ctrl_ack);
    h.advance(35);
    h.nav(kBootstrapState | kAck);
    EXPECT_TRUE(h.out.send_ctrl_ack);
    // Cleared, and the drone now sends demo navdata with options.
    h.advance(10);
    h.nav(kThreads | kDemo);
    EXPECT_EQ(h.sm.state(), ConnectionState::Connected);
    EXPECT_EQ(h.sm.counters().configs_sent, 1u);
}

TEST(LinkState, FullModeWritesTheOptionsMaskAndCustomIdsFirst) {
    LinkSetup s;
    s.navdata_demo = false;
    s.navdata_options = 0x0FFFFFFF;
    s.ids = {"d2e081a3", "be27e2e4", "d87f7e0c"};
    Harness h(s);
    h.start();
    std::vector<std::string> keys;
    h.nav(kBootstrapState, 1);
    for (int i = 0; i < 5; ++i) {
        ASSERT_EQ(h.out.configs.size(), 1u) << "exchange " << i;
        keys.push_back(h.out.configs[0].first + "=" + h.out.configs[0].second);
        h.ack_config(kBootstrapState & ~kDemo);
        if (i < 4) {
            ASSERT_EQ(h.sm.state(), ConnectionState::Configuring);
        }
    }
    EXPECT_EQ(keys, (std::vector<std::string>{
                        "custom:session_id=d2e081a3", "custom:profile_id=be27e2e4",
                        "custom:application_id=d87f7e0c", "general:navdata_demo=FALSE",
                        "general:navdata_options=268435455"}));
    h.advance(5);
    h.nav(kThreads);  // full mode: demo bit clear, options present
    EXPECT_EQ(h.sm.state(), ConnectionState::Connected);
}

TEST(LinkState, FullNavdataWithTheOptionsUsedIsTheDefaultAndDemoTheFallback) {
    // Issue 17 item 5: 200 Hz navdata (demo off) with the options the classifier and the
    // odometry read (demo: attitude, velocities, altitude; time), by default.
    const LinkSetup defaults;
    EXPECT_FALSE(defaults.navdata_demo);
    EXPECT_EQ(defaults.navdata_options, (1u << 0) | (1u << 1));
    Harness h(defaults);
    h.start();
    h.nav(kBootstrapState, 1);
    std::vector<std::string> keys;
    for (int i = 0; i < 2; ++i) {
        ASSERT_EQ(h.out.configs.size(), 1u) << "exchange " << i;
        keys.push_back(h.out.configs[0].first + "=" + h.out.configs[0].second);
        h.ack_config(kBootstrapState & ~kDemo);
    }
    EXPECT_EQ(keys, (std::vector<std::string>{"general:navdata_demo=FALSE",
                                              "general:navdata_options=3"}));
    // A drone that keeps sending demo navdata (15 Hz) is used as it is once settled.
    for (int i = 0; i < 100 && h.sm.state() != ConnectionState::Connected; ++i) {
        h.advance(65);
        h.nav(kThreads | kDemo);
    }
    ASSERT_EQ(h.sm.state(), ConnectionState::Connected);
    EXPECT_NE(h.sm.state_reason().find("demo although full"), std::string::npos)
        << h.sm.state_reason();
}

TEST(LinkState, AnUnacknowledgedConfigIsRetriedThenTheSequenceRestarts) {
    Harness h;
    h.start();
    h.nav(kBootstrapState, 1);
    ASSERT_EQ(h.out.configs.size(), 1u);
    int sends = 1;
    for (int i = 0; i < 160; ++i) {  // 1.6 s of bootstrap navdata without the ACK bit
        h.advance(10);
        h.nav(kBootstrapState);
        sends += static_cast<int>(h.out.configs.size());
    }
    // 3 attempts 500 ms apart, then the whole configuration starts again (a 4th send).
    EXPECT_EQ(sends, 4);
    EXPECT_EQ(h.sm.counters().config_timeouts, 1u);
    EXPECT_EQ(h.sm.state(), ConnectionState::Configuring);
}

TEST(LinkState, SequenceGapsAreCountedAndOldPacketsDropped) {
    Harness h;
    h.connect_demo();
    const auto gaps0 = h.sm.counters().sequence_gaps;
    const std::uint32_t last = h.seq;
    EXPECT_TRUE(h.nav(kThreads | kDemo, 200));
    EXPECT_TRUE(h.nav(kThreads | kDemo, 205));
    EXPECT_EQ(h.sm.counters().sequence_gaps - gaps0, (200u - last - 1u) + 4u);
    EXPECT_FALSE(h.nav(kThreads | kDemo, 203));  // late
    EXPECT_FALSE(h.nav(kThreads | kDemo, 205));  // duplicate
    EXPECT_EQ(h.sm.counters().out_of_order, 2u);
    EXPECT_TRUE(h.nav(kThreads | kDemo, 206));
}

TEST(LinkState, SilenceIsLinkLostWithinHalfASecondAndRecoveredAtOnce) {
    Harness h;
    h.connect_demo();
    h.tick_for(495);
    EXPECT_EQ(h.sm.state(), ConnectionState::Connected);
    EXPECT_TRUE(h.out.send_trigger);  // silence > 100 ms: wake-up re-sent while still connected
    h.tick_for(10);
    EXPECT_EQ(h.sm.state(), ConnectionState::LinkLost);
    EXPECT_TRUE(h.out.link_lost);
    EXPECT_EQ(h.sm.counters().link_losses, 1u);
    EXPECT_EQ(h.sm.state_reason(), "no navdata for more than 500 ms");
    h.tick_for(1000);
    EXPECT_TRUE(h.out.send_trigger);
    // The reason stays true however long the silence lasts (no figure frozen at the loss).
    EXPECT_EQ(h.sm.state_reason(), "no navdata for more than 500 ms");
    // Data flows again, with a lower sequence (a new stream after the silence): connected at once.
    EXPECT_TRUE(h.nav(kThreads | kDemo | kFly, 50));
    EXPECT_TRUE(h.out.link_restored);
    EXPECT_EQ(h.sm.state(), ConnectionState::Connected);
    // The AT sender adopts the drone's state as it is now, not as it was before the loss.
    ASSERT_TRUE(h.out.connected);
    EXPECT_EQ(*h.out.connected, kThreads | kDemo | kFly);
    EXPECT_FALSE(h.out.drone_restarted);
    EXPECT_EQ(h.sm.counters().sequence_resets, 1u);
    EXPECT_FALSE(h.nav(kThreads | kDemo | kFly, 49));  // once: from then on, order again
    const auto gaps0 = h.sm.counters().sequence_gaps;
    EXPECT_TRUE(h.nav(kThreads | kDemo | kFly, 53));
    EXPECT_EQ(h.sm.counters().sequence_gaps - gaps0, 2u);
}

TEST(LinkState, ALinkLossWhoseSequenceGoesOnCountsWhatWasLostInTheSilence) {
    Harness h;
    h.connect_demo();
    h.nav(kThreads | kDemo, 1000);
    h.tick_for(600);
    ASSERT_EQ(h.sm.state(), ConnectionState::LinkLost);
    const auto gaps0 = h.sm.counters().sequence_gaps;
    EXPECT_TRUE(h.nav(kThreads | kDemo, 1120));  // 600 ms of 200 Hz navdata went missing
    EXPECT_EQ(h.sm.state(), ConnectionState::Connected);
    EXPECT_EQ(h.sm.counters().sequence_gaps - gaps0, 119u);
    EXPECT_EQ(h.sm.counters().sequence_resets, 0u);
}

TEST(LinkState, EnteringConnectedIsAnEdgeCarryingTheDroneState) {
    Harness h;
    h.start();
    h.advance(20);
    h.nav(kBootstrapState, 1);
    EXPECT_FALSE(h.out.connected);
    h.advance(10);
    h.nav(kThreads | kDemo | kFly | kAck);
    EXPECT_FALSE(h.out.connected);  // configuring
    h.advance(10);
    h.nav(kThreads | kDemo | kFly);
    ASSERT_EQ(h.sm.state(), ConnectionState::Connected);
    ASSERT_TRUE(h.out.connected);
    EXPECT_EQ(*h.out.connected, kThreads | kDemo | kFly);
    h.advance(10);
    h.nav(kThreads | kDemo | kFly);
    EXPECT_FALSE(h.out.connected);  // once
}

TEST(LinkState, ADroneRestartIsDetectedAndReconfigured) {
    Harness h;
    h.connect_demo();
    h.nav(kThreads | kDemo, 5000);
    EXPECT_TRUE(h.nav(kBootstrapState, 1));  // rebooted: sequence from 1, bootstrap again
    EXPECT_EQ(h.sm.counters().drone_restarts, 1u);
    EXPECT_TRUE(h.out.drone_restarted);  // the AT sender forgets the take-off intent
    EXPECT_EQ(h.sm.state(), ConnectionState::Configuring);
    ASSERT_EQ(h.out.configs.size(), 1u);
    EXPECT_EQ(h.out.configs[0].first, "general:navdata_demo");
    h.ack_config(kThreads | kDemo);
    EXPECT_EQ(h.sm.state(), ConnectionState::Connected);
}

TEST(LinkState, AComWatchdogEventIsCountedOnceAndNeitherHidesLossesNorLetsLatePacketsIn) {
    Harness h;
    h.connect_demo();
    h.nav(kThreads | kDemo | kComWdg, 900);
    h.nav(kThreads | kDemo | kComWdg, 901);
    EXPECT_EQ(h.sm.counters().com_watchdog_events, 1u);  // AtScheduler answers it every cycle
    // The sequence goes on: what went missing around the event is counted, as anywhere else.
    const auto gaps0 = h.sm.counters().sequence_gaps;
    EXPECT_TRUE(h.nav(kThreads | kDemo, 905));
    EXPECT_EQ(h.sm.counters().sequence_gaps - gaps0, 3u);
    // A late packet is late even with the bit set; a step far back with it is a new stream.
    EXPECT_FALSE(h.nav(kThreads | kDemo | kComWdg, 903));
    EXPECT_EQ(h.sm.counters().sequence_resets, 0u);
    EXPECT_TRUE(h.nav(kThreads | kDemo | kComWdg, 1));
    EXPECT_EQ(h.sm.counters().sequence_resets, 1u);
    EXPECT_EQ(h.sm.counters().com_watchdog_events, 2u);
    EXPECT_TRUE(h.nav(kThreads | kDemo, 2));
    EXPECT_FALSE(h.nav(kThreads | kDemo, 1));  // and the new stream has its own order
    EXPECT_EQ(h.sm.counters().sequence_gaps - gaps0, 3u);
    // Without the bit (and without a restart) a step far back is only old.
    EXPECT_FALSE(h.nav(kThreads | kDemo, 0));
    EXPECT_EQ(h.sm.counters().out_of_order, 3u);
}

TEST(LinkState, AVerifiedWriteReadsTheValueBack) {
    Harness h;
    h.connect_demo();
    const auto id = h.sm.write_config("control:altitude_max", "3000", true);
    h.advance(5);
    h.nav(kThreads | kDemo);
    ASSERT_EQ(h.out.configs.size(), 1u);
    h.ack_config(kThreads | kDemo);
    h.advance(5);
    h.nav(kThreads | kDemo);
    EXPECT_TRUE(h.out.send_ctrl_get_config || h.sm.pending_jobs() == 1);
    ConfigMap dump;
    dump.set("control:altitude_max", "3000");
    LinkActions out;
    h.sm.on_config_dump(dump, h.now, out);
    ASSERT_EQ(out.done.size(), 1u);
    EXPECT_EQ(out.done[0].id, id);
    EXPECT_EQ(out.done[0].outcome, ConfigOutcome::Verified);
}

TEST(LinkState, AKeyTheDroneIgnoredIsReported) {
    Harness h;
    h.connect_demo();
    h.sm.write_config("control:euler_angle_max", "0.25", true);
    h.sm.write_config("video:no_such_key", "1", true);
    std::size_t sent_with_dump = 0;  // the next write goes out as soon as the previous one ends
    for (int k = 0; k < 2; ++k) {
        h.advance(5);
        h.nav(kThreads | kDemo);
        ASSERT_EQ(h.out.configs.size() + sent_with_dump, 1u) << "write " << k;
        h.ack_config(kThreads | kDemo);
        h.advance(5);
        h.nav(kThreads | kDemo);
        ConfigMap dump;
        dump.set("control:euler_angle_max", "2.0943952e-01");  // unchanged: the write was ignored
        LinkActions out;
        h.sm.on_config_dump(dump, h.now, out);
        sent_with_dump = out.configs.size();
        ASSERT_EQ(out.done.size(), 1u);
        EXPECT_EQ(out.done[0].outcome, ConfigOutcome::Ignored);
        EXPECT_NE(out.done[0].detail.find(k == 0 ? "reports control:euler_angle_max = 2.09"
                                                 : "no key video:no_such_key"),
                  std::string::npos)
            << out.done[0].detail;
    }
    // Same value printed differently (%e) counts as verified.
    h.sm.write_config("control:euler_angle_max", "0.25", true);
    h.advance(5);
    h.nav(kThreads | kDemo);
    h.ack_config(kThreads | kDemo);
    h.advance(5);
    h.nav(kThreads | kDemo);
    ConfigMap dump;
    dump.set("control:euler_angle_max", "2.5000000e-01");
    LinkActions out;
    h.sm.on_config_dump(dump, h.now, out);
    ASSERT_EQ(out.done.size(), 1u);
    EXPECT_EQ(out.done[0].outcome, ConfigOutcome::Verified);
}

TEST(LinkState, LosingTheLinkCancelsPendingUserWrites) {
    Harness h;
    h.connect_demo();
    const auto id = h.sm.write_config("leds:leds_anim", "3,1073741824,2", false);
    h.tick_for(600);
    ASSERT_EQ(h.sm.state(), ConnectionState::LinkLost);
    bool cancelled = false;
    for (auto& d : h.out.done) cancelled |= d.id == id && d.outcome == ConfigOutcome::Cancelled;
    EXPECT_TRUE(cancelled);
    EXPECT_EQ(h.sm.pending_jobs(), 0u);
}

TEST(LinkState, StopDisconnectsAndIgnoresNavdata) {
    Harness h;
    h.connect_demo();
    LinkActions out;
    h.sm.stop(out);
    EXPECT_EQ(h.sm.state(), ConnectionState::Disconnected);
    EXPECT_FALSE(h.nav(kThreads | kDemo));
    h.tick_for(1000);
    EXPECT_FALSE(h.out.send_trigger);
}
