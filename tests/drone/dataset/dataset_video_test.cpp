// video.h264 datasets: written live (DatasetWriter) or in one pass (VideoDatasetWriter), read
// back and decoded through H264Decoder.

#include "support/dataset_fixtures.hpp"

#include "drone/dataset/dataset_source.hpp"
#include "drone/dataset/video_dataset_writer.hpp"
#include "drone/dataset/video_frames.hpp"
#include "drone/dataset/writer.hpp"

#include <gtest/gtest.h>

namespace gs {
namespace {

using namespace dataset;
namespace fs = std::filesystem;

// Re-records the PaVE fixture's H.264 access units as a dataset, then decodes it back.
TEST(DatasetVideo, DecodesEveryFrameAndSeeks) {
    const fs::path f = fs::path(GS_FIXTURES_DIR) / "ardrone/node-ar-drone_pave.bin";
    if (!fs::exists(f)) GTEST_SKIP() << "fixture missing";
    const std::string bytes = test::read_file(f);
    const auto* p = reinterpret_cast<const std::uint8_t*>(bytes.data());
    auto units = split_access_units(std::span(p, bytes.size()));
    ASSERT_GT(units.size(), 2u);
    // Keep from the first IDR on.
    std::size_t first = 0;
    while (first < units.size() && !units[first].idr) ++first;
    ASSERT_LT(first, units.size());
    test::TempDir t;
    FakeClock clock(0);
    DatasetWriterOptions o;
    o.width = 640;
    o.height = 360;
    o.write_raw = false;
    auto w = DatasetWriter::create(t / "rec", o, clock);
    ASSERT_TRUE(w);
    for (std::size_t i = first; i < units.size(); ++i)
        ASSERT_TRUE((*w)->add_frame(static_cast<TimeNs>(i) * 33'000'000,
                                    std::span(p + units[i].offset, units[i].size)));
    (*w)->close();
    test::make_assets(t / "assets");
    DatasetOpenOptions oo;
    oo.assets_dir = t / "assets";
    auto d = Dataset::open(t / "rec", oo);
    ASSERT_TRUE(d) << to_string(d.error());
    auto store = open_frames(*d);
    ASSERT_TRUE(store) << to_string(store.error());
    std::vector<cv::Mat> seq;
    cv::Mat img;
    for (std::int64_t i = 0; i < (*store)->count(); ++i) {
        auto e = (*store)->read(i, img);
        ASSERT_FALSE(e) << to_string(*e);
        seq.push_back(img.clone());
    }
    const std::int64_t last = (*store)->count() - 1;
    ASSERT_FALSE((*store)->read(last, img));  // random access decodes forward from an IDR
    EXPECT_EQ(cv::norm(img, seq.back(), cv::NORM_INF), 0.0);
}

// The real capture's access units from its first IDR on.
struct Units {
    std::string bytes;
    std::vector<std::span<const std::uint8_t>> aus;
};
Units fixture_units() {
    Units u;
    const fs::path f = fs::path(GS_FIXTURES_DIR) / "ardrone/node-ar-drone_pave.bin";
    if (!fs::exists(f)) return u;
    u.bytes = test::read_file(f);
    const auto* p = reinterpret_cast<const std::uint8_t*>(u.bytes.data());
    bool started = false;
    for (const auto& a : split_access_units(std::span(p, u.bytes.size()))) {
        started = started || a.idr;
        if (started) u.aus.emplace_back(p + a.offset, a.size);
    }
    return u;
}

// The one-pass writer (imports, rendered flights, eval-assist --record): a dataset that opens
// and decodes every frame with the rows as given, numbered in order whatever frame number the
// caller put in a row, the extra files beside; and nothing a reader takes for a flight before
// finish() (flight.json is written last).
TEST(DatasetVideo, AOnePassWriterMakesADatasetOnlyWhenFinished) {
    const Units u = fixture_units();
    if (u.aus.size() < 3) GTEST_SKIP() << "fixture missing";
    test::TempDir t;
    test::make_assets(t / "assets");
    DatasetOpenOptions oo;
    oo.assets_dir = t / "assets";
    auto w = VideoDatasetWriter::create(t / "one");
    ASSERT_TRUE(w) << w.error();
    for (std::size_t i = 0; i < u.aus.size(); ++i) {
        FrameRow row;
        row.frame = 1000;  // the writer numbers the frames
        row.nav.t_ns = static_cast<TimeNs>(i) * 33'333'000;
        row.nav.roll_deg = 0.5 * static_cast<double>(i);
        row.nav.altitude_m = 1.25;
        w->add(u.aus[i], row);
    }
    EXPECT_EQ(w->frames(), static_cast<std::int64_t>(u.aus.size()));
    EXPECT_FALSE(Dataset::open(t / "one", oo)) << "a dataset before finish()";
    EXPECT_FALSE(fs::exists(t / "one" / "flight.json"));
    DatasetInfo info;
    info.width = 640;
    info.height = 360;
    info.fps = 30;
    info.frames = 1;  // finish() counts them
    info.source = "test";
    ASSERT_FALSE(w->finish(info, {{"labels.csv", "frame,distance_m,lateral_m\n0,2,0\n"}}));
    EXPECT_EQ(test::read_file(t / "one" / "labels.csv"), "frame,distance_m,lateral_m\n0,2,0\n");
    auto d = Dataset::open(t / "one", oo);
    ASSERT_TRUE(d) << to_string(d.error());
    ASSERT_EQ(d->frames().size(), u.aus.size());
    EXPECT_EQ(d->info().frames, static_cast<std::int64_t>(u.aus.size()));
    for (std::size_t i = 0; i < u.aus.size(); ++i) {
        EXPECT_EQ(d->frames()[i].frame, static_cast<std::int64_t>(i));
        EXPECT_DOUBLE_EQ(d->frames()[i].nav.roll_deg, 0.5 * static_cast<double>(i));
    }
    auto store = open_frames(*d);
    ASSERT_TRUE(store) << to_string(store.error());
    cv::Mat img;
    for (std::int64_t i = 0; i < (*store)->count(); ++i) {
        auto e = (*store)->read(i, img);
        ASSERT_FALSE(e) << "frame " << i << ": " << to_string(*e);
        EXPECT_EQ(img.cols, 640);
    }
}

TEST(DatasetVideo, AOnePassWriterRefusesAFolderThatHoldsFiles) {
    test::TempDir t;
    test::write_file(t / "full" / "notes.txt", "mine\n");
    auto w = VideoDatasetWriter::create(t / "full");
    ASSERT_FALSE(w);
    EXPECT_NE(w.error().find("not an empty directory"), std::string::npos) << w.error();
    EXPECT_EQ(test::read_file(t / "full" / "notes.txt"), "mine\n");
    EXPECT_TRUE(VideoDatasetWriter::create(t / "empty"));
}

}  // namespace
}  // namespace gs
