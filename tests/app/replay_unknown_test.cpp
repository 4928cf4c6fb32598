// "Clear" only when measured, headless (issue 13, point 5): a recording with a gap (1 s of
// frames missing) has the frame after it unknown in every region (vision::UnknownReason::Gap),
// the classifier starts again after it, summary.json counts the unknown frames per region and
// why, and decisions.csv keeps its header and its 0/1 decisions (an unknown region is 0: not
// unsafe).
#include "cli_test_util.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace gs::test {
namespace {

namespace fs = std::filesystem;
const fs::path kShippedFlight = fs::path(GS_TEST_DATA_DIR) / "flights" / "ci_pillar_left";

// A copy of the shipped flight whose frames from `from` on were captured `shift_ms` later.
fs::path flight_with_a_gap(const fs::path& dir, int from, double shift_ms) {
    fs::create_directories(dir);
    for (const auto& e : fs::directory_iterator(kShippedFlight))
        if (e.path().filename() != "frames.csv") fs::copy(e.path(), dir / e.path().filename());
    std::ifstream in(kShippedFlight / "frames.csv");
    std::ofstream out(dir / "frames.csv");
    std::string line;
    std::getline(in, line);
    out << line << '\n';
    while (std::getline(in, line)) {
        const auto c1 = line.find(',');
        const auto c2 = line.find(',', c1 + 1);
        const int frame = std::stoi(line.substr(0, c1));
        double t = std::stod(line.substr(c1 + 1, c2 - c1 - 1));
        if (frame >= from) t += shift_ms;
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.6f", t);
        out << frame << ',' << buf << line.substr(c2) << '\n';
    }
    return dir;
}

std::vector<std::vector<std::string>> unknown_test_csv_rows(const fs::path& p) {
    std::vector<std::vector<std::string>> rows;
    std::istringstream in(read_text(p));
    std::string line;
    while (std::getline(in, line)) {
        std::vector<std::string> cells;
        std::string cell;
        std::istringstream ls(line);
        while (std::getline(ls, cell, ',')) cells.push_back(cell);
        if (!line.empty() && line.back() == ',') cells.emplace_back();
        rows.push_back(cells);
    }
    return rows;
}

TEST(ReplayUnknown, AGapMakesTheNextFrameUnknownCountedInTheSummaryNotInDecisionsCsv) {
    const fs::path base = scratch_dir("replay_unknown", "gap");
    const fs::path flight = flight_with_a_gap(base / "flight", 80, 1000.0);
    const fs::path out = base / "out";
    const CmdResult r = run_cli("replay " + flight.string() + " --out " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.out;

    const auto summary = nlohmann::json::parse(read_text(out / "summary.json"));
    ASSERT_TRUE(summary.contains("unknown_frames")) << summary.dump(2);
    ASSERT_TRUE(summary.contains("unknown_reasons"));
    for (const char* region : {"left", "center", "right"}) {
        const auto& why = summary["unknown_reasons"][region];
        ASSERT_TRUE(why.contains("frames missing")) << region << ": " << why.dump();
        EXPECT_EQ(why["frames missing"].get<int>(), 1) << region;
        // The gap frame plus whatever the classifier needs to warm up again.
        EXPECT_GE(summary["unknown_frames"][region].get<int>(), 1) << region;
        EXPECT_LE(summary["unknown_frames"][region].get<int>(), summary["frames"].get<int>());
    }

    // decisions.csv: the same header, one row per frame, decisions 0 or 1 only.
    const auto rows = unknown_test_csv_rows(out / "decisions.csv");
    ASSERT_EQ(rows.size(), 154u);
    const std::vector<std::string> header = {
        "frame",        "t_ms",        "left",       "center",       "right",      "left_score",
        "center_score", "right_score", "left_state", "center_state", "right_state"};
    EXPECT_EQ(rows[0], header);
    for (std::size_t i = 1; i < rows.size(); ++i) {
        ASSERT_EQ(rows[i].size(), 11u) << i;
        for (int c = 2; c < 5; ++c) EXPECT_TRUE(rows[i][c] == "0" || rows[i][c] == "1") << i;
        // The state says what the 0 means: clear, still (only approaching things judged) or
        // unknown; a 1 is always unsafe.
        for (int c = 8; c < 11; ++c) {
            const std::string& st = rows[i][c];
            EXPECT_TRUE(rows[i][c - 6] == "1" ? st == "unsafe"
                                              : st == "clear" || st == "still" || st == "unknown")
                << i << ": " << rows[i][c - 6] << " " << st;
            // Unknown exactly where no score was written.
            EXPECT_EQ(st == "unknown", rows[i][c - 3].empty()) << i << ": " << st;
        }
    }
    // The gap frame is not unsafe anywhere: it is unknown.
    EXPECT_EQ(rows[81][2], "0");
    EXPECT_EQ(rows[81][3], "0");
    EXPECT_EQ(rows[81][4], "0");
    EXPECT_EQ(rows[81][8], "unknown");
    EXPECT_EQ(rows[81][9], "unknown");
    EXPECT_EQ(rows[81][10], "unknown");

    // The shipped flight has no gap: nothing counted as missing.
    const fs::path out2 = base / "out_clean";
    const CmdResult r2 = run_cli("replay " + kShippedFlight.string() + " --out " + out2.string());
    ASSERT_EQ(r2.exit_code, 0) << r2.out;
    const auto clean = nlohmann::json::parse(read_text(out2 / "summary.json"));
    for (const char* region : {"left", "center", "right"})
        EXPECT_FALSE(clean["unknown_reasons"][region].contains("frames missing")) << region;
    fs::remove_all(base);
}

}  // namespace
}  // namespace gs::test
