#include "drone/link/at_scheduler.hpp"

#include <gtest/gtest.h>

using namespace gs;
using namespace gs::link;

namespace {
constexpr std::uint32_t kEmergencyBit = 1u << 31;

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
    EXPECT_EQ(cycle(s), "AT*REF=1,290717696\rAT*PCMD=2,0,0,0,0,0\r");
    EXPECT_EQ(cycle(s), "AT*REF=3,290717696\rAT*PCMD=4,0,0,0,0,0\r");
    EXPECT_EQ(s.counters().cycles, 2u);
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

TEST(AtScheduler, LosingTheLinkDropsTheMoveSoNothingStaleIsReplayed) {
    AtScheduler s;
    s.set_fly(true);
    s.set_move({0, -0.5f, 0, 0});
    s.on_link_lost();
    EXPECT_EQ(cycle(s), "AT*REF=1,290718208\rAT*PCMD=2,0,0,0,0,0\r");  // still flying, hovering
    EXPECT_EQ(s.counters().stale_moves_dropped, 1u);
    EXPECT_EQ(cycle(s), "AT*REF=3,290718208\rAT*PCMD=4,0,0,0,0,0\r");
}

TEST(AtScheduler, EmergencyBitIsHeldOnlyUntilTheDroneShowsTheToggle) {
    AtScheduler s;
    s.set_fly(true);
    s.request_emergency(false, ms_to_ns(0));
    const std::uint32_t flying = 0x0F800001;
    EXPECT_EQ(cycle(s, ms_to_ns(30), flying).substr(0, 19), "AT*REF=1,290718464\r");  // bits 8+9
    EXPECT_EQ(cycle(s, ms_to_ns(60), flying).substr(0, 19), "AT*REF=3,290718464\r");
    // The drone reports EMERGENCY: the bit is released at once.
    EXPECT_EQ(cycle(s, ms_to_ns(90), flying | kEmergencyBit).substr(0, 19), "AT*REF=5,290718208\r");
    EXPECT_FALSE(s.emergency_pending());
    // Leaving the emergency: held until the drone clears bit 31.
    s.set_fly(false);
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
    OneShot cfg;
    cfg.kind = OneShot::Kind::Config;
    cfg.key = "general:ardrone_name";
    cfg.value = "bad\"name";
    s.queue(cfg);
    EXPECT_EQ(cycle(s), "AT*REF=1,290717696\rAT*PCMD=2,0,0,0,0,0\r");
    EXPECT_EQ(s.counters().encode_errors, 1u);
}
