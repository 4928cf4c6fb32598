// `ardrone-gs inspect navdata` run as a process (GS_BINARY) on the real captures.
#include "cli_test_util.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <string>

namespace {

using gs::test::CmdResult;

std::string fixture(const char* name) {
    return std::string(GS_FIXTURES_DIR) + "/ardrone/" + name;
}

TEST(InspectNavdata, JsonOfFullCaptureHasTheValues) {
    const CmdResult r = gs::test::run_cli_stdout("inspect navdata " +
                                                 fixture("node-ar-drone_navdata.bin") + " --json");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["header"], 0x55667788U);
    EXPECT_EQ(j["drone_state"], 0x4F8000D0U);
    EXPECT_EQ(j["drone_state_bits"]["COM_WATCHDOG"], true);
    EXPECT_EQ(j["drone_state_bits"]["FLY"], false);
    EXPECT_EQ(j["sequence"], 300711);
    EXPECT_EQ(j["vision_defined"], 1);
    EXPECT_EQ(j["checksum"], 46179);
    EXPECT_EQ(j["options"].size(), 29U);
    EXPECT_EQ(j["options"][27]["name"], "gps");
    EXPECT_EQ(j["file_size"], 2120);

    const auto& d = j["demo"];
    EXPECT_EQ(d["ctrl_state"], 0x00020000);
    EXPECT_EQ(d["ctrl_state_major_name"], "CTRL_LANDED");
    EXPECT_TRUE(d["ctrl_state_minor_name"].is_null());
    EXPECT_EQ(d["vbat_flying_percentage"], 50);
    EXPECT_EQ(d["theta"], 2974.0);
    EXPECT_EQ(d["phi"], 550.0);
    EXPECT_EQ(d["psi"], 1933.0);
    EXPECT_EQ(d["altitude"], 0);
    // The float's exact value survives the JSON text round trip.
    EXPECT_EQ(d["vx"].get<double>(), static_cast<double>(0.0585307739675045f));
    EXPECT_EQ(d["vy"].get<double>(), static_cast<double>(-0.8817979097366333f));

    EXPECT_EQ(j["time"]["time"], 0x2D4EF0B5U);
    EXPECT_EQ(j["time"]["time_seconds"], 362);
    EXPECT_EQ(j["time"]["time_microseconds"], 979125);
    EXPECT_DOUBLE_EQ(j["time"]["time_s"].get<double>(), 362.979125);
    EXPECT_EQ(j["raw_measures"]["raw_accs"], nlohmann::json({2040, 2036, 2528}));
    EXPECT_EQ(j["raw_measures"]["vbat_raw"], 11686);
    EXPECT_EQ(j["pressure_raw"]["Pression_meas"], 101586);
    EXPECT_EQ(j["pressure_raw"]["Temperature_meas"], 435);
    EXPECT_EQ(j["magneto"]["mx"], 30);
    EXPECT_EQ(j["kalman_pressure"]["bool_effet_sol"], 1);
    EXPECT_EQ(j["watchdog"]["watchdog"], 4822);
    EXPECT_EQ(j["video_stream"]["frame_number"], 46105);
    EXPECT_DOUBLE_EQ(j["gps"]["latitude"].get<double>(), 34.0905016);
    EXPECT_DOUBLE_EQ(j["gps"]["longitude"].get<double>(), -118.2766877);
    EXPECT_EQ(j["gps"]["nb_satellites"], 9);
    EXPECT_EQ(j["gps"]["channels"][0], nlohmann::json({{"sat", 10}, {"cn0", 26}}));
    EXPECT_EQ(j["gps"]["channels"][11], nlohmann::json({{"sat", 138}, {"cn0", 0}}));
    EXPECT_FALSE(j.contains("zimmu_3000"));
    EXPECT_TRUE(j["skipped"].empty());
}

TEST(InspectNavdata, JsonReportsOpaqueTag27) {
    const CmdResult r = gs::test::run_cli_stdout(
        "inspect navdata " + fixture("node-ar-drone_navdata_2013.bin") + " --json");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["checksum"], 57639);
    ASSERT_EQ(j["skipped"].size(), 1U);
    EXPECT_EQ(j["skipped"][0]["tag"], 27);
    EXPECT_EQ(j["skipped"][0]["size"], 480);
    EXPECT_FALSE(j.contains("gps"));
}

TEST(InspectNavdata, HumanOutputShowsFieldsUnitsAndBitNames) {
    const CmdResult r = gs::test::run_cli_stdout("inspect navdata " +
                                                 fixture("uav-pilot_navdata_demo_inflight.bin"));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_NE(r.out.find("0x0F8004F5"), std::string::npos);
    EXPECT_NE(
        r.out.find("set: FLY VISION ALTITUDE USER_FEEDBACK_START COMMAND CAMERA NAVDATA_DEMO"),
        std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("[demo]"), std::string::npos);
    EXPECT_NE(r.out.find("[vision_detect]"), std::string::npos);
    EXPECT_NE(r.out.find("-92 mdeg"), std::string::npos);
    EXPECT_NE(r.out.find("14668 mdeg"), std::string::npos);
    EXPECT_NE(r.out.find("534 mm"), std::string::npos);
    EXPECT_NE(r.out.find("CTRL_FLYING, minor 0 OK"), std::string::npos);
    EXPECT_NE(r.out.find("checksum        9187"), std::string::npos);
}

TEST(InspectNavdata, MissingFileFailsWithMessage) {
    const CmdResult r = gs::test::run_cli_stdout("inspect navdata /nonexistent/navdata.bin 2>&1");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.out.find("cannot open /nonexistent/navdata.bin: no such file"), std::string::npos)
        << r.out;
}

TEST(InspectNavdata, BadPacketFailsWithTheReason) {
    const std::string path = ::testing::TempDir() + "inspect_navdata_bad.bin";
    {
        std::ifstream in(fixture("node-ar-drone_navdata_2012.bin"), std::ios::binary);
        std::string bytes(1916, '\0');
        ASSERT_TRUE(in.read(bytes.data(), static_cast<std::streamsize>(bytes.size())));
        bytes[20] = static_cast<char>(bytes[20] + 1);
        std::ofstream(path, std::ios::binary) << bytes;
    }
    const CmdResult r = gs::test::run_cli_stdout("inspect navdata " + path + " 2>&1");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.out.find("bad checksum, expected: 36359, got: 36358"), std::string::npos) << r.out;
    std::remove(path.c_str());
}

}  // namespace
