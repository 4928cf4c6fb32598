// app::Session without the window (app_core only), checked through the session's published
// values: the source lifecycle (open, switch, close), replay control, recording control and the
// request visitor's other handlers (classifier, calibration).

#include "app/session.hpp"
#include "support/dataset_fixtures.hpp"
#include "support/wait.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

namespace gs::app {
namespace {

using namespace std::chrono_literals;
using test::wait_until;

const std::string kFlight = std::string(GS_TEST_DATA_DIR) + "/flights/ci_pillar_left";

SessionOptions headless_options() {
    SessionOptions o;
    o.replay_autoplay = false;
    o.record_root = ::testing::TempDir();
    return o;
}

template <class T>
T latest(const LatestValue<T>& slot) {
    return slot.latest().value_or(T{});
}

// Reads the session's messages until one contains `text` (kept in `seen` for the failure text).
bool wait_message(Session& s, const std::string& text, std::vector<std::string>& seen,
                  std::chrono::milliseconds timeout = 10s) {
    return wait_until(
               [&] {
                   while (auto m = s.next_message()) {
                       seen.push_back(*m);
                       if (m->find(text) != std::string::npos) return true;
                   }
                   return false;
               },
               timeout)
        .has_value();
}

std::string joined(const std::vector<std::string>& v) {
    std::string out;
    for (const auto& m : v) out += m + "\n";
    return out;
}

TEST(Session, ReplaysADatasetThroughTheClassifierAndCloses) {
    Session s(headless_options());
    ASSERT_TRUE(s.request(OpenReplay{kFlight}));
    ASSERT_TRUE(wait_until([&] { return latest(s.replay()).open; }, 10s))
        << latest(s.replay()).error << latest(s.source()).error;
    const ReplayInfo r = latest(s.replay());
    EXPECT_EQ(r.path, kFlight);
    EXPECT_EQ(r.frame_count, 153);
    EXPECT_EQ(latest(s.source()).kind, SessionSource::Replay);
    EXPECT_EQ(latest(s.calibration()).origin, "dataset " + kFlight);
    EXPECT_TRUE(r.missing_inputs.empty()) << r.missing_inputs.front();

    // Stepping classifies each frame once, in order.
    for (int i = 0; i < 5; ++i) ASSERT_TRUE(s.request(ReplayStep{1}));
    ASSERT_TRUE(wait_until([&] { return latest(s.replay()).frame == 4; }, 10s))
        << latest(s.replay()).frame;
    ASSERT_TRUE(wait_until(
        [&] {
            const auto out = latest(s.output());
            return out && out->frame.index == 4;
        },
        10s));
    const auto out = latest(s.output());
    EXPECT_EQ(out->classifier, latest(s.classifier()).active);
    EXPECT_EQ(out->result.frame_index, 4);
    EXPECT_GE(s.frames_processed(), 5u);

    ASSERT_TRUE(s.request(CloseSource{}));
    ASSERT_TRUE(wait_until([&] { return latest(s.source()).kind == SessionSource::None; }, 10s));
    EXPECT_FALSE(latest(s.replay()).open);
}

// Issue 14 point 7: the session tells the window which inputs the classifier lacks.
TEST(Session, AFlightWithoutVelocityAndAltitudeSaysWhatTheClassifierLacks) {
    test::TempDir tmp;
    const auto flight = (tmp.path() / "attitude_only").string();
    test::copy_attitude_only(kFlight, flight);
    Session s(headless_options());
    ASSERT_TRUE(s.request(OpenReplay{flight}));
    ASSERT_TRUE(wait_until([&] { return latest(s.replay()).open; }, 10s))
        << latest(s.replay()).error << latest(s.source()).error;
    const auto missing = latest(s.replay()).missing_inputs;
    ASSERT_EQ(missing.size(), 3u);
    EXPECT_NE(missing[0].find("no velocity"), std::string::npos) << missing[0];
}

TEST(Session, AMissingDatasetIsReportedNotOpened) {
    Session s(headless_options());
    ASSERT_TRUE(s.request(OpenReplay{kFlight + "_does_not_exist"}));
    ASSERT_TRUE(wait_until([&] { return !latest(s.source()).error.empty(); }, 10s));
    EXPECT_EQ(latest(s.source()).kind, SessionSource::None);
    EXPECT_FALSE(latest(s.replay()).open);
}

TEST(Session, FliesTheVirtualDroneAndClassifiesItsVideo) {
    Session s(headless_options());
    ASSERT_TRUE(s.request(StartSim{"thesis_pillar_left", false}));
    ASSERT_TRUE(wait_until([&] { return latest(s.source()).kind == SessionSource::Sim; }, 10s))
        << latest(s.source()).error;
    const SourceInfo src = latest(s.source());
    ASSERT_TRUE(src.link);
    ASSERT_TRUE(src.virtual_drone);
    EXPECT_EQ(src.scenario, "thesis_pillar_left");
    ASSERT_TRUE(
        wait_until([&] { return src.link->state() == link::ConnectionState::Connected; }, 10s))
        << src.link->status().reason;
    const std::uint64_t before = s.frames_processed();
    ASSERT_TRUE(wait_until([&] { return s.frames_processed() >= before + 10; }, 15s))
        << "frames processed: " << s.frames_processed();
    const auto out = latest(s.output());
    ASSERT_TRUE(out);
    EXPECT_EQ(out->source_id, src.id);
    EXPECT_FALSE(out->frame.image.empty());

    ASSERT_TRUE(s.request(CloseSource{}));
    ASSERT_TRUE(wait_until([&] { return latest(s.source()).kind == SessionSource::None; }, 10s));
}

TEST(Session, SwitchesSourcesWithoutAClose) {
    Session s(headless_options());
    ASSERT_TRUE(s.request(OpenReplay{kFlight}));
    ASSERT_TRUE(wait_until([&] { return latest(s.replay()).open; }, 10s));
    const SourceInfo replay = latest(s.source());
    EXPECT_EQ(replay.opens_handled, 1u);
    EXPECT_EQ(latest(s.opening()).count, 1u);

    // Another source replaces the replay: a new id, the replay closed, the drone's calibration.
    ASSERT_TRUE(s.request(StartSim{"thesis_pillar_left", false}));
    EXPECT_EQ(latest(s.opening()).kind, SessionSource::Sim);  // said before the thread sees it
    ASSERT_TRUE(wait_until([&] { return latest(s.source()).kind == SessionSource::Sim; }, 10s))
        << latest(s.source()).error;
    const SourceInfo sim = latest(s.source());
    EXPECT_GT(sim.id, replay.id);
    EXPECT_EQ(sim.opens_handled, 2u);
    EXPECT_TRUE(sim.link);
    EXPECT_FALSE(latest(s.replay()).open);
    EXPECT_EQ(latest(s.calibration()).source_id, sim.id);
    EXPECT_NE(latest(s.calibration()).origin, "dataset " + kFlight);

    // And back: the link and the virtual drone are gone from the published source.
    ASSERT_TRUE(s.request(OpenReplay{kFlight}));
    ASSERT_TRUE(wait_until([&] { return latest(s.source()).kind == SessionSource::Replay; }, 10s));
    const SourceInfo again = latest(s.source());
    EXPECT_GT(again.id, sim.id);
    EXPECT_FALSE(again.link);
    EXPECT_FALSE(again.virtual_drone);
    EXPECT_EQ(again.opens_handled, 3u);
    EXPECT_EQ(latest(s.calibration()).origin, "dataset " + kFlight);
}

TEST(Session, ReplayControlsSeekStepPaceAndLoop) {
    Session s(headless_options());
    std::vector<std::string> seen;
    // Without a replay the controls are refused, and said so.
    ASSERT_TRUE(s.request(ReplaySeek{3}));
    ASSERT_TRUE(wait_message(s, "no replay open", seen)) << joined(seen);

    ASSERT_TRUE(s.request(OpenReplay{kFlight}));
    ASSERT_TRUE(wait_until([&] { return latest(s.replay()).open; }, 10s));
    EXPECT_FALSE(latest(s.replay()).playing);  // headless_options: no autoplay

    // A seek while paused shows the frame there; past the end it is clamped to the last frame.
    ASSERT_TRUE(s.request(ReplaySeek{40}));
    ASSERT_TRUE(wait_until([&] { return latest(s.replay()).frame == 40; }, 10s))
        << latest(s.replay()).frame;
    ASSERT_TRUE(s.request(ReplaySeek{1'000'000}));
    ASSERT_TRUE(wait_until([&] { return latest(s.replay()).frame == 152; }, 10s))
        << latest(s.replay()).frame;
    // One step back.
    ASSERT_TRUE(s.request(ReplayStep{-1}));
    ASSERT_TRUE(wait_until([&] { return latest(s.replay()).frame == 151; }, 10s))
        << latest(s.replay()).frame;
    ASSERT_TRUE(wait_until(
        [&] {
            const auto out = latest(s.output());
            return out && out->frame.index == 151;
        },
        10s));

    // Speed is clamped to the pacing's range; loop and play are kept as asked.
    ASSERT_TRUE(s.request(ReplaySpeed{100.0}));
    ASSERT_TRUE(s.request(ReplayLoop{true}));
    ASSERT_TRUE(wait_until([&] { return latest(s.replay()).loop; }, 10s));
    EXPECT_DOUBLE_EQ(latest(s.replay()).speed, Pacing::kMaxSpeed);
    ASSERT_TRUE(s.request(ReplaySpeed{0.0}));
    ASSERT_TRUE(wait_until([&] { return latest(s.replay()).speed == Pacing::kMinSpeed; }, 10s));
    ASSERT_TRUE(s.request(ReplayPlay{true}));
    ASSERT_TRUE(wait_until([&] { return latest(s.replay()).playing; }, 10s));
    ASSERT_TRUE(s.request(ReplayPlay{false}));
    ASSERT_TRUE(wait_until([&] { return !latest(s.replay()).playing; }, 10s));
}

TEST(Session, RecordsALiveSourceAndStops) {
    Session s(headless_options());
    std::vector<std::string> seen;
    // A replay is already recorded: refused, said so, nothing published as recording.
    ASSERT_TRUE(s.request(OpenReplay{kFlight}));
    ASSERT_TRUE(wait_until([&] { return latest(s.replay()).open; }, 10s));
    ASSERT_TRUE(s.request(RecordStart{}));
    ASSERT_TRUE(wait_message(s, "recording needs a drone", seen)) << joined(seen);
    EXPECT_FALSE(s.recording().latest());

    ASSERT_TRUE(s.request(StartSim{"thesis_pillar_left", false}));
    ASSERT_TRUE(wait_until([&] { return latest(s.source()).kind == SessionSource::Sim; }, 10s))
        << latest(s.source()).error;
    const std::filesystem::path dir =
        std::filesystem::path(::testing::TempDir()) / "session_test_recording";
    std::filesystem::remove_all(dir);
    ASSERT_TRUE(s.request(RecordStart{dir.string()}));
    ASSERT_TRUE(wait_until(
        [&] {
            const RecordingInfo r = latest(s.recording());
            return r.status.recording && r.status.frames >= 5 && r.status.navdata > 0;
        },
        20s))
        << latest(s.recording()).status.error << joined(seen);
    // The status is republished while recording, with the free space where it writes.
    const RecordingInfo during = latest(s.recording());
    EXPECT_EQ(during.last_path, dir.string());
    EXPECT_TRUE(known(during.disk_free_bytes));
    EXPECT_GT(during.status.bytes, 0u);

    ASSERT_TRUE(s.request(RecordStop{}));
    ASSERT_TRUE(wait_until([&] { return !latest(s.recording()).status.recording; }, 10s));
    const RecordingInfo after = latest(s.recording());
    EXPECT_EQ(after.last_path, dir.string());
    EXPECT_GE(after.status.frames, during.status.frames);
    EXPECT_TRUE(std::filesystem::exists(dir / "flight.json"));
    EXPECT_TRUE(std::filesystem::exists(dir / "frames.csv"));
    ASSERT_TRUE(wait_message(s, "recording stopped", seen)) << joined(seen);
    std::filesystem::remove_all(dir);
}

// Issue 14 point 4: a full disk during a recording started from the window. The recorder stops
// itself at the first failed write (here injected into frames.csv, as a full disk fails it); the
// session says so once, in a message naming the dataset and the disk (the window's status bar
// and message log show the session's messages), publishes the error for the recording window,
// leaves a dataset that opens, and the flight goes on: the drone stays up, the link connected,
// AT commands still sent every 30 ms.
TEST(Session, AFullDiskStopsTheRecordingWithOneMessageAndTheFlightGoesOn) {
    SessionOptions o = headless_options();
    o.record_inject_failure_file = "frames.csv";
    o.record_inject_failure_after_bytes = 2000;  // the header and ~25 rows: about 1 s
    Session s(o);
    std::vector<std::string> seen;
    ASSERT_TRUE(s.request(StartSim{"thesis_pillar_left", false}));
    ASSERT_TRUE(wait_until([&] { return latest(s.source()).kind == SessionSource::Sim; }, 10s))
        << latest(s.source()).error;
    const SourceInfo src = latest(s.source());
    ASSERT_TRUE(src.link && src.virtual_drone);
    ASSERT_TRUE(
        wait_until([&] { return src.link->state() == link::ConnectionState::Connected; }, 10s))
        << src.link->status().reason;
    (void)src.link->submit(link::Takeoff{});
    auto up = [&] {
        const sim::VirtualDroneStatus d = src.virtual_drone->status();
        return d.flight.flying() && d.flight.z_m > 0.5;
    };
    ASSERT_TRUE(wait_until(up, 20s)) << src.virtual_drone->status().flight.z_m;

    test::TempDir tmp;
    const std::filesystem::path dir = tmp.path() / "full_disk";
    ASSERT_TRUE(s.request(RecordStart{dir.string()}));
    // (30 s: the ThreadSanitizer tree runs this test too, five- to fifteen-fold slower.)
    ASSERT_TRUE(wait_message(s, "the disk holding it is full", seen, 30s)) << joined(seen);
    const std::string& said = seen.back();
    EXPECT_NE(said.find(dir.string()), std::string::npos) << said;  // the dataset
    EXPECT_NE(said.find("frames.csv"), std::string::npos) << said;  // the file that failed
    EXPECT_NE(said.find("frames on disk are kept"), std::string::npos) << said;
    // Published before it is said (a TSan run once read the state between the two).
    const RecordingInfo r = latest(s.recording());
    EXPECT_FALSE(r.status.recording);
    EXPECT_TRUE(r.status.disk_full);
    EXPECT_EQ(r.status.error, said);  // the recording window shows the same sentence
    EXPECT_GT(r.status.frames, 0u);

    // The flight goes on: 60 more AT datagrams (about 2 s) while connected and flying, and the
    // session keeps classifying the video.
    const std::uint64_t at0 = src.link->status().at.counters.datagrams;
    const std::uint64_t frames0 = s.frames_processed();
    ASSERT_TRUE(wait_until(
        [&] {
            return src.link->status().at.counters.datagrams >= at0 + 60 &&
                   s.frames_processed() >= frames0 + 20;
        },
        30s))
        << src.link->status().at.counters.datagrams - at0 << " AT datagrams, "
        << s.frames_processed() - frames0 << " frames";
    EXPECT_EQ(src.link->state(), link::ConnectionState::Connected);
    EXPECT_TRUE(up());
    EXPECT_FALSE(latest(s.recording()).status.recording);

    // Said once, whatever the session published since.
    while (auto m = s.next_message()) seen.push_back(*m);
    const auto times = std::count_if(seen.begin(), seen.end(), [](const std::string& m) {
        return m.find("the disk holding it") != std::string::npos;
    });
    EXPECT_EQ(times, 1) << joined(seen);

    // What is on disk opens, with the frames the recorder counted.
    auto d = dataset::Dataset::open(dir);
    ASSERT_TRUE(d) << to_string(d.error());
    EXPECT_EQ(static_cast<std::uint64_t>(d->frame_count()), r.status.frames);
}

TEST(Session, ClassifierAndCalibrationRequestsAreHandled) {
    Session s(headless_options());
    std::vector<std::string> seen;
    const ClassifierInfo first = latest(s.classifier());
    ASSERT_FALSE(first.available.empty());

    ASSERT_TRUE(s.request(SelectClassifier{"no_such_classifier"}));
    ASSERT_TRUE(wait_until([&] { return !latest(s.classifier()).error.empty(); }, 10s));
    EXPECT_EQ(latest(s.classifier()).active, first.active);

    const std::string other = first.available.back();
    ASSERT_TRUE(s.request(SelectClassifier{other}));
    ASSERT_TRUE(wait_until(
        [&] {
            const ClassifierInfo c = latest(s.classifier());
            return c.active == other && c.error.empty();
        },
        10s));
    ASSERT_TRUE(s.request(SetClassifierParam{"no_such_parameter", 1.0}));
    ASSERT_TRUE(wait_until([&] { return !latest(s.classifier()).error.empty(); }, 10s));

    // An invalid calibration is refused, a valid one applied (and said so).
    ASSERT_TRUE(s.request(ApplyCalibration{CameraCalibration{}, "nothing"}));
    ASSERT_TRUE(wait_message(s, "is not valid", seen)) << joined(seen);
    CameraCalibration cam = latest(s.calibration()).camera;
    ASSERT_TRUE(cam.valid());
    cam.fx *= 1.01;
    ASSERT_TRUE(s.request(ApplyCalibration{cam, "a test"}));
    ASSERT_TRUE(wait_until([&] { return latest(s.calibration()).origin == "a test"; }, 10s));
    EXPECT_DOUBLE_EQ(latest(s.calibration()).camera.fx, cam.fx);
    ASSERT_TRUE(wait_message(s, "calibration applied", seen)) << joined(seen);
}

}  // namespace
}  // namespace gs::app
