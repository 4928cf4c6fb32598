// The flow classifier's FOE when the navdata and the images disagree (FlowParams::foe_arbitrate),
// on a flight of the closed-loop suite: seed 2027's fifth open flight at 1.5 m/s, flown with the
// assist off and recorded, then replayed. In its first metres (the drone pitching to accelerate,
// over a tiled floor) the images' FOE sits 90-120 px below the navdata's while the tracked points'
// fitted flows run radially from the navdata's; rated about the images' FOE, floor points read a
// third of their time to contact and land inside the corridor: a centre alarm in open space,
// which braked the assist. With the points arbitrating, the navdata's FOE is used and the centre
// stays quiet, while every obstacle flight of the offline suites is still caught (README).

#include "cli_test_util.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>

namespace gs::test {
namespace {

namespace fs = std::filesystem;

nlohmann::json replay_summary(const fs::path& flight, const fs::path& out, const std::string& set) {
    const CmdResult r =
        run_cli("replay " + flight.string() + " -q --strict " + set + " --out " + out.string());
    EXPECT_EQ(r.exit_code, 0) << r.out;
    std::ifstream in(out / "summary.json");
    return nlohmann::json::parse(in);
}

TEST(FoeArbitration, AnOpenFlightsFirstMetresRaiseNoCentreAlarmWhenThePointsSideWithTheNavdata) {
    const fs::path out = scratch_dir("foe_arbitration", "flight");
    const CmdResult r = run_cli(
        "eval-assist --speeds 1.5 --assist off --only open-none-1.5-15 -q --seed 2027 --record "
        "--out " +
        out.string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const fs::path flight = out / "open-none-1.5-15-off";
    ASSERT_TRUE(fs::exists(flight / "frames.csv"));

    // The images decide (the old rule): the centre alarms in open space.
    const auto before = replay_summary(flight, out / "images_decide", "--set foe_arbitrate=0");
    const int centre_before = before["flagged_frames"]["center"].get<int>();
    EXPECT_GE(centre_before, 10);

    // The default: the points arbitrate, and nothing is flagged ahead.
    const auto now = replay_summary(flight, out / "arbitrated", "");
    EXPECT_EQ(now["flagged_frames"]["center"].get<int>(), 0);
    EXPECT_EQ(now["parameters"]["foe_arbitrate"].get<double>(), 2.0);
    // Not by judging less: the centre is as often measured as before.
    EXPECT_EQ(now["unknown_frames"]["center"], before["unknown_frames"]["center"]);
    EXPECT_EQ(now["frames"], before["frames"]);
}

}  // namespace
}  // namespace gs::test
