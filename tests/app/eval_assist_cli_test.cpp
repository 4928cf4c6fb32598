// `ardrone-gs eval-assist --suite smoke` from the command line: the four outputs exist and parse,
// and report.json's numbers are those of flights.csv's rows.
#include "cli_test_util.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <map>
#include <sstream>

namespace gs::test {
namespace {

namespace fs = std::filesystem;

std::vector<std::map<std::string, std::string>> eval_rows(const fs::path& f) {
    std::vector<std::map<std::string, std::string>> rows;
    std::ifstream in(f);
    std::string line;
    std::vector<std::string> header;
    auto split = [](const std::string& l) {
        std::vector<std::string> c;
        std::stringstream ss(l);
        std::string x;
        while (std::getline(ss, x, ',')) c.push_back(x);
        if (!l.empty() && l.back() == ',') c.emplace_back();
        return c;
    };
    if (std::getline(in, line)) header = split(line);
    while (std::getline(in, line)) {
        const auto c = split(line);
        EXPECT_EQ(c.size(), header.size()) << line;
        std::map<std::string, std::string> r;
        for (std::size_t i = 0; i < header.size() && i < c.size(); ++i) r[header[i]] = c[i];
        rows.push_back(r);
    }
    return rows;
}

TEST(EvalAssistCli, SmokeSuiteWritesReportsThatAgreeWithFlightsCsv) {
    const fs::path out = scratch_dir("eval_assist_cli", "smoke");
    const CmdResult r =
        run_cli("eval-assist --suite smoke --speeds 1.0 --assist both -j 2 -q --seed 3 --out " +
                out.string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    for (const char* f : {"report.json", "flights.csv", "report.md", "stopping.svg"})
        EXPECT_TRUE(fs::exists(out / f)) << f;
    std::ifstream js(out / "report.json");
    const auto j = nlohmann::json::parse(js);
    const auto rows = eval_rows(out / "flights.csv");
    ASSERT_FALSE(rows.empty());
    for (const char* side : {"assist_on", "assist_off"}) {
        const std::string a = std::string(side) == "assist_on" ? "on" : "off";
        int flights = 0, collisions = 0, open = 0, nuisance = 0, completed = 0;
        for (const auto& row : rows) {
            if (row.at("assist") != a) continue;
            ++flights;
            collisions += std::stoi(row.at("collided"));
            completed += std::stoi(row.at("completed"));
            if (row.at("kind") == "open") {
                ++open;
                nuisance += std::stoi(row.at("braked"));
            }
        }
        ASSERT_TRUE(j.contains(side)) << side;
        const auto& s = j[side];
        EXPECT_EQ(s["flights"].get<int>(), flights) << side;
        EXPECT_EQ(s["collisions"].get<int>(), collisions) << side;
        EXPECT_EQ(s["open_flights"].get<int>(), open) << side;
        EXPECT_EQ(s["nuisance_brakes"].get<int>(), nuisance) << side;
        EXPECT_EQ(s["completed"].get<int>(), completed) << side;
        EXPECT_NEAR(s["collision_rate"].get<double>(),
                    flights ? static_cast<double>(collisions) / flights : 0.0, 1e-9);
    }
    // Each brake says what was really ahead when it began: on the pillar flight the pillar,
    // straight ahead, at least as far as the nearest obstacle's clearance (the ray starts at the
    // drone's centre, the clearance at its hull) and within a metre of it.
    int ahead_brakes = 0;
    for (const auto& row : rows) {
        if (row.at("assist") != "on" || row.at("kind") != "ahead" || row.at("braked") != "1")
            continue;
        ++ahead_brakes;
        const double ahead = std::stod(row.at("brake_ahead_m"));
        const double clearance = std::stod(row.at("brake_clearance_m"));
        EXPECT_GE(ahead, clearance) << row.at("name");
        EXPECT_LT(ahead, clearance + 1.0) << row.at("name");
        EXPECT_NEAR(std::stod(row.at("brake_ahead_ttc_s")),
                    ahead / std::stod(row.at("brake_speed_mps")), 0.01)
            << row.at("name");
    }
    EXPECT_GE(ahead_brakes, 1);
    const std::string md = read_text(out / "report.md");
    EXPECT_NE(md.find("# Collision-prevention assist"), std::string::npos);
    EXPECT_NE(read_text(out / "stopping.svg").find("<svg"), std::string::npos);
}

TEST(EvalAssistCli, RecordWritesEachFlightAsADatasetThatReplays) {
    // --record: each flight as a dataset (what the classifier was given, with the ground truth),
    // for `replay` to show why the assist did what it did. --set reaches the classifier.
    const fs::path out = scratch_dir("eval_assist_cli", "record");
    const CmdResult r = run_cli(
        "eval-assist --suite smoke --speeds 1.0 --assist on --only open-none -q --seed 3 "
        "--record --set confirm_frames=3 --out " +
        out.string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    std::ifstream js(out / "report.json");
    const auto j = nlohmann::json::parse(js);
    EXPECT_EQ(j["set"], nlohmann::json::array({"confirm_frames=3"}));
    const auto rows = eval_rows(out / "flights.csv");
    ASSERT_EQ(rows.size(), 1u);
    const fs::path flight = out / (rows[0].at("name") + "-on");
    for (const char* f : {"flight.json", "frames.csv", "video.h264"})
        ASSERT_TRUE(fs::exists(flight / f)) << flight / f;
    const auto frames = eval_rows(flight / "frames.csv");
    // Every frame from the hover before the pilot's start, so at least the flight's own.
    EXPECT_GE(frames.size(), static_cast<std::size_t>(std::stoi(rows[0].at("frames"))));
    EXPECT_FALSE(frames.front().at("gt_x_m").empty());  // the ground truth is there

    const fs::path replayed = out / "replayed";
    const CmdResult rp = run_cli("replay " + flight.string() +
                                 " --strict -q --set confirm_frames=3 --out " + replayed.string());
    ASSERT_EQ(rp.exit_code, 0) << rp.out;
    std::ifstream sj(replayed / "summary.json");
    const auto summary = nlohmann::json::parse(sj);
    EXPECT_EQ(summary["frames"].get<std::size_t>(), frames.size());
    EXPECT_EQ(summary["decode_errors"].get<int>(), 0);
}

TEST(EvalAssistCli, ABadClassifierParameterIsRefusedBeforeAnythingFlies) {
    const fs::path out = scratch_dir("eval_assist_cli", "bad_set");
    const CmdResult r = run_cli(
        "eval-assist --suite smoke --speeds 1.0 -q --set no_such_key=1 --out " + out.string());
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.out.find("no_such_key"), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(out / "report.json"));
}

}  // namespace
}  // namespace gs::test
