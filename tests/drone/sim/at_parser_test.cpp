#include "drone/sim/at_parser.hpp"

#include "drone/protocol/at.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace at = gs::sim::at;
using gs::transport::Endpoint;

namespace {

at::ParsedDatagram parse_ok(std::string_view text) {
    auto p = at::parse_datagram(text);
    EXPECT_TRUE(p) << "datagram rejected: " << text;
    return p ? std::move(*p) : at::ParsedDatagram{};
}

// Encodes, parses, and expects exactly one command equal to `expected` with the same seq.
void expect_round_trip(const std::string& encoded, at::Seq seq,
                       const at::CommandBody& expected) {
    auto p = parse_ok(encoded);
    ASSERT_EQ(p.commands.size(), 1u) << encoded;
    EXPECT_TRUE(p.skipped.empty()) << encoded;
    EXPECT_EQ(p.commands[0].seq, seq);
    EXPECT_EQ(p.commands[0].body, expected) << encoded;
}

}  // namespace

// ---- Round trips: encoder -> parser, one per command ----------------------------------------

TEST(AtRoundTrip, Ref) {
    expect_round_trip(at::ref(26, at::ref_input(true, false)), 26,
                      at::Ref{290718208u});
    expect_round_trip(at::ref(3, 0x80000000u), 3, at::Ref{0x80000000u});
}

TEST(AtRoundTrip, Pcmd) {
    expect_round_trip(at::pcmd(10, at::kPcmdProgressive, -0.1f, 0.8f, -1.0f, 0.3f), 10,
                      at::Pcmd{1, -0.1f, 0.8f, -1.0f, 0.3f});
    expect_round_trip(at::hover(11), 11, at::Pcmd{0, 0.0f, 0.0f, 0.0f, 0.0f});
}

TEST(AtRoundTrip, PcmdMag) {
    expect_round_trip(at::pcmd_mag(12, 5, 0.25f, -0.5f, 0.75f, -0.125f, 0.9f, 0.1f), 12,
                      at::PcmdMag{5, 0.25f, -0.5f, 0.75f, -0.125f, 0.9f, 0.1f});
}

TEST(AtRoundTrip, Ftrim) {
    expect_round_trip(at::ftrim(13), 13, at::Ftrim{});
}

TEST(AtRoundTrip, Calib) {
    expect_round_trip(at::calib(14, 0), 14, at::Calib{0});
}

TEST(AtRoundTrip, Config) {
    expect_round_trip(*at::config(15, "leds:leds_anim", "1,1077936128,3"), 15,
                      at::Config{"leds:leds_anim", "1,1077936128,3"});
    expect_round_trip(*at::config(16, "general:ardrone_name", ""), 16,
                      at::Config{"general:ardrone_name", ""});
}

TEST(AtRoundTrip, ConfigIds) {
    expect_round_trip(*at::config_ids(17, "d2e081a3", "be27e2e4", "d87f7e0c"), 17,
                      at::ConfigIds{"d2e081a3", "be27e2e4", "d87f7e0c"});
}

TEST(AtRoundTrip, Comwdg) {
    expect_round_trip(at::comwdg(18), 18, at::Comwdg{});
}

TEST(AtRoundTrip, Ctrl) {
    expect_round_trip(at::ctrl(19, at::CtrlMode::Ack), 19, at::Ctrl{5, 0});
    expect_round_trip(at::ctrl(20, at::CtrlMode::CfgGet), 20, at::Ctrl{4, 0});
}

TEST(AtRoundTrip, Led) {
    expect_round_trip(at::led(21, 9, 2.0f, 3), 21, at::Led{9, 2.0f, 3});
}

TEST(AtRoundTrip, Anim) {
    expect_round_trip(at::anim(22, 8, 2000), 22, at::Anim{8, 2000});
}

TEST(AtRoundTrip, PackedDatagramKeepsOrderAndSeqs) {
    at::SeqCounter seq;
    std::vector<std::string> cmds{at::ref(seq.next(), at::kRefBase),
                                  at::hover(seq.next()),
                                  *at::config_ids(seq.next(), "00000000", "00000000", "00000000"),
                                  *at::config(seq.next(), "general:navdata_demo", "TRUE"),
                                  at::ctrl(seq.next(), at::CtrlMode::Ack)};
    auto dgs = at::pack(cmds);
    ASSERT_TRUE(dgs);
    ASSERT_EQ(dgs->size(), 1u);
    auto p = parse_ok((*dgs)[0]);
    ASSERT_EQ(p.commands.size(), 5u);
    for (std::size_t i = 0; i < 5; ++i) EXPECT_EQ(p.commands[i].seq, i + 1);
    EXPECT_TRUE(std::holds_alternative<at::Ref>(p.commands[0].body));
    EXPECT_TRUE(std::holds_alternative<at::Pcmd>(p.commands[1].body));
    EXPECT_TRUE(std::holds_alternative<at::ConfigIds>(p.commands[2].body));
    EXPECT_EQ(p.commands[3].body,
              (at::CommandBody{at::Config{"general:navdata_demo", "TRUE"}}));
    EXPECT_EQ(p.commands[4].body, (at::CommandBody{at::Ctrl{5, 0}}));
}

// ---- Accepted variants ----------------------------------------------------------------------

TEST(AtParser, AcceptsLfTerminatorsLikeDeveloperGuideExample) {
    auto p = parse_ok("AT*PCMD=21625,1,0,0,0,0\nAT*REF=21626,290717696\n");
    ASSERT_EQ(p.commands.size(), 2u);
    EXPECT_EQ(p.commands[0].seq, 21625u);
    EXPECT_EQ(p.commands[0].body, (at::CommandBody{at::Pcmd{1, 0, 0, 0, 0}}));
    EXPECT_EQ(p.commands[1].body, (at::CommandBody{at::Ref{290717696u}}));
    EXPECT_TRUE(p.skipped.empty());
}

TEST(AtParser, AcceptsCrLfAndIgnoresEmptyLines) {
    auto p = parse_ok("AT*COMWDG=1\r\n\r\nAT*COMWDG=2\r\n");
    ASSERT_EQ(p.commands.size(), 2u);
    EXPECT_EQ(p.commands[1].seq, 2u);
    EXPECT_TRUE(p.skipped.empty());
}

TEST(AtParser, AcceptsTrailingCommaFtrim) {
    auto p = parse_ok("AT*FTRIM=5,\r");
    ASSERT_EQ(p.commands.size(), 1u);
    EXPECT_EQ(p.commands[0].seq, 5u);
    EXPECT_EQ(p.commands[0].body, (at::CommandBody{at::Ftrim{}}));
}

TEST(AtParser, NodeFirstCommandSeqZeroParses) {
    // The parser accepts 0; ignoring it is the SeqFilter's job.
    auto p = parse_ok("AT*REF=0,0\rAT*PCMD=1,0,0,0,0,0\r");
    ASSERT_EQ(p.commands.size(), 2u);
    EXPECT_EQ(p.commands[0].seq, 0u);
}

TEST(AtParser, EmptyDatagramHasNoCommands) {
    auto p = parse_ok("");
    EXPECT_TRUE(p.commands.empty());
    EXPECT_TRUE(p.skipped.empty());
}

TEST(AtParser, ExactlyMaxSizeIsAccepted) {
    auto cmd = at::config(1, "k", std::string(1005, 'x'));
    ASSERT_TRUE(cmd);
    ASSERT_EQ(cmd->size(), 1024u);
    auto p = parse_ok(*cmd);
    ASSERT_EQ(p.commands.size(), 1u);
}

// ---- Rejections -----------------------------------------------------------------------------

TEST(AtParser, RejectsDatagramOver1024Whole) {
    std::string big;
    while (big.size() <= 1024) big += at::comwdg(1);
    auto p = at::parse_datagram(big);
    ASSERT_FALSE(p);
    EXPECT_EQ(p.error(), at::DatagramError::TooLong);
    EXPECT_FALSE(at::to_string(p.error()).empty());
}

TEST(AtParser, SkipsMalformedCommandsWithReasonAndKeepsTheRest) {
    struct Case {
        std::string line;
        at::SkipReason reason;
    };
    const std::vector<Case> cases{
        {"XX*REF=1,0", at::SkipReason::NotAtCommand},
        {"AT*REF", at::SkipReason::NotAtCommand},
        {"AT*ref=1,0", at::SkipReason::NotAtCommand},
        {"AT*=1,0", at::SkipReason::NotAtCommand},
        {"AT*PMODE=1,2", at::SkipReason::UnknownCommand},
        {"AT*REF=,0", at::SkipReason::BadSequence},
        {"AT*REF=-1,0", at::SkipReason::BadSequence},
        {"AT*REF=2147483648,0", at::SkipReason::BadSequence},
        {"AT*REF=x,0", at::SkipReason::BadSequence},
        {"AT*REF=1,2147483648", at::SkipReason::BadNumber},
        {"AT*REF=1,99999999999999999999999", at::SkipReason::BadNumber},
        {"AT*REF=1,12a", at::SkipReason::BadNumber},
        {"AT*REF=1, 5", at::SkipReason::BadNumber},
        {"AT*REF=1,\"5\"", at::SkipReason::BadNumber},
        {"AT*PCMD=1,1,0,0,,0", at::SkipReason::BadNumber},
        {"AT*REF=1", at::SkipReason::WrongArgCount},
        {"AT*REF=1,0,0", at::SkipReason::WrongArgCount},
        {"AT*CTRL=1,5", at::SkipReason::WrongArgCount},  // UCAPA style; SDK needs two
        {"AT*PCMD=1,1,0,0,0", at::SkipReason::WrongArgCount},
        {"AT*PCMD_MAG=1,1,0,0,0,0,0,0,0,0,0,0", at::SkipReason::WrongArgCount},
        {"AT*COMWDG=1,,", at::SkipReason::WrongArgCount},
        {"AT*CONFIG=1,\"k\"", at::SkipReason::WrongArgCount},
        {"AT*CONFIG=1,\"k\",v", at::SkipReason::BadString},
        {"AT*CONFIG=1,\"k\",\"v", at::SkipReason::BadString},
        {"AT*CONFIG=1,\"k\"x,\"v\"", at::SkipReason::BadString},
        {"AT*CONFIG=1,\"k\",\"a\tb\"", at::SkipReason::BadString},
    };
    std::string dg;
    for (const auto& c : cases) dg += c.line + '\r';
    dg += at::comwdg(7);  // a good command after all the bad ones still gets through
    ASSERT_LE(dg.size(), at::kMaxDatagramBytes);
    auto p = parse_ok(dg);
    ASSERT_EQ(p.skipped.size(), cases.size());
    std::size_t offset = 0;
    for (std::size_t i = 0; i < cases.size(); ++i) {
        EXPECT_EQ(p.skipped[i].reason, cases[i].reason)
            << cases[i].line << " -> " << at::to_string(p.skipped[i].reason);
        EXPECT_EQ(p.skipped[i].offset, offset) << cases[i].line;
        offset += cases[i].line.size() + 1;
    }
    ASSERT_EQ(p.commands.size(), 1u);
    EXPECT_EQ(p.commands[0].body, (at::CommandBody{at::Comwdg{}}));
}

TEST(AtParser, CountsUnterminatedTail) {
    auto p = parse_ok("AT*COMWDG=1\rAT*COMWDG=2");
    ASSERT_EQ(p.commands.size(), 1u);
    ASSERT_EQ(p.skipped.size(), 1u);
    EXPECT_EQ(p.skipped[0], (at::Skipped{at::SkipReason::Unterminated, 12}));
}

TEST(AtParser, QuotedCommaDoesNotSplitValue) {
    auto p = parse_ok("AT*CONFIG=3,\"control:flight_anim\",\"8,2000\"\r");
    ASSERT_EQ(p.commands.size(), 1u);
    EXPECT_EQ(p.commands[0].body,
              (at::CommandBody{at::Config{"control:flight_anim", "8,2000"}}));
}

TEST(AtParser, ParseIntoReusesAndClears) {
    at::ParsedDatagram out;
    const std::string a = "AT*COMWDG=1\rAT*COMWDG=2\rbad\r";
    auto n = at::parse_datagram_into(
        {reinterpret_cast<const std::uint8_t*>(a.data()), a.size()}, out);
    ASSERT_TRUE(n);
    EXPECT_EQ(*n, 2u);
    EXPECT_EQ(out.skipped.size(), 1u);
    const std::string b = "AT*FTRIM=3\r";
    n = at::parse_datagram_into({reinterpret_cast<const std::uint8_t*>(b.data()), b.size()},
                                     out);
    ASSERT_TRUE(n);
    EXPECT_EQ(*n, 1u);
    EXPECT_EQ(out.commands.size(), 1u);
    EXPECT_TRUE(out.skipped.empty());
}

TEST(AtParser, EveryReasonHasText) {
    for (std::size_t i = 0; i < at::kSkipReasonCount; ++i) {
        EXPECT_NE(at::to_string(static_cast<at::SkipReason>(i)), "unknown skip reason");
    }
}

// ---- Fuzz-style: random bytes, truncations, huge numbers never crash ------------------------

TEST(AtParserFuzz, RandomAndMutatedBytesNeverCrashAndAccountForEveryLine) {
    std::mt19937 rng(12345);
    // Random bytes from an AT-ish alphabet or any byte, and valid datagrams with a few bytes
    // mutated, so both the shallow and the deep parsing paths are exercised.
    const std::string alphabet = "AT*REFPCMD_GONFIWLX=,\"\r\n0123456789-";
    const std::string valid =
        at::ref(1, at::kRefBase) + at::pcmd(2, 1, 0.1f, 0.2f, 0.3f, 0.4f) +
        *at::config(3, "general:navdata_demo", "TRUE") + at::ftrim(4) +
        at::ctrl(5, at::CtrlMode::Ack) + at::led(6, 1, 3.0f, 3);
    std::vector<std::uint8_t> buf;
    std::size_t total_commands = 0, total_skipped = 0;
    for (int iter = 0; iter < 20000; ++iter) {
        if (iter % 2 == 0) {
            buf.assign(valid.begin(), valid.end());
            const int mutations = 1 + static_cast<int>(rng() % 3);
            for (int m = 0; m < mutations; ++m) {
                buf[rng() % buf.size()] =
                    iter % 4 == 0 ? static_cast<std::uint8_t>(rng())
                                  : static_cast<std::uint8_t>(alphabet[rng() % alphabet.size()]);
            }
        } else {
            buf.resize(std::uniform_int_distribution<std::size_t>(0, 1100)(rng));
            const bool any_byte = iter % 4 == 1;
            for (auto& b : buf) {
                b = any_byte ? static_cast<std::uint8_t>(rng())
                             : static_cast<std::uint8_t>(alphabet[rng() % alphabet.size()]);
            }
        }
        auto p = at::parse_datagram(buf);
        if (buf.size() > at::kMaxDatagramBytes) {
            EXPECT_FALSE(p);
            continue;
        }
        ASSERT_TRUE(p);
        total_commands += p->commands.size();
        total_skipped += p->skipped.size();
        // Every non-empty line is either a command or a skip: nothing dropped silently.
        std::size_t lines = 0;
        std::size_t start = 0;
        for (std::size_t i = 0; i <= buf.size(); ++i) {
            if (i == buf.size() || buf[i] == '\r' || buf[i] == '\n') {
                if (i > start) ++lines;
                start = i + 1;
            }
        }
        ASSERT_EQ(p->commands.size() + p->skipped.size(), lines);
    }
    EXPECT_GT(total_commands, 0u);
    EXPECT_GT(total_skipped, 0u);
}

TEST(AtParserFuzz, EveryTruncationOfAValidDatagramIsSafe) {
    at::SeqCounter seq;
    const std::vector<std::string> cmds{
        at::ref(seq.next(), at::kRefBase),
        at::pcmd(seq.next(), 1, 0.1f, -0.2f, 0.3f, -0.4f),
        at::pcmd_mag(seq.next(), 5, 0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f),
        *at::config_ids(seq.next(), "00000000", "00000000", "00000000"),
        *at::config(seq.next(), "general:navdata_demo", "TRUE"),
        at::led(seq.next(), 1, 3.0f, 3),
        at::anim(seq.next(), 8, 2000),
        at::ftrim(seq.next()),
        at::calib(seq.next()),
        at::comwdg(seq.next()),
        at::ctrl(seq.next(), at::CtrlMode::Ack)};
    std::string full;
    for (const auto& c : cmds) full += c;
    for (std::size_t len = 0; len <= full.size(); ++len) {
        auto p = parse_ok(std::string_view(full).substr(0, len));
        // Truncation only ever loses the cut command; all complete ones before it survive.
        std::size_t complete = 0, bytes = 0;
        while (complete < cmds.size() && bytes + cmds[complete].size() <= len) {
            bytes += cmds[complete++].size();
        }
        ASSERT_EQ(p.commands.size(), complete) << "len " << len;
        EXPECT_EQ(p.skipped.size(), len > bytes ? 1u : 0u) << "len " << len;
    }
}

TEST(AtParserFuzz, HugeNumbersAndManyFieldsAreSkipped) {
    std::string many = "AT*PCMD=1";
    for (int i = 0; i < 400; ++i) many += ",0";
    many += '\r';
    auto p = parse_ok(many);
    EXPECT_TRUE(p.commands.empty());
    ASSERT_EQ(p.skipped.size(), 1u);
    EXPECT_EQ(p.skipped[0].reason, at::SkipReason::WrongArgCount);

    const std::string huge =
        "AT*REF=" + std::string(900, '9') + ",0\rAT*REF=1,-" + std::string(50, '9') + "\r";
    p = parse_ok(huge);
    EXPECT_TRUE(p.commands.empty());
    ASSERT_EQ(p.skipped.size(), 2u);
    EXPECT_EQ(p.skipped[0].reason, at::SkipReason::BadSequence);
    EXPECT_EQ(p.skipped[1].reason, at::SkipReason::BadNumber);

    p = parse_ok("AT*REF=1,-2147483648\rAT*REF=2147483647,2147483647\r");
    ASSERT_EQ(p.commands.size(), 2u);
    EXPECT_EQ(p.commands[0].body, (at::CommandBody{at::Ref{0x80000000u}}));
    EXPECT_EQ(p.commands[1].seq, 2147483647u);
}

// ---- Sequence filter (§2.2) -----------------------------------------------------------------

TEST(AtSeqFilter, AcceptsOnlyIncreasingNumbers) {
    at::SeqFilter f;
    const Endpoint c = Endpoint::loopback(40000);
    EXPECT_TRUE(f.accept(c, 1));
    EXPECT_TRUE(f.accept(c, 2));
    EXPECT_TRUE(f.accept(c, 5));   // gaps are fine (lost datagrams)
    EXPECT_FALSE(f.accept(c, 5));  // duplicate
    EXPECT_FALSE(f.accept(c, 3));  // late, reordered
    EXPECT_TRUE(f.accept(c, 6));
    EXPECT_EQ(f.last_accepted(), 6u);
    EXPECT_EQ(f.accepted(), 4u);
    EXPECT_EQ(f.rejected(), 2u);
}

TEST(AtSeqFilter, FirstCommandNumberedZeroIsIgnored) {
    at::SeqFilter f;
    const Endpoint c = Endpoint::loopback(40000);
    EXPECT_FALSE(f.accept(c, 0));  // NODE's first command (§10 #4)
    EXPECT_TRUE(f.accept(c, 1));
}

TEST(AtSeqFilter, SeqOneRestartsTheCounter) {
    at::SeqFilter f;
    const Endpoint c = Endpoint::loopback(40000);
    EXPECT_TRUE(f.accept(c, 1000));
    EXPECT_FALSE(f.accept(c, 999));
    EXPECT_TRUE(f.accept(c, 1));  // restarted ground station
    EXPECT_TRUE(f.accept(c, 2));
    EXPECT_FALSE(f.accept(c, 2));
    EXPECT_EQ(f.restarts(), 1u);
}

TEST(AtSeqFilter, NewClientResetsTheCounter) {
    at::SeqFilter f;
    const Endpoint a = Endpoint::loopback(40000);
    const Endpoint b = Endpoint::loopback(40001);  // same host, new source port
    EXPECT_TRUE(f.accept(a, 500));
    EXPECT_TRUE(f.accept(b, 10));  // would be stale for a, but b is a new client
    EXPECT_EQ(f.restarts(), 1u);
    EXPECT_FALSE(f.accept(b, 9));
    EXPECT_TRUE(f.accept(a, 20));  // back to a: starts afresh too
    EXPECT_EQ(f.restarts(), 2u);
    const Endpoint other_host = Endpoint::from_octets(192, 168, 1, 2, 40000);
    EXPECT_TRUE(f.accept(other_host, 3));
}

TEST(AtSeqFilter, FiltersParsedCommandsOfADatagram) {
    // REF 5 + PCMD 6 accepted, then a reordered old datagram (3, 4) is ignored whole.
    at::SeqFilter f;
    const Endpoint c = Endpoint::loopback(40000);
    int accepted = 0;
    for (const char* dg : {"AT*REF=5,290717696\rAT*PCMD=6,0,0,0,0,0\r",
                           "AT*REF=3,290717696\rAT*PCMD=4,0,0,0,0,0\r"}) {
        for (const auto& cmd : parse_ok(dg).commands) accepted += f.accept(c, cmd.seq) ? 1 : 0;
    }
    EXPECT_EQ(accepted, 2);
    EXPECT_EQ(f.rejected(), 2u);
}
