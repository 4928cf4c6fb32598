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
    const std::string md = read_text(out / "report.md");
    EXPECT_NE(md.find("# Collision-prevention assist"), std::string::npos);
    EXPECT_NE(read_text(out / "stopping.svg").find("<svg"), std::string::npos);
}

}  // namespace
}  // namespace gs::test
