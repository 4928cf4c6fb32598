// app::Session without the window (app_core only): the same source lifecycle the GUI drives,
// checked through the session's published values.

#include "app/session.hpp"
#include "support/dataset_fixtures.hpp"
#include "support/wait.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <string>

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

}  // namespace
}  // namespace gs::app
