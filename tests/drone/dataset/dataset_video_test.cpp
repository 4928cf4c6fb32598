// video.h264 datasets decoded through H264Decoder. Enabled once drone/h264_decoder.cpp (written
// by another helper) is in the tree; until then this file compiles to nothing.
#if __has_include("drone/h264_decoder.cpp")

#include "support/dataset_fixtures.hpp"

#include "drone/dataset/dataset_source.hpp"
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

}  // namespace
}  // namespace gs

#endif
