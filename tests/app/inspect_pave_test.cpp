// `ardrone-gs inspect pave` run as a process on the real captures.
#include "cli_test_util.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <string>

namespace {

using RunResult = gs::test::CmdResult;

std::string capture(const std::string& name) {
    return std::string(GS_FIXTURES_DIR) + "/ardrone/" + name;
}

TEST(InspectPave, JsonListsTheTwentyFramesWithTheirNumbers) {
    const RunResult r =
        gs::test::run_cli_stdout("inspect pave " + capture("node-ar-drone_pave.bin") + " --json");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["file_size"], 102747);
    ASSERT_EQ(j["frames"].size(), 20u);
    for (std::size_t i = 0; i < 20; ++i) {
        const auto& f = j["frames"][i];
        EXPECT_EQ(f["index"], i);
        EXPECT_EQ(f["frame_number"], i == 0 ? 17368u : 17562u + i);
        EXPECT_EQ(f["header_size"], 64);
        EXPECT_EQ(f["signature"], "PaVE");
        EXPECT_EQ(f["frame_type_name"], (i == 3 || i == 18) ? "IDR" : "P");
    }
    const auto& f0 = j["frames"][0];
    EXPECT_EQ(f0["offset"], 0);
    EXPECT_EQ(f0["payload_size"], 2632);
    EXPECT_EQ(f0["timestamp"], 1792570814u);
    EXPECT_EQ(f0["stream_byte_position_lw"], 72366960u);
    EXPECT_EQ(f0["stream_id"], 5);
    EXPECT_EQ(f0["advertised_size"], 2632);
    EXPECT_EQ(f0["video_codec"], 4);
    EXPECT_EQ(j["frames"][1]["offset"], 2696);
    EXPECT_TRUE(j["resyncs"].empty());
    EXPECT_TRUE(j["trailing"].is_null());
    EXPECT_EQ(j["stats"]["frames"], 20);
}

TEST(InspectPave, JsonReportsTheResyncAndTheTrailingPartialFrame) {
    const RunResult r = gs::test::run_cli_stdout(
        "inspect pave " + capture("uav-pilot_ardrone_video_stream_dump_bad_pave.bin") + " --json");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["frames"].size(), 23u);
    ASSERT_EQ(j["resyncs"].size(), 1u);
    EXPECT_EQ(j["resyncs"][0]["offset"], 12355);
    EXPECT_EQ(j["resyncs"][0]["resume_offset"], 14991);
    EXPECT_EQ(j["resyncs"][0]["bytes_skipped"], 2636);
    EXPECT_EQ(j["frames"][1]["offset"], 14991);
    EXPECT_EQ(j["frames"][1]["frame_number"], 17083);
    ASSERT_TRUE(j["trailing"].is_object());
    EXPECT_EQ(j["trailing"]["header"]["frame_number"], 17105);
    EXPECT_EQ(j["trailing"]["header"]["payload_size"], 2864);
    EXPECT_EQ(j["trailing"]["payload_bytes_present"], 205);
    EXPECT_EQ(j["trailing"]["offset"], 102127);
}

TEST(InspectPave, TextListsEveryFrameAndTheSummary) {
    const RunResult r =
        gs::test::run_cli_stdout("inspect pave " + capture("node-ar-drone_pave-68.bin"));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_NE(r.out.find("245401"), std::string::npos);
    EXPECT_NE(r.out.find("245405"), std::string::npos);
    EXPECT_NE(r.out.find("IDR"), std::string::npos);
    EXPECT_NE(r.out.find("24971 bytes: 5 frames"), std::string::npos) << r.out;
}

TEST(InspectPave, DecodeWritesSeventeenPngsFromTheFirstIdr) {
    const auto dir =
        std::filesystem::temp_directory_path() / ("gs_inspect_pave_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    const RunResult r = gs::test::run_cli_stdout(
        "inspect pave " + capture("node-ar-drone_pave.bin") + " --json --decode " + dir.string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["decode"]["images"], 17);
    EXPECT_EQ(j["decode"]["stats"]["skipped_waiting_idr"], 3);
    EXPECT_TRUE(j["frames"][2]["image"].is_null());
    EXPECT_EQ(j["frames"][3]["image"], "000000.png");
    EXPECT_EQ(j["frames"][19]["image"], "000016.png");
    std::size_t files = 0;
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
        (void)e;
        ++files;
    }
    EXPECT_EQ(files, 17u);
    for (int i = 0; i < 17; ++i) {
        char name[32];
        std::snprintf(name, sizeof name, "%06d.png", i);
        const cv::Mat img = cv::imread((dir / name).string(), cv::IMREAD_UNCHANGED);
        ASSERT_FALSE(img.empty()) << name;
        EXPECT_EQ(img.cols, 640);
        EXPECT_EQ(img.rows, 360);
        EXPECT_EQ(img.channels(), 3);
    }
    std::filesystem::remove_all(dir);
}

TEST(InspectPave, MissingFileFailsWithAMessage) {
    const RunResult r = gs::test::run_cli_stdout("inspect pave /nonexistent/capture.bin 2>&1");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.out.find("cannot open /nonexistent/capture.bin: no such file"), std::string::npos)
        << r.out;
}

}  // namespace
