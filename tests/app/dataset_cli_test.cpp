// The headless commands on thesis-style image folders and with the options they share
// (app/cli_options): export to the thesis layout and back replays to the same decisions; --fps
// times a folder that has no timestamps; frames that cannot be read make replay and eval fail
// with the count while their outputs are still written; eval's progress line on a terminal;
// --calibration FILE on replay (also its --undistort video), eval, odometry and record.
#include "cli_test_util.hpp"
#include "drone/dataset/csv.hpp"
#include "drone/dataset/dataset.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace gs::test::thesis_cli {  // named: the app tests are one unity build
namespace {
namespace fs = std::filesystem;

const fs::path kFlight = fs::path(GS_TEST_DATA_DIR) / "flights" / "ci_pillar_left";
constexpr int kFlightFrames = 153;
constexpr int kShortFrames = 24;  // the short thesis folder: the flight's first 24 frames

void write_file_text(const fs::path& p, const std::string& text) {
    std::ofstream(p, std::ios::binary) << text;
}

nlohmann::json read_json(const fs::path& p) {
    return nlohmann::json::parse(read_text(p));
}

std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) out.push_back(l);
    return out;
}

// decisions.csv's t_ms of row `frame`.
std::string t_ms_of(const fs::path& decisions, int frame) {
    const auto rows = lines_of(read_text(decisions));
    if (static_cast<std::size_t>(frame + 1) >= rows.size()) return "(no row)";
    const std::string& r = rows[static_cast<std::size_t>(frame + 1)];
    const auto a = r.find(',');
    return r.substr(a + 1, r.find(',', a + 1) - a - 1);
}

// `ardrone-gs ARGS` with stdout and stderr on a pseudo-terminal: what a user at a terminal sees.
CmdResult run_cli_on_terminal(const std::string& args) {
    CmdResult r;
    const int master = posix_openpt(O_RDWR | O_NOCTTY);
    if (master < 0 || grantpt(master) != 0 || unlockpt(master) != 0) return r;
    const std::string slave_name = ptsname(master);
    const std::string cmd = std::string(GS_BINARY) + " " + args;
    const pid_t pid = fork();
    if (pid == 0) {
        setsid();
        const int slave = open(slave_name.c_str(), O_RDWR);
        if (slave < 0) _exit(126);
        dup2(slave, STDOUT_FILENO);
        dup2(slave, STDERR_FILENO);
        close(slave);
        close(master);
        execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
        _exit(127);
    }
    char buf[4096];
    for (;;) {
        const ssize_t n = read(master, buf, sizeof buf);
        if (n > 0) {
            r.out.append(buf, static_cast<std::size_t>(n));
        } else if (n < 0 && errno == EINTR) {
            continue;
        } else {
            break;  // EIO: the child closed the terminal
        }
    }
    close(master);
    int status = 0;
    waitpid(pid, &status, 0);
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

// The shipped flight exported once to the thesis layout, and a short thesis folder cut from it
// (its first frames, imu.txt lines and labels; no side files unless a test adds them).
class ThesisCli : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        root_ = new fs::path(scratch_dir("thesis_cli", "suite"));
        export_ = new CmdResult(run_cli("dataset export-thesis " + kFlight.string() + " " +
                                        (*root_ / "thesis").string()));
    }
    static void TearDownTestSuite() {
        fs::remove_all(*root_);
        delete root_;
        delete export_;
    }
    void SetUp() override { ASSERT_EQ(export_->exit_code, 0) << export_->out; }
    static fs::path thesis() { return *root_ / "thesis"; }

    // A folder of the first kShortFrames images + their imu.txt lines + labels.json.
    static fs::path short_folder(const std::string& name) {
        const fs::path dst = scratch_dir("thesis_cli", name);
        const auto imu = lines_of(read_text(thesis() / "imu.txt"));
        std::ofstream out(dst / "imu.txt");
        for (int i = 0; i < kShortFrames; ++i) {
            char img[32];
            std::snprintf(img, sizeof img, "%06d.png", i);
            fs::copy_file(thesis() / img, dst / img);
            out << imu[static_cast<std::size_t>(i)] << '\n';
        }
        fs::copy_file(thesis() / "labels.json", dst / "labels.json");
        return dst;
    }
    static inline fs::path* root_ = nullptr;
    static inline CmdResult* export_ = nullptr;
};

TEST_F(ThesisCli, ExportThenImportReplaysToTheSameDecisions) {
    const fs::path back = scratch_dir("thesis_cli", "imported") / "flight";
    const CmdResult imp =
        run_cli("dataset import-thesis " + thesis().string() + " " + back.string());
    ASSERT_EQ(imp.exit_code, 0) << imp.out;
    // The values per frame come back: times, attitude, velocities, altitude, ground truth.
    auto a = dataset::Dataset::open(kFlight);
    auto b = dataset::Dataset::open(back);
    ASSERT_TRUE(a && b);
    ASSERT_EQ(b->frame_count(), kFlightFrames);
    EXPECT_EQ(b->info().fps, a->info().fps);
    EXPECT_FALSE(b->calibration_is_default());
    EXPECT_EQ(b->calibration().cx, a->calibration().cx);
    ASSERT_TRUE(b->labels());
    EXPECT_EQ(b->labels()->scenario, a->labels()->scenario);
    for (std::size_t i = 0; i < a->frames().size(); ++i) {
        const NavState& x = a->frames()[i].nav;
        const NavState& y = b->frames()[i].nav;
        ASSERT_NEAR(static_cast<double>(y.t_ns), static_cast<double>(x.t_ns), 1.0) << i;
        ASSERT_DOUBLE_EQ(y.roll_deg, x.roll_deg) << i;
        ASSERT_DOUBLE_EQ(y.pitch_deg, x.pitch_deg) << i;
        ASSERT_DOUBLE_EQ(y.yaw_deg, x.yaw_deg) << i;
        ASSERT_DOUBLE_EQ(y.vx_mps, x.vx_mps) << i;
        ASSERT_DOUBLE_EQ(y.vz_mps, x.vz_mps) << i;
        ASSERT_DOUBLE_EQ(y.altitude_m, x.altitude_m) << i;
        ASSERT_DOUBLE_EQ(b->frames()[i].gt.x_m, a->frames()[i].gt.x_m) << i;
    }
    // The same decisions from the dataset, the thesis folder and the imported dataset.
    const fs::path base = scratch_dir("thesis_cli", "decisions");
    for (const auto& [in, out] :
         {std::pair{kFlight, base / "original"}, std::pair{thesis(), base / "thesis"},
          std::pair{back, base / "imported"}}) {
        const CmdResult r = run_cli("replay " + in.string() + " -q --out " + out.string());
        ASSERT_EQ(r.exit_code, 0) << r.out;
    }
    const std::string original = read_text(base / "original/decisions.csv");
    EXPECT_EQ(lines_of(original).size(), static_cast<std::size_t>(kFlightFrames + 1));
    EXPECT_EQ(read_text(base / "thesis/decisions.csv"), original);
    EXPECT_EQ(read_text(base / "imported/decisions.csv"), original);
    EXPECT_EQ(read_json(base / "imported/summary.json")["score"],
              read_json(base / "original/summary.json")["score"]);
}

TEST_F(ThesisCli, FpsTimesAFolderWithoutTimestamps) {
    const fs::path folder = short_folder("fps");
    const fs::path out = scratch_dir("thesis_cli", "fps_out");
    // docs/dataset.md: 25 fps unless told.
    ASSERT_EQ(run_cli("replay " + folder.string() + " -q --out " + (out / "a").string()).exit_code,
              0);
    EXPECT_EQ(t_ms_of(out / "a/decisions.csv", 10), "400");
    CmdResult r =
        run_cli("replay " + folder.string() + " -q --fps 10 --out " + (out / "b").string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_EQ(t_ms_of(out / "b/decisions.csv", 10), "1000");
    r = run_cli("eval " + folder.string() + " -q --fps 12.5 --out " + (out / "c").string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_EQ(t_ms_of(out / "c" / folder.filename() / "decisions.csv", 10), "800");
    // Validated: a number in (0, 1000], and only for thesis-style folders.
    for (const char* bad : {"0", "abc", "2000"}) {
        r = run_cli("replay " + folder.string() + " --fps " + bad + " --out " +
                    (out / "d").string());
        EXPECT_NE(r.exit_code, 0) << bad;
        EXPECT_NE(r.out.find("--fps"), std::string::npos) << r.out;
        EXPECT_NE(r.out.find("frame rate"), std::string::npos) << r.out;
    }
    r = run_cli("replay " + kFlight.string() + " --fps 10 --out " + (out / "e").string());
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.out.find("--fps is only for thesis-style image folders"), std::string::npos)
        << r.out;
    r = run_cli("odometry " + kFlight.string() + " --fps 10");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.out.find("--fps is only for thesis-style image folders"), std::string::npos)
        << r.out;
}

TEST_F(ThesisCli, UnreadableFramesFailTheRunButTheOutputsAreWritten) {
    const fs::path folder = short_folder("unreadable");
    write_file_text(folder / "000007.png", "not a png");
    write_file_text(folder / "000015.png", "");
    const fs::path out = scratch_dir("thesis_cli", "unreadable_out");
    CmdResult r = run_cli("replay " + folder.string() + " -q --out " + (out / "replay").string());
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.out.find("2 of 24 frames could not be read"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("000007.png"), std::string::npos) << r.out;
    const nlohmann::json s = read_json(out / "replay/summary.json");
    EXPECT_EQ(s["frames"], kShortFrames);
    EXPECT_EQ(s["decode_errors"], 2);
    EXPECT_EQ(lines_of(read_text(out / "replay/decisions.csv")).size(),
              static_cast<std::size_t>(kShortFrames + 1));

    r = run_cli("eval " + folder.string() + " -q --out " + (out / "eval").string());
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.out.find("2 of 24 frames could not be read"), std::string::npos) << r.out;
    const nlohmann::json rep = read_json(out / "eval/report.json");
    ASSERT_EQ(rep["read_errors"].size(), 1U);
    EXPECT_NE(read_text(out / "eval/report.md").find("Evaluated with errors"), std::string::npos);
    EXPECT_TRUE(fs::exists(out / "eval" / folder.filename() / "summary.json"));
}

TEST_F(ThesisCli, EvalShowsProgressOnATerminalOnly) {
    const fs::path folder = short_folder("progress");
    const fs::path out = scratch_dir("thesis_cli", "progress_out");
    const CmdResult tty =
        run_cli_on_terminal("eval " + folder.string() + " --out " + (out / "tty").string());
    ASSERT_EQ(tty.exit_code, 0) << tty.out;
    // "eval: 1 / 1 flights, 24 / 24 frames, 180 frames/s, 0 s left"
    EXPECT_NE(tty.out.find("eval: 1 / 1 flights, 24 / 24 frames, "), std::string::npos) << tty.out;
    EXPECT_NE(tty.out.find(" frames/s, "), std::string::npos) << tty.out;
    EXPECT_NE(tty.out.find(" s left"), std::string::npos) << tty.out;
    const CmdResult piped =
        run_cli("eval " + folder.string() + " --out " + (out / "pipe").string());
    ASSERT_EQ(piped.exit_code, 0) << piped.out;
    EXPECT_EQ(piped.out.find("frames/s"), std::string::npos) << piped.out;
    EXPECT_NE(piped.out.find("evaluated 1 flights"), std::string::npos) << piped.out;
}

TEST_F(ThesisCli, CalibrationFileReachesTheUndistortedVideo) {
    const fs::path folder = short_folder("calibration");
    const fs::path out = scratch_dir("thesis_cli", "calibration_out");
    // The flight's own calibration as a file, and one without distortion.
    const nlohmann::json own = read_json(kFlight / "flight.json")["calibration"];
    nlohmann::json flat = own;
    flat["dist"] = {0, 0, 0, 0, 0};
    write_file_text(out / "own.json", own.dump());
    write_file_text(out / "flat.json", flat.dump());
    fs::copy_file(thesis() / "imu_meta.json",
                  folder / "imu_meta.json");  // the flight's calibration
    auto replay = [&](const std::string& extra, const std::string& name) {
        const CmdResult r = run_cli("replay " + folder.string() + " -q --video --undistort " +
                                    extra + " --out " + (out / name).string());
        EXPECT_EQ(r.exit_code, 0) << r.out;
        return read_text(out / name / "overlay.mp4");
    };
    const std::string dflt = replay("", "default");
    const std::string same = replay("--calibration " + (out / "own.json").string(), "own");
    const std::string other = replay("--calibration " + (out / "flat.json").string(), "flat");
    ASSERT_FALSE(dflt.empty());
    EXPECT_EQ(same, dflt) << "the same calibration from a file draws the same video";
    EXPECT_NE(other, dflt) << "another calibration must change the undistorted video";
    EXPECT_EQ(read_text(out / "own/decisions.csv"), read_text(out / "default/decisions.csv"));
    // eval takes it too, for every flight.
    const CmdResult ev =
        run_cli("eval " + folder.string() + " -q --calibration " + (out / "flat.json").string() +
                " --out " + (out / "eval").string());
    ASSERT_EQ(ev.exit_code, 0) << ev.out;
    EXPECT_EQ(read_json(out / "eval" / folder.filename() / "summary.json")["calibration"],
              (out / "flat.json").string());
    EXPECT_EQ(read_json(out / "flat/summary.json")["calibration"], (out / "flat.json").string());
}

// The line of `text` that starts with `prefix` (empty when none).
std::string line_starting(const std::string& text, const std::string& prefix) {
    for (const auto& l : lines_of(text))
        if (l.rfind(prefix, 0) == 0) return l;
    return {};
}

TEST(ThesisOdometry, FpsAndCalibrationOnABottomCameraFolder) {
    // A short generated bottom-camera flight (15 fps) in the thesis layout.
    const fs::path dir = scratch_dir("thesis_odometry", "flight");
    CmdResult r = run_cli("odometry " + (dir / "d").string() +
                          " --generate hover --duration 1 --no-top --summary");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    r = run_cli("dataset export-thesis " + (dir / "d").string() + " " + (dir / "t").string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const CmdResult own = run_cli("odometry " + (dir / "t").string() + " --summary");
    ASSERT_EQ(own.exit_code, 0) << own.out;
    EXPECT_NE(own.out.find("16 frames at 15.0 fps"), std::string::npos) << own.out;
    r = run_cli("odometry " + (dir / "t").string() + " --fps 5 --summary");
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_NE(r.out.find("16 frames at 5.0 fps"), std::string::npos) << r.out;
    // --calibration replaces the bottom camera's: twice the focal length, other motion in metres.
    nlohmann::json cal = read_json(dir / "t/imu_meta.json").value("calibration", nlohmann::json());
    if (cal.is_null()) {
        cal = read_json(fs::path(GS_ASSETS_DIR) / "calibration/ardrone2_bottom.json");
    }
    cal["fx"] = cal["fx"].get<double>() * 2;
    cal["fy"] = cal["fy"].get<double>() * 2;
    write_file_text(dir / "long.json", cal.dump());
    r = run_cli("odometry " + (dir / "t").string() + " --summary --calibration " +
                (dir / "long.json").string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const std::string x_own = line_starting(own.out, "X Axis"),
                      x_long = line_starting(r.out, "X Axis");
    ASSERT_FALSE(x_own.empty()) << own.out;
    EXPECT_NE(x_long, x_own) << r.out;
}

TEST(CalibrationOption, MissingOrMalformedFileIsRefusedEverywhere) {
    const fs::path dir = scratch_dir("calibration_option", "bad");
    write_file_text(dir / "bad.json", R"({"fx": 500, "fy": 500, "cx": 320})");
    write_file_text(dir / "broken.json", "{ not json");
    for (const std::string& cmd : {"replay " + kFlight.string() + " --out " + (dir / "o").string(),
                                   "eval " + kFlight.string() + " --out " + (dir / "o").string(),
                                   "odometry " + kFlight.string(),
                                   "record --sim ci_pillar_left --out " + (dir / "r").string()}) {
        CmdResult r = run_cli(cmd + " --calibration " + (dir / "none.json").string());
        EXPECT_NE(r.exit_code, 0) << cmd;
        EXPECT_NE(r.out.find("--calibration: " + (dir / "none.json").string() + ": file not found"),
                  std::string::npos)
            << cmd << "\n"
            << r.out;
        r = run_cli(cmd + " --calibration " + (dir / "bad.json").string());
        EXPECT_NE(r.exit_code, 0) << cmd;
        EXPECT_NE(r.out.find("bad.json: missing required key 'cy'"), std::string::npos)
            << cmd << "\n"
            << r.out;
    }
    const CmdResult r = run_cli("replay " + kFlight.string() + " --out " + (dir / "o").string() +
                                " --calibration " + (dir / "broken.json").string());
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.out.find("broken.json"), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(dir / "r")) << "record refuses before recording";
    EXPECT_FALSE(fs::exists(dir / "o" / "decisions.csv"));
}

}  // namespace
}  // namespace gs::test::thesis_cli
