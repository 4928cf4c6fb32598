// The Recorder on the real stack: the virtual drone flying a scripted approach over loopback
// sockets, the DroneLink, and the dataset it writes; raw/ replayed through the real parsers.
#include "support/dataset_fixtures.hpp"

#include "drone/dataset/raw.hpp"
#include "drone/dataset/raw_replay.hpp"
#include "drone/link/drone_link.hpp"
#include "drone/record/recorder.hpp"
#include "drone/sim/scenarios.hpp"
#include "drone/sim/virtual_drone.hpp"
#include "support/virtual_drone.hpp"
#include "support/wait.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <memory>
#include <thread>

namespace gs {
namespace {
using namespace std::chrono_literals;

using test::wait_until;

bool same(double a, double b) {
    return (std::isnan(a) && std::isnan(b)) || a == b;
}

// The virtual drone flying thesis_pillar_left and a link connected to it, video flowing.
struct Flight {
    std::unique_ptr<sim::VirtualDrone> drone;
    std::unique_ptr<link::DroneLink> link;
    std::string error;

    Flight() {
        auto scene = sim::resolve_scene("thesis_pillar_left");
        if (!scene) {
            error = sim::to_string(scene.error());
            return;
        }
        sim::VirtualDroneOptions vo = test::loopback_drone_options(*scene);
        vo.autopilot = true;
        drone = std::make_unique<sim::VirtualDrone>(vo);
        if (auto s = drone->start(); !s) {
            error = s.error().message;
            return;
        }
        link = std::make_unique<link::DroneLink>(test::link_config_for(*drone));
        if (auto s = link->start(); !s) {
            error = s.error().message;
            return;
        }
        if (!wait_until([&] { return link->state() == link::ConnectionState::Connected; }, 10s))
            error = "no connection: " + link->status().reason;
        else if (!wait_until([&] { return link->video().latest().has_value(); }, 10s))
            error = "no video";
    }
    ~Flight() {
        if (link) link->stop();
        if (drone) drone->stop();
    }
};

class RecorderFlight : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        dir_ = new test::TempDir;
        flight_ = new Flight;
        if (!flight_->error.empty()) return;
        record::Recorder rec(*flight_->link, flight_->drone.get());
        auto s = rec.start(*dir_ / "rec");
        if (!s) {
            flight_->error = s.error().message;
            return;
        }
        const auto during = rec.status();
        recording_seen_ = during.recording && during.path == (*dir_ / "rec").string();
        const auto gen0 = flight_->link->video().generation();
        std::this_thread::sleep_for(2500ms);
        final_ = rec.stop();
        frames_seen_ = flight_->link->video().generation() - gen0;
    }
    static void TearDownTestSuite() {
        delete flight_;
        delete dir_;
    }
    void SetUp() override { ASSERT_TRUE(flight_->error.empty()) << flight_->error; }

    static inline test::TempDir* dir_ = nullptr;
    static inline Flight* flight_ = nullptr;
    static inline record::RecorderStatus final_;
    static inline bool recording_seen_ = false;
    static inline std::uint64_t frames_seen_ = 0;  // frames the link decoded while recording
};

TEST_F(RecorderFlight, WritesADatasetTheReaderOpensWithGroundTruth) {
    EXPECT_TRUE(recording_seen_);
    EXPECT_FALSE(final_.recording);
    auto d = dataset::Dataset::open(*dir_ / "rec");
    ASSERT_TRUE(d) << to_string(d.error());
    // 2.5 s at 30 fps: up to ~75 frames. The virtual drone renders slower on a loaded machine
    // (or under the sanitizers), so what counts is that every frame the link received is there,
    // less those before the first IDR (at most a GOP of 15) and the one in flight at each end.
    EXPECT_LE(d->frame_count(), 80);
    EXPECT_GE(d->frame_count() + 15 + 2, static_cast<std::int64_t>(frames_seen_));
    EXPECT_GE(d->frame_count(), 5);
    EXPECT_EQ(d->info().frames, d->frame_count());
    EXPECT_FALSE(d->calibration_is_default());  // written into flight.json
    EXPECT_TRUE(d->video_path());
    EXPECT_TRUE(d->raw_dir());
    EXPECT_GE(d->navdata().size(), 30u);  // demo navdata, 15 Hz
    // The status is what is on disk.
    EXPECT_EQ(final_.frames, static_cast<std::uint64_t>(d->frame_count()));
    EXPECT_EQ(final_.navdata, d->navdata().size());
    EXPECT_EQ(final_.drops, 0u);
    EXPECT_GT(final_.bytes, 100'000u);
    EXPECT_TRUE(final_.error.empty()) << final_.error;

    ASSERT_TRUE(d->labels());
    EXPECT_EQ(d->labels()->scenario, dataset::Scenario::Left);
    ASSERT_TRUE(d->label_rows());
    ASSERT_EQ(d->label_rows()->size(), static_cast<std::size_t>(d->frame_count()));
    const auto& labels = *d->label_rows();
    // The pillar's centre is 0.5 m left of the flight line; the drone flies towards it.
    for (const auto& l : labels) {
        EXPECT_NEAR(l.lateral_m, -0.5, 0.1) << l.frame;
        EXPECT_GT(l.distance_m, 3.0) << l.frame;
        EXPECT_LT(l.distance_m, 7.1) << l.frame;
    }
    for (std::size_t i = 1; i < labels.size(); ++i)
        EXPECT_LE(labels[i].distance_m, labels[i - 1].distance_m + 1e-3) << i;
    // gt_* columns: the camera pose, which moves forward as the distance shrinks.
    const auto& rows = d->frames();
    EXPECT_NEAR(rows.front().gt.x_m + labels.front().distance_m,
                rows.back().gt.x_m + labels.back().distance_m, 0.05);
}

TEST_F(RecorderFlight, FrameAttitudeIsTheNavdataInterpolatedAtCapture) {
    auto d = dataset::Dataset::open(*dir_ / "rec");
    ASSERT_TRUE(d) << to_string(d.error());
    const auto& navs = d->navdata();
    ASSERT_GE(navs.size(), 2u);
    std::size_t bracketed = 0, outside = 0;
    for (const dataset::FrameRow& f : d->frames()) {
        const TimeNs t = f.nav.t_ns;
        auto after = std::lower_bound(navs.begin(), navs.end(), t,
                                      [](const NavState& s, TimeNs v) { return s.t_ns < v; });
        if (after == navs.begin() || after == navs.end()) {
            ++outside;
            continue;
        }
        const NavState want = interpolate(*(after - 1), *after, t);
        EXPECT_DOUBLE_EQ(f.nav.roll_deg, want.roll_deg) << f.frame;
        EXPECT_DOUBLE_EQ(f.nav.pitch_deg, want.pitch_deg) << f.frame;
        EXPECT_NEAR(f.nav.yaw_deg, want.yaw_deg, 1e-9) << f.frame;
        EXPECT_DOUBLE_EQ(f.nav.altitude_m, want.altitude_m) << f.frame;
        ++bracketed;
    }
    // Only frames captured before the first or after the last navdata sample (15 Hz: 67 ms,
    // two frames, at each end, plus the video's latency at the start) are not bracketed.
    EXPECT_EQ(bracketed + outside, static_cast<std::size_t>(d->frame_count()));
    EXPECT_LE(outside, 6u);
    // the drone pitches nose-down to fly forward in this flight: the attitude is real navdata
    double min_pitch = 0;
    for (const dataset::FrameRow& f : d->frames()) min_pitch = std::min(min_pitch, f.nav.pitch_deg);
    EXPECT_LT(min_pitch, -1.0);
}

TEST_F(RecorderFlight, RawReplayThroughTheProtocolParsersReproducesFramesCsv) {
    auto d = dataset::Dataset::open(*dir_ / "rec");
    ASSERT_TRUE(d) << to_string(d.error());
    auto dec = dataset::make_protocol_replay_decoders();
    auto replayed = dataset::replay_raw(*dir_ / "rec/raw", dec);
    ASSERT_TRUE(replayed) << to_string(replayed.error());
    ASSERT_EQ(replayed->size(), d->frames().size());
    for (std::size_t i = 0; i < replayed->size(); ++i) {
        const dataset::FrameRow& a = (*replayed)[i];
        const dataset::FrameRow& b = d->frames()[i];
        EXPECT_EQ(a.frame, b.frame);
        EXPECT_EQ(a.nav.t_ns, b.nav.t_ns) << i;
        EXPECT_TRUE(same(a.nav.roll_deg, b.nav.roll_deg)) << i;
        EXPECT_TRUE(same(a.nav.pitch_deg, b.nav.pitch_deg)) << i;
        EXPECT_TRUE(same(a.nav.yaw_deg, b.nav.yaw_deg)) << i;
        EXPECT_TRUE(same(a.nav.vx_mps, b.nav.vx_mps)) << i;
        EXPECT_TRUE(same(a.nav.altitude_m, b.nav.altitude_m)) << i;
    }
    // every AT datagram sent went into raw/at.log (the link sends at least every 30 ms)
    auto at = dataset::read_at_log(*dir_ / "rec/raw");
    ASSERT_TRUE(at) << to_string(at.error());
    EXPECT_GE(at->size(), 60u);
    EXPECT_EQ(final_.at, at->size());
}

// A recording consumer that never drains its queues cannot slow the link down: its queues fill,
// every further item is dropped and counted, and flight data keeps flowing.
TEST(Recorder, AStalledConsumerNeverBlocksTheLink) {
    Flight flight;
    ASSERT_TRUE(flight.error.empty()) << flight.error;
    auto raw = flight.link->subscribe_raw(4);
    auto units = flight.link->subscribe_access_units(2);
    const auto nav0 = flight.link->status().navdata.accepted;
    const auto frames0 = flight.link->video().generation();
    std::this_thread::sleep_for(1000ms);
    const auto st = flight.link->status();
    const auto frames = flight.link->video().generation() - frames0;
    EXPECT_EQ(raw->size(), 4u);
    EXPECT_EQ(units->size(), 2u);
    EXPECT_GT(raw->dropped(), 20u);  // navdata at 15 Hz + AT at 33 Hz + video chunks, for 1 s
    // Every access unit past the queue's 2 is dropped and counted (30 fps; fewer when the
    // virtual drone renders slowly on a loaded machine); one may be in flight at each end.
    EXPECT_GE(units->dropped() + 2 + 2, frames);
    EXPECT_GT(units->dropped(), 3u);
    EXPECT_EQ(st.state, link::ConnectionState::Connected);
    EXPECT_GT(st.navdata.accepted, nav0 + 10);
    EXPECT_GT(frames, 5u);
    flight.link->unsubscribe(raw.get());
    flight.link->unsubscribe(units.get());
    const auto dropped = raw->dropped();
    std::this_thread::sleep_for(200ms);
    EXPECT_LE(raw->dropped(), dropped + 2);  // at most what was in flight while unsubscribing
}

// Queues far too small for the streams: whatever is lost is counted, and what the status says
// was written is what the dataset holds.
TEST(Recorder, TinyQueuesStillGiveAConsistentDatasetAndHonestCounts) {
    Flight flight;
    ASSERT_TRUE(flight.error.empty()) << flight.error;
    test::TempDir t;
    record::Recorder rec(*flight.link, flight.drone.get());
    record::RecorderOptions o;
    o.raw_queue = 2;
    o.access_unit_queue = 1;
    o.writer.queue_capacity = 2;
    ASSERT_TRUE(rec.start(t / "rec", o));
    EXPECT_FALSE(rec.start(t / "other"));  // one recording at a time
    std::this_thread::sleep_for(1500ms);
    const auto st = rec.stop();
    EXPECT_EQ(st.drops, st.dropped_link + st.dropped_writer + st.dropped_tap);
    EXPECT_EQ(flight.link->state(), link::ConnectionState::Connected);
    auto d = dataset::Dataset::open(t / "rec");
    ASSERT_TRUE(d) << to_string(d.error());
    EXPECT_EQ(st.frames, static_cast<std::uint64_t>(d->frame_count()));
    EXPECT_EQ(st.navdata, d->navdata().size());
    std::printf(
        "tiny queues: %llu frames, %llu navdata, drops %llu (link %llu, writer %llu)\n",
        static_cast<unsigned long long>(st.frames), static_cast<unsigned long long>(st.navdata),
        static_cast<unsigned long long>(st.drops), static_cast<unsigned long long>(st.dropped_link),
        static_cast<unsigned long long>(st.dropped_writer));
}

}  // namespace
}  // namespace gs
