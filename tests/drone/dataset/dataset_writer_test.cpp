#include "support/dataset_fixtures.hpp"

#include "drone/dataset/dataset.hpp"
#include "drone/dataset/frame_store.hpp"
#include "drone/dataset/raw.hpp"
#include "drone/dataset/writer.hpp"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>
#include <csignal>
#include <thread>

namespace gs {
namespace {

using namespace dataset;
namespace fs = std::filesystem;
using test::TempDir;

NavState nav_at(double roll, double pitch, double yaw) {
    NavState s;
    s.roll_deg = roll;
    s.pitch_deg = pitch;
    s.yaw_deg = yaw;
    s.vx_mps = roll / 10;
    s.altitude_m = 1.0;
    return s;
}

DatasetOpenOptions with_assets(const TempDir& t) {
    test::make_assets(t / "assets");
    DatasetOpenOptions o;
    o.assets_dir = t / "assets";
    return o;
}

TEST(DatasetWriter, RoundTripWithInterpolatedAttitude) {
    TempDir t;
    FakeClock clock(5'000 * kNsPerMs);
    const TimeNs t0 = clock.now_ns();
    DatasetWriterOptions o;
    o.width = 64;
    o.height = 48;
    o.fps = 25;
    o.write_images = true;
    auto w = DatasetWriter::create(t / "rec", o, clock);
    ASSERT_TRUE(w) << to_string(w.error());
    const std::vector<std::uint8_t> dgram = {0x88, 0x77, 0x66, 0x55, 1, 2, 3};
    // navdata every 10 ms: roll = t/10ms, so the value at any instant is known exactly.
    // Frames every 40 ms at t = 40 k + 4 ms, each sent after the navdata that follows it (video
    // lags).
    int nav_i = 0;
    for (int k = 0; k < 10; ++k) {
        const TimeNs cap = t0 + (40 * k + 4) * kNsPerMs;
        while (t0 + nav_i * 10 * kNsPerMs <= cap + 20 * kNsPerMs) {
            NavState s = nav_at(nav_i, -nav_i, nav_i * 2.0);
            s.seq = static_cast<std::uint32_t>(nav_i);
            s.drone_state = 0x80000000u | static_cast<std::uint32_t>(nav_i);
            ASSERT_TRUE((*w)->add_navdata(t0 + nav_i * 10 * kNsPerMs, dgram, s));
            ++nav_i;
        }
        ASSERT_TRUE((*w)->add_frame(cap, {}, test::test_image(k, 64, 48),
                                    FrameLabel{5.0 - k * 0.5, 0.25, {}}));
        ASSERT_TRUE((*w)->add_at(cap, "AT*PCMD=1,0,0,0,0,0\rAT*REF=2,290717696\r"));
    }
    FlightLabels labels;
    labels.scenario = Scenario::Right;
    labels.json = R"({"obstacle": "box"})";
    ASSERT_TRUE((*w)->set_labels(labels));
    (*w)->close();
    const auto st = (*w)->stats();
    EXPECT_TRUE(st.closed);
    EXPECT_EQ(st.frames_written, 10u);
    EXPECT_EQ(st.navdata_written, static_cast<std::uint64_t>(nav_i));
    EXPECT_EQ(st.dropped_queue_full, 0u);
    EXPECT_EQ(st.write_errors, 0u) << st.first_error;

    auto d = Dataset::open(t / "rec", with_assets(t));
    ASSERT_TRUE(d) << to_string(d.error());
    EXPECT_EQ(d->info().source, "recorded");
    ASSERT_EQ(d->info().frames, 10);
    ASSERT_EQ(d->frame_count(), 10);
    for (int k = 0; k < 10; ++k) {
        const auto& r = d->frames()[static_cast<std::size_t>(k)];
        const double tm = 40.0 * k + 4;
        EXPECT_EQ(r.nav.t_ns, static_cast<TimeNs>(tm * kNsPerMs));
        // halfway between samples tm-4 and tm+6 ... roll = tm / 10 exactly (linear in time)
        EXPECT_NEAR(r.nav.roll_deg, tm / 10, 1e-12) << k;
        EXPECT_NEAR(r.nav.pitch_deg, -tm / 10, 1e-12);
        EXPECT_NEAR(r.nav.yaw_deg, tm / 5, 1e-12);
        EXPECT_NEAR(r.nav.vx_mps, tm / 100, 1e-12);
        EXPECT_EQ(r.nav.altitude_m, 1.0);
        EXPECT_TRUE(std::isnan(r.nav.vy_mps));
    }
    ASSERT_EQ(d->navdata().size(), static_cast<std::size_t>(nav_i));
    EXPECT_EQ(d->navdata()[3].t_ns, 30 * kNsPerMs);
    EXPECT_EQ(d->navdata()[3].roll_deg, 3.0);
    EXPECT_EQ(*d->navdata()[3].seq, 3u);
    EXPECT_EQ(*d->navdata()[3].drone_state, 0x80000003u);
    ASSERT_TRUE(d->labels());
    EXPECT_EQ(d->labels()->scenario, Scenario::Right);
    EXPECT_NE(d->labels()->json.find("\"box\""), std::string::npos);
    ASSERT_TRUE(d->label_rows());
    ASSERT_EQ(d->label_rows()->size(), 10u);
    EXPECT_EQ((*d->label_rows())[4].distance_m, 3.0);
    auto store = open_image_frames(*d);
    ASSERT_TRUE(store);
    cv::Mat img;
    ASSERT_FALSE((*store)->read(7, img));
    EXPECT_EQ(cv::norm(img, test::test_image(7, 64, 48), cv::NORM_INF), 0.0);

    // raw/ holds every datagram with its receive time, and every AT datagram exactly.
    auto raw = read_navdata_bin(t / "rec/raw");
    ASSERT_TRUE(raw);
    EXPECT_FALSE(raw->truncated_tail);
    ASSERT_EQ(raw->records.size(), static_cast<std::size_t>(nav_i));
    EXPECT_EQ(raw->records[5].t_us, 50'000);
    EXPECT_EQ(raw->records[5].payload, dgram);
    auto at = read_at_log(t / "rec/raw");
    ASSERT_TRUE(at) << to_string(at.error());
    ASSERT_EQ(at->size(), 10u);
    EXPECT_EQ((*at)[2].t_us, 84'000);
    EXPECT_EQ((*at)[2].datagram, "AT*PCMD=1,0,0,0,0,0\rAT*REF=2,290717696\r");
}

TEST(DatasetWriter, VideoModeSkipsUntilIdrAndWritesOneAccessUnitPerFrame) {
    TempDir t;
    FakeClock clock(0);
    DatasetWriterOptions o;
    o.width = 64;
    o.height = 48;
    o.write_raw = false;
    auto w = DatasetWriter::create(t / "rec", o, clock);
    ASSERT_TRUE(w);
    (*w)->add_frame(1 * kNsPerMs,
                    test::fake_access_unit(false, 50, 1));  // P before any IDR: skipped
    for (int i = 0; i < 8; ++i)
        (*w)->add_frame((10 + 33 * i) * kNsPerMs, test::fake_access_unit(i % 4 == 0, 60 + i, 2));
    (*w)->close();
    EXPECT_EQ((*w)->stats().frames_skipped, 1u);
    EXPECT_EQ((*w)->stats().frames_written, 8u);
    auto d = Dataset::open(t / "rec", with_assets(t));
    ASSERT_TRUE(d) << to_string(d.error());
    ASSERT_TRUE(d->video_path());
    ASSERT_EQ(d->video_units().size(), 8u);
    EXPECT_EQ(d->video_units()[3].size, 6u + 63);
    EXPECT_TRUE(d->video_units()[4].idr);
    // no navdata at all: attitude unknown, not zero
    EXPECT_TRUE(std::isnan(d->frames()[2].nav.roll_deg));
    EXPECT_EQ(d->frames()[2].nav.t_ns, 76 * kNsPerMs);
    EXPECT_FALSE(fs::exists(t / "rec/raw"));
}

TEST(DatasetWriter, InterpolationUsesTheTwoNeighbouringSamples) {
    TempDir t;
    FakeClock clock(0);
    DatasetWriterOptions o;
    o.width = 8;
    o.height = 8;
    o.write_images = true;
    auto w = DatasetWriter::create(t / "rec", o, clock);
    ASSERT_TRUE(w);
    // frame before any navdata, frame between, frame exactly on a sample, frame after the last
    (*w)->add_frame(1 * kNsPerMs, {}, test::test_image(0, 8, 8));
    (*w)->add_navdata(2 * kNsPerMs, {}, nav_at(10, 0, 170));
    (*w)->add_navdata(12 * kNsPerMs, {}, nav_at(20, 4, -170));  // yaw wraps through 180
    (*w)->add_frame(4 * kNsPerMs, {}, test::test_image(1, 8, 8));
    (*w)->add_frame(12 * kNsPerMs, {}, test::test_image(2, 8, 8));
    (*w)->add_frame(30 * kNsPerMs, {}, test::test_image(3, 8, 8));
    (*w)->close();
    auto d = Dataset::open(t / "rec", with_assets(t));
    ASSERT_TRUE(d) << to_string(d.error());
    ASSERT_EQ(d->frame_count(), 4);
    EXPECT_EQ(d->frames()[0].nav.roll_deg, 10.0);  // nearest: the first sample
    EXPECT_NEAR(d->frames()[1].nav.roll_deg, 12.0, 1e-12);
    EXPECT_NEAR(d->frames()[1].nav.pitch_deg, 0.8, 1e-12);
    EXPECT_NEAR(d->frames()[1].nav.yaw_deg, 174.0, 1e-9);  // 170 + 20 * 0.2 the short way
    EXPECT_EQ(d->frames()[2].nav.roll_deg, 20.0);
    EXPECT_EQ(d->frames()[3].nav.roll_deg, 20.0);  // nearest: the last sample
}

TEST(DatasetWriter, FullQueueDropsAndCountsWithoutBlocking) {
    TempDir t;
    FakeClock clock(0);
    DatasetWriterOptions o;
    o.width = 8;
    o.height = 8;
    o.queue_capacity = 4;
    auto w = DatasetWriter::create(t / "rec", o, clock);
    ASSERT_TRUE(w);
    const std::vector<std::uint8_t> big(60'000, 0x42);
    std::uint64_t refused = 0;
    constexpr int kN = 20'000;
    for (int i = 0; i < kN; ++i)
        if (!(*w)->add_navdata(i * kNsPerMs, big, nav_at(1, 2, 3))) ++refused;
    (*w)->close();
    const auto st = (*w)->stats();
    EXPECT_GT(refused, 0u);
    EXPECT_EQ(st.dropped_queue_full, refused);
    EXPECT_EQ(st.enqueued + st.dropped_queue_full, static_cast<std::uint64_t>(kN));
    EXPECT_EQ(st.navdata_written, st.enqueued);
    // pushing after close is refused and counted, not blocked
    EXPECT_FALSE((*w)->add_at(0, "AT*COMWDG=1\r"));
    EXPECT_EQ((*w)->stats().dropped_queue_full, refused + 1);
}

TEST(DatasetWriter, RefusesANonEmptyDirectory) {
    TempDir t;
    test::write_file(t / "rec/something", "x");
    FakeClock clock(0);
    auto w = DatasetWriter::create(t / "rec", {}, clock);
    ASSERT_FALSE(w);
    EXPECT_EQ(w.error().code, FileErrorCode::Io);
}

TEST(RawFiles, TruncatedTailAndAbsurdLengths) {
    std::string buf;
    const std::vector<std::uint8_t> a = {1, 2, 3}, b = {9};
    append_raw_record(buf, 100, a);
    append_raw_record(buf, 250, b);
    auto span = [&](std::size_t n) {
        return std::span(reinterpret_cast<const std::uint8_t*>(buf.data()), n);
    };
    auto full = parse_navdata_bin(span(buf.size()));
    ASSERT_TRUE(full);
    ASSERT_EQ(full->records.size(), 2u);
    EXPECT_EQ(full->records[1].t_us, 250);
    EXPECT_EQ(full->records[1].payload, b);
    for (std::size_t cut = 16; cut < buf.size(); ++cut) {  // killed mid-record 2
        auto r = parse_navdata_bin(span(cut));
        ASSERT_TRUE(r);
        EXPECT_EQ(r->records.size(), 1u);
        EXPECT_TRUE(r->truncated_tail);
    }
    std::string bad;
    append_raw_record(bad, 1, a);
    bad[8] = '\xFF';
    bad[9] = '\xFF';
    bad[10] = '\xFF';
    bad[11] = '\x7F';
    auto r =
        parse_navdata_bin(std::span(reinterpret_cast<const std::uint8_t*>(bad.data()), bad.size()));
    ASSERT_FALSE(r);
    EXPECT_EQ(to_string(r.error()),
              "raw/navdata.bin: record 0 at byte 0 claims 2147483647 bytes (limit 65507)");

    std::string log;
    const std::string dg = "AT*CONFIG=1,\"a\\b\"\r\x01\n";
    append_at_line(log, 42, dg);
    EXPECT_EQ(log, "42 AT*CONFIG=1,\"a\\\\b\"\\r\\x01\\n\n");
    auto at = parse_at_log(log);
    ASSERT_TRUE(at);
    ASSERT_EQ(at->size(), 1u);
    EXPECT_EQ((*at)[0].datagram, dg);
    auto e = parse_at_log("12 AT\\q\n");
    ASSERT_FALSE(e);
    EXPECT_EQ(to_string(e.error()), "raw/at.log:1:6: unknown escape \\q");
}

// Records with a fast fake producer in a child process, SIGKILLs it mid-flight, and checks the
// dataset opens and holds frames up to within 1 s of the kill.
TEST(DatasetWriter, KilledRecordingIsReadableToWithinOneSecond) {
    TempDir t;
    int pipefd[2];
    ASSERT_EQ(::pipe(pipefd), 0);
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        ::close(pipefd[0]);
        SteadyClock& clock = SteadyClock::instance();
        DatasetWriterOptions o;
        o.width = 64;
        o.height = 48;
        auto w = DatasetWriter::create(t / "rec", o, clock);
        if (!w) ::_exit(2);
        const TimeNs t0 = (*w)->start_ns();
        const std::vector<std::uint8_t> dgram(500, 0x11);
        const std::vector<std::uint8_t> chunk(4000, 0x22);
        for (int i = 0;; ++i) {  // 200 Hz navdata, 25 fps frames, until killed
            const TimeNs now = clock.now_ns();
            // roll grows with the sample index (within the ±90° docs/dataset.md allows)
            (*w)->add_navdata(now, dgram, nav_at(std::min(i * 0.1, 89.0), 0, 0));
            if (i % 8 == 0) {
                (*w)->add_video_bytes(now, chunk);
                (*w)->add_frame(now - 1 * kNsPerMs, test::fake_access_unit(i % 240 == 0, 3000, 3));
                const TimeNs produced = now - 1 * kNsPerMs - t0;
                if (::write(pipefd[1], &produced, sizeof produced) != sizeof produced) ::_exit(3);
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(5));  // the fake link's pace
        }
    }
    ::close(pipefd[1]);
    // Let it record ~2.5 s of flight, then kill it without warning.
    TimeNs last = -1, v = 0;
    while (last < 2'500 * kNsPerMs) {
        const ssize_t n = ::read(pipefd[0], &v, sizeof v);
        ASSERT_EQ(n, static_cast<ssize_t>(sizeof v)) << "child stopped early";
        last = v;
    }
    ASSERT_EQ(::kill(pid, SIGKILL), 0);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status));
    while (::read(pipefd[0], &v, sizeof v) == static_cast<ssize_t>(sizeof v)) last = v;
    ::close(pipefd[0]);

    auto d = Dataset::open(t / "rec", with_assets(t));
    ASSERT_TRUE(d) << to_string(d.error());
    ASSERT_GT(d->frame_count(), 0);
    const TimeNs kept = d->frames().back().nav.t_ns;
    EXPECT_GE(kept, last - 1'000 * kNsPerMs) << "last produced " << last << " ns, kept " << kept;
    EXPECT_LE(kept, last);
    std::printf("killed recording: last frame produced at %.3f s, dataset holds frames to %.3f s\n",
                ns_to_ms(last) / 1000, ns_to_ms(kept) / 1000);
    EXPECT_FALSE(d->info().frames);  // flight.json was never finalised
    // attitude came from navdata: roll = sample index, increasing
    EXPECT_GT(d->frames().back().nav.roll_deg, d->frames().front().nav.roll_deg);
    auto raw = read_navdata_bin(t / "rec/raw");
    ASSERT_TRUE(raw) << to_string(raw.error());
    EXPECT_GE(raw->records.back().t_us * 1000, last - 1'000 * kNsPerMs);
}

}  // namespace
}  // namespace gs
