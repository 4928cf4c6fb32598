// The Replay window's controls through the real wiring: Actions -> GuiAdapter -> Session (its
// thread, the DatasetSource pacing) -> the snapshot the window draws. On the shipped labelled
// flight tests/data/flights/ci_pillar_left (153 frames of H.264 at 30 fps): play / pause, step
// forward and back, seek, speed 0.25x-8x (clamped), loop at the end, and play again after the
// end. Waits are bounded polls on the snapshot.
#include "app/gui_adapter.hpp"
#include "app/session.hpp"
#include "session_fixture.hpp"
#include "support/dataset_fixtures.hpp"
#include "support/wait.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <optional>
#include <thread>

namespace gs::ui::test {
namespace {

using namespace std::chrono_literals;

const std::string kFlight = std::string(GS_TEST_DATA_DIR) + "/flights/ci_pillar_left";
constexpr std::int64_t kFrames = 153;

class ReplayControls : public SessionFixture {
protected:
    void start(bool autoplay, const char* classifier = nullptr,
               const std::string& flight = kFlight) {
        app::SessionOptions so;
        so.replay_autoplay = autoplay;
        if (classifier) so.classifier = classifier;
        make_session(so);
        frame_period = std::chrono::milliseconds(5);
        Actions open;
        open.replay_open = flight;
        adapter->consume(open);
    }
    // Runs window frames for `d` and returns how many dataset frames the replay advanced.
    std::int64_t advance_during(std::chrono::milliseconds d) {
        step();
        const std::int64_t f0 = snap.replay.frame;
        const auto t0 = std::chrono::steady_clock::now();
        while (std::chrono::steady_clock::now() - t0 < d) {
            step();
            std::this_thread::sleep_for(5ms);
        }
        return snap.replay.frame - f0;
    }
    // The frame shown: status, video and classifier all agree.
    bool showing(std::int64_t k) const {
        return snap.replay.frame == k && snap.video.index == k && !snap.video.bgr.empty();
    }
};

TEST_F(ReplayControls, PlayPauseStepSeekSpeedAndLoopOnTheShippedFlight) {
    ASSERT_TRUE(std::filesystem::exists(kFlight + "/flight.json")) << kFlight;
    start(/*autoplay=*/true);
    ASSERT_TRUE(run_until([&] { return snap.replay.open && snap.replay.frame > 3; }, 15s))
        << (snap.messages.empty() ? "" : snap.messages.back().text);
    EXPECT_EQ(snap.connection.state, LinkState::Replay);
    EXPECT_EQ(snap.replay.frame_count, kFrames);
    EXPECT_TRUE(snap.replay.playing);
    EXPECT_DOUBLE_EQ(snap.replay.speed, 1.0);
    EXPECT_FALSE(snap.classifier.decisions.empty()) << "replayed frames are classified";

    // Pause: the position holds.
    step([](Actions& a) { a.replay_pause = true; });
    // A frame in flight when the pause landed: wait until the frame shown is the position held.
    ASSERT_TRUE(run_until([&] { return !snap.replay.playing && showing(snap.replay.frame); }, 5s));
    const std::int64_t held = snap.replay.frame;
    EXPECT_EQ(advance_during(300ms), 0);
    EXPECT_EQ(snap.replay.frame, held);

    // Step forward twice, back once.
    step([](Actions& a) { a.replay_step = 1; });
    ASSERT_TRUE(run_until([&] { return showing(held + 1); }, 5s)) << snap.replay.frame;
    step([](Actions& a) { a.replay_step = 1; });
    ASSERT_TRUE(run_until([&] { return showing(held + 2); }, 5s)) << snap.replay.frame;
    step([](Actions& a) { a.replay_step = -1; });
    ASSERT_TRUE(run_until([&] { return showing(held + 1); }, 5s)) << snap.replay.frame;
    EXPECT_FALSE(snap.replay.playing) << "stepping pauses";

    // Seek while paused shows the frame sought; out of range is clamped.
    step([](Actions& a) { a.replay_seek = 100; });
    ASSERT_TRUE(run_until([&] { return showing(100); }, 5s)) << snap.replay.frame;
    step([](Actions& a) { a.replay_seek = 5000; });
    ASSERT_TRUE(run_until([&] { return showing(kFrames - 1); }, 5s)) << snap.replay.frame;
    step([](Actions& a) { a.replay_seek = 10; });
    ASSERT_TRUE(run_until([&] { return showing(10); }, 5s)) << snap.replay.frame;

    // Speed: clamped to 0.25x .. 8x; a slow replay advances far less than a fast one.
    step([](Actions& a) { a.replay_speed = 0.01; });
    ASSERT_TRUE(run_until([&] { return snap.replay.speed == 0.25; }, 5s)) << snap.replay.speed;
    step([](Actions& a) { a.replay_play = true; });
    ASSERT_TRUE(run_until([&] { return snap.replay.playing; }, 5s));
    const std::int64_t slow = advance_during(1000ms);
    EXPECT_LE(slow, 12) << "0.25x of 30 fps is 7.5 frames per second";
    step([](Actions& a) { a.replay_pause = true; });
    ASSERT_TRUE(run_until([&] { return !snap.replay.playing; }, 5s));
    step([](Actions& a) { a.replay_seek = 10; });
    ASSERT_TRUE(run_until([&] { return showing(10); }, 5s)) << snap.replay.frame;
    step([](Actions& a) { a.replay_speed = 100.0; });
    ASSERT_TRUE(run_until([&] { return snap.replay.speed == 8.0; }, 5s)) << snap.replay.speed;
    step([](Actions& a) { a.replay_play = true; });
    ASSERT_TRUE(run_until([&] { return snap.replay.playing; }, 5s));
    const std::int64_t fast = advance_during(1000ms);
    std::printf("advance in 1 s: %lld frames at 0.25x, %lld at 8x\n", static_cast<long long>(slow),
                static_cast<long long>(fast));
    EXPECT_GE(fast, 3 * std::max<std::int64_t>(slow, 1));

    // Without loop the replay stops at its last frame; Play then starts over. (The second of 8x
    // above may have reached the end already: pause, seek, play from there, wait for the end.)
    step([](Actions& a) { a.replay_pause = true; });
    ASSERT_TRUE(run_until([&] { return !snap.replay.playing; }, 5s));
    step([](Actions& a) { a.replay_seek = kFrames - 20; });
    ASSERT_TRUE(run_until([&] { return showing(kFrames - 20); }, 5s)) << snap.replay.frame;
    step([](Actions& a) { a.replay_play = true; });
    ASSERT_TRUE(run_until([&] { return snap.replay.playing; }, 5s));
    ASSERT_TRUE(run_until([&] { return !snap.replay.playing; }, 15s)) << snap.replay.frame;
    EXPECT_EQ(snap.replay.frame, kFrames - 1);
    bool said_end = false;
    for (const auto& m : snap.messages)
        said_end = said_end || m.text == "replay: end of the flight";
    EXPECT_TRUE(said_end);
    // At 1x, so the start-over is seen before the replay reaches the end again (at 8x the
    // whole flight takes 0.6 s).
    step([](Actions& a) {
        a.replay_speed = 1.0;
        a.replay_play = true;
    });
    ASSERT_TRUE(
        run_until([&] { return snap.replay.playing && snap.replay.frame < kFrames - 20; }, 10s))
        << snap.replay.frame;

    // Loop: past the end it goes on from frame 0, still playing.
    step([](Actions& a) {
        a.replay_loop = true;
        a.replay_seek = kFrames - 15;
    });
    ASSERT_TRUE(run_until([&] { return snap.replay.loop; }, 5s));
    ASSERT_TRUE(run_until([&] { return snap.replay.frame >= kFrames - 5; }, 15s))
        << snap.replay.frame;
    ASSERT_TRUE(run_until([&] { return snap.replay.frame < 20; }, 15s)) << snap.replay.frame;
    EXPECT_TRUE(snap.replay.playing);
    step([](Actions& a) { a.replay_pause = true; });
    ASSERT_TRUE(run_until([&] { return !snap.replay.playing; }, 5s));
}

TEST_F(ReplayControls, TheReplayWindowDrawsTheStateAndItsSliderSpeedsArePowersOfTwo) {
    start(/*autoplay=*/false);
    ASSERT_TRUE(run_until([&] { return snap.replay.open; }, 15s));
    EXPECT_FALSE(snap.replay.playing);
    // Paused at open: the first Step shows frame 0.
    step([](Actions& a) { a.replay_step = 1; });
    ASSERT_TRUE(run_until([&] { return showing(0); }, 5s)) << snap.replay.frame;
    for (double s : {0.25, 0.5, 1.0, 2.0, 4.0, 8.0}) {
        step([s](Actions& a) { a.replay_speed = s; });
        ASSERT_TRUE(run_until([&] { return snap.replay.speed == s; }, 5s)) << s;
        EXPECT_GT(last_vertices, 1000);
    }
    // Controls without a replay are refused with a message, not a crash.
    step([](Actions& a) { a.disconnect = true; });
    ASSERT_TRUE(run_until([&] { return !snap.replay.open; }, 5s));
    step([](Actions& a) { a.replay_play = true; });
    bool said = false;
    ASSERT_TRUE(run_until(
        [&] {
            for (const auto& m : snap.messages) said = said || m.text == "no replay open";
            return said;
        },
        5s));
}

// Issue 14 point 7: a flight whose frames.csv holds only frame,t_ms,roll_deg (allowed) leaves
// the flow classifier without velocity, altitude, pitch and yaw. The Replay window says so, in
// the words replay and eval print, for as long as that flight is open; the thesis classifier
// (roll alone) and a complete flight get no such note.
TEST_F(ReplayControls, TheWindowSaysWhichInputsTheClassifierLacksAndWhatItCosts) {
    gs::test::TempDir tmp;
    const auto flight = tmp.path() / "attitude_only";
    gs::test::copy_attitude_only(kFlight, flight);
    const auto notes_once_open = [&](const char* classifier, const std::string& path) {
        start(/*autoplay=*/false, classifier, path);
        EXPECT_TRUE(run_until([&] { return snap.replay.open; }, 15s)) << path;
        step();  // the frame that draws the opened flight's notes
        const auto notes = gui.view().layout.replay_notes;
        adapter.reset();
        session.reset();
        std::string all;
        for (const auto& n : notes) all += n + "\n";
        return all;
    };
    const std::string flow = notes_once_open(nullptr, flight.string());
    for (const char* what : {"no velocity (vx_mps, vy_mps, vz_mps) in 100 % of the frames",
                             "no altitude", "no attitude (pitch, yaw)", "time to contact alone"})
        EXPECT_NE(flow.find(what), std::string::npos) << what << "\n" << flow;
    EXPECT_EQ(flow.find("no roll"), std::string::npos) << flow;
    EXPECT_EQ(notes_once_open("thesis", flight.string()), "");
    EXPECT_EQ(notes_once_open(nullptr, kFlight), "");
}

// Issue 6: the centre-scale plot carries the centre threshold where it means something: for the
// thesis classifier (tangent slope of the fitted scale vs the threshold) as a line of the
// threshold's slope ending at the newest fitted point; for the flow classifier (expansion rate
// in 1/s vs the threshold) as a horizontal line beside the corridor points' rate.
TEST_F(ReplayControls, CentreScalePlotShowsTheCentreThresholdForBothClassifiers) {
    start(/*autoplay=*/true, "thesis");
    auto plot = [&](std::string_view name) {
        std::optional<PlotData> out;
        for (const auto& p : snap.classifier.plots)
            if (p.name == name) out = p;
        return out;
    };
    auto series = [](const std::optional<PlotData>& p, std::string_view name) {
        std::optional<SeriesData> out;
        if (p)
            for (const auto& sd : p->series)
                if (sd.name == name) out = sd;
        return out;
    };
    ASSERT_TRUE(run_until([&] { return snap.replay.open; }, 15s));
    step([](Actions& a) { a.replay_speed = 4.0; });
    // The thesis fit needs fit_window (30) filtered scales first.
    ASSERT_TRUE(
        run_until([&] { return series(plot("center_scale"), "threshold slope").has_value(); }, 20s))
        << "frame " << snap.replay.frame;
    {
        const auto p = plot("center_scale");
        const auto th = series(p, "threshold slope");
        const auto fitted = series(p, "scale_fitted");
        ASSERT_TRUE(p && th && fitted);
        ASSERT_EQ(th->x.size(), 2u);
        ASSERT_EQ(th->y.size(), 2u);
        ASSERT_EQ(snap.classifier.decisions.size(), 3u);
        const double thr = snap.classifier.decisions[1].threshold;  // centre
        EXPECT_NEAR((th->y[1] - th->y[0]) / (th->x[1] - th->x[0]), thr, 1e-12);
        EXPECT_NEAR(th->x[1] - th->x[0], 30.0, 1e-9) << "spans the fit window";
        // It ends at the newest fitted point.
        double last_x = 0, last_y = 0;
        for (std::size_t i = 0; i < fitted->y.size() && i < fitted->x.size(); ++i)
            if (std::isfinite(fitted->y[i])) {
                last_x = fitted->x[i];
                last_y = fitted->y[i];
            }
        EXPECT_DOUBLE_EQ(th->x[1], last_x);
        EXPECT_DOUBLE_EQ(th->y[1], last_y);
        EXPECT_NE(p->title.find("thr "), std::string::npos) << p->title;
        EXPECT_TRUE(p->thresholds.empty()) << "a horizontal line would mean nothing on a ratio";
    }

    step([](Actions& a) { a.classifier_select = "flow"; });
    ASSERT_TRUE(run_until(
        [&] {
            const auto p = plot("center_scale");
            return snap.classifier.active == "flow" && p && !p->thresholds.empty() &&
                   series(p, "points_rate").has_value();
        },
        20s));
    const auto p = plot("center_scale");
    ASSERT_TRUE(p);
    EXPECT_FALSE(series(p, "threshold slope"));
    ASSERT_EQ(p->thresholds.size(), 1u);
    EXPECT_NE(p->thresholds[0].name.find("centre threshold"), std::string::npos);
    ASSERT_EQ(snap.classifier.decisions.size(), 3u);
    EXPECT_DOUBLE_EQ(p->thresholds[0].y, snap.classifier.decisions[1].threshold);
    step();
    EXPECT_GT(last_vertices, 1000);
}

}  // namespace
}  // namespace gs::ui::test
