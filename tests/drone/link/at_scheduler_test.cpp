#include "drone/link/at_scheduler.hpp"
#include "support/state_bits.hpp"

#include <gtest/gtest.h>

using namespace gs;
using namespace gs::link;

namespace {
constexpr std::uint32_t kEmergencyBit = test::kEmergency;
constexpr std::uint32_t kLanded = test::kThreads;  // threads running, FLY clear
constexpr std::uint32_t kFlying = kLanded | test::kFly;
constexpr std::uint32_t kWatchdogBit = test::kComWdg;
constexpr std::uint32_t kBootstrapBit = test::kBootstrap;
const std::string kRefLand = "290717696", kRefFly = "290718208", kRefToggle = "290717952";

bool has(const std::string& cycle_text, const std::string& what) {
    return cycle_text.find(what) != std::string::npos;
}
// The REF input this cycle sent, or "" when it sent none.
std::string ref_of(const std::string& cycle_text) {
    const auto p = cycle_text.find("AT*REF=");
    if (p == std::string::npos) return "";
    const auto comma = cycle_text.find(',', p);
    return cycle_text.substr(comma + 1, cycle_text.find('\r', p) - comma - 1);
}

std::string cycle(AtScheduler& s, TimeNs now = 0, std::optional<std::uint32_t> state = {}) {
    std::vector<std::string> out;
    s.build(now, state, out);
    std::string all;
    for (auto& d : out) all += d;
    return all;
}
}  // namespace

TEST(AtScheduler, IdleCycleIsRefLandedPlusHoverWithConsecutiveSequenceNumbers) {
    AtScheduler s;
    s.on_connected(kLanded);
    EXPECT_EQ(cycle(s), "AT*REF=1,290717696\rAT*PCMD=2,0,0,0,0,0\r");
    EXPECT_EQ(cycle(s), "AT*REF=3,290717696\rAT*PCMD=4,0,0,0,0,0\r");
    EXPECT_EQ(s.counters().cycles, 2u);
}

TEST(AtScheduler, BeforeTheDroneStateIsKnownOnlyAKeepAliveIsSentAndOnlyHoverWhileLost) {
    AtScheduler s;
    EXPECT_EQ(s.intent(), FlyIntent::Unknown);
    // No REF at all: REF without the take-off bit would land a drone that is already flying.
    EXPECT_EQ(cycle(s), "AT*COMWDG=1\r");
    EXPECT_EQ(cycle(s, ms_to_ns(30), kBootstrapBit | kWatchdogBit), "AT*COMWDG=2\r");
    s.on_link_lost();
    // Stale state: the watchdog bit is not answered; PCMD hover alone, no REF.
    EXPECT_EQ(cycle(s, ms_to_ns(60), kWatchdogBit), "AT*PCMD=3,0,0,0,0,0\r");
    s.on_link_restored();
    EXPECT_EQ(cycle(s, ms_to_ns(90)), "AT*COMWDG=4\r");
    EXPECT_EQ(s.counters().comwdg_sent, 3u);
}

TEST(AtScheduler, ConnectingToAFlyingDroneAdoptsItsFlyingStateAndLandIsTheEdge) {
    AtScheduler s;
    s.on_connected(kFlying);
    EXPECT_EQ(s.intent(), FlyIntent::Fly);
    EXPECT_EQ(s.counters().flying_adopted, 1u);
    EXPECT_EQ(cycle(s, ms_to_ns(30), kFlying), "AT*REF=1,290718208\rAT*PCMD=2,0,0,0,0,0\r");
    EXPECT_EQ(ref_of(cycle(s, ms_to_ns(60), kFlying)), kRefFly);
    s.set_fly(false);  // Land: the take-off bit goes from set to clear
    EXPECT_EQ(ref_of(cycle(s, ms_to_ns(90), kFlying)), kRefLand);

    AtScheduler landed;
    landed.on_connected(kLanded);
    EXPECT_EQ(landed.intent(), FlyIntent::Land);
    EXPECT_EQ(ref_of(cycle(landed, 0, kLanded)), kRefLand);
    AtScheduler in_emergency;
    in_emergency.on_connected(kLanded | kEmergencyBit);
    EXPECT_EQ(in_emergency.intent(), FlyIntent::Land);
    EXPECT_EQ(in_emergency.counters().flying_adopted, 0u);
}

TEST(AtScheduler, CuttingTheMotorsAndResettingTheEmergencyNeverTakesOffAgain) {
    AtScheduler s;
    s.on_connected(kLanded);
    s.set_fly(true);
    EXPECT_EQ(ref_of(cycle(s, ms_to_ns(30), kLanded)), kRefFly);
    EXPECT_EQ(ref_of(cycle(s, ms_to_ns(60), kFlying)), kRefFly);
    s.request_emergency(false, ms_to_ns(70));  // cut the motors
    EXPECT_FALSE(s.fly());
    EXPECT_EQ(ref_of(cycle(s, ms_to_ns(90), kFlying)), kRefToggle);  // bit 8 alone, never 9
    EXPECT_EQ(ref_of(cycle(s, ms_to_ns(120), kLanded | kEmergencyBit)), kRefLand);
    s.request_emergency(true, ms_to_ns(130));  // reset the emergency
    EXPECT_EQ(ref_of(cycle(s, ms_to_ns(150), kLanded | kEmergencyBit)), kRefToggle);
    for (int i = 0; i < 100; ++i) {
        EXPECT_EQ(ref_of(cycle(s, ms_to_ns(180 + 30 * i), kLanded)), kRefLand) << i;
    }
    EXPECT_EQ(s.counters().takeoff_intents_dropped, 0u);  // the pilot did it, not the drone
}

TEST(AtScheduler, TheDroneReportingAnEmergencyOnItsOwnDropsTheTakeOffIntent) {
    AtScheduler s;
    s.on_connected(kLanded);
    s.set_fly(true);
    EXPECT_EQ(ref_of(cycle(s, ms_to_ns(30), kFlying)), kRefFly);
    // Motors cut by the drone (a crash, the cut-out system): the intent goes.
    EXPECT_EQ(ref_of(cycle(s, ms_to_ns(60), kLanded | kEmergencyBit)), kRefLand);
    EXPECT_EQ(s.intent(), FlyIntent::Land);
    EXPECT_EQ(s.counters().takeoff_intents_dropped, 1u);
    // The emergency is cleared later (by anyone): the drone stays on the ground.
    EXPECT_EQ(ref_of(cycle(s, ms_to_ns(90), kLanded)), kRefLand);
}

TEST(AtScheduler, TheDroneLandingOnItsOwnDropsTheTakeOffIntent) {
    AtScheduler s;
    s.on_connected(kLanded);
    s.set_fly(true);
    // FLY is not up yet in the first cycles after Take off: that is not a landing.
    EXPECT_EQ(ref_of(cycle(s, ms_to_ns(30), kLanded)), kRefFly);
    EXPECT_EQ(ref_of(cycle(s, ms_to_ns(60), kLanded)), kRefFly);
    EXPECT_EQ(ref_of(cycle(s, ms_to_ns(90), kFlying)), kRefFly);
    // Battery critical, lost communication...: it landed while we wanted to fly.
    EXPECT_EQ(ref_of(cycle(s, ms_to_ns(120), kLanded)), kRefLand);
    EXPECT_EQ(s.counters().takeoff_intents_dropped, 1u);
}

TEST(AtScheduler, ATakeOffTheDroneNeverShowsIsDroppedAfterTheTimeout) {
    AtScheduler s(NavdataIds{}, ms_to_ns(2000), ms_to_ns(5000));
    s.on_connected(kLanded);
    s.set_fly(true);
    EXPECT_EQ(ref_of(cycle(s, ms_to_ns(1000), kLanded)), kRefFly);
    EXPECT_EQ(ref_of(cycle(s, ms_to_ns(5990), kLanded)), kRefFly);
    // Refused (angles out of range, say): a later change must not make it take off.
    EXPECT_EQ(ref_of(cycle(s, ms_to_ns(6010), kLanded)), kRefLand);
    EXPECT_EQ(s.counters().takeoff_timeouts, 1u);
    EXPECT_EQ(s.counters().takeoff_intents_dropped, 1u);
}

TEST(AtScheduler, ADroneRestartClearsTheTakeOffIntentUntilThePilotPressesTakeOffAgain) {
    AtScheduler s;
    s.on_connected(kLanded);
    s.set_fly(true);
    s.set_move({0, -0.5f, 0, 0});
    EXPECT_EQ(ref_of(cycle(s, ms_to_ns(30), kFlying)), kRefFly);
    s.on_drone_restart();
    EXPECT_EQ(cycle(s, ms_to_ns(60), kBootstrapBit), "AT*REF=3,290717696\rAT*PCMD=4,0,0,0,0,0\r");
    EXPECT_EQ(s.counters().takeoff_intents_dropped, 1u);
    EXPECT_EQ(s.counters().stale_moves_dropped, 1u);
    // Connected again: the intent is known (Land), nothing is adopted.
    s.on_connected(kLanded);
    EXPECT_EQ(ref_of(cycle(s, ms_to_ns(90), kLanded)), kRefLand);
    s.set_fly(true);
    EXPECT_EQ(ref_of(cycle(s, ms_to_ns(120), kLanded)), kRefFly);
}

TEST(AtScheduler, FlyAndMoveAreRepeatedEveryCycleAndClamped) {
    AtScheduler s;
    s.set_fly(true);
    s.set_move({0.5f, -7.0f, 0.0f, 1.0f});  // pitch clamped to -1
    const std::string expected_pcmd = ",1,1056964608,-1082130432,0,1065353216\r";
    EXPECT_EQ(cycle(s), "AT*REF=1,290718208\rAT*PCMD=2" + expected_pcmd);
    EXPECT_EQ(cycle(s), "AT*REF=3,290718208\rAT*PCMD=4" + expected_pcmd);
    s.hover();
    EXPECT_EQ(cycle(s), "AT*REF=5,290718208\rAT*PCMD=6,0,0,0,0,0\r");
    s.set_move({0, 0, 0, 0});  // all zero is a hover, not a progressive command
    EXPECT_FALSE(s.moving());
    s.set_move({std::numeric_limits<float>::quiet_NaN(), 0, 0, 0.2f});
    EXPECT_EQ(s.move().roll, 0.0f);
}

TEST(AtScheduler, LosingTheLinkSendsHoverOnlyAndTheIntentIsAdoptedWhenItReturns) {
    AtScheduler s;
    s.on_connected(kLanded);
    s.set_fly(true);
    s.set_move({0, -0.5f, 0, 0});
    EXPECT_EQ(ref_of(cycle(s, ms_to_ns(30), kFlying)), kRefFly);
    s.on_link_lost();
    // The drone may have rebooted: a replayed take-off bit would start it. Hover, no REF.
    EXPECT_EQ(cycle(s, ms_to_ns(60), kFlying), "AT*PCMD=3,0,0,0,0,0\r");
    EXPECT_EQ(s.intent(), FlyIntent::Unknown);
    EXPECT_EQ(s.counters().stale_moves_dropped, 1u);
    s.set_fly(true);  // nobody knows what the drone does: ignored
    EXPECT_EQ(s.counters().takeoffs_while_lost, 1u);
    EXPECT_EQ(cycle(s, ms_to_ns(90), kFlying), "AT*PCMD=4,0,0,0,0,0\r");
    // Back, still flying: kept flying, and the Move is not replayed.
    s.on_connected(kFlying);
    EXPECT_EQ(cycle(s, ms_to_ns(120), kFlying), "AT*REF=5,290718208\rAT*PCMD=6,0,0,0,0,0\r");

    // Lost again, and the drone comes back landed: Land.
    s.on_link_lost();
    s.on_connected(kLanded);
    EXPECT_EQ(ref_of(cycle(s, ms_to_ns(150), kLanded)), kRefLand);
}

TEST(AtScheduler, LandAndEmergencyAreSentEvenWhileTheLinkIsLost) {
    AtScheduler s;
    s.on_connected(kFlying);
    s.on_link_lost();
    s.set_fly(false);
    EXPECT_EQ(ref_of(cycle(s, ms_to_ns(30), kFlying)), kRefLand);
    s.request_emergency(false, ms_to_ns(40));
    EXPECT_EQ(ref_of(cycle(s, ms_to_ns(60), kFlying)), kRefToggle);
}

TEST(AtScheduler, TheComWatchdogBitIsAnsweredEveryCycleWhileTheDroneReportsIt) {
    AtScheduler s;
    s.on_connected(kLanded);
    // Every cycle, so a lost AT*COMWDG datagram is answered again at the next one.
    for (int i = 0; i < 5; ++i) {
        EXPECT_TRUE(has(cycle(s, ms_to_ns(30 * i), kLanded | kWatchdogBit), "AT*COMWDG=")) << i;
    }
    EXPECT_EQ(s.counters().comwdg_sent, 5u);
    EXPECT_FALSE(has(cycle(s, ms_to_ns(150), kLanded), "AT*COMWDG="));
    // Not in bootstrap mode (docs/protocol.md §1.3 step 8), not from a stale state while lost.
    EXPECT_FALSE(has(cycle(s, ms_to_ns(180), kBootstrapBit | kWatchdogBit), "AT*COMWDG="));
    s.on_link_lost();
    EXPECT_FALSE(has(cycle(s, ms_to_ns(210), kLanded | kWatchdogBit), "AT*COMWDG="));
    EXPECT_EQ(s.counters().comwdg_sent, 5u);
}

TEST(AtScheduler, EmergencyBitIsHeldOnlyUntilTheDroneShowsTheToggle) {
    AtScheduler s;
    s.set_fly(true);
    s.request_emergency(false, ms_to_ns(0));
    const std::uint32_t flying = 0x0F800001;
    EXPECT_EQ(cycle(s, ms_to_ns(30), flying).substr(0, 19), "AT*REF=1,290717952\r");  // bit 8
    EXPECT_EQ(cycle(s, ms_to_ns(60), flying).substr(0, 19), "AT*REF=3,290717952\r");
    // The drone reports EMERGENCY: the bit is released at once.
    EXPECT_EQ(cycle(s, ms_to_ns(90), flying | kEmergencyBit).substr(0, 19), "AT*REF=5,290717696\r");
    EXPECT_FALSE(s.emergency_pending());
    // Leaving the emergency: held until the drone clears bit 31.
    s.request_emergency(true, ms_to_ns(100));
    EXPECT_EQ(cycle(s, ms_to_ns(120), kEmergencyBit).substr(0, 19), "AT*REF=7,290717952\r");
    EXPECT_EQ(cycle(s, ms_to_ns(150), 0x0F800000).substr(0, 19), "AT*REF=9,290717696\r");
}

TEST(AtScheduler, AnUnansweredEmergencyRequestTimesOut) {
    AtScheduler s(NavdataIds{}, ms_to_ns(2000));
    s.request_emergency(false, 0);
    EXPECT_NE(cycle(s, ms_to_ns(1990), 0).find("290717952"), std::string::npos);
    EXPECT_EQ(cycle(s, ms_to_ns(2010), 0).find("290717952"), std::string::npos);
    EXPECT_EQ(s.counters().emergency_timeouts, 1u);
}

TEST(AtScheduler, OneShotsFollowTheControlCommandsConfigPrecededByItsIds) {
    AtScheduler s(NavdataIds{"d2e081a3", "be27e2e4", "d87f7e0c"});
    s.on_connected(kLanded);
    OneShot cfg;
    cfg.kind = OneShot::Kind::Config;
    cfg.key = "general:navdata_demo";
    cfg.value = "TRUE";
    s.queue(cfg);
    s.queue({OneShot::Kind::Ctrl, {}, {}, 5, 0, 0});
    s.queue({OneShot::Kind::Comwdg, {}, {}, 0, 0, 0});
    EXPECT_EQ(cycle(s),
              "AT*REF=1,290717696\rAT*PCMD=2,0,0,0,0,0\r"
              "AT*CONFIG_IDS=3,\"d2e081a3\",\"be27e2e4\",\"d87f7e0c\"\r"
              "AT*CONFIG=4,\"general:navdata_demo\",\"TRUE\"\r"
              "AT*CTRL=5,5,0\rAT*COMWDG=6\r");
    EXPECT_EQ(s.queued(), 0u);  // sent once
    EXPECT_EQ(cycle(s), "AT*REF=7,290717696\rAT*PCMD=8,0,0,0,0,0\r");
}

TEST(AtScheduler, ManyOneShotsArePackedIntoDatagramsOfAtMost1024Bytes) {
    AtScheduler s;
    s.on_connected(kLanded);
    for (int i = 0; i < 40; ++i) {
        OneShot cfg;
        cfg.kind = OneShot::Kind::Config;
        cfg.key = "custom:session_desc";
        cfg.value = std::string(30, 'a' + static_cast<char>(i % 26));
        s.queue(cfg);
    }
    std::vector<std::string> out;
    s.build(0, std::nullopt, out);
    ASSERT_GT(out.size(), 1u);
    std::size_t commands = 0;
    for (const auto& d : out) {
        EXPECT_LE(d.size(), 1024u);
        EXPECT_EQ(d.back(), '\r');
        commands += static_cast<std::size_t>(std::count(d.begin(), d.end(), '\r'));
    }
    EXPECT_EQ(commands, 2u + 80u);
}

TEST(AtScheduler, AConfigValueWithAQuoteIsRefusedAndCounted) {
    AtScheduler s;
    s.on_connected(kLanded);
    OneShot cfg;
    cfg.kind = OneShot::Kind::Config;
    cfg.key = "general:ardrone_name";
    cfg.value = "bad\"name";
    s.queue(cfg);
    EXPECT_EQ(cycle(s), "AT*REF=1,290717696\rAT*PCMD=2,0,0,0,0,0\r");
    EXPECT_EQ(s.counters().encode_errors, 1u);
}
