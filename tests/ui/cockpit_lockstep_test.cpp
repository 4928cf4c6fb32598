// Offscreen runs that mean what they say (issue 13, point 13). The offscreen window steps the
// virtual drone's clock once per window frame (tests/drone/link/lockstep_test.cpp shows the drone
// flies by that clock alone): screenshot k is the flight at k/30 s, on any machine.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace gs::test {
namespace {

namespace fs = std::filesystem;

// The offscreen window on a live source: window frame k is the flight at k/30 s.
TEST(Lockstep, OffscreenLiveFrameKIsTheFlightAtKOver30Seconds) {
    const fs::path out = fs::temp_directory_path() / ("gs_lockstep_" + std::to_string(::getpid()));
    fs::remove_all(out);
    fs::create_directories(out);
    const std::string cmd =
        std::string("xvfb-run -a -s '-screen 0 1920x1080x24' ") + GS_BINARY +
        " --offscreen --sim thesis_pillar_left --autopilot --frames 45 --screenshot-every 15 "
        "--out " +
        out.string() + " >" + (out / "log.txt").string() + " 2>&1";
    const int st = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(st) && WEXITSTATUS(st) == 0) << cmd;
    for (int k : {15, 30, 45}) {
        char name[32];
        std::snprintf(name, sizeof name, "frame_%06d.json", k);
        std::ifstream in(out / name);
        ASSERT_TRUE(in) << name;
        const auto j = nlohmann::json::parse(in);
        // Screenshot k is window frame k - 1, at (k - 1) / 30 s of flight, showing the video
        // frame rendered then.
        EXPECT_NEAR(j["clock_s"].get<double>(), (k - 1) / 30.0, 1e-6) << name;
        EXPECT_EQ(j["video_index"].get<int>(), k - 1) << name;
        EXPECT_EQ(j["status"]["source"], "VIRTUAL DRONE");
    }
    fs::remove_all(out);
}

}  // namespace
}  // namespace gs::test
