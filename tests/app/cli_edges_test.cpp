// Issue 14 point 9: command-line edges. Each is refused with one clear line and a non-zero exit
// before any work: directories and FIFOs given as files, empty or non-video captures, frame ranges
// out of bounds or reversed, unknown --split values, negative seeds, unbounded delays, output
// paths that cannot be written, a --out folder that holds someone else's files. Numbers in range
// messages are short, JSON errors carry no library prefix, `sim --quiet` is quiet and a client
// that disconnects is not reported as an error. `params` lists every parameter --set accepts.
#include "cli_test_util.hpp"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

namespace gs::test::cli_edges {  // named: the app tests are one unity build
namespace {
namespace fs = std::filesystem;

const fs::path kFlight = fs::path(GS_TEST_DATA_DIR) / "flights" / "ci_pillar_left";

void write_text(const fs::path& p, const std::string& text) {
    std::ofstream(p, std::ios::binary) << text;
}

// One line, naming the problem; the program's own prefix and no usage dump.
void expect_one_line_error(const CmdResult& r, const std::string& needle) {
    EXPECT_NE(r.exit_code, 0) << r.out;
    EXPECT_NE(r.out.find(needle), std::string::npos) << r.out;
    EXPECT_LE(std::count(r.out.begin(), r.out.end(), '\n'), 2) << r.out;
    EXPECT_EQ(r.out.find("[json.exception"), std::string::npos) << r.out;
}

TEST(CliEdges, DirectoriesAndFifosGivenAsFilesAreRefusedWithoutReading) {
    const auto dir = scratch_dir("cli_edges", "files");
    const auto fifo = dir / "pipe";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    for (const std::string cmd : {"inspect navdata", "inspect pave"}) {
        auto r = run_cli(cmd + " " + dir.string());
        expect_one_line_error(r, "is a directory, not a regular file");
        EXPECT_EQ(r.out.find("9223372036854775807"), std::string::npos) << r.out;
        const auto t0 = std::chrono::steady_clock::now();
        r = run_cli(cmd + " " + fifo.string());
        expect_one_line_error(r, "is a FIFO, not a regular file");
        EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(10));
    }
    auto r = run_cli("calibrate " + fifo.string() + " --board 9x6 --square 0.05");
    expect_one_line_error(r, "is a FIFO, not an image file or a folder");
    r = run_cli("replay " + kFlight.string() + " --out " + (dir / "o").string() +
                " --calibration " + dir.string());
    expect_one_line_error(r, "not a regular file");
}

TEST(CliEdges, InspectPaveOnAnEmptyOrNonVideoFileFails) {
    const auto dir = scratch_dir("cli_edges", "pave");
    write_text(dir / "empty.bin", "");
    write_text(dir / "text.bin", std::string(5000, 'a'));
    auto r = run_cli("inspect pave " + (dir / "empty.bin").string());
    EXPECT_NE(r.exit_code, 0) << r.out;
    EXPECT_NE(r.out.find("no PaVE frame in 0 bytes"), std::string::npos) << r.out;
    r = run_cli("inspect pave --json " + (dir / "text.bin").string());
    EXPECT_NE(r.exit_code, 0) << r.out;
    EXPECT_NE(r.out.find("no PaVE frame in 5000 bytes"), std::string::npos) << r.out;
    // A real capture still passes.
    r = run_cli("inspect pave " + std::string(GS_FIXTURES_DIR) + "/ardrone/node-ar-drone_pave.bin");
    EXPECT_EQ(r.exit_code, 0) << r.out;
}

TEST(CliEdges, OutputPathsAreCheckedBeforeAnyWork) {
    const auto dir = scratch_dir("cli_edges", "out");
    write_text(dir / "afile", "x");
    const auto t0 = std::chrono::steady_clock::now();
    auto r = run_cli("calibrate " + kFlight.string() +
                     " --board 9x6 --square 0.05 --out /missing/dir/c.json");
    expect_one_line_error(r, "/missing/dir does not exist");
    EXPECT_EQ(r.out.find("Calibrating"), std::string::npos) << r.out;  // refused before work
    r = run_cli("odometry " + kFlight.string() + " --out " + (dir / "afile").string());
    expect_one_line_error(r, "is a file, not a directory");
    r = run_cli("replay " + kFlight.string() + " --out " + (dir / "afile" / "x").string());
    expect_one_line_error(r, "is not a directory");
    EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(20));
}

TEST(CliEdges, ReplayRefusesAFolderHoldingOtherFilesUnlessForced) {
    const auto dir = scratch_dir("cli_edges", "replay");
    fs::create_directories(dir / "mine");
    write_text(dir / "mine" / "thesis.pdf", "precious");
    auto r = run_cli("replay -q " + kFlight.string() + " --out " + (dir / "mine").string());
    expect_one_line_error(r, "already holds thesis.pdf");
    EXPECT_FALSE(fs::exists(dir / "mine" / "decisions.csv"));
    // Its own earlier output is written over; --force writes anywhere.
    r = run_cli("replay -q " + kFlight.string() + " --out " + (dir / "own").string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    r = run_cli("replay -q " + kFlight.string() + " --out " + (dir / "own").string());
    EXPECT_EQ(r.exit_code, 0) << r.out;
    r = run_cli("replay -q " + kFlight.string() + " --out " + (dir / "mine").string() + " --force");
    EXPECT_EQ(r.exit_code, 0) << r.out;
    EXPECT_EQ(read_text(dir / "mine" / "thesis.pdf"), "precious");
}

TEST(CliEdges, FrameRangesSplitsSeedsAndDelaysAreChecked) {
    const auto dir = scratch_dir("cli_edges", "ranges");
    const std::string frames = "dataset frames " + kFlight.string() + " " + (dir / "f").string();
    expect_one_line_error(run_cli(frames + " --from 400"),
                          "--from 400 is past the last frame (152)");
    expect_one_line_error(run_cli(frames + " --to 999"), "--to 999 is past the last frame (152)");
    expect_one_line_error(run_cli(frames + " --from 5 --to 2"), "--to 2 is before --from 5");
    EXPECT_FALSE(fs::exists(dir / "f"));  // nothing created
    auto r = run_cli(frames + " --from 150 --to 152");
    EXPECT_EQ(r.exit_code, 0) << r.out;
    EXPECT_TRUE(fs::exists(dir / "f" / "000152.png"));

    expect_one_line_error(
        run_cli("eval " + kFlight.string() + " --out " + (dir / "e").string() + " --split tuning"),
        "--split");
    expect_one_line_error(
        run_cli("generate --scene thesis_pillar_left --seed -1 --out " + (dir / "g").string()),
        "expected an integer from 0 to 18446744073709551615, got '-1'");
    expect_one_line_error(
        run_cli("odometry " + (dir / "o").string() + " --generate hover --top-delay 30"),
        "expected a delay in seconds in [0, 1], got '30'");
}

TEST(CliEdges, RangeMessagesAreShort) {
    for (const std::string args : {"sim --seconds -1",
                                   "record --sim warehouse --out /tmp/x "
                                   "--seconds -2",
                                   "odometry /tmp/x --duration -1"}) {
        const auto r = run_cli(args);
        EXPECT_NE(r.exit_code, 0) << args;
        EXPECT_EQ(r.out.find("1797693134862315"), std::string::npos) << r.out;
        EXPECT_LT(r.out.size(), 400u) << r.out;
    }
}

TEST(CliEdges, JsonErrorsNameFileAndKeyWithoutLibraryPrefixes) {
    const auto dir = scratch_dir("cli_edges", "json");
    write_text(dir / "cal.json", R"({"fx": 1e400, "fy": 500, "cx": 320, "cy": 180})");
    auto r = run_cli("replay " + kFlight.string() + " --out " + (dir / "o").string() +
                     " --calibration " + (dir / "cal.json").string());
    expect_one_line_error(r, "'fx'");
    EXPECT_NE(r.out.find("cal.json"), std::string::npos) << r.out;
    write_text(dir / "bad.json", R"({"fx": 500,, })");
    r = run_cli("replay " + kFlight.string() + " --out " + (dir / "o").string() +
                " --calibration " + (dir / "bad.json").string());
    expect_one_line_error(r, "bad.json:1:");
}

TEST(CliEdges, SimQuietPrintsNothing) {
    const auto r = run_cli_stdout("sim --quiet --seconds 0.3 --port-base " +
                                  std::to_string(21000 + ::getpid() % 3000 * 10));
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_EQ(r.out, "");
}

TEST(CliEdges, ParamsListsEveryClassifierAndOdometryParameter) {
    const auto r = run_cli("params");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    for (const char* key : {"Classifier 'flow'", "Classifier 'thesis'", "odo.max_corners",
                            "filter.spike_translation_m", "Visual odometry"})
        EXPECT_NE(r.out.find(key), std::string::npos) << key;
    const auto only = run_cli("params --odometry");
    EXPECT_EQ(only.out.find("Classifier"), std::string::npos);
    expect_one_line_error(run_cli("params --classifier nope"), "--classifier");
}

}  // namespace
}  // namespace gs::test::cli_edges
