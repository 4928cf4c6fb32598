#include "support/dataset_fixtures.hpp"

#include "drone/dataset/dataset_source.hpp"
#include "drone/dataset/thesis.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

namespace gs {
namespace {

using namespace dataset;
namespace fs = std::filesystem;
using test::TempDir;

DatasetSource open_source(const fs::path& dir, const Clock& clock, Pacing p) {
    auto d = Dataset::open(dir);
    EXPECT_TRUE(d);
    auto frames = open_image_frames(*d);
    EXPECT_TRUE(frames);
    return DatasetSource(std::move(*d), std::move(*frames), clock, p);
}

TEST(DatasetSource, RealtimePacingFollowsTheClock) {
    TempDir t;
    test::make_png_dataset(t.path(), 6);  // frames every 40 ms
    FakeClock clock(1'000 * kNsPerMs);
    auto src = open_source(t.path(), clock, Pacing::realtime());
    FrameSample f;
    ASSERT_EQ(src.next(f), SourceStatus::Sample);  // frame 0 is due at once
    EXPECT_EQ(f.index, 0);
    // Played when the pacing clock says, but a recording has no receive time.
    EXPECT_EQ(f.recv_ns, 0);
    EXPECT_EQ(f.capture_ns, 0);
    ASSERT_EQ(src.next(f), SourceStatus::NotYet);
    EXPECT_EQ(src.wait_hint_ns(), 40 * kNsPerMs);
    clock.advance(std::chrono::milliseconds(39));
    ASSERT_EQ(src.next(f), SourceStatus::NotYet);
    EXPECT_EQ(src.wait_hint_ns(), 1 * kNsPerMs);
    clock.advance(std::chrono::milliseconds(1));
    ASSERT_EQ(src.next(f), SourceStatus::Sample);
    EXPECT_EQ(f.index, 1);
    EXPECT_EQ(f.t_ns, 40 * kNsPerMs);
    EXPECT_EQ(f.nav.roll_deg, 1.0);
    EXPECT_EQ(cv::norm(f.image, test::test_image(1, 64, 48), cv::NORM_INF), 0.0);
    // 4x speed: the next 40 ms of flight take 10 ms
    src.set_pacing(Pacing::realtime(4));
    ASSERT_EQ(src.next(f), SourceStatus::NotYet);
    EXPECT_EQ(src.wait_hint_ns(), 10 * kNsPerMs);
    clock.advance(std::chrono::milliseconds(10));
    ASSERT_EQ(src.next(f), SourceStatus::Sample);
    EXPECT_EQ(f.index, 2);
    // speeds outside 0.25..8 are clamped
    src.set_pacing(Pacing::realtime(100));
    ASSERT_EQ(src.next(f), SourceStatus::NotYet);
    EXPECT_EQ(src.wait_hint_ns(), 5 * kNsPerMs);
    clock.advance(std::chrono::milliseconds(5));
    ASSERT_EQ(src.next(f), SourceStatus::Sample);
    EXPECT_EQ(f.index, 3);
    // A consumer that stalls (here 10 s) gets the next frame, then playback resumes at pace
    // from there instead of bursting through the backlog.
    src.set_pacing(Pacing::realtime());
    clock.advance(std::chrono::seconds(10));
    ASSERT_EQ(src.next(f), SourceStatus::Sample);
    EXPECT_EQ(f.index, 4);
    ASSERT_EQ(src.next(f), SourceStatus::NotYet);
    EXPECT_EQ(src.wait_hint_ns(), 40 * kNsPerMs);
    clock.advance(std::chrono::milliseconds(40));
    ASSERT_EQ(src.next(f), SourceStatus::Sample);
    EXPECT_EQ(f.index, 5);
    EXPECT_EQ(src.next(f), SourceStatus::End);
}

TEST(DatasetSource, FastestDeliversEverythingInOrderWithNavdataFirst) {
    TempDir t;
    test::make_png_dataset(t.path(), 4);
    test::write_file(t / "navdata.csv",
                     "t_ms,roll_deg\n0,0\n20,0.5\n40,1\n60,1.5\n80,2\n100,2.5\n");
    FakeClock clock(0);
    auto src = open_source(t.path(), clock, Pacing::fastest());
    std::vector<std::string> order;
    auto tag = [](char c, TimeNs when) {
        std::string s(1, c);
        s += std::to_string(when / kNsPerMs);
        return s;
    };
    FrameSample f;
    NavState n;
    while (true) {
        while (src.next_nav(n) == SourceStatus::Sample) order.push_back(tag('n', n.t_ns));
        const auto s = src.next(f);
        if (s == SourceStatus::End) break;
        ASSERT_EQ(s, SourceStatus::Sample);
        order.push_back(tag('f', f.t_ns));
    }
    while (src.next_nav(n) == SourceStatus::Sample) order.push_back(tag('n', n.t_ns));
    EXPECT_EQ(order, (std::vector<std::string>{"n0", "f0", "n20", "n40", "f40", "n60", "n80", "f80",
                                               "n100", "f120"}));
}

TEST(DatasetSource, SeekStepAndPause) {
    TempDir t;
    test::make_png_dataset(t.path(), 6);
    FakeClock clock(0);
    auto src = open_source(t.path(), clock, Pacing::realtime());
    FrameSample f;
    EXPECT_FALSE(src.seek(6));
    EXPECT_FALSE(src.seek(-1));
    ASSERT_TRUE(src.seek(3));
    ASSERT_EQ(src.next(f), SourceStatus::Sample);
    EXPECT_EQ(f.index, 3);
    EXPECT_EQ(f.nav.yaw_deg, 30.0);
    src.set_paused(true);
    clock.advance(std::chrono::seconds(10));
    EXPECT_EQ(src.next(f), SourceStatus::Paused);
    ASSERT_EQ(src.step(f), SourceStatus::Sample);
    EXPECT_EQ(f.index, 4);
    src.set_paused(false);
    ASSERT_EQ(src.next(f), SourceStatus::NotYet);  // resumes at frame 4's time, not 10 s later
    EXPECT_EQ(src.wait_hint_ns(), 40 * kNsPerMs);
    ASSERT_TRUE(src.seek(0));
    ASSERT_EQ(src.next(f), SourceStatus::Sample);
    EXPECT_EQ(f.index, 0);
    EXPECT_EQ(src.frame_count(), 6);
}

TEST(DatasetSource, UnreadableFrameIsAnErrorNotACrash) {
    TempDir t;
    test::make_png_dataset(t.path(), 2);
    FakeClock clock(0);
    auto src = open_source(t.path(), clock, Pacing::fastest());
    test::write_file(t / "frames/000001.png", "garbage");
    FrameSample f;
    ASSERT_EQ(src.next(f), SourceStatus::Sample);
    ASSERT_EQ(src.next(f), SourceStatus::Error);
    EXPECT_EQ(src.last_error(), "frame 1: frames/000001.png: not a decodable PNG/JPEG image");
    EXPECT_EQ(src.read_errors(), 1);
    // The bad frame is skipped, not retried forever.
    EXPECT_EQ(src.next(f), SourceStatus::End);
}

TEST(Thesis, ExportThenImportRoundTrip) {
    TempDir t;
    test::make_png_dataset(t / "d", 4);
    test::make_assets(t / "assets");
    DatasetOpenOptions oo;
    oo.assets_dir = t / "assets";
    auto d = Dataset::open(t / "d", oo);
    ASSERT_TRUE(d);
    auto frames = open_image_frames(*d);
    ASSERT_TRUE(frames);
    ASSERT_FALSE(export_thesis(*d, **frames, t / "thesis"));
    EXPECT_EQ(test::read_file(t / "thesis/imu.txt").substr(0, 30),
              "0 0 0 nan nan\n1 -0.5 10 nan na");

    auto back = import_thesis(t / "thesis", t / "back", {}, oo);
    ASSERT_TRUE(back) << to_string(back.error());
    EXPECT_EQ(back->info().fps, 25);
    EXPECT_EQ(back->info().source, "imported");
    ASSERT_EQ(back->frame_count(), 4);
    for (std::size_t i = 0; i < 4; ++i) {
        const auto& a = d->frames()[i].nav;
        const auto& b = back->frames()[i].nav;
        EXPECT_EQ(b.t_ns, a.t_ns);  // 40 ms = 1 / 25 fps
        EXPECT_EQ(b.roll_deg, a.roll_deg);
        EXPECT_EQ(b.pitch_deg, a.pitch_deg);
        EXPECT_EQ(b.yaw_deg, a.yaw_deg);
        EXPECT_TRUE(std::isnan(b.vx_mps));
        EXPECT_EQ(b.altitude_m, a.altitude_m);  // imu_extra.csv carries it
    }
    // The dataset's own calibration travels in imu_meta.json.
    EXPECT_FALSE(back->calibration_is_default());
    EXPECT_EQ(back->calibration().fx, d->calibration().fx);
    EXPECT_EQ(back->calibration().dist, d->calibration().dist);
    auto bf = open_image_frames(*back);
    ASSERT_TRUE(bf);
    cv::Mat img;
    ASSERT_FALSE((*bf)->read(3, img));
    EXPECT_EQ(cv::norm(img, test::test_image(3, 64, 48), cv::NORM_INF), 0.0);
}

TEST(Thesis, NaturalOrderOnlyTxtAndErrors) {
    TempDir t;
    test::make_assets(t / "assets");
    DatasetOpenOptions oo;
    oo.assets_dir = t / "assets";
    std::string imu;
    fs::create_directories(t / "thesis");
    for (int i = 1; i <= 11; ++i) {
        cv::imwrite((t / ("thesis/image_" + std::to_string(i) + ".png")).string(),
                    test::test_image(i, 16, 8));
        imu += std::to_string(i) + "\t0 0 0.5 -0.5\n";
    }
    test::write_file(t / "thesis/log.txt", imu);
    ThesisImportOptions o;
    o.fps = 10;
    auto d = open_thesis_folder(t / "thesis", o, oo);
    ASSERT_TRUE(d) << to_string(d.error());
    ASSERT_EQ(d->frame_count(), 11);
    EXPECT_EQ(d->image_files()[1].filename(), "image_2.png");
    EXPECT_EQ(d->image_files()[10].filename(), "image_11.png");
    EXPECT_EQ(d->frames()[10].nav.t_ns, 1'000 * kNsPerMs);
    EXPECT_EQ(d->frames()[10].nav.roll_deg, 11.0);
    EXPECT_EQ(d->frames()[10].nav.vy_mps, -0.5);
    EXPECT_EQ(d->calibration().fx, 14.0);  // 560 scaled from 640 to 16 pixels wide

    test::write_file(t / "thesis/log.txt", imu + "12 0 0 1\n");
    auto e = open_thesis_folder(t / "thesis", o, oo);
    ASSERT_FALSE(e);
    EXPECT_EQ(to_string(e.error()),
              "log.txt:12:9: expected 5 values (roll pitch yaw vx vy), got 4");
    test::write_file(t / "thesis/log.txt", imu + "12 0 0 1 x\n");
    e = open_thesis_folder(t / "thesis", o, oo);
    ASSERT_FALSE(e);
    EXPECT_EQ(to_string(e.error()), "log.txt:12:10: expected a finite number or nan, got 'x'");
    test::write_file(t / "thesis/log.txt", imu + "12 0 0 1 2\n");
    e = open_thesis_folder(t / "thesis", o, oo);
    ASSERT_FALSE(e);
    EXPECT_EQ(to_string(e.error()), "log.txt: 12 lines but the folder holds 11 images");
}

}  // namespace
}  // namespace gs
