#include "drone/protocol/config.hpp"

#include <gtest/gtest.h>

#include <random>

using namespace gs;
using namespace gs::protocol;

namespace {
// Lines quoted in docs/protocol.md §5.2 from a real AR.Drone dump.
constexpr std::string_view kDump =
    "general:num_version_config = 1\n"
    "general:ardrone_name = My Drone\n"
    "general:soft_build_date = 2011-07-13 09:52\n"
    "control:altitude_max = 3000\n"
    "control:euler_angle_max = 1.5000001e-01\n"
    "control:gyros_offset = { 1.6490200e+03 1.6510120e+03 1.6575740e+03 }\n"
    "general:navdata_demo = TRUE\n"
    "network:owner_mac = 00:00:00:00:00:00\n"
    "control:flight_anim = 0,0\n";

std::span<const std::uint8_t> bytes(std::string_view s) {
    return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}
}  // namespace

TEST(ConfigDump, ParsesTheRealDumpLinesOfTheProtocolReference) {
    auto c = parse_config_dump(kDump);
    ASSERT_TRUE(c);
    EXPECT_EQ(c->size(), 9u);
    EXPECT_EQ(c->get("general:ardrone_name"), "My Drone");
    EXPECT_EQ(c->get("general:soft_build_date"), "2011-07-13 09:52");
    EXPECT_EQ(config_int(*c->get("control:altitude_max")), 3000);
    EXPECT_NEAR(*config_float(*c->get("control:euler_angle_max")), 0.15, 1e-7);
    auto g = config_vector(*c->get("control:gyros_offset"));
    ASSERT_TRUE(g);
    ASSERT_EQ(g->size(), 3u);
    EXPECT_DOUBLE_EQ((*g)[2], 1657.574);
    EXPECT_EQ(config_bool(*c->get("general:navdata_demo")), true);
    EXPECT_EQ(c->get("network:owner_mac"), "00:00:00:00:00:00");
    EXPECT_EQ(c->get("control:flight_anim"), "0,0");
    EXPECT_FALSE(c->get("control:missing"));
}

TEST(ConfigDump, FormatThenParseRoundTrips) {
    auto c = parse_config_dump(kDump);
    ASSERT_TRUE(c);
    const std::string dump = format_config_dump(*c);
    EXPECT_EQ(dump.back(), '\0');
    auto again = parse_config_dump(dump);
    ASSERT_TRUE(again);
    EXPECT_EQ(again->entries(), c->entries());
}

TEST(ConfigDump, ReaderAssemblesAnyChunkingUpToTheNul) {
    auto c = parse_config_dump(kDump);
    const std::string dump = format_config_dump(*c) + "general:next = 1\n";
    std::mt19937 rng(7);
    for (int trial = 0; trial < 50; ++trial) {
        ConfigDumpReader r;
        std::optional<Expected<ConfigMap, ConfigParseError>> got;
        std::size_t pos = 0;
        int completions = 0;
        while (pos < dump.size()) {
            std::size_t n = std::min<std::size_t>(1 + rng() % 40, dump.size() - pos);
            auto res = r.push(bytes(std::string_view(dump).substr(pos, n)));
            if (res) {
                got = std::move(res);
                ++completions;
            }
            pos += n;
        }
        ASSERT_EQ(completions, 1);
        ASSERT_TRUE(*got);
        EXPECT_EQ((*got)->entries(), c->entries());
        EXPECT_EQ(r.buffered(), std::string_view("general:next = 1\n").size());
    }
}

TEST(ConfigDump, MalformedLinesAreReportedWithTheirLineNumber) {
    auto bad = parse_config_dump("a:b = 1\nno equals here\n");
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.error().error, ConfigError::MissingEquals);
    EXPECT_EQ(bad.error().line, 2u);
    auto empty_key = parse_config_dump(" = 3\n");
    ASSERT_FALSE(empty_key);
    EXPECT_EQ(empty_key.error().error, ConfigError::EmptyKey);
    auto bad_key = parse_config_dump("a b:c = 3\n");
    ASSERT_FALSE(bad_key);
    EXPECT_EQ(bad_key.error().error, ConfigError::BadKey);
}

TEST(ConfigDump, AnOversizedDumpIsRefusedWithoutGrowingWithoutBound) {
    ConfigDumpReader r(1024);
    std::string junk(4000, 'x');
    auto res = r.push(bytes(junk));
    ASSERT_TRUE(res);
    ASSERT_FALSE(*res);
    EXPECT_EQ(res->error().error, ConfigError::DumpTooLarge);
    EXPECT_LE(r.buffered(), 1024u);
}

TEST(ConfigValues, FormatsAndTextChecks) {
    EXPECT_EQ(config_format_float(0.15), "1.5000000e-01");
    EXPECT_FALSE(config_int("12a"));
    EXPECT_FALSE(config_bool("true"));
    EXPECT_FALSE(config_vector("{ 1 x }"));
    EXPECT_EQ(config_vector("{ }")->size(), 0u);
    EXPECT_TRUE(config_text_ok("general:navdata_demo"));
    EXPECT_FALSE(config_text_ok("a\"b"));
    EXPECT_FALSE(config_text_ok("a\rb"));
    EXPECT_FALSE(config_text_ok("a\nb"));
}
