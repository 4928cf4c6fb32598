// Issue 14 point 4: a full disk. Recording into a 3 MiB tmpfs left navdata.csv ending in half a
// line and every command refused the flight. The writer now stops at the first failed write, cuts
// the failing file back to its last whole line or record, writes nothing more, and what is on disk
// opens and replays. Tested with an injected ENOSPC part-way into every file the writer writes.
#include "support/dataset_fixtures.hpp"

#include "drone/dataset/dataset.hpp"
#include "drone/dataset/raw.hpp"
#include "drone/dataset/writer.hpp"

#include <gtest/gtest.h>

#include <cerrno>
#include <map>
#include <thread>

namespace gs::writer_failure_test {  // named: the drone tests are one unity build
namespace {
namespace fs = std::filesystem;
using namespace std::chrono_literals;
using test::TempDir;

constexpr int kFrames = 60;

DatasetWriterOptions options(const TempDir& t) {
    DatasetWriterOptions o;
    o.width = 64;
    o.height = 48;
    o.fps = 25;
    o.flush_interval = std::chrono::milliseconds(1);
    o.max_buffer_bytes = 1024;  // many small flushes: the failure lands mid-recording
    test::make_assets(t / "assets");
    return o;
}

// A flight of kFrames fake access units with navdata, video bytes, AT datagrams, a second video
// connection and ground truth; returns how many add_*() calls the writer refused.
int record(DatasetWriter& w, FakeClock& clock) {
    int refused = 0;
    const TimeNs t0 = clock.now_ns();
    FlightLabels labels;
    labels.scenario = Scenario::Left;
    refused += !w.set_labels(labels);
    const std::vector<std::uint8_t> dgram(120, 0x5A);
    for (int k = 0; k < kFrames; ++k) {
        const TimeNs t = t0 + k * 40 * kNsPerMs;
        for (int i = 0; i < 8; ++i) {
            NavState s;
            s.roll_deg = k;
            s.altitude_m = 1;
            s.seq = static_cast<std::uint32_t>(k * 8 + i);
            refused += !w.add_navdata(t + i * 5 * kNsPerMs, dgram, s);
        }
        const auto au = test::fake_access_unit(k % 15 == 0, 300, static_cast<std::uint8_t>(k));
        refused += !w.add_video_bytes(t, au);
        if (k == kFrames / 2) refused += !w.add_video_connection(t);
        refused += !w.add_capture_time(static_cast<std::uint32_t>(k + 1),
                                       static_cast<std::uint32_t>(33 * k), t);
        refused += !w.add_frame(t, au, {}, FrameLabel{10.0 - k * 0.1, 0.5, {}});
        refused += !w.add_at(t, "AT*PCMD=" + std::to_string(k) + ",0,0,0,0,0\r");
        clock.advance(std::chrono::milliseconds(40));
    }
    return refused;
}

std::map<std::string, std::uintmax_t> sizes_of_a_good_run() {
    TempDir t;
    FakeClock clock(1000 * kNsPerMs);
    auto w = DatasetWriter::create(t / "rec", options(t), clock);
    EXPECT_TRUE(w);
    EXPECT_EQ(record(**w, clock), 0);
    (*w)->close();
    std::map<std::string, std::uintmax_t> out;
    for (const auto& e : fs::recursive_directory_iterator(t / "rec"))
        if (e.is_regular_file())
            out[fs::relative(e.path(), t / "rec").generic_string()] = e.file_size();
    return out;
}

class WriterDiskFull : public ::testing::TestWithParam<std::string> {};

TEST_P(WriterDiskFull, StopsAtTheFirstFailureAndLeavesADatasetThatOpens) {
    const std::string file = GetParam();
    static const auto good = sizes_of_a_good_run();
    ASSERT_TRUE(good.count(file)) << file << " is not written by a good run";
    TempDir t;
    FakeClock clock(1000 * kNsPerMs);
    auto o = options(t);
    o.inject_failure_file = file;
    o.inject_failure_after_bytes = good.at(file) / 2;
    auto w = DatasetWriter::create(t / "rec", o, clock);
    ASSERT_TRUE(w) << to_string(w.error());
    (void)record(**w, clock);
    const bool at_close = file == "flight.json";  // rewritten with the count when closing
    if (!at_close) {
        // Stopped at once: from then on nothing more is taken.
        const auto t0 = std::chrono::steady_clock::now();
        while (!(*w)->stats().stopped && std::chrono::steady_clock::now() - t0 < 10s) {
            clock.advance(10ms);  // the writer flushes on stream time too
            std::this_thread::sleep_for(1ms);
        }
        ASSERT_TRUE((*w)->stats().stopped);
        EXPECT_FALSE((*w)->add_at(clock.now_ns(), "AT*REF=1,0\r"));
        EXPECT_FALSE((*w)->add_frame(clock.now_ns(), test::fake_access_unit(true, 10, 1)));
    }
    (*w)->close();
    const auto st = (*w)->stats();

    // Stopped, saying which file and why.
    EXPECT_TRUE(st.stopped);
    EXPECT_EQ(st.first_error.rfind(file + ": write failed", 0), 0u) << st.first_error;
    EXPECT_EQ(st.first_errno, ENOSPC);
    if (!at_close) {
        EXPECT_LT(st.frames_written, static_cast<std::uint64_t>(kFrames));
    }
    // Nothing beyond the failure point, and whole lines / records only.
    if (file != "flight.json" && file != "labels.json") {
        ASSERT_TRUE(fs::exists(t / "rec" / file));
        EXPECT_LT(fs::file_size(t / "rec" / file), good.at(file));
    }
    for (const char* text :
         {"frames.csv", "navdata.csv", "labels.csv", "raw/at.log", "raw/video_connections.csv"}) {
        if (!fs::exists(t / "rec" / text)) continue;
        const std::string s = test::read_file(t / "rec" / text);
        EXPECT_TRUE(s.empty() || s.back() == '\n') << text << " ends inside a line";
    }
    auto nav = read_navdata_bin(t / "rec" / "raw");
    ASSERT_TRUE(nav) << to_string(nav.error());
    EXPECT_FALSE(nav->truncated_tail);
    ASSERT_TRUE(read_at_log(t / "rec" / "raw"));
    auto chunks = read_video_chunks(t / "rec" / "raw");
    ASSERT_TRUE(chunks);
    const auto pave = fs::file_size(t / "rec" / "raw" / "video.pave");
    std::uint64_t chunk_bytes = 0;
    for (const auto& c : *chunks) chunk_bytes += c.length;
    EXPECT_LE(chunk_bytes, pave);

    // The dataset opens without a warning about a cut line and every row has its pixels.
    DatasetOpenOptions oo;
    oo.assets_dir = t / "assets";
    auto d = Dataset::open(t / "rec", oo);
    ASSERT_TRUE(d) << file << ": " << to_string(d.error());
    EXPECT_EQ(static_cast<std::uint64_t>(d->frame_count()), st.frames_written);
    for (const auto& wmsg : d->warnings())
        EXPECT_EQ(wmsg.find("incomplete last line"), std::string::npos) << wmsg;
}

INSTANTIATE_TEST_SUITE_P(EveryFile, WriterDiskFull,
                         ::testing::Values("frames.csv", "navdata.csv", "video.h264", "labels.csv",
                                           "raw/navdata.bin", "raw/video.pave",
                                           "raw/video_chunks.bin", "raw/at.log",
                                           "raw/video_connections.csv", "raw/capture_times.csv",
                                           "flight.json", "labels.json"),
                         [](const auto& param_info) {
                             std::string n = param_info.param;
                             for (char& c : n)
                                 if (c == '/' || c == '.') c = '_';
                             return n;
                         });

TEST(WriterFrameTimes, EqualCaptureTimesAreMovedApartAndCounted) {
    // Issue 14 point 3: frames completed by one TCP read got one time; no two rows may share it.
    TempDir t;
    FakeClock clock(1000 * kNsPerMs);
    auto o = options(t);
    auto w = DatasetWriter::create(t / "rec", o, clock);
    ASSERT_TRUE(w);
    const TimeNs t0 = clock.now_ns();
    for (int k = 0; k < 6; ++k) {
        const TimeNs cap = t0 + (k < 3 ? 40 : 80) * kNsPerMs;  // two bunches of three
        ASSERT_TRUE((*w)->add_frame(cap, test::fake_access_unit(k == 0, 50, 1)));
    }
    (*w)->close();
    EXPECT_EQ((*w)->stats().frame_time_adjusted, 4u);
    DatasetOpenOptions oo;
    oo.assets_dir = t / "assets";
    auto d = Dataset::open(t / "rec", oo);
    ASSERT_TRUE(d) << to_string(d.error());
    ASSERT_EQ(d->frame_count(), 6);
    for (int k = 1; k < 6; ++k)
        EXPECT_GT(d->frames()[k].nav.t_ns, d->frames()[k - 1].nav.t_ns) << k;
    EXPECT_EQ(d->frames()[3].nav.t_ns, 80 * kNsPerMs);
}

TEST(WriterConnections, EveryVideoConnectionIsARowWithItsOffset) {
    TempDir t;
    FakeClock clock(1000 * kNsPerMs);
    auto w = DatasetWriter::create(t / "rec", options(t), clock);
    ASSERT_TRUE(w);
    const std::vector<std::uint8_t> bytes(1000, 7);
    ASSERT_TRUE((*w)->add_video_bytes(clock.now_ns(), bytes));
    clock.advance(std::chrono::milliseconds(250));
    ASSERT_TRUE((*w)->add_video_connection(clock.now_ns()));
    ASSERT_TRUE((*w)->add_video_bytes(clock.now_ns(), bytes));
    (*w)->close();
    EXPECT_EQ(test::read_file(t / "rec" / "raw" / "video_connections.csv"),
              "offset,t_us\n0,0\n1000,250000\n");
    EXPECT_EQ((*w)->stats().video_connections, 2u);
}

}  // namespace
}  // namespace gs::writer_failure_test
