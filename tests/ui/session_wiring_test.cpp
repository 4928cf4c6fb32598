// The window wired to a drone: synthetic key presses go through Gui::frame -> GuiAdapter ->
// DroneLink -> loopback -> the virtual drone, and what the virtual drone did (its flight state,
// its drone_state bits, the AT datagrams on the wire) is checked. Real sockets and threads, so
// waits are bounded polls on the drone's own state, never fixed sleeps standing in for logic.
#include "app/gui_adapter.hpp"
#include "app/session.hpp"
#include "drone/dataset/dataset.hpp"
#include "drone/sim/at_parser.hpp"
#include "session_fixture.hpp"

#include <GLFW/glfw3.h>
#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <thread>

namespace gs::ui::test {
namespace {

using namespace std::chrono_literals;
using app::SessionOptions;

class Wiring : public SessionFixture {
protected:
    app::SourceInfo src() const { return session->source().latest().value_or(app::SourceInfo{}); }
};

// Every PCMD the link sent, parsed from the AT datagrams it published as raw events.
std::vector<sim::at::Pcmd> sent_pcmds(BoundedQueue<link::RawEvent>& raw) {
    std::vector<sim::at::Pcmd> out;
    while (auto e = raw.try_pop()) {
        if (e->kind != link::RawEvent::Kind::At) continue;
        auto p = sim::at::parse_datagram(std::span<const std::uint8_t>(e->bytes));
        if (!p) continue;
        for (const auto& c : p->commands)
            if (const auto* pc = std::get_if<sim::at::Pcmd>(&c.body)) out.push_back(*pc);
    }
    return out;
}

TEST_F(Wiring, TakeoffKeyWHeldAndEmergencyKeyReachTheVirtualDroneEscapeDoesNot) {
    SessionOptions so;
    so.sim_video = false;  // flight only: keeps the test light
    start(so, "thesis_pillar_center");
    ASSERT_TRUE(run_until([&] { return snap.connection.state == LinkState::Connected; }, 8s))
        << snap.connection.reason;
    EXPECT_EQ(snap.connection.source, SourceKind::Sim);
    const auto s = src();
    ASSERT_TRUE(s.link && s.virtual_drone);
    auto drone = s.virtual_drone;
    auto raw = s.link->subscribe_raw(8192);

    // T: one take-off edge; the virtual drone climbs to its hover.
    const Actions ta = step(key(PilotKey::Takeoff));
    EXPECT_TRUE(ta.takeoff);
    ASSERT_TRUE(
        run_until([&] { return drone->status().flight.major == sim::CtrlMajor::Hovering; }, 10s))
        << "never hovering; messages: " << (snap.messages.empty() ? "" : snap.messages.back().text);
    EXPECT_TRUE(snap.telemetry.state && snap.telemetry.state->flying);

    // W held for a second and a half: forward (nose down) on the wire and in the drone.
    const double x0 = drone->ground_truth().pose.x_m;
    (void)sent_pcmds(*raw);  // forget the take-off's hover PCMDs
    const InputState w = key(PilotKey::Forward);
    const auto t0 = std::chrono::steady_clock::now();
    double min_pitch_deg = 0;
    while (std::chrono::steady_clock::now() - t0 < 1500ms) {
        step(w);
        min_pitch_deg = std::min(min_pitch_deg, drone->status().flight.pitch_deg);
        std::this_thread::sleep_for(10ms);
    }
    EXPECT_EQ(adapter->moves_sent(), 1u) << "a held key is one Move, repeated by the link";
    const auto pcmds = sent_pcmds(*raw);
    int forward = 0;
    for (const auto& p : pcmds)
        if ((p.flags & 1) && p.pitch < 0 && p.roll == 0 && p.gaz == 0 && p.yaw == 0) ++forward;
    // The link repeats the command every 30 ms: ~50 in 1.5 s.
    EXPECT_GE(forward, 30) << pcmds.size() << " PCMDs sent";
    const float gain = Keymap::defaults().keyboard_gain;
    bool exact = false;
    for (const auto& p : pcmds) exact = exact || p.pitch == -gain;
    EXPECT_TRUE(exact) << "PCMD pitch should be -" << gain;
    EXPECT_LT(min_pitch_deg, -3.0) << "the drone never pitched nose down";
    EXPECT_GT(drone->ground_truth().pose.x_m - x0, 0.3) << "the drone did not move forward";

    // Letting go: one Hover, PCMD flags back to 0 on the wire (within a few AT cycles, however
    // loaded the machine).
    step();
    EXPECT_EQ(adapter->hovers_sent(), 1u);
    std::vector<sim::at::Pcmd> after;
    EXPECT_TRUE(run_until(
        [&] {
            for (const auto& p : sent_pcmds(*raw)) after.push_back(p);
            return !after.empty() && (after.back().flags & 1) == 0;
        },
        3s))
        << "no hover after release: " << after.size() << " PCMDs sent since";
    EXPECT_EQ(adapter->hovers_sent(), 1u);

    // Escape, a desktop reflex ("close this"), does nothing to the flying drone: the link keeps
    // sending for another 40 AT commands and the drone keeps flying.
    InputState esc;
    esc.keys.set(GLFW_KEY_ESCAPE);
    const Actions esc_a = step(esc);
    EXPECT_FALSE(esc_a.emergency || esc_a.land || esc_a.takeoff || esc_a.quit);
    step();
    const auto at0 = drone->status().counters.at_commands;
    ASSERT_TRUE(run_until([&] { return drone->status().counters.at_commands > at0 + 40; }, 5s));
    EXPECT_TRUE(drone->status().flight.motors_on);
    EXPECT_EQ((drone->status().drone_state >> 31) & 1u, 0u) << "Escape cut the motors";

    // The emergency key (F12): the drone cuts its motors and reports bit 31.
    EXPECT_EQ(Keymap::defaults().key(PilotKey::Emergency), GLFW_KEY_F12);
    const Actions ea = step(key(PilotKey::Emergency));
    EXPECT_TRUE(ea.emergency);
    ASSERT_TRUE(run_until(
        [&] { return protocol::navdata::DroneState{drone->status().drone_state}.emergency(); }, 5s))
        << "emergency bit never set";
    EXPECT_FALSE(drone->status().flight.motors_on);
    ASSERT_TRUE(
        run_until([&] { return snap.telemetry.state && snap.telemetry.state->emergency; }, 3s));
}

TEST_F(Wiring, TakeoffRefusedOnLowBatteryShowsTheReasonAsAMessage) {
    SessionOptions so;
    so.sim_video = false;
    so.sim_battery_pct = 12.0;
    start(so, "thesis_pillar_center");
    ASSERT_TRUE(run_until([&] { return snap.connection.state == LinkState::Connected; }, 8s));
    ASSERT_TRUE(run_until([&] { return snap.telemetry.valid; }, 3s));
    step(key(PilotKey::Takeoff));
    // Refused in the window before it reaches the link (the button is disabled, the key's press
    // is logged with the reason): "take-off refused: battery 12 % is below the 20 % minimum".
    auto has_refusal = [&] {
        for (const auto& m : snap.messages)
            if (m.text.find("take-off refused: battery 12 %") != std::string::npos) return true;
        return false;
    };
    ASSERT_TRUE(run_until(has_refusal, 3s))
        << (snap.messages.empty() ? "" : snap.messages.back().text);
    EXPECT_FALSE(src().virtual_drone->status().flight.motors_on);
}

TEST_F(Wiring, HudBatteryGaugeShowsTheNavdataBatteryOfTheVirtualDrone) {
    SessionOptions so;
    so.sim_battery_pct = 37.0;
    start(so, "warehouse");
    // Bootstrap navdata carries no demo option (battery unknown): wait for the configured stream.
    ASSERT_TRUE(run_until(
        [&] {
            return snap.telemetry.valid && !std::isnan(snap.telemetry.nav.battery_pct) &&
                   !snap.video.bgr.empty();
        },
        10s))
        << snap.connection.reason;
    step();
    const double nav_pct = snap.telemetry.nav.battery_pct;
    // Navdata carries whole percent; the drone idles down from 37 % very slowly.
    ASSERT_GE(nav_pct, 36.0);
    ASSERT_LE(nav_pct, 37.0);
    const LayoutReport& l = gui.view().layout;
    char want[16];
    std::snprintf(want, sizeof want, "%.0f%%", nav_pct);
    EXPECT_EQ(l.battery_text, want);
    const double inner = static_cast<double>(l.battery_outline.w()) - 4.0;
    ASSERT_GT(inner, 10.0);
    EXPECT_NEAR(static_cast<double>(l.battery_fill.w()) / inner, nav_pct / 100.0, 0.005);
    EXPECT_EQ(l.battery_color, colors::kWarn) << "below 40 % the gauge is amber";
    // Every navdata field is listed, grouped by option.
    bool demo_battery = false;
    for (const auto& f : snap.telemetry.fields)
        demo_battery =
            demo_battery || (f.group == "demo" && f.name.rfind("vbat_flying_percentage", 0) == 0 &&
                             std::stod(f.value) == nav_pct);
    EXPECT_TRUE(demo_battery);

    // Link health: packet rate and throughput for all three streams, every byte counted by the
    // link: a navdata datagram is at least its header and the demo option's 148 bytes; an AT
    // datagram every 30 ms carries a REF and a PCMD (each "AT*..." is over 20 bytes).
    ASSERT_TRUE(run_until(
        [&] {
            // Rates are measured over one-second windows: 0 until the first has passed.
            return snap.link.navdata.rate_hz > 0 && snap.link.at.rate_hz > 0 &&
                   snap.link.video.rate_hz > 0 && snap.link.video.bytes_per_s > 0;
        },
        5s));
    const StreamHealth& n = snap.link.navdata;
    const StreamHealth& at = snap.link.at;
    ASSERT_GT(n.rate_hz, 5.0);
    EXPECT_GE(n.bytes_per_s / n.rate_hz, 148.0);
    EXPECT_LE(n.bytes_per_s / n.rate_hz, 4096.0);
    ASSERT_GT(at.rate_hz, 15.0);
    EXPECT_GE(at.bytes_per_s / at.rate_hz, 40.0);
    EXPECT_LE(at.bytes_per_s / at.rate_hz, 200.0);
    EXPECT_GT(snap.link.video.rate_hz, 5.0);
    EXPECT_GT(snap.link.video.bytes_per_s, 1000.0);
}

TEST_F(Wiring, RKeyRecordsTheVirtualDroneAsADatasetThatOpensForReplay) {
    const std::filesystem::path root =
        std::filesystem::temp_directory_path() / ("gs_wiring_rec_" + std::to_string(::getpid()));
    std::filesystem::remove_all(root);
    SessionOptions so;
    so.record_root = root;
    start(so, "thesis_pillar_left");
    ASSERT_TRUE(run_until([&] { return !snap.video.bgr.empty(); }, 10s)) << snap.connection.reason;
    const Actions ra = step(key(PilotKey::Record));
    EXPECT_TRUE(ra.record_start);
    ASSERT_TRUE(run_until([&] { return snap.recording.active && snap.recording.frames >= 15; }, 8s))
        << snap.recording.error << (snap.messages.empty() ? "" : " / " + snap.messages.back().text);
    step();  // release R
    const Actions rb = step(key(PilotKey::Record));
    EXPECT_TRUE(rb.record_stop);
    ASSERT_TRUE(run_until([&] { return !snap.recording.active; }, 8s));
    const std::string path = snap.recording.path;
    ASSERT_FALSE(path.empty());
    EXPECT_EQ(std::filesystem::path(path).parent_path(), root);
    auto ds = dataset::Dataset::open(path);
    ASSERT_TRUE(ds) << to_string(ds.error());
    EXPECT_GE(ds->frame_count(), 15);
    EXPECT_EQ(static_cast<std::uint64_t>(ds->frame_count()), snap.recording.frames);
    EXPECT_TRUE(ds->has_navdata());
    std::filesystem::remove_all(root);
}

// The bottom camera on the virtual drone flying its scripted flight: the session runs the visual
// odometry (not the classifier) on its frames, the window gets per-sample estimates and a path,
// and the flight-path map draws it beside the navdata path on equal scales.
TEST_F(Wiring, BottomCameraRunsVisualOdometryBesideTheNavdataPath) {
    const std::filesystem::path root =
        std::filesystem::temp_directory_path() / ("gs_wiring_bottom_" + std::to_string(::getpid()));
    std::filesystem::remove_all(root);
    SessionOptions so;
    so.record_root = root;
    session = std::make_unique<app::Session>(so);
    adapter = std::make_unique<app::GuiAdapter>(*session);
    adapter->set_start_camera(1);  // what `--camera bottom` does
    ASSERT_TRUE(session->request(app::StartSim{"thesis_pillar_center", true}));
    ASSERT_TRUE(run_until(
        [&] {
            return snap.odometry.active && snap.odometry.samples >= 20 &&
                   snap.odometry.path_x.size() >= 10;
        },
        25s))
        << "camera " << snap.video.camera << ", samples " << snap.odometry.samples << "; "
        << (snap.messages.empty() ? "" : snap.messages.back().text);
    step();
    const OdometryView& o = snap.odometry;
    EXPECT_EQ(snap.video.camera, "bottom");
    EXPECT_FALSE(snap.classifier.not_running.empty()) << "the classifier is for the front camera";
    EXPECT_TRUE(snap.classifier.decisions.empty());
    EXPECT_GT(o.samples - o.invalid, o.samples / 2) << "most samples give an estimate";
    EXPECT_EQ(o.path_x.size(), o.path_y.size());
    EXPECT_TRUE(std::isfinite(o.distance_m) && o.distance_m > 0) << "altitude from navdata";
    EXPECT_TRUE(std::isfinite(o.x_m) && std::isfinite(o.y_m));
    EXPECT_TRUE(std::isfinite(o.nav_x_m) && std::isfinite(o.nav_y_m));
    // Flying forward at 1 m/s the samples are not thrown away as spikes, and the visual path
    // follows the navdata one.
    EXPECT_LT(o.spike_samples, o.samples / 4) << "spike-zeroed samples";
    const double travelled = std::hypot(o.nav_x_m, o.nav_y_m);
    if (travelled > 0.3) {
        EXPECT_LT(std::hypot(o.x_m - o.nav_x_m, o.y_m - o.nav_y_m), 0.25 * travelled + 0.1)
            << "visual (" << o.x_m << ", " << o.y_m << ") navdata (" << o.nav_x_m << ", "
            << o.nav_y_m << ")";
    }
    // The newest path point is the current pose (x right = eq. 6.2 y, y forward = eq. 6.2 x).
    EXPECT_DOUBLE_EQ(o.path_x.back(), o.y_m);
    EXPECT_DOUBLE_EQ(o.path_y.back(), o.x_m);

    const LayoutReport::FlightPath& fp = gui.view().layout.flight_path;
    ASSERT_TRUE(fp.drawn);
    ASSERT_EQ(fp.series.size(), 2u);
    EXPECT_EQ(fp.series[0], "navdata");
    EXPECT_EQ(fp.series[1], "visual odometry");
    EXPECT_TRUE(fp.legend);
    EXPECT_EQ(fp.odometry_points, o.path_x.size());
    ASSERT_GT(fp.x_per_px, 0);
    EXPECT_NEAR(fp.y_per_px / fp.x_per_px, 1.0, 1e-6) << "equal scale on both axes";
    EXPECT_TRUE(std::isfinite(fp.odometry_x0) && std::isfinite(fp.odometry_y0));

    // Recorded now, the dataset is a bottom-camera one (flight.json "camera": "bottom").
    ASSERT_TRUE(step(key(PilotKey::Record)).record_start);
    ASSERT_TRUE(run_until([&] { return snap.recording.active && snap.recording.frames >= 5; }, 8s))
        << snap.recording.error;
    step();
    ASSERT_TRUE(step(key(PilotKey::Record)).record_stop);
    ASSERT_TRUE(run_until([&] { return !snap.recording.active; }, 8s));
    auto ds = dataset::Dataset::open(snap.recording.path);
    ASSERT_TRUE(ds) << to_string(ds.error());
    EXPECT_EQ(ds->info().camera, CameraId::Bottom);
    EXPECT_GE(ds->frame_count(), 5);
    std::filesystem::remove_all(root);
}

}  // namespace
}  // namespace gs::ui::test
