// Issue 14 point 7: a frames.csv with only frame,t_ms,roll_deg (allowed) made the classifier flag
// all three regions in most frames without a word. replay and eval now say which inputs the
// classifier lacked and what that costs (the window shows the same lines: app/session).
#include "cli_test_util.hpp"
#include "support/dataset_fixtures.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>

namespace gs::test::missing_inputs {  // named: the app tests are one unity build
namespace {
namespace fs = std::filesystem;

const fs::path kFlight = fs::path(GS_TEST_DATA_DIR) / "flights" / "ci_pillar_left";

// The shipped flight with frames.csv cut down to the required columns.
fs::path attitude_only_flight(const std::string& name) {
    const auto dir = scratch_dir("missing_inputs", name);
    copy_attitude_only(kFlight, dir / "flight");
    return dir;
}

TEST(MissingInputs, ReplaySaysWhatTheClassifierLackedAndWhatItCosts) {
    const auto dir = attitude_only_flight("replay");
    const auto r =
        run_cli("replay -q " + (dir / "flight").string() + " --out " + (dir / "out").string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    for (const char* what : {"no velocity (vx_mps, vy_mps, vz_mps) in 100 % of the frames",
                             "no altitude", "no attitude (pitch, yaw)", "time to contact alone"})
        EXPECT_NE(r.out.find(what), std::string::npos) << what << "\n" << r.out;
    EXPECT_EQ(r.out.find("no roll"), std::string::npos) << r.out;
    const auto j = nlohmann::json::parse(read_text(dir / "out" / "summary.json"));
    ASSERT_EQ(j["missing_inputs"].size(), 3u) << j["missing_inputs"].dump();
    EXPECT_EQ(j["missing_inputs"][0]["input"], "velocity");
    EXPECT_EQ(j["missing_inputs"][0]["unknown_share"], 1.0);

    // The thesis classifier uses the roll alone: nothing is missing for it.
    const auto t = run_cli("replay -q --classifier thesis " + (dir / "flight").string() +
                           " --out " + (dir / "out_thesis").string());
    ASSERT_EQ(t.exit_code, 0) << t.out;
    EXPECT_EQ(t.out.find("note:"), std::string::npos) << t.out;

    // A complete flight has no note.
    const auto full =
        run_cli("replay -q " + kFlight.string() + " --out " + (dir / "out_full").string());
    ASSERT_EQ(full.exit_code, 0) << full.out;
    EXPECT_EQ(full.out.find("note:"), std::string::npos) << full.out;
}

TEST(MissingInputs, EvalReportsThemPerFlight) {
    const auto dir = attitude_only_flight("eval");
    const auto r =
        run_cli("eval -q " + (dir / "flight").string() + " --out " + (dir / "out").string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const std::string md = read_text(dir / "out" / "report.md");
    EXPECT_NE(md.find("## Inputs the classifier lacked"), std::string::npos) << md;
    EXPECT_NE(md.find("no velocity"), std::string::npos) << md;
    const auto j = nlohmann::json::parse(read_text(dir / "out" / "report.json"));
    EXPECT_EQ(j["flights"][0]["missing_inputs"].size(), 3u);
}

}  // namespace
}  // namespace gs::test::missing_inputs
