#include "support/dataset_fixtures.hpp"

#include "drone/dataset/raw_replay.hpp"
#include "drone/dataset/writer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>

namespace gs {
namespace {

using namespace dataset;

// Stand-in parsers (the real navdata parser and PaVE framer are bound after merge): a navdata
// datagram is a little-endian double roll; every video chunk completes one frame captured 1 ms
// before it arrived.
RawReplayDecoders fake_decoders() {
    RawReplayDecoders d;
    d.navdata = [](std::span<const std::uint8_t> b, TimeNs) -> std::optional<NavState> {
        if (b.size() != 8) return std::nullopt;
        NavState s;
        std::memcpy(&s.roll_deg, b.data(), 8);
        return s;
    };
    d.video = [](std::span<const std::uint8_t>, TimeNs recv, std::vector<TimeNs>& out) {
        out.push_back(recv - 1 * kNsPerMs);
    };
    return d;
}

TEST(RawReplay, ReproducesTheRecordedFramesCsv) {
    test::TempDir t;
    FakeClock clock(0);
    DatasetWriterOptions o;
    o.width = 8;
    o.height = 8;
    auto w = DatasetWriter::create(t / "rec", o, clock);
    ASSERT_TRUE(w);
    int frame = 0;
    for (int i = 0; i < 400; ++i) {  // 2 s of 200 Hz navdata, a frame about every 33 ms
        const TimeNs tn = i * 5 * kNsPerMs + 1;
        const double roll = 80 * std::sin(0.0005 * i * i);  // not linear, within ±90°
        std::uint8_t b[8];
        std::memcpy(b, &roll, 8);
        NavState s;
        s.roll_deg = roll;
        ASSERT_TRUE((*w)->add_navdata(tn, b, s));
        const TimeNs tv = (33 * frame + 7) * kNsPerMs;
        if (tv >= tn - 1 && tv < tn + 5 * kNsPerMs - 1) {
            const std::vector<std::uint8_t> chunk(100, static_cast<std::uint8_t>(frame));
            ASSERT_TRUE((*w)->add_video_bytes(tv, chunk));
            ASSERT_TRUE((*w)->add_frame(tv - 1 * kNsPerMs, test::fake_access_unit(true, 20, 1)));
            ++frame;
        }
    }
    (*w)->close();
    auto written = parse_frames_csv(test::read_file(t / "rec/frames.csv"));
    ASSERT_TRUE(written);
    ASSERT_EQ(written->size(), static_cast<std::size_t>(frame));

    auto dec = fake_decoders();
    auto replayed = replay_raw(t / "rec/raw", dec);
    ASSERT_TRUE(replayed) << to_string(replayed.error());
    ASSERT_EQ(replayed->size(), written->size());
    for (std::size_t i = 0; i < written->size(); ++i) {
        EXPECT_EQ((*replayed)[i].frame, (*written)[i].frame);
        EXPECT_EQ((*replayed)[i].nav.t_ns, (*written)[i].nav.t_ns);
        EXPECT_DOUBLE_EQ((*replayed)[i].nav.roll_deg, (*written)[i].nav.roll_deg) << i;
    }
}

// A recording with every raw/ file, by the writer, for the stand-in parsers below: 2 s of 200 Hz
// navdata, a frame about every 33 ms (one 100-byte chunk each, every byte the frame's index), its
// capture time in raw/capture_times.csv, two video resets (three connections) and an AT datagram
// every 30 ms.
struct RawRecording {
    int frames = 0;
    int at = 0;
    int connections = 1;
};

RawRecording write_raw_recording(const std::filesystem::path& dir) {
    FakeClock clock(0);
    DatasetWriterOptions o;
    o.width = 8;
    o.height = 8;
    auto w = DatasetWriter::create(dir, o, clock);
    EXPECT_TRUE(w) << to_string(w.error());
    RawRecording r;
    for (int i = 0; i < 400; ++i) {
        const TimeNs tn = i * 5 * kNsPerMs + 1;
        const double roll = 80 * std::sin(0.0005 * i * i);
        std::uint8_t b[8];
        std::memcpy(b, &roll, 8);
        NavState s;
        s.roll_deg = roll;
        EXPECT_TRUE((*w)->add_navdata(tn, b, s));
        if (i % 6 == 0) {
            (*w)->add_at(tn + 2 * kNsPerMs, "AT*REF=" + std::to_string(r.at + 1) + ",290717696\r");
            ++r.at;
        }
        const TimeNs tv = (33 * r.frames + 7) * kNsPerMs;
        if (tv >= tn - 1 && tv < tn + 5 * kNsPerMs - 1) {
            if (r.frames == 20 || r.frames == 40) {  // a video reset before this frame's bytes
                EXPECT_TRUE((*w)->add_video_connection(tv - 3 * kNsPerMs));
                ++r.connections;
            }
            const std::vector<std::uint8_t> chunk(100, static_cast<std::uint8_t>(r.frames));
            EXPECT_TRUE((*w)->add_video_bytes(tv, chunk));
            const TimeNs capture = tv - 2 * kNsPerMs;
            EXPECT_TRUE((*w)->add_capture_time(static_cast<std::uint32_t>(r.frames + 1),
                                               static_cast<std::uint32_t>(r.frames * 33 + 1),
                                               capture));
            EXPECT_TRUE((*w)->add_frame(capture, test::fake_access_unit(true, 20, 1)));
            ++r.frames;
        }
    }
    (*w)->close();
    return r;
}

// What the stand-in parsers were told, besides the rows.
struct Seen {
    std::vector<TimeNs> connections;           // begin_connection calls
    std::map<std::uint32_t, TimeNs> captures;  // capture_times.csv by frame number
    std::vector<std::vector<std::uint8_t>> video_fed =
        std::vector<std::vector<std::uint8_t>>(1);  // bytes per connection
};

// fake_decoders(), and: a chunk's frame is captured at its recorded capture time
// (raw/capture_times.csv, by frame number = first byte + 1) or else 1 ms before it arrived; every
// connection begun and every byte fed is noted in `seen`.
RawReplayDecoders recording_decoders(const std::shared_ptr<Seen>& seen) {
    RawReplayDecoders d = fake_decoders();
    d.begin_connection = [seen](TimeNs opened) {
        seen->connections.push_back(opened);
        seen->video_fed.emplace_back();
    };
    d.capture_times = [seen](std::vector<RecordedCapture> c) {
        for (const RecordedCapture& x : c) seen->captures[x.frame_number] = x.t_ns;
    };
    d.video = [seen](std::span<const std::uint8_t> b, TimeNs recv, std::vector<TimeNs>& out) {
        seen->video_fed.back().insert(seen->video_fed.back().end(), b.begin(), b.end());
        const auto it = seen->captures.find(std::uint32_t{b[0]} + 1u);
        out.push_back(it != seen->captures.end() ? it->second : recv - 1 * kNsPerMs);
    };
    return d;
}

bool mentions(const std::vector<std::string>& warnings, const std::string& file) {
    return std::any_of(warnings.begin(), warnings.end(), [&](const std::string& w) {
        return w.find(file) != std::string::npos && w.find("cut short") != std::string::npos;
    });
}

std::string joined(const std::vector<std::string>& v) {
    std::string s;
    for (const auto& x : v) s += x + "\n";
    return s;
}

// Where the last record or line of each raw/ file begins (its length given by the format).
std::size_t last_line_start(const std::string& text) {
    const std::size_t nl = text.rfind('\n', text.size() - 2);
    return nl == std::string::npos ? 0 : nl + 1;
}

// Issue 14 point 4, DATASET.md 1.1: "a navdata.csv or raw/ file cut inside its last line or record
// is read with a warning". Each raw/ file of a recording is cut inside its last record (or line):
// replay_raw (or the file's reader, for raw/at.log, which replay does not need) reads everything
// before the cut as from the whole file, and says which file was cut.
TEST(RawCutShort, EachRawFileCutInsideItsLastRecordIsReadUpToTheCutWithAWarningNamingIt) {
    test::TempDir t;
    const RawRecording rec = write_raw_recording(t / "rec");
    ASSERT_EQ(rec.connections, 3);
    ASSERT_GT(rec.frames, 50);
    const auto raw = t / "rec/raw";

    // The whole recording: every frame, every connection, no warning.
    auto full_seen = std::make_shared<Seen>();
    auto full_dec = recording_decoders(full_seen);
    std::vector<std::string> none;
    auto full = replay_raw(raw, full_dec, &none);
    ASSERT_TRUE(full) << to_string(full.error());
    EXPECT_TRUE(none.empty()) << joined(none);
    auto written = parse_frames_csv(test::read_file(t / "rec/frames.csv"));
    ASSERT_TRUE(written);
    ASSERT_EQ(full->size(), static_cast<std::size_t>(rec.frames));
    for (std::size_t i = 0; i < full->size(); ++i)
        ASSERT_EQ((*full)[i].nav.t_ns, (*written)[i].nav.t_ns) << i;
    ASSERT_EQ(full_seen->connections.size(), 2u);
    auto full_nav = read_navdata_bin(raw, &none);
    auto full_at = read_at_log(raw, &none);
    ASSERT_TRUE(full_nav && full_at);
    ASSERT_EQ(full_nav->records.size(), 400u);
    ASSERT_EQ(full_at->size(), static_cast<std::size_t>(rec.at));
    EXPECT_TRUE(none.empty()) << joined(none);

    struct Cut {
        std::string file;
        std::size_t at;       // bytes kept
        bool header = false;  // cut inside the header line: the file holds no whole line
    };
    const std::string nav_bin = test::read_file(raw / "navdata.bin");
    const std::size_t nav_last = nav_bin.size() - (12 + 8);  // 8-byte payloads
    const std::string chunks_bin = test::read_file(raw / "video_chunks.bin");
    const std::string pave = test::read_file(raw / "video.pave");
    const std::string at_log = test::read_file(raw / "at.log");
    const std::string conns = test::read_file(raw / "video_connections.csv");
    const std::string caps = test::read_file(raw / "capture_times.csv");
    const std::vector<Cut> cuts = {
        {"navdata.bin", nav_last + 5},                // inside the last record's header
        {"navdata.bin", nav_last + 12 + 3},           // inside its payload
        {"video_chunks.bin", chunks_bin.size() - 7},  // inside the last record
        {"video.pave", pave.size() - 50},             // inside the last chunk's bytes
        {"at.log", last_line_start(at_log) + 4},
        {"at.log", at_log.size() - 1},  // only the newline missing: still an incomplete line
        {"video_connections.csv", last_line_start(conns) + 2},  // inside the offset
        {"video_connections.csv", conns.rfind(',') + 1},        // the time empty
        {"video_connections.csv", 5, true},                     // inside the header
        {"capture_times.csv", last_line_start(caps) + 1},       // inside the frame number
        {"capture_times.csv", caps.rfind(',') + 1},             // the time empty
        {"capture_times.csv", caps.size() - 4},  // inside the time: what is left parses
        {"capture_times.csv", 10, true},         // inside the header
    };
    int case_no = 0;
    for (const Cut& c : cuts) {
        SCOPED_TRACE("raw/" + c.file + " cut to " + std::to_string(c.at) + " bytes");
        const auto dir = t / ("cut" + std::to_string(case_no++));
        std::filesystem::copy(t / "rec", dir, std::filesystem::copy_options::recursive);
        std::filesystem::resize_file(dir / "raw" / c.file, c.at);

        std::vector<std::string> warnings;
        auto seen = std::make_shared<Seen>();
        auto dec = recording_decoders(seen);
        auto rows = replay_raw(dir / "raw", dec, &warnings);
        if (!rows) {
            ADD_FAILURE() << to_string(rows.error());
            continue;
        }
        if (c.file == "at.log") {
            EXPECT_TRUE(warnings.empty()) << joined(warnings);  // replay does not read it
            auto at = read_at_log(dir / "raw", &warnings);
            ASSERT_TRUE(at) << to_string(at.error());
            ASSERT_EQ(at->size(), full_at->size() - 1);
            for (std::size_t i = 0; i < at->size(); ++i)
                EXPECT_EQ((*at)[i].datagram, (*full_at)[i].datagram) << i;
        }
        EXPECT_EQ(warnings.size(), 1u) << joined(warnings);
        EXPECT_TRUE(mentions(warnings, "raw/" + c.file)) << joined(warnings);

        // Everything before the cut is read: the frames whose bytes (or capture time) are
        // whole, exactly as from the whole file.
        const bool video = c.file == "video_chunks.bin" || c.file == "video.pave";
        ASSERT_EQ(rows->size(), video ? full->size() - 1 : full->size());
        std::size_t same = rows->size();
        if (c.file == "capture_times.csv") {
            // The frames whose capture time was cut away take the receiver's own estimate.
            const std::size_t kept = c.header ? 0 : static_cast<std::size_t>(rec.frames - 1);
            EXPECT_EQ(seen->captures.size(), kept);
            same = kept;
            EXPECT_NE((*rows)[kept].nav.t_ns, (*full)[kept].nav.t_ns);
        }
        for (std::size_t i = 0; i < same; ++i) {
            EXPECT_EQ((*rows)[i].nav.t_ns, (*full)[i].nav.t_ns) << i;
            EXPECT_DOUBLE_EQ((*rows)[i].nav.roll_deg, (*full)[i].nav.roll_deg) << i;
        }
        if (c.file == "navdata.bin") {
            auto nav = read_navdata_bin(dir / "raw");
            ASSERT_TRUE(nav);
            EXPECT_TRUE(nav->truncated_tail);
            ASSERT_EQ(nav->records.size(), 399u);
            EXPECT_EQ(nav->records.back().payload, full_nav->records[398].payload);
        }
        // The connections before the cut are kept; a cut last row loses only its own, a cut
        // header all of them (one connection, as without the file).
        const std::size_t connections = c.file != "video_connections.csv" ? 2u : c.header ? 0u : 1u;
        EXPECT_EQ(seen->connections.size(), connections);
    }
}

// DATASET.md 1.0 had no raw/video_connections.csv ("older datasets stay readable"): its
// raw/video.pave replays as one connection, every byte fed in order, every frame rebuilt, no
// warning. With the file, the same bytes are fed as the three connections it lists.
TEST(RawReplay, ADataset10RawWithoutVideoConnectionsReplaysAsOneConnection) {
    test::TempDir t;
    const RawRecording rec = write_raw_recording(t / "rec");
    const std::string pave = test::read_file(t / "rec/raw/video.pave");
    {
        auto seen = std::make_shared<Seen>();
        auto dec = recording_decoders(seen);
        std::vector<std::string> warnings;
        auto rows = replay_raw(t / "rec/raw", dec, &warnings);
        ASSERT_TRUE(rows) << to_string(rows.error());
        EXPECT_EQ(rows->size(), static_cast<std::size_t>(rec.frames));
        ASSERT_EQ(seen->video_fed.size(), 3u);
        EXPECT_EQ(seen->video_fed[1].size(), 20u * 100u);  // frames 20-39
    }
    std::filesystem::remove(t / "rec/raw/video_connections.csv");
    auto seen = std::make_shared<Seen>();
    auto dec = recording_decoders(seen);
    std::vector<std::string> warnings;
    auto rows = replay_raw(t / "rec/raw", dec, &warnings);
    ASSERT_TRUE(rows) << to_string(rows.error());
    EXPECT_TRUE(warnings.empty()) << joined(warnings);
    EXPECT_TRUE(seen->connections.empty());
    ASSERT_EQ(seen->video_fed.size(), 1u);
    EXPECT_EQ(seen->video_fed[0], std::vector<std::uint8_t>(pave.begin(), pave.end()));
    auto written = parse_frames_csv(test::read_file(t / "rec/frames.csv"));
    ASSERT_TRUE(written);
    ASSERT_EQ(rows->size(), written->size());
    for (std::size_t i = 0; i < rows->size(); ++i) {
        EXPECT_EQ((*rows)[i].nav.t_ns, (*written)[i].nav.t_ns) << i;
        EXPECT_DOUBLE_EQ((*rows)[i].nav.roll_deg, (*written)[i].nav.roll_deg) << i;
    }
}

}  // namespace
}  // namespace gs
