// The pilot's path through the assist (app/pilot_path.hpp) on synthetic decisions and navdata:
// what it sends for the pilot's input, the stale-decision rule, the toggle and the override, the
// replay dry run and the recording's assist.csv. The same path over real sockets, with the
// window's keys: tests/ui/assist_wiring_test.cpp.
#include "app/pilot_path.hpp"
#include "app/session.hpp"
#include "drone/core/file_io.hpp"
#include "drone/dataset/csv.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

namespace gs::app {
namespace {

constexpr TimeNs kPpMs = 1'000'000;

PipelineOutput pp_decision(RegionState centre, TimeNs recv_ns, std::int64_t index,
                           RegionState left = RegionState::Clear,
                           RegionState right = RegionState::Clear) {
    PipelineOutput o;
    o.camera = CameraId::Front;
    o.classifier = "thesis";
    o.frame.index = index;
    o.frame.t_ns = recv_ns;
    o.frame.recv_ns = recv_ns;
    o.frame.frame_number = static_cast<std::uint32_t>(100 + index);
    o.result.frame_index = index;
    const RegionState st[3] = {left, centre, right};
    for (int i = 0; i < 3; ++i) {
        auto& d = o.result.regions[static_cast<std::size_t>(i)];
        d.valid = st[i] == RegionState::Clear || st[i] == RegionState::Unsafe;
        d.unsafe = st[i] == RegionState::Unsafe;
        d.score = d.valid ? 0.5 : kUnknown;
    }
    return o;
}

NavState pp_flying_at(double vx) {
    NavState n;
    n.vx_mps = vx;
    n.vy_mps = 0;
    n.yaw_deg = 0;
    n.drone_state = 1u;  // FLY
    return n;
}

bool pp_is_move(const std::optional<link::Command>& c) {
    return c && std::holds_alternative<link::Move>(*c);
}
// The Move sent (NaN fields when what was sent is not a Move).
link::Move pp_move(const std::optional<link::Command>& c) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    return pp_is_move(c) ? std::get<link::Move>(*c) : link::Move{nan, nan, nan, nan};
}
bool pp_is_hover(const std::optional<link::Command>& c) {
    return c && std::holds_alternative<link::Hover>(*c);
}

const link::Move kPpForward{0, -0.3f, 0, 0};

TEST(PilotPath, ForwardIntoAnUnsafeCentreIsBrakedThenHeldAtZero) {
    PilotPath p;
    p.on_navdata(pp_flying_at(1.2));
    p.on_output(pp_decision(RegionState::Clear, 0, 0));
    auto c = p.step(kPpForward, 10 * kPpMs);
    ASSERT_TRUE(pp_is_move(c));
    EXPECT_FLOAT_EQ(pp_move(c).pitch, -0.3f) << "clear ahead: the pilot's forward passes";
    EXPECT_EQ(p.status().line, "ASSIST ON");

    p.on_output(pp_decision(RegionState::Unsafe, 40 * kPpMs, 1));
    c = p.step(kPpForward, 50 * kPpMs);
    ASSERT_TRUE(pp_is_move(c));
    EXPECT_GT(pp_move(c).pitch, 0.0f) << "braking: nose up";
    EXPECT_EQ(p.status().action, "BRAKING");
    EXPECT_TRUE(p.status().acting);
    EXPECT_EQ(p.status().line.rfind("BRAKING: obstacle ahead", 0), 0u) << p.status().line;
    const auto log = p.take_new();
    ASSERT_EQ(log.size(), 1u);
    EXPECT_EQ(log[0].action, AssistAction::Braking);
    EXPECT_FLOAT_EQ(log[0].before.pitch, -0.3f);
    EXPECT_GT(log[0].after.pitch, 0.0f);
    EXPECT_EQ(log[0].pave_frame, 101u);
    EXPECT_TRUE(p.take_new().empty()) << "each intervention is handed out once";

    // Slowed down (under the creep speed): forward held at zero (the drone's hover), the
    // obstacle still there.
    p.on_navdata(pp_flying_at(0.03));
    p.on_output(pp_decision(RegionState::Unsafe, 80 * kPpMs, 2));
    c = p.step(kPpForward, 90 * kPpMs);
    EXPECT_TRUE(pp_is_hover(c)) << "forward held at zero";
    EXPECT_EQ(p.status().action, "HOLDING");
    // Yaw and climb pass while held; forward does not.
    c = p.step(link::Move{0, -0.3f, 0.4f, 0.5f}, 100 * kPpMs);
    ASSERT_TRUE(pp_is_move(c));
    EXPECT_FLOAT_EQ(pp_move(c).pitch, 0.0f);
    EXPECT_FLOAT_EQ(pp_move(c).gaz, 0.4f);
    EXPECT_FLOAT_EQ(pp_move(c).yaw, 0.5f);
    // Backing away is never limited.
    c = p.step(link::Move{0, 0.4f, 0, 0}, 110 * kPpMs);
    ASSERT_TRUE(pp_is_move(c));
    EXPECT_FLOAT_EQ(pp_move(c).pitch, 0.4f);
}

TEST(PilotPath, SideUnsafeZeroesOnlyTheRollTowardIt) {
    PilotPath p;
    p.on_navdata(pp_flying_at(0.0));
    p.on_output(pp_decision(RegionState::Clear, 0, 0, RegionState::Unsafe, RegionState::Clear));
    auto c = p.step(link::Move{-0.4f, 0, 0, 0.2f}, 10 * kPpMs);
    ASSERT_TRUE(pp_is_move(c));
    EXPECT_FLOAT_EQ(pp_move(c).roll, 0.0f);
    EXPECT_FLOAT_EQ(pp_move(c).yaw, 0.2f);
    EXPECT_EQ(p.status().action, "LEFT BLOCKED");
    EXPECT_EQ(p.status().line.rfind("LEFT BLOCKED", 0), 0u);
    c = p.step(link::Move{0.4f, 0, 0, 0.2f}, 20 * kPpMs);
    ASSERT_TRUE(pp_is_move(c));
    EXPECT_FLOAT_EQ(pp_move(c).roll, 0.4f) << "away from the unsafe side passes";
}

TEST(PilotPath, ABrakePendingWhileSteeringAwayFromASideIsShownWithIt) {
    // Flying forward at 1.5 m/s, the centre and the left unsafe, the right clear: the assist
    // steers right now and confirms the centre's alarm. The status says both, the steering
    // first, and flags the confirmation (the HUD's amber, the status bar's banner).
    // The flow classifier's decision: its scores are rates (1/s), so the centre's alarm places
    // the obstacle (3 s to contact) and leaves time to confirm it.
    PipelineOutput d =
        pp_decision(RegionState::Unsafe, 0, 0, RegionState::Unsafe, RegionState::Clear);
    d.classifier = "flow";
    d.result.regions[0].score = 0.5;
    d.result.regions[1].score = 1.0 / 3.0;
    d.result.regions[2].score = 0.1;
    PilotPath p;
    p.on_navdata(pp_flying_at(1.5));
    p.on_output(d);
    auto c = p.step(link::Move{0, -0.5f, 0, 0}, 10 * kPpMs);
    ASSERT_TRUE(pp_is_move(c));
    EXPECT_GT(pp_move(c).roll, 0.0f) << "steered right, away from the left";
    const AssistStatus s = p.status();
    EXPECT_EQ(s.action, "STEERING RIGHT");
    EXPECT_TRUE(s.acting);
    EXPECT_TRUE(s.confirming);
    EXPECT_EQ(s.line.rfind("STEERING right: obstacle left", 0), 0u) << s.line;
    EXPECT_NE(s.line.find("; CONFIRMING: centre alarm"), std::string::npos) << s.line;
    EXPECT_NE(s.line.find("braking if it holds"), std::string::npos) << s.line;
    // Where the line does not fit (a small window), the action words still say both.
    EXPECT_EQ(s.brief, "STEERING RIGHT; BRAKE PENDING");
    // The left alone: steering, nothing pending.
    PilotPath q;
    q.on_navdata(pp_flying_at(1.5));
    q.on_output(pp_decision(RegionState::Clear, 0, 0, RegionState::Unsafe, RegionState::Clear));
    (void)q.step(link::Move{0, -0.5f, 0, 0}, 10 * kPpMs);
    EXPECT_EQ(q.status().action, "STEERING RIGHT");
    EXPECT_FALSE(q.status().confirming);
    EXPECT_EQ(q.status().line.find("CONFIRMING"), std::string::npos) << q.status().line;
    EXPECT_EQ(q.status().brief, "STEERING RIGHT");
}

TEST(PilotPath, UnknownCentreNeverBrakesAndSaysSo) {
    PilotPath p;
    p.on_navdata(pp_flying_at(1.0));
    p.on_output(pp_decision(RegionState::Unknown, 0, 0));
    auto c = p.step(kPpForward, 10 * kPpMs);
    ASSERT_TRUE(pp_is_move(c));
    EXPECT_FLOAT_EQ(pp_move(c).pitch, -0.3f);
    EXPECT_TRUE(p.status().unknown);
    EXPECT_EQ(p.status().line, "UNKNOWN: no evidence ahead, not braking");
}

// The stale rule (app/pilot_path.hpp): a decision older than stale_after_s never starts a brake
// and never counts as clear; a brake under way ends, then forward stays held.
TEST(PilotPath, StaleDecisionsNeitherBrakeForeverNorCountAsClear) {
    const double stale_s = AssistParams{}.stale_after_s;
    const TimeNs stale_ns = static_cast<TimeNs>(stale_s * 1e9) + 50 * kPpMs;
    {
        // An unsafe decision that is already stale: no brake, said as stale.
        PilotPath p;
        p.on_navdata(pp_flying_at(1.0));
        p.on_output(pp_decision(RegionState::Unsafe, 0, 0));
        auto c = p.step(kPpForward, stale_ns);
        ASSERT_TRUE(pp_is_move(c));
        EXPECT_FLOAT_EQ(pp_move(c).pitch, -0.3f);
        EXPECT_EQ(p.status().line, "UNKNOWN: classifier stale, no evidence ahead, not braking");
    }
    // A brake, then the video stalls: the brake ends once slow (and within max_brake_s even if
    // the drone never slows), forward then stays at zero while the decisions stay stale.
    PilotPath p;
    p.on_navdata(pp_flying_at(1.0));
    p.on_output(pp_decision(RegionState::Unsafe, 0, 0));
    ASSERT_GT(pp_move(p.step(kPpForward, 10 * kPpMs)).pitch, 0.0f);
    const TimeNs end = static_cast<TimeNs>((AssistParams{}.max_brake_s + 0.2) * 1e9);
    std::optional<link::Command> c;
    for (TimeNs t = 20 * kPpMs; t <= end; t += 30 * kPpMs) c = p.step(kPpForward, t);
    EXPECT_EQ(p.status().action, "HOLDING") << "braking never outlasts max_brake_s";
    EXPECT_NE(p.status().line.find("stale"), std::string::npos) << p.status().line;
    p.on_navdata(pp_flying_at(0.05));
    for (TimeNs t = end; t <= end + 5'000 * kPpMs; t += 30 * kPpMs) c = p.step(kPpForward, t);
    EXPECT_EQ(p.status().action, "HOLDING") << "stale is not clear: forward stays held";
    const auto last = p.last().command;
    EXPECT_FALSE(last.progressive && last.pitch != 0.0f);
    // A fresh clear decision with the drone moving again releases the hold after
    // forget_after_clear_s (the unit's rule), so the hold is not forever either. Moving toward
    // the obstacle with no room first brakes again, and what is read while braking does not
    // count: the navdata's speed here never falls, so that brake ends at max_brake_s.
    const TimeNs t0 = end + 5'100 * kPpMs;
    p.on_navdata(pp_flying_at(0.5));
    const double release_s = AssistParams{}.max_brake_s + AssistParams{}.forget_after_clear_s + 0.8;
    for (TimeNs t = t0; t <= t0 + static_cast<TimeNs>(release_s * 1e9); t += 30 * kPpMs) {
        p.on_output(pp_decision(RegionState::Clear, t, 10 + t / kPpMs));
        c = p.step(kPpForward, t + kPpMs);
    }
    EXPECT_EQ(p.status().action, "WATCHING") << p.status().line;
    EXPECT_TRUE(p.last().command.progressive);
    EXPECT_FLOAT_EQ(p.last().command.pitch, -0.3f) << "forward passes again";
}

// A decision is as old as its frame's capture, not its arrival: a frame the air or a queue held
// back (here 0.45 s, a Wi-Fi stall) shows the obstacle where it stood then. Just after it
// arrives it is still fresh enough to brake on; once stale_after_s has passed since its capture
// (not since its arrival) it is stale, and says so.
TEST(PilotPath, ADecisionIsAsOldAsItsFramesCaptureNotItsArrival) {
    const double stale_s = AssistParams{}.stale_after_s;
    const TimeNs capture = 1'000 * kPpMs, held = 450 * kPpMs;
    const TimeNs arrival = capture + held;
    ASSERT_LT(held, static_cast<TimeNs>(stale_s * 1e9)) << "the test needs a fresh arrival";
    // Stepped 100 ms after it arrived: 0.55 s after its capture, stale; by its arrival
    // 0.1 s old.
    const TimeNs now = arrival + 100 * kPpMs;
    ASSERT_GT(now - capture, static_cast<TimeNs>(stale_s * 1e9));
    for (const bool has_capture : {true, false}) {
        PilotPath p;
        p.on_navdata(pp_flying_at(1.0));
        PipelineOutput o = pp_decision(RegionState::Unsafe, arrival, 0);
        o.frame.capture_ns = has_capture ? capture : 0;
        p.on_output(o);
        // At its arrival it is 0.45 s old either way (or 0): fresh, it brakes.
        PilotPath q;
        q.on_navdata(pp_flying_at(1.0));
        q.on_output(o);
        EXPECT_GT(pp_move(q.step(kPpForward, arrival + 10 * kPpMs)).pitch, 0.0f) << has_capture;
        auto c = p.step(kPpForward, now);
        ASSERT_TRUE(pp_is_move(c));
        if (has_capture) {
            EXPECT_FLOAT_EQ(pp_move(c).pitch, -0.3f) << "stale: no brake on it";
            EXPECT_EQ(p.status().line, "UNKNOWN: classifier stale, no evidence ahead, not braking");
        } else {
            // A source without a capture clock: the arrival is all that is known.
            EXPECT_GT(pp_move(c).pitch, 0.0f);
        }
    }
}

TEST(PilotPath, OffAndOverridePassThePilotsCommandUnchanged) {
    PilotPath p;
    p.on_navdata(pp_flying_at(1.2));
    p.on_output(pp_decision(RegionState::Unsafe, 0, 0));
    p.set_enabled(false);
    auto c = p.step(kPpForward, 10 * kPpMs);
    ASSERT_TRUE(pp_is_move(c));
    EXPECT_FLOAT_EQ(pp_move(c).pitch, -0.3f);
    EXPECT_EQ(p.status().line, "ASSIST OFF");
    EXPECT_TRUE(p.take_new().empty()) << "off is not an intervention";
    p.set_enabled(true);
    p.set_override(true);
    c = p.step(link::Move{0, -0.35f, 0, 0}, 20 * kPpMs);
    ASSERT_TRUE(pp_is_move(c));
    EXPECT_FLOAT_EQ(pp_move(c).pitch, -0.35f);
    EXPECT_EQ(p.status().action, "OVERRIDE");
    p.set_override(false);
    c = p.step(link::Move{0, -0.35f, 0, 0}, 30 * kPpMs);
    ASSERT_TRUE(pp_is_move(c));
    EXPECT_GT(pp_move(c).pitch, 0.0f) << "released: the assist brakes again";
}

TEST(PilotPath, OnTheGroundNothingIsLimited) {
    PilotPath p;
    NavState n = pp_flying_at(0);
    n.drone_state = 0u;
    p.on_navdata(n);
    p.on_output(pp_decision(RegionState::Unsafe, 0, 0));
    auto c = p.step(kPpForward, 10 * kPpMs);
    ASSERT_TRUE(pp_is_move(c));
    EXPECT_FLOAT_EQ(pp_move(c).pitch, -0.3f);
}

TEST(PilotPath, ReplayDryRunShowsTheBrakeAndSendsNothing) {
    PilotPath p;
    // A replayed frame: no receive time; the dataset's velocity says "moving forward".
    PipelineOutput o = pp_decision(RegionState::Unsafe, 0, 5);
    o.frame.recv_ns = 0;
    o.frame.t_ns = 2'000 * kPpMs;
    NavState n = pp_flying_at(1.1);
    n.drone_state.reset();  // a dataset without drone_state counts as flying
    p.on_navdata(n);
    p.on_output(o);
    p.dry_run(std::nullopt);
    const AssistStatus s = p.status();
    EXPECT_TRUE(s.dry_run);
    EXPECT_EQ(s.action, "BRAKING");
    EXPECT_EQ(s.line.rfind("DRY RUN (replay, nothing sent): BRAKING", 0), 0u) << s.line;
    EXPECT_EQ(s.brief, "DRY RUN: BRAKING");
    EXPECT_EQ(p.moves(), 0u);
    EXPECT_EQ(p.hovers(), 0u);
    EXPECT_EQ(p.take_new().size(), 1u);
}

// A replay as the window plays it (dataset/dataset_source.cpp): its frames carry their capture
// time and no receive time. The dry run's clock is the frames' time, so its timers run: a centre
// alarm with time to spare is confirmed, then brakes once it has held confirm_s. When the source
// stamped each frame with the replay's pacing as a receive time, the path timed decisions by
// that while the dry run's clock never moved, and the alarm stayed "confirming" for as long as it
// held (DatasetSource.RealtimePacingFollowsTheClock now checks there is none).
TEST(PilotPath, AReplaysDryRunRunsOnTheFramesOwnClock) {
    PilotPath p;
    NavState n = pp_flying_at(1.1);
    n.drone_state.reset();
    p.on_navdata(n);
    const TimeNs frame_ns = 33 * kPpMs;
    std::vector<std::string> actions;
    for (int k = 0; k < 20; ++k) {
        PipelineOutput o = pp_decision(RegionState::Unsafe, 0, k);
        o.classifier = "flow";                        // the score is 1/TTC
        o.result.regions[1].score = 0.4;              // 2.5 s: 2.1 m ahead at 1.1 m/s
        o.frame.t_ns = 2'000 * kPpMs + k * frame_ns;  // the dataset's time
        o.frame.recv_ns = 0;                          // no receive time: a replay
        o.frame.frame_number.reset();
        p.on_output(o);
        p.dry_run(std::nullopt);
        actions.push_back(p.status().action);
    }
    EXPECT_EQ(actions.front(), "CONFIRMING") << "2.1 m ahead leaves time to confirm";
    const auto braking = std::find(actions.begin(), actions.end(), "BRAKING");
    ASSERT_NE(braking, actions.end()) << "the dry run's clock never moved: " << actions.back();
    // confirm_s (0.25 s) of the alarm is 8 frames of 33 ms, within the time it may wait.
    const auto at = braking - actions.begin();
    EXPECT_GE(at, 7);
    EXPECT_LE(at, 9);
    EXPECT_EQ(p.moves(), 0u) << "a dry run sends nothing";
}

TEST(PilotPath, AssistCsvMapsEachInterventionToTheDatasetFrame) {
    namespace fs = std::filesystem;
    const fs::path dir =
        fs::temp_directory_path() / ("gs_assist_csv_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir / "raw");
    {
        std::ofstream f(dir / "frames.csv");
        f << "frame,t_ms,roll_deg\n0,0.000,0\n1,33.333,0\n2,66.667,0\n";
        std::ofstream c(dir / "raw" / "capture_times.csv");
        c << "frame_number,timestamp_ms,t_us\n500,10,0\n501,43,33333\n502,77,66667\n";
    }
    const TimeNs start = 1'000 * kPpMs;
    Intervention i;
    i.t_ns = start + 100 * kPpMs;
    i.frame = 42;  // the link's index: not the dataset's
    i.pave_frame = 502;
    i.decision_ns = start + 80 * kPpMs;
    i.action = AssistAction::Braking;
    i.reason = "BRAKING: obstacle ahead, contact in 1.8 s";
    i.before = FlightCommand{true, 0, -0.3f, 0, 0};
    i.after = FlightCommand{true, 0, 1.0f, 0, 0};
    Intervention j = i;
    j.pave_frame = 999;  // not kept by the recording: no frame
    j.action = AssistAction::LimitLeft;
    j.region = vision::Region::Left;
    const auto problem = write_assist_csv(dir, start, {i, j});
    ASSERT_FALSE(problem) << to_string(*problem);
    auto text = gs::read_text_file(dir / "assist.csv", "assist.csv", 1u << 20);
    ASSERT_TRUE(text);
    auto t = gs::dataset::csv::Table::parse(std::move(*text), "assist.csv");
    ASSERT_TRUE(t) << to_string(t.error());
    ASSERT_EQ(t->rows(), 2u);
    auto cell = [&](std::size_t row, const char* name) {
        const auto c = t->column(name);
        if (!c) {
            ADD_FAILURE() << "no column " << name;
            return std::string();
        }
        return std::string(t->field(row, *c));
    };
    EXPECT_EQ(cell(0, "t_ms"), "100.000");
    EXPECT_EQ(cell(0, "frame"), "2");
    EXPECT_EQ(cell(0, "pave_frame"), "502");
    EXPECT_EQ(cell(0, "decision_ms"), "80.000");
    EXPECT_EQ(cell(0, "action"), "BRAKING");
    EXPECT_EQ(cell(0, "region"), "centre");
    EXPECT_EQ(cell(0, "reason"), "BRAKING: obstacle ahead; contact in 1.8 s");
    EXPECT_EQ(cell(0, "before_pitch"), "-0.300");
    EXPECT_EQ(cell(0, "after_pitch"), "1.000");
    EXPECT_EQ(cell(1, "frame"), "");
    EXPECT_EQ(cell(1, "action"), "LIMIT LEFT");
    EXPECT_EQ(cell(1, "region"), "left");
    fs::remove_all(dir);
}

}  // namespace
}  // namespace gs::app
