// The Recorder on the real stack: the virtual drone flying a scripted approach over loopback
// sockets, the DroneLink, and the dataset it writes; raw/ replayed through the real parsers.
#include "support/dataset_fixtures.hpp"

#include "drone/dataset/frame_store.hpp"
#include "drone/dataset/raw.hpp"
#include "drone/dataset/raw_replay.hpp"
#include "drone/dataset/video_frames.hpp"
#include "drone/link/drone_link.hpp"
#include "drone/record/recorder.hpp"
#include "drone/sim/loopback.hpp"
#include "drone/sim/scenarios.hpp"
#include "drone/sim/virtual_drone.hpp"
#include "support/wait.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <fstream>
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
        sim::VirtualDroneOptions vo = sim::loopback_options(*scene);
        vo.autopilot = true;
        drone = std::make_unique<sim::VirtualDrone>(vo);
        if (auto s = drone->start(); !s) {
            error = s.error().message;
            return;
        }
        link = std::make_unique<link::DroneLink>(sim::link_config(*drone));
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
        // About 2.5 s of flight: 60 frames and 400 navdata samples on disk (longer on a slow
        // machine or under a sanitizer: the test waits for what was recorded, not for time).
        if (!wait_until([&] { return rec.status().frames >= 60 && rec.status().navdata >= 400; },
                        60s))
            flight_->error = "the recording did not reach 60 frames";
        frames_before_stop_ = flight_->link->video().generation() - gen0;
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
    static inline std::uint64_t frames_seen_ = 0;  // frames the link decoded until stop() returned
    static inline std::uint64_t frames_before_stop_ = 0;  // ... until stop() was called
};

TEST_F(RecorderFlight, WritesADatasetTheReaderOpensWithGroundTruth) {
    EXPECT_TRUE(recording_seen_);
    EXPECT_FALSE(final_.recording);
    auto d = dataset::Dataset::open(*dir_ / "rec");
    ASSERT_TRUE(d) << to_string(d.error());
    // Every frame the link received is there, less those before the first IDR (at most a GOP
    // of 15) and the one in flight at each end.
    EXPECT_GE(d->frame_count() + 15 + 2, static_cast<std::int64_t>(frames_before_stop_));
    EXPECT_LE(d->frame_count(), static_cast<std::int64_t>(frames_seen_) + 2);
    EXPECT_GE(d->frame_count(), 60);
    EXPECT_EQ(d->info().frames, d->frame_count());
    EXPECT_FALSE(d->calibration_is_default());  // written into flight.json
    EXPECT_TRUE(d->video_path());
    EXPECT_TRUE(d->raw_dir());
    EXPECT_GE(d->navdata().size(), 400u);  // full navdata, 200 Hz
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
    // The pillar's centre is 0.6 m left of the flight line; the drone flies towards it. The
    // recording starts before it; where it ends depends on how fast frames came (60 frames are
    // about 2.5 s here, but under ThreadSanitizer the renderer is so slow that the drone, which
    // flies in real time, may have passed the pillar by then).
    EXPECT_GT(labels.front().distance_m, 0.0);
    for (const auto& l : labels) {
        EXPECT_NEAR(l.lateral_m, -0.6, 0.1) << l.frame;
        EXPECT_LT(l.distance_m, 7.1) << l.frame;
    }
    for (std::size_t i = 1; i < labels.size(); ++i)
        EXPECT_LE(labels[i].distance_m, labels[i - 1].distance_m + 1e-3) << i;
    // gt_* columns: the camera pose, which moves forward as the distance shrinks.
    const auto& rows = d->frames();
    EXPECT_NEAR(rows.front().gt.x_m + labels.front().distance_m,
                rows.back().gt.x_m + labels.back().distance_m, 0.05);
    // collisions.csv: written from the virtual drone's ground truth, the header alone when the
    // flight (which passes 9 cm from the pillar) touched nothing.
    std::ifstream collisions(*dir_ / "rec" / "collisions.csv");
    ASSERT_TRUE(collisions.good());
    std::string header, row;
    std::getline(collisions, header);
    EXPECT_EQ(header, "t_ms,frame,crash,kind,what,x_m,y_m,z_m,speed_mps,approach_mps");
    EXPECT_FALSE(std::getline(collisions, row)) << row;
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
    std::vector<std::string> warnings;  // a whole recording is not cut short anywhere
    auto replayed = dataset::replay_raw(*dir_ / "rec/raw", dec, &warnings);
    ASSERT_TRUE(replayed) << to_string(replayed.error());
    EXPECT_TRUE(warnings.empty()) << warnings.front();
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
    // Flight data keeps flowing while nobody drains: 20 more frames, 100 more navdata samples.
    ASSERT_TRUE(wait_until(
        [&] {
            return flight.link->video().generation() > frames0 + 20 &&
                   flight.link->status().navdata.accepted > nav0 + 100;
        },
        30s));
    const auto st = flight.link->status();
    const auto frames = flight.link->video().generation() - frames0;
    EXPECT_EQ(raw->size(), 4u);
    EXPECT_EQ(units->size(), 2u);
    EXPECT_GT(raw->dropped(), 100u);  // every navdata datagram, AT datagram and video chunk
    // Every access unit past the queue's 2 is dropped and counted (30 fps; fewer when the
    // virtual drone renders slowly on a loaded machine); one may be in flight at each end.
    EXPECT_GE(units->dropped() + 2 + 2, frames);
    EXPECT_GT(units->dropped(), 3u);
    EXPECT_EQ(st.state, link::ConnectionState::Connected);
    flight.link->unsubscribe(raw.get());
    flight.link->unsubscribe(units.get());
    const auto dropped = raw->dropped();
    const auto nav1 = flight.link->status().navdata.accepted;
    ASSERT_TRUE(
        wait_until([&] { return flight.link->status().navdata.accepted > nav1 + 40; }, 10s));
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
    const auto frames0 = flight.link->video().generation();
    ASSERT_TRUE(wait_until([&] { return flight.link->video().generation() > frames0 + 40; }, 30s));
    const auto st = rec.stop();
    EXPECT_EQ(st.drops, st.dropped_link + st.dropped_writer + st.dropped_tap +
                            st.dropped_reference_lost + st.dropped_no_picture +
                            st.dropped_not_h264 + st.dropped_cut_by_reset);
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

// Issue 14 points 1-3 on the real stack: a video reset that cuts an IDR frame, duplicated and
// reordered navdata, while recording. Every frame frames.csv has replays, every frame not kept
// is a drop with its reason, navdata.csv holds what the link accepted in order, no two frames
// share a time, and raw/ (with its connection boundaries) replays into the same frames.csv.
TEST(RecorderFaults, AResetInsideAnIdrAndReorderedNavdataLeaveADatasetThatReplaysExactly) {
    Flight flight;
    ASSERT_TRUE(flight.error.empty()) << flight.error;
    test::TempDir t;
    record::Recorder rec(*flight.link, flight.drone.get());
    ASSERT_TRUE(rec.start(t / "rec"));
    const auto connects0 = flight.link->status().video.connects;
    ASSERT_TRUE(wait_until([&] { return rec.status().frames > 10; }, 10s));
    sim::NavdataFaults f;
    f.reorder = 0.2;
    f.duplicate = 0.2;
    flight.drone->inject(sim::FaultNavdata{f});
    flight.drone->inject(sim::FaultVideoReset{/*during_idr=*/true});
    ASSERT_TRUE(wait_until([&] { return flight.link->status().video.connects > connects0; }, 5s));
    const auto decoded = flight.link->status().video.decoded;
    ASSERT_TRUE(
        wait_until([&] { return flight.link->status().video.decoded > decoded + 20; }, 10s));
    flight.drone->inject(sim::FaultNavdata{});
    const auto st = rec.stop();
    const auto c = flight.drone->status().counters;
    EXPECT_GT(c.navdata_duplicated + c.navdata_reordered, 5u);

    auto d = dataset::Dataset::open(t / "rec");
    ASSERT_TRUE(d) << to_string(d.error());
    EXPECT_EQ(st.frames, static_cast<std::uint64_t>(d->frame_count()));
    // The reset cost the P-frames after it until the next IDR, each counted with its reason.
    EXPECT_GT(st.dropped_reference_lost, 0u);
    EXPECT_EQ(st.drops, st.dropped_reference_lost + st.dropped_cut_by_reset);
    EXPECT_EQ(st.dropped_link + st.dropped_writer + st.dropped_no_picture, 0u);
    // The reset's, and one per reconnection after a video silence on a slow machine.
    EXPECT_GE(st.video_connections, 2u);
    EXPECT_EQ(test::read_file(t / "rec/raw/video_connections.csv").rfind("offset,t_us\n0,0\n", 0),
              0u);

    // Every row's frame decodes (before: "access unit 437 produced no picture").
    auto frames = dataset::open_frames(*d);
    ASSERT_TRUE(frames) << to_string(frames.error());
    cv::Mat img;
    for (std::int64_t i = 0; i < d->frame_count(); ++i) {
        auto e = (*frames)->read(i, img);
        EXPECT_FALSE(e) << "frame " << i << ": " << (e ? to_string(*e) : "");
    }
    // navdata.csv: what the link accepted, in order (no duplicate, no late packet).
    ASSERT_EQ(d->navdata().size(), st.navdata_accepted);
    // ... every one the link accepted from the first recorded to the last, none lost between.
    EXPECT_EQ(st.navdata_link_span, st.navdata_accepted);
    for (std::size_t i = 1; i < d->navdata().size(); ++i) {
        ASSERT_TRUE(d->navdata()[i].seq);
        EXPECT_GT(*d->navdata()[i].seq, *d->navdata()[i - 1].seq) << "row " << i;
    }
    // No two frames share a capture time.
    for (std::size_t i = 1; i < d->frames().size(); ++i)
        EXPECT_GT(d->frames()[i].nav.t_ns, d->frames()[i - 1].nav.t_ns) << i;

    // raw/ through the real parsers, connection boundaries included, gives frames.csv.
    auto dec = dataset::make_protocol_replay_decoders();
    std::vector<std::string> warnings;  // a whole recording is not cut short anywhere
    auto replayed = dataset::replay_raw(t / "rec/raw", dec, &warnings);
    ASSERT_TRUE(replayed) << to_string(replayed.error());
    EXPECT_TRUE(warnings.empty()) << warnings.front();
    ASSERT_EQ(replayed->size(), d->frames().size());
    for (std::size_t i = 0; i < replayed->size(); ++i) {
        EXPECT_EQ((*replayed)[i].nav.t_ns, d->frames()[i].nav.t_ns) << i;
        EXPECT_TRUE(same((*replayed)[i].nav.roll_deg, d->frames()[i].nav.roll_deg)) << i;
        EXPECT_TRUE(same((*replayed)[i].nav.pitch_deg, d->frames()[i].nav.pitch_deg)) << i;
    }
}

}  // namespace
}  // namespace gs
