// `ardrone-gs record` run as a process against its in-process virtual drone: the dataset it
// writes, the live decisions it logs (re-run over the recorded dataset, they must be identical),
// a recording killed without warning, and a clear failure without a drone.
#include "app/pipeline.hpp"
#include "cli_test_util.hpp"
#include "drone/dataset/csv.hpp"
#include "drone/dataset/dataset.hpp"
#include "drone/dataset/raw.hpp"
#include "drone/dataset/raw_replay.hpp"
#include "drone/dataset/video_frames.hpp"
#include "vision/classifier.hpp"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace {
namespace fs = std::filesystem;
using namespace std::chrono_literals;
using RunResult = gs::test::CmdResult;

fs::path make_temp_dir() {
    std::string tmpl = (fs::temp_directory_path() / "gs_record_XXXXXX").string();
    if (::mkdtemp(tmpl.data()) == nullptr) return {};
    return tmpl;
}

// One 4 s recording of the scripted left-pillar approach with the live classifier, shared by
// the tests below.
class RecordCommand : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        tmp_ = new fs::path(make_temp_dir());
        result_ = new RunResult(
            gs::test::run_cli("record --sim thesis_pillar_left --autopilot --seconds 4 --out " +
                              (*tmp_ / "flight").string() + " --classifier thesis"));
    }
    static void TearDownTestSuite() {
        std::error_code ec;
        fs::remove_all(*tmp_, ec);
        delete tmp_;
        delete result_;
    }
    void SetUp() override { ASSERT_EQ(result_->exit_code, 0) << result_->out; }
    static fs::path dir() { return *tmp_ / "flight"; }

    static inline fs::path* tmp_ = nullptr;
    static inline RunResult* result_ = nullptr;
};

TEST_F(RecordCommand, FourSecondsOfTheVirtualDroneMakeADatasetWithLabels) {
    EXPECT_NE(result_->out.find("recorded "), std::string::npos) << result_->out;
    EXPECT_NE(result_->out.find(" 0 drops"), std::string::npos) << result_->out;
    auto d = gs::dataset::Dataset::open(dir());
    ASSERT_TRUE(d) << gs::to_string(d.error());
    // 30 fps for 4 s; the virtual drone renders in real time and falls behind on a loaded machine
    // (ctest -j2 beside the other programs), so only a few seconds of frames are required here.
    // That no frame the link delivered was lost is the " 0 drops" above.
    EXPECT_GE(d->frame_count(), 45);
    EXPECT_LE(d->frame_count(), 120 + 15);
    EXPECT_EQ(d->info().frames, d->frame_count());
    EXPECT_FALSE(d->calibration_is_default());
    EXPECT_TRUE(d->has_navdata());
    ASSERT_TRUE(d->labels());
    EXPECT_EQ(d->labels()->scenario, gs::dataset::Scenario::Left);
    ASSERT_TRUE(d->label_rows());
    const auto& labels = *d->label_rows();
    ASSERT_EQ(labels.size(), static_cast<std::size_t>(d->frame_count()));
    for (std::size_t i = 1; i < labels.size(); ++i)
        EXPECT_LE(labels[i].distance_m, labels[i - 1].distance_m + 1e-3) << i;
    // The script hovers 1 s then flies at 1 m/s: over 4 s the pillar comes > 1.5 m closer.
    EXPECT_LT(labels.back().distance_m, labels.front().distance_m - 1.5);
}

TEST_F(RecordCommand, FrameAttitudeIsTheNavdataInterpolation) {
    auto d = gs::dataset::Dataset::open(dir());
    ASSERT_TRUE(d) << gs::to_string(d.error());
    const auto& navs = d->navdata();
    std::size_t checked = 0;
    for (const auto& f : d->frames()) {
        auto after =
            std::lower_bound(navs.begin(), navs.end(), f.nav.t_ns,
                             [](const gs::NavState& s, gs::TimeNs v) { return s.t_ns < v; });
        if (after == navs.begin() || after == navs.end()) continue;
        const gs::NavState want = gs::interpolate(*(after - 1), *after, f.nav.t_ns);
        EXPECT_DOUBLE_EQ(f.nav.roll_deg, want.roll_deg) << f.frame;
        EXPECT_DOUBLE_EQ(f.nav.pitch_deg, want.pitch_deg) << f.frame;
        EXPECT_DOUBLE_EQ(f.nav.vx_mps, want.vx_mps) << f.frame;
        ++checked;
    }
    EXPECT_GE(checked + 2, static_cast<std::size_t>(d->frame_count()));
}

TEST_F(RecordCommand, RawReplayReproducesFramesCsv) {
    auto d = gs::dataset::Dataset::open(dir());
    ASSERT_TRUE(d) << gs::to_string(d.error());
    auto dec = gs::dataset::make_protocol_replay_decoders();
    auto rows = gs::dataset::replay_raw(dir() / "raw", dec);
    ASSERT_TRUE(rows) << gs::to_string(rows.error());
    ASSERT_EQ(rows->size(), d->frames().size());
    auto same = [](double a, double b) { return (std::isnan(a) && std::isnan(b)) || a == b; };
    for (std::size_t i = 0; i < rows->size(); ++i) {
        EXPECT_EQ((*rows)[i].nav.t_ns, d->frames()[i].nav.t_ns) << i;
        EXPECT_TRUE(same((*rows)[i].nav.roll_deg, d->frames()[i].nav.roll_deg)) << i;
        EXPECT_TRUE(same((*rows)[i].nav.pitch_deg, d->frames()[i].nav.pitch_deg)) << i;
        EXPECT_TRUE(same((*rows)[i].nav.yaw_deg, d->frames()[i].nav.yaw_deg)) << i;
    }
}

// `dataset check-raw` (scripts/soak.sh runs it): raw/ replayed through the protocol parsers gives
// frames.csv, said with the frame counts, exit 0; a row that differs is named, with how far the
// replay agreed, exit 1; raw/video.pave cut inside a chunk is replayed up to the cut with a
// warning naming the file, and the missing frames are counted, exit 1; no raw/: a clear error.
TEST_F(RecordCommand, DatasetCheckRawSaysWhetherRawReplaysToFramesCsv) {
    auto d = gs::dataset::Dataset::open(dir());
    ASSERT_TRUE(d) << gs::to_string(d.error());
    const std::string n = std::to_string(d->frame_count());
    const RunResult ok = gs::test::run_cli("dataset check-raw " + dir().string());
    EXPECT_EQ(ok.exit_code, 0) << ok.out;
    EXPECT_NE(ok.out.find("  frames: " + n + " replayed, " + n + " in frames.csv\n"),
              std::string::npos)
        << ok.out;
    EXPECT_NE(ok.out.find("every frame as in frames.csv"), std::string::npos) << ok.out;
    EXPECT_EQ(ok.out.find("warning"), std::string::npos) << ok.out;

    // frames.csv edited at frame 10 (its pitch): named, the first 10 frames agreed.
    const fs::path edited = gs::test::scratch_dir("check_raw", "edited");
    fs::copy(dir(), edited, fs::copy_options::recursive);
    std::istringstream in(gs::test::read_text(edited / "frames.csv"));
    std::string text;
    int line_no = 0;
    for (std::string line; std::getline(in, line); ++line_no) {
        if (line_no == 11) {  // frame 10: frame,t_ms,roll_deg,pitch_deg,...
            std::size_t at = 0;
            for (int comma = 0; comma < 3; ++comma) at = line.find(',', at) + 1;
            line = line.substr(0, at) + "-77.5" + line.substr(line.find(',', at));
        }
        text += line + "\n";
    }
    std::ofstream(edited / "frames.csv", std::ios::trunc) << text;
    const RunResult bad = gs::test::run_cli("dataset check-raw " + edited.string());
    EXPECT_EQ(bad.exit_code, 1) << bad.out;
    EXPECT_NE(bad.out.find("the first 10 frames as in frames.csv"), std::string::npos) << bad.out;
    EXPECT_NE(bad.out.find("raw/ does not reproduce frames.csv: frame 10: frames.csv has '10,"),
              std::string::npos)
        << bad.out;
    EXPECT_NE(bad.out.find(",-77.5,"), std::string::npos) << bad.out;

    // raw/video.pave cut in the middle of the chunk halfway through it.
    const fs::path cut = gs::test::scratch_dir("check_raw", "cut");
    fs::copy(dir(), cut, fs::copy_options::recursive);
    auto chunks = gs::dataset::read_video_chunks(cut / "raw");
    ASSERT_TRUE(chunks) << gs::to_string(chunks.error());
    std::size_t k = chunks->size() / 2;
    while (k < chunks->size() && (*chunks)[k].length < 2) ++k;
    ASSERT_LT(k, chunks->size());
    fs::resize_file(cut / "raw" / "video.pave", (*chunks)[k].offset + (*chunks)[k].length / 2);
    const RunResult short_raw = gs::test::run_cli("dataset check-raw " + cut.string());
    EXPECT_EQ(short_raw.exit_code, 1) << short_raw.out;
    EXPECT_NE(short_raw.out.find("  warning: raw/video.pave: ends inside chunk " +
                                 std::to_string(k) + " "),
              std::string::npos)
        << short_raw.out;
    const auto at = short_raw.out.find("  frames: ");
    ASSERT_NE(at, std::string::npos) << short_raw.out;
    const long replayed = std::strtol(short_raw.out.c_str() + at + 10, nullptr, 10);
    EXPECT_GT(replayed, 0) << short_raw.out;
    EXPECT_LT(replayed, d->frame_count()) << short_raw.out;
    EXPECT_NE(
        short_raw.out.find("the first " + std::to_string(replayed) + " frames as in frames.csv"),
        std::string::npos)
        << short_raw.out;
    EXPECT_NE(short_raw.out.find(std::to_string(d->frame_count() - replayed) +
                                 " frames.csv rows after the replay's last frame (raw/ was cut "
                                 "short: see the warnings)"),
              std::string::npos)
        << short_raw.out;

    // A dataset without raw/ (rendered, not recorded).
    const RunResult none =
        gs::test::run_cli("dataset check-raw " GS_TEST_DATA_DIR "/flights/ci_pillar_left");
    EXPECT_EQ(none.exit_code, 1) << none.out;
    EXPECT_NE(none.out.find("no raw/ folder (recordings write one): nothing to replay"),
              std::string::npos)
        << none.out;
}

// The classifier re-run over the recorded dataset (pixels from video.h264, time and attitude
// from frames.csv) through the same pipeline as replay decides exactly what the live run logged,
// a capture gap included (a loaded machine can make one: the pipeline then starts the classifier
// again and the frame is unknown, live and replayed alike).
TEST_F(RecordCommand, LiveDecisionsAreReproducedFromTheDataset) {
    auto d = gs::dataset::Dataset::open(dir());
    ASSERT_TRUE(d) << gs::to_string(d.error());
    auto live = gs::dataset::csv::Table::parse(gs::test::read_text(dir() / "live_decisions.csv"),
                                               "live_decisions.csv");
    ASSERT_TRUE(live) << gs::to_string(live.error());
    const std::vector<std::string> cols = {
        "frame",        "t_ms",        "left",       "center",       "right",      "left_score",
        "center_score", "right_score", "left_state", "center_state", "right_state"};
    ASSERT_EQ(live->header(), cols);
    ASSERT_EQ(live->rows(), static_cast<std::size_t>(d->frame_count()));

    gs::app::ObstaclePipeline pipeline("thesis", d->calibration());
    auto store = gs::dataset::open_video_frames(*d);
    ASSERT_TRUE(store) << gs::to_string(store.error());
    cv::Mat image;
    int unsafe_frames = 0;
    for (std::int64_t i = 0; i < d->frame_count(); ++i) {
        ASSERT_FALSE((*store)->read(i, image)) << i;
        const gs::dataset::FrameRow& row = d->frames()[static_cast<std::size_t>(i)];
        gs::FrameSample sample;
        sample.index = i;
        sample.t_ns = row.nav.t_ns;
        sample.image = image;
        sample.nav = row.nav;
        const auto& res = pipeline.process(sample);
        const auto r = static_cast<std::size_t>(i);
        EXPECT_EQ(live->field(r, 0), std::to_string(i));
        EXPECT_EQ(live->field(r, 1), gs::dataset::csv::format_ms(row.nav.t_ns)) << i;
        for (std::size_t k = 0; k < 3; ++k) {
            const auto& reg = res.regions[k];
            EXPECT_EQ(live->field(r, 2 + k), reg.unsafe ? "1" : "0") << "frame " << i << " " << k;
            EXPECT_EQ(live->field(r, 5 + k), gs::dataset::csv::format_number(reg.score))
                << "frame " << i << " " << k;
            unsafe_frames += reg.unsafe ? 1 : 0;
        }
    }
    std::printf("live decisions reproduced over %lld frames (%d unsafe region-frames)\n",
                static_cast<long long>(d->frame_count()), unsafe_frames);
}

TEST(Record, KilledRecordingIsReadableToWithinOneSecond) {
    const fs::path tmp = make_temp_dir();
    const fs::path out = tmp / "flight";
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        const int devnull = ::open("/dev/null", O_WRONLY);
        ::dup2(devnull, STDOUT_FILENO);
        ::dup2(devnull, STDERR_FILENO);
        ::execl(GS_BINARY, GS_BINARY, "record", "--sim", "thesis_pillar_center", "--autopilot",
                "--out", out.c_str(), static_cast<char*>(nullptr));
        ::_exit(127);
    }
    // The recording starts when flight.json appears (the writer's time 0).
    std::chrono::steady_clock::time_point started;
    bool seen = false;
    for (int i = 0; i < 3000 && !seen; ++i) {
        if (fs::exists(out / "flight.json")) {
            started = std::chrono::steady_clock::now();
            seen = true;
        } else {
            std::this_thread::sleep_for(10ms);
        }
    }
    if (!seen) ::kill(pid, SIGKILL);
    ASSERT_TRUE(seen) << "the recording never started";
    // Let it record 60 frames (about 2 s; longer on a loaded machine), then kill it.
    const auto rows = [&] {
        std::ifstream f(out / "frames.csv");
        return std::count(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>(),
                          '\n');
    };
    for (int i = 0; i < 3000 && rows() < 61; ++i) std::this_thread::sleep_for(10ms);
    ASSERT_GE(rows(), 61) << "the recording wrote no 60 frames within 30 s";
    const double elapsed_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started)
            .count();
    ASSERT_EQ(::kill(pid, SIGKILL), 0);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status));

    auto d = gs::dataset::Dataset::open(out);
    ASSERT_TRUE(d) << gs::to_string(d.error());
    ASSERT_GT(d->frame_count(), 0);
    EXPECT_FALSE(d->info().frames);  // never finalised
    const double kept_ms = gs::ns_to_ms(d->frames().back().nav.t_ns);
    EXPECT_GE(kept_ms, elapsed_ms - 1000.0);
    EXPECT_LE(kept_ms, elapsed_ms + 100.0);
    std::printf("killed record: %.0f ms recorded, dataset holds frames to %.0f ms (%lld frames)\n",
                elapsed_ms, kept_ms, static_cast<long long>(d->frame_count()));
    std::error_code ec;
    fs::remove_all(tmp, ec);
}

TEST(Record, FailsClearlyWhenNoDroneAnswers) {
    const fs::path tmp = make_temp_dir();
    const RunResult r = gs::test::run_cli("record --drone 127.0.0.2 --connect-timeout 0.5 --out " +
                                          (tmp / "x").string());
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.out.find("no connection to the drone at 127.0.0.2 within 0.5 s"), std::string::npos)
        << r.out;
    EXPECT_FALSE(fs::exists(tmp / "x"));  // nothing recorded
    const RunResult both =
        gs::test::run_cli("record --drone 127.0.0.2 --sim warehouse --out " + (tmp / "y").string());
    EXPECT_NE(both.exit_code, 0);
    const RunResult neither = gs::test::run_cli("record --out " + (tmp / "z").string());
    EXPECT_NE(neither.exit_code, 0);
    EXPECT_NE(neither.out.find("--drone ADDR or --sim SCENARIO"), std::string::npos) << neither.out;
    std::error_code ec;
    fs::remove_all(tmp, ec);
}

// Issue 14 point 4 on a real full disk: recording into a 3 MiB tmpfs stops at once with a
// message naming the dataset and the disk, and what is on disk opens and replays every frame.
TEST(Record, AFullDiskStopsTheRecordingWithAClearMessageAndLeavesADatasetThatReplays) {
    const fs::path tmp = make_temp_dir();
    struct RemoveAll {  // declared first: runs after the unmount below
        fs::path p;
        ~RemoveAll() {
            std::error_code ec;
            fs::remove_all(p, ec);
        }
    } remove_tmp{tmp};
    const fs::path mnt = tmp / "tiny";
    fs::create_directories(mnt);
    if (std::system(("mount -t tmpfs -o size=3m tmpfs " + mnt.string() + " 2>/dev/null").c_str()) !=
        0)
        GTEST_SKIP() << "cannot mount a tmpfs here (needs root): the injected failures of "
                        "WriterDiskFull cover every file instead";
    struct Unmount {
        fs::path p;
        ~Unmount() { (void)std::system(("umount " + p.string()).c_str()); }
    } unmount{mnt};
    const fs::path out = mnt / "flight";
    const RunResult r =
        gs::test::run_cli("record --sim thesis_pillar_left --seconds 120 --out " + out.string());
    EXPECT_NE(r.exit_code, 0) << r.out;  // the recording could not be completed
    EXPECT_NE(r.out.find("recording stopped: " + out.string()), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("No space left on device"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("the disk holding it is full: " + mnt.string()), std::string::npos)
        << r.out;
    auto d = gs::dataset::Dataset::open(out);
    ASSERT_TRUE(d) << gs::to_string(d.error());
    ASSERT_GT(d->frame_count(), 10);
    for (const auto& w : d->warnings())
        EXPECT_EQ(w.find("incomplete last line"), std::string::npos) << w;
    const RunResult replay =
        gs::test::run_cli("replay -q " + out.string() + " --out " + (tmp / "replay").string());
    EXPECT_EQ(replay.exit_code, 0) << replay.out;
    EXPECT_NE(gs::test::read_text(tmp / "replay" / "summary.json")
                  .find("\"processed\": " + std::to_string(d->frame_count())),
              std::string::npos);
}

}  // namespace
