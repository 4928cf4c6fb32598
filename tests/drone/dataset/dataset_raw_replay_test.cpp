#include "support/dataset_fixtures.hpp"

#include "drone/dataset/raw_replay.hpp"
#include "drone/dataset/writer.hpp"

#include <gtest/gtest.h>

#include <cstring>

namespace gs {
namespace {

using namespace dataset;

// Stand-in parsers (the real navdata parser and PaVE framer are bound after merge): a navdata
// datagram is a little-endian double roll; every video chunk completes one frame captured 1 ms
// before it arrived.
RawReplayDecoders fake_decoders() {
    RawReplayDecoders d;
    d.navdata = [](std::span<const std::uint8_t> b) -> std::optional<NavState> {
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
        const double roll = 0.1 * i * i - i;
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

}  // namespace
}  // namespace gs
