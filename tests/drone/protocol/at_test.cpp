#include "drone/protocol/at.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace at = gs::protocol::at;

// ---- §7.1 test vectors ----------------------------------------------------------------------

TEST(AtEncoder, GenericCommandMatchesNodeVector) {
    const std::array<at::Arg, 2> args{std::int32_t{2}, at::RawArg{"3"}};
    auto cmd = at::command(1, "FOO", args);
    ASSERT_TRUE(cmd);
    EXPECT_EQ(*cmd, "AT*FOO=1,2,3\r");
}

TEST(AtEncoder, RefWithoutDefaultBits) {
    EXPECT_EQ(at::ref(100, 20), "AT*REF=100,20\r");
}

TEST(AtEncoder, RefTakeoffConstant) {
    EXPECT_EQ(at::ref(26, at::ref_input(true, false)), "AT*REF=26,290718208\r");
}

TEST(AtEncoder, RefConstantsMatchProtocolTable) {
    EXPECT_EQ(at::ref_input(false, false), 290717696u);
    EXPECT_EQ(at::ref_input(true, false), 290718208u);
    EXPECT_EQ(at::ref_input(false, true), 290717952u);
    EXPECT_EQ(at::kRefBase, 0x11540000u);
    EXPECT_EQ(at::ref(1, at::ref_input(false, false)), "AT*REF=1,290717696\r");
    EXPECT_EQ(at::ref(2, at::ref_input(false, true)), "AT*REF=2,290717952\r");
}

TEST(AtEncoder, RefHighBitPrintedAsSignedInt) {
    // The drone parses %d: bit 31 must come out as a negative int32, not 2147483648.
    EXPECT_EQ(at::ref(3, 0x80000000u), "AT*REF=3,-2147483648\r");
}

TEST(AtEncoder, ComwdgHasNoTrailingComma) {
    EXPECT_EQ(at::comwdg(100), "AT*COMWDG=100\r");
}

TEST(AtEncoder, PcmdProgressivePitch) {
    EXPECT_EQ(at::pcmd(10, at::kPcmdProgressive, 0.0f, 0.8f, 0.0f, 0.0f),
              "AT*PCMD=10,1,0,1061997773,0,0\r");
}

TEST(AtEncoder, PcmdProgressiveYaw) {
    EXPECT_EQ(at::pcmd(7, at::kPcmdProgressive, 0.0f, 0.0f, 0.0f, 0.75f),
              "AT*PCMD=7,1,0,0,0,1061158912\r");
}

TEST(AtEncoder, PcmdNodeLeftClockwise) {
    // NODE pcmd({left:0.1, clockwise:0.3}): roll = f(-0.1), yaw = f(0.3).
    EXPECT_EQ(at::pcmd(5, at::kPcmdProgressive, -0.1f, 0.0f, 0.0f, 0.3f),
              "AT*PCMD=5,1,-1110651699,0,0,1050253722\r");
}

TEST(AtEncoder, HoverIsFlagZeroAllZeros) {
    EXPECT_EQ(at::hover(11), "AT*PCMD=11,0,0,0,0,0\r");
}

TEST(AtEncoder, PcmdFlagsCombine) {
    EXPECT_EQ(at::kPcmdProgressive | at::kPcmdCombinedYaw |
                  at::kPcmdAbsoluteControl,
              7);
    EXPECT_EQ(at::pcmd(1, at::kPcmdProgressive | at::kPcmdCombinedYaw,
                                 0.5f, -0.5f, 1.0f, -1.0f),
              "AT*PCMD=1,3,1056964608,-1090519040,1065353216,-1082130432\r");
}

TEST(AtEncoder, PcmdClampsOutOfRangeAndNan) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(at::pcmd(1, 1, 2.0f, -3.0f, nan, -0.0f),
              "AT*PCMD=1,1,1065353216,-1082130432,0,0\r");
}

TEST(AtEncoder, PcmdMagHasSixFloats) {
    EXPECT_EQ(at::pcmd_mag(
                  9, at::kPcmdProgressive | at::kPcmdAbsoluteControl, 0.0f,
                  -0.8f, 0.0f, 0.0f, 0.5f, 0.1f),
              "AT*PCMD_MAG=9,5,0,-1085485875,0,0,1056964608,1036831949\r");
}

TEST(AtEncoder, ConfigQuotesKeyAndValue) {
    auto cmd = at::config(3, "foo", "bar");
    ASSERT_TRUE(cmd);
    EXPECT_EQ(*cmd, "AT*CONFIG=3,\"foo\",\"bar\"\r");
}

TEST(AtEncoder, ConfigNavdataDemoLikeNode) {
    auto cmd = at::config(2, "general:navdata_demo", "TRUE");
    ASSERT_TRUE(cmd);
    EXPECT_EQ(*cmd, "AT*CONFIG=2,\"general:navdata_demo\",\"TRUE\"\r");
}

TEST(AtEncoder, CtrlAckHasTwoArguments) {
    EXPECT_EQ(at::ctrl(3, at::CtrlMode::Ack), "AT*CTRL=3,5,0\r");
    EXPECT_EQ(at::ctrl(4, at::CtrlMode::CfgGet), "AT*CTRL=4,4,0\r");
    EXPECT_EQ(at::ctrl(5, 6, 0), "AT*CTRL=5,6,0\r");
}

TEST(AtEncoder, LedsAnimValueMatchesNode) {
    EXPECT_EQ(at::leds_anim_value(1, 3.0f, 3), "1,1077936128,3");
    EXPECT_EQ(at::leds_anim_value(9, 2.0f, 3),
              "9,1073741824,3");  // NODE default: redSnake 2 Hz 3 s
    auto cmd = at::config(8, "leds:leds_anim", at::leds_anim_value(1, 3.0f, 3));
    ASSERT_TRUE(cmd);
    EXPECT_EQ(*cmd, "AT*CONFIG=8,\"leds:leds_anim\",\"1,1077936128,3\"\r");
}

TEST(AtEncoder, FlightAnimValueMatchesNode) {
    EXPECT_EQ(at::flight_anim_value(8, 2000), "8,2000");
    auto cmd =
        at::config(9, "control:flight_anim", at::flight_anim_value(8, 2000));
    ASSERT_TRUE(cmd);
    EXPECT_EQ(*cmd, "AT*CONFIG=9,\"control:flight_anim\",\"8,2000\"\r");
}

TEST(AtEncoder, OtherCommands) {
    EXPECT_EQ(at::ftrim(12), "AT*FTRIM=12\r");
    EXPECT_EQ(at::calib(13), "AT*CALIB=13,0\r");
    EXPECT_EQ(at::led(14, 1, 3.0f, 3), "AT*LED=14,1,1077936128,3\r");
    EXPECT_EQ(at::anim(15, 8, 2000), "AT*ANIM=15,8,2000\r");
}

TEST(AtEncoder, ConfigIdsLikeCvd) {
    auto cmd = at::config_ids(20, "d2e081a3", "be27e2e4", "d87f7e0c");
    ASSERT_TRUE(cmd);
    EXPECT_EQ(*cmd, "AT*CONFIG_IDS=20,\"d2e081a3\",\"be27e2e4\",\"d87f7e0c\"\r");
}

// ---- §2.3 floats ----------------------------------------------------------------------------

TEST(AtFloat, ProtocolExamples) {
    EXPECT_EQ(at::float_to_int(-0.8f), -1085485875);
    EXPECT_EQ(at::float_to_int(0.8f), 1061997773);
    EXPECT_EQ(at::float_to_int(0.75f), 1061158912);
    EXPECT_EQ(at::float_to_int(0.5f), 1056964608);
    EXPECT_EQ(at::float_to_int(-0.5f), -1090519040);
    EXPECT_EQ(at::float_to_int(1.0f), 1065353216);
    EXPECT_EQ(at::float_to_int(-1.0f), -1082130432);
    EXPECT_EQ(at::float_to_int(0.1f), 1036831949);
    EXPECT_EQ(at::float_to_int(2.0f), 1073741824);
    EXPECT_EQ(at::float_to_int(3.0f), 1077936128);
    EXPECT_EQ(at::float_to_int(3.5f), 1080033280);
    EXPECT_EQ(at::float_to_int(10.0f), 1092616192);
    EXPECT_EQ(at::float_to_int(0.0f), 0);
}

TEST(AtFloat, NegativeZeroIsSentAsZero) {
    EXPECT_EQ(at::float_to_int(-0.0f), 0);
}

TEST(AtFloat, BitPatternRoundTrips) {
    EXPECT_EQ(static_cast<std::uint32_t>(at::float_to_int(-0.8f)), 0xBF4CCCCDu);
    EXPECT_EQ(at::int_to_float(-1085485875), -0.8f);
    EXPECT_EQ(at::int_to_float(1080033280), 3.5f);
}

// ---- Sequence counter -----------------------------------------------------------------------

TEST(AtSeqCounter, StartsAtOneAndGivesOneNumberPerCommand) {
    at::SeqCounter c;
    EXPECT_EQ(c.peek(), 1u);
    const at::Seq a = c.next();
    const at::Seq b = c.next();
    EXPECT_EQ(at::ref(a, at::kRefBase) + at::hover(b),
              "AT*REF=1,290717696\rAT*PCMD=2,0,0,0,0,0\r");
    EXPECT_EQ(c.peek(), 3u);
    c.reset();
    EXPECT_EQ(c.next(), 1u);
}

TEST(AtSeqCounter, WrapsToOneAfterInt32Max) {
    at::SeqCounter c(2147483646u);
    EXPECT_EQ(c.next(), 2147483646u);
    EXPECT_EQ(c.next(), 2147483647u);
    EXPECT_EQ(c.next(), 1u);  // the drone takes 1 as a restart
    EXPECT_EQ(c.next(), 2u);
}

TEST(AtSeqCounter, OutOfRangeStartBecomesOne) {
    EXPECT_EQ(at::SeqCounter(0).peek(), 1u);
    EXPECT_EQ(at::SeqCounter(2147483648u).peek(), 1u);
    EXPECT_EQ(at::SeqCounter(42).peek(), 42u);
}

// ---- Rejections -----------------------------------------------------------------------------

TEST(AtEncoder, ConfigRejectsQuoteAndControlCharacters) {
    const std::array<std::string_view, 6> bads{"a\"b", "a\rb", "a\nb", std::string_view("a\0b", 3),
                                               "\t",   "x\x7f"};
    for (const std::string_view bad : bads) {
        auto k = at::config(1, bad, "v");
        ASSERT_FALSE(k) << "key accepted: " << bad;
        EXPECT_EQ(k.error(), at::AtError::ForbiddenCharacter);
        auto v = at::config(1, "k", bad);
        ASSERT_FALSE(v);
        EXPECT_EQ(v.error(), at::AtError::ForbiddenCharacter);
    }
}

TEST(AtEncoder, ConfigAcceptsCommasAndSpacesInValue) {
    auto cmd = at::config(1, "general:ardrone_name", "My Drone, 2");
    ASSERT_TRUE(cmd);
    EXPECT_EQ(*cmd, "AT*CONFIG=1,\"general:ardrone_name\",\"My Drone, 2\"\r");
}

TEST(AtEncoder, ConfigRejectsCommandLongerThanDatagram) {
    // "AT*CONFIG=1,"k","<v>"\r" is 19 bytes + value: 1005 fits exactly, 1006 does not.
    auto fits = at::config(1, "k", std::string(1005, 'x'));
    ASSERT_TRUE(fits);
    EXPECT_EQ(fits->size(), 1024u);
    auto too_long = at::config(1, "k", std::string(1006, 'x'));
    ASSERT_FALSE(too_long);
    EXPECT_EQ(too_long.error(), at::AtError::CommandTooLong);
}

TEST(AtEncoder, ConfigIdsRejectsBadIds) {
    auto quote = at::config_ids(1, "0000000\"", "00000000", "00000000");
    ASSERT_FALSE(quote);
    EXPECT_EQ(quote.error(), at::AtError::ForbiddenCharacter);
    auto lf = at::config_ids(1, "00000000", "0000\n000", "00000000");
    ASSERT_FALSE(lf);
    EXPECT_EQ(lf.error(), at::AtError::ForbiddenCharacter);
    auto short_id = at::config_ids(1, "00000000", "00000000", "0000000");
    ASSERT_FALSE(short_id);
    EXPECT_EQ(short_id.error(), at::AtError::BadConfigId);
    auto not_hex = at::config_ids(1, "0000000g", "00000000", "00000000");
    ASSERT_FALSE(not_hex);
    EXPECT_EQ(not_hex.error(), at::AtError::BadConfigId);
    EXPECT_TRUE(at::config_ids(1, "00000000", "00000000", "00000000"));
    EXPECT_TRUE(at::config_ids(1, "ABCDEF01", "abcdef01", "12345678"));
}

TEST(AtEncoder, GenericCommandRejectsBadNamesAndArgs) {
    const std::array<at::Arg, 1> none{std::int32_t{2}};
    EXPECT_EQ(at::command(1, "foo", none).error(), at::AtError::BadName);
    EXPECT_EQ(at::command(1, "", none).error(), at::AtError::BadName);
    EXPECT_EQ(at::command(1, "A=B", none).error(), at::AtError::BadName);
    const std::array<at::Arg, 1> comma{at::RawArg{"1,2"}};
    EXPECT_EQ(at::command(1, "MISC", comma).error(),
              at::AtError::ForbiddenCharacter);
    const std::array<at::Arg, 1> cr{at::QuotedArg{"a\r"}};
    EXPECT_EQ(at::command(1, "MISC", cr).error(),
              at::AtError::ForbiddenCharacter);
    const std::array<at::Arg, 4> misc{std::int32_t{2}, std::int32_t{20},
                                                std::int32_t{2000}, std::int32_t{3000}};
    auto ok = at::command(4, "MISC", misc);
    ASSERT_TRUE(ok);
    EXPECT_EQ(*ok, "AT*MISC=4,2,20,2000,3000\r");
    const std::array<at::Arg, 2> mixed{0.5f, at::QuotedArg{"x,y"}};
    EXPECT_EQ(*at::command(5, "X", mixed), "AT*X=5,1056964608,\"x,y\"\r");
}

TEST(AtErrors, EveryErrorHasText) {
    for (auto e : {at::AtError::ForbiddenCharacter, at::AtError::BadName,
                   at::AtError::BadConfigId, at::AtError::CommandTooLong,
                   at::AtError::Unterminated}) {
        EXPECT_FALSE(at::to_string(e).empty());
        EXPECT_NE(at::to_string(e), "unknown AT error");
    }
}

// ---- Packing --------------------------------------------------------------------------------

TEST(AtPack, ConcatenatesSmallCommandsInOrder) {
    const std::vector<std::string> cmds{at::ref(1, at::kRefBase),
                                        at::hover(2), at::comwdg(3)};
    auto d = at::pack(cmds);
    ASSERT_TRUE(d);
    ASSERT_EQ(d->size(), 1u);
    EXPECT_EQ((*d)[0], "AT*REF=1,290717696\rAT*PCMD=2,0,0,0,0,0\rAT*COMWDG=3\r");
}

TEST(AtPack, NeverExceedsLimitNorSplitsCommands) {
    // 100 CONFIGs of 100 bytes each: 10 per datagram at 1024 (1000 bytes), 10 datagrams.
    std::vector<std::string> cmds;
    for (at::Seq s = 1; s <= 100; ++s) {
        auto c = at::config(s, "k",
                                      std::string(100 - 19 -
                                                      (s < 10    ? 0
                                                       : s < 100 ? 1
                                                                 : 2),
                                                  'v'));
        ASSERT_TRUE(c);
        ASSERT_EQ(c->size(), 100u);
        cmds.push_back(*c);
    }
    auto d = at::pack(cmds);
    ASSERT_TRUE(d);
    ASSERT_EQ(d->size(), 10u);
    std::string joined;
    for (const auto& dg : *d) {
        EXPECT_LE(dg.size(), at::kMaxDatagramBytes);
        EXPECT_EQ(dg.size(), 1000u);
        EXPECT_EQ(dg.substr(0, 3), "AT*");
        EXPECT_EQ(dg.back(), '\r');
        joined += dg;
    }
    std::string expected;
    for (const auto& c : cmds) expected += c;
    EXPECT_EQ(joined, expected);
}

TEST(AtPack, ExactFitStaysInOneDatagram) {
    // Two commands of 512 bytes fill 1024 exactly; a third byte-wise would overflow.
    auto a = at::config(1, "k", std::string(512 - 19, 'a'));
    auto b = at::config(2, "k", std::string(512 - 19, 'b'));
    auto c = at::ftrim(3);
    ASSERT_TRUE(a && b);
    const std::vector<std::string> cmds{*a, *b, c};
    auto d = at::pack(cmds);
    ASSERT_TRUE(d);
    ASSERT_EQ(d->size(), 2u);
    EXPECT_EQ((*d)[0].size(), 1024u);
    EXPECT_EQ((*d)[1], "AT*FTRIM=3\r");
}

TEST(AtPack, SmallerLimitIsHonoured) {
    const std::vector<std::string> cmds{at::hover(1), at::hover(2),
                                        at::hover(3)};  // 21 B each
    auto d = at::pack(cmds, 42);
    ASSERT_TRUE(d);
    ASSERT_EQ(d->size(), 2u);
    EXPECT_EQ((*d)[0], "AT*PCMD=1,0,0,0,0,0\rAT*PCMD=2,0,0,0,0,0\r");
    EXPECT_EQ((*d)[1], "AT*PCMD=3,0,0,0,0,0\r");
}

TEST(AtPack, SingleCommandOverLimitIsAnError) {
    const std::vector<std::string> cmds{at::hover(1),
                                        "AT*X=1," + std::string(1020, '1') + "\r"};
    auto d = at::pack(cmds);
    ASSERT_FALSE(d);
    EXPECT_EQ(d.error(), at::AtError::CommandTooLong);
}

TEST(AtPack, RejectsUnterminatedOrMultipleCommands) {
    const std::vector<std::string> no_cr{"AT*COMWDG=1"};
    EXPECT_EQ(at::pack(no_cr).error(), at::AtError::Unterminated);
    const std::vector<std::string> two{"AT*COMWDG=1\rAT*COMWDG=2\r"};
    EXPECT_EQ(at::pack(two).error(), at::AtError::Unterminated);
    const std::vector<std::string> lf{"AT*COMWDG=1\n\r"};
    EXPECT_EQ(at::pack(lf).error(), at::AtError::Unterminated);
}

TEST(AtPack, EmptyInputGivesNoDatagram) {
    auto d = at::pack(std::span<const std::string>{});
    ASSERT_TRUE(d);
    EXPECT_TRUE(d->empty());
}

TEST(AtPack, PackIntoReusesOutput) {
    std::vector<std::string> out;
    const std::vector<std::string> three{at::hover(1), at::hover(2),
                                         at::hover(3)};
    auto n = at::pack_into(three, out, 21);
    ASSERT_TRUE(n);
    EXPECT_EQ(*n, 3u);
    const std::vector<std::string> one{at::comwdg(4)};
    n = at::pack_into(one, out, 21);
    ASSERT_TRUE(n);
    ASSERT_EQ(*n, 1u);
    EXPECT_EQ(out[0], "AT*COMWDG=4\r");
    EXPECT_GE(out.size(), 3u);  // elements kept for reuse; only out[0..n) is meaningful
}
