// The cockpit against the virtual drone over real sockets (Gui -> GuiAdapter -> Session ->
// DroneLink -> loopback -> VirtualDrone), issue 13:
//  - point 8: start-up says what is happening as it happens, the source as it really is;
//  - points 5 and 6: a stalled video shows as stale (0 fps, its age, the overlay) and no region
//    stays "clear" (the session republishes them unknown, StaleVideo);
//  - point 11: Drone -> Settings writes go out with the multiconfiguration ids, are confirmed by
//    reading the configuration back, and the virtual drone honours them (tilt, vertical speed,
//    yaw rate, altitude, video, navdata rate); what the drone ignores is shown as ignored.
// Waits are bounded polls on the drone's or the window's state.
#include "app/gui_adapter.hpp"
#include "app/session.hpp"
#include "session_fixture.hpp"
#include "ui/controls.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <thread>

namespace gs::ui::test {
namespace {

using namespace std::chrono_literals;

class CockpitLive : public SessionFixture {
protected:
    app::SourceInfo src() const { return session->source().latest().value_or(app::SourceInfo{}); }
    // Writes through the window's settings path (Actions -> GuiAdapter -> SetConfig).
    void write(const std::string& key, const std::string& value) {
        Actions a;
        a.config_writes.emplace_back(key, value);
        adapter->consume(a);
    }
    const ConfigWrite* last_write(const std::string& key) { return snap.config.last_write(key); }
    bool settled(const std::string& key) {
        const ConfigWrite* w = last_write(key);
        return w && w->state != ConfigWriteState::Pending;
    }
    void move(float roll, float pitch, float gaz, float yaw) {
        Actions a;
        a.manual = true;
        a.pilot = {roll, pitch, gaz, yaw};
        adapter->consume(a);
    }
};

TEST_F(CockpitLive, StartUpSaysStartingTheVirtualDroneNeverDisconnected) {
    app::SessionOptions so;
    so.sim_video = true;
    start(so, "warehouse");
    // The very first frame, before the session thread has even seen the request.
    step();
    EXPECT_TRUE(snap.connection.opening);
    EXPECT_EQ(snap.connection.source, SourceKind::Sim);
    EXPECT_EQ(snap.connection.activity, "Starting virtual drone 'warehouse'...");
    EXPECT_EQ(gui.view().layout.status.source, "VIRTUAL DRONE");
    std::vector<std::string> seen{snap.connection.activity};
    bool said_disconnected = false;
    ASSERT_TRUE(run_until(
        [&] {
            if (snap.connection.state == LinkState::Disconnected) said_disconnected = true;
            if (seen.back() != snap.connection.activity) seen.push_back(snap.connection.activity);
            return snap.connection.state == LinkState::Connected && !snap.video.bgr.empty() &&
                   snap.connection.activity.empty();
        },
        20s));
    EXPECT_FALSE(said_disconnected) << "said 'Disconnected' while starting the virtual drone";
    EXPECT_TRUE(gui.view().settings.use_sim) << "the Connection window shows another source";
    std::string all;
    for (const auto& a : seen) all += "[" + a + "] ";
    std::printf("activities: %s\n", all.c_str());
    for (const auto& a : seen)
        EXPECT_TRUE(a.empty() || a.rfind("Starting", 0) == 0 || a.rfind("Connecting", 0) == 0 ||
                    a.rfind("Configuring", 0) == 0 || a == "Waiting for video...")
            << a;
}

TEST_F(CockpitLive, ConnectingToADroneSaysSoWithItsAddress) {
    session = std::make_unique<app::Session>(app::SessionOptions{});
    adapter = std::make_unique<app::GuiAdapter>(*session);
    ASSERT_TRUE(session->request(app::ConnectDrone{"127.0.0.1"}));  // nobody answers there
    step();
    EXPECT_EQ(snap.connection.source, SourceKind::Drone);
    EXPECT_EQ(snap.connection.activity, "Connecting to 127.0.0.1...");
    ASSERT_TRUE(run_until([&] { return src().kind == app::SessionSource::Drone; }, 5s));
    step();
    EXPECT_EQ(snap.connection.state, LinkState::Connecting);
    EXPECT_EQ(snap.connection.activity, "Connecting to 127.0.0.1...");
    EXPECT_FALSE(gui.view().settings.use_sim);
    EXPECT_EQ(gui.view().layout.status.source, "LIVE DRONE");
}

TEST_F(CockpitLive, StalledVideoIsStaleAndNoRegionStaysClear) {
    start({}, "thesis_pillar_left");
    ASSERT_TRUE(run_until(
        [&] {
            return snap.connection.state == LinkState::Connected && snap.video.index > 20 &&
                   snap.video.fps > 10;
        },
        20s));
    EXPECT_FALSE(snap.video.stale);
    src().virtual_drone->inject(sim::FaultVideoStall{2500});
    // The picture freezes: within the deadline the window says stale, 0 fps, the age growing.
    ASSERT_TRUE(run_until(
        [&] {
            return snap.video.stale && snap.video.fps < 0.5 &&
                   !gui.view().layout.video_stale_text.empty();
        },
        4s))
        << "fps " << snap.video.fps << " age " << snap.video.age_ms;
    EXPECT_GT(snap.video.age_ms, kStaleAfterMs);
    for (const auto& b : gui.view().layout.region_bars) {
        EXPECT_FALSE(b.known) << b.name;
        EXPECT_FALSE(b.flagged) << b.name;
    }
    // The session too: its latest output has every region unknown for stale video.
    ASSERT_TRUE(run_until(
        [&] {
            const auto o = session->output().latest();
            return o && *o && (*o)->stale;
        },
        2s));
    const auto o = *session->output().latest();
    for (const auto& d : o->result.regions) {
        EXPECT_FALSE(d.valid);
        EXPECT_FALSE(d.unsafe);
        EXPECT_EQ(d.unknown, vision::UnknownReason::StaleVideo);
    }
    // Video back: fresh, and the rate is measured, not a burst (it never reads far above 30).
    double max_fps = 0;
    ASSERT_TRUE(run_until(
        [&] {
            if (known(snap.video.fps)) max_fps = std::max(max_fps, snap.video.fps);
            return !snap.video.stale && snap.video.fps > 10;
        },
        8s));
    EXPECT_LT(max_fps, 45.0);
    EXPECT_TRUE(gui.view().layout.video_stale_text.empty());
}

TEST_F(CockpitLive, SettingsAreConfirmedByReadBackAndTheVirtualDroneFliesByThem) {
    app::SessionOptions so;
    so.sim_video = false;
    start(so, "thesis_open_hall");
    ASSERT_TRUE(run_until(
        [&] { return snap.connection.state == LinkState::Connected && snap.config.read; }, 15s))
        << "no configuration read back";
    ASSERT_NE(snap.config.get("control:euler_angle_max"), nullptr);
    auto drone = src().virtual_drone;
    // 5 deg of tilt, 0.3 m/s vertical, 40 deg/s yaw, 1.5 m ceiling.
    write("control:euler_angle_max", "0.08726646");
    write("control:control_vz_max", "300");
    write("control:control_yaw", "0.6981317");
    write("control:altitude_max", "1500");
    for (const char* k : {"control:euler_angle_max", "control:control_vz_max",
                          "control:control_yaw", "control:altitude_max"}) {
        ASSERT_TRUE(run_until([&] { return settled(k); }, 10s)) << k;
        EXPECT_EQ(last_write(k)->state, ConfigWriteState::Confirmed)
            << k << ": " << last_write(k)->detail;
    }
    EXPECT_EQ(drone->status().counters.configs_without_ids, 0u)
        << "a CONFIG went without its CONFIG_IDS";
    // The window shows the read-back values.
    step();
    gui.view().open.drone_settings = true;
    step();
    std::size_t confirmed = 0;
    for (const auto& [k, st] : gui.view().layout.setting_status) confirmed += st == "confirmed";
    EXPECT_EQ(confirmed, 4u);

    // Fly: the drone keeps to what was set.
    Actions t;
    t.takeoff = true;
    adapter->consume(t);
    ASSERT_TRUE(
        run_until([&] { return drone->status().flight.major == sim::CtrlMajor::Hovering; }, 15s));
    double max_vz = 0, max_alt = 0, max_pitch = 0, max_yaw_rate = 0;
    auto watch = [&] {
        const sim::FlightState f = drone->status().flight;
        max_vz = std::max(max_vz, f.vz_mps);
        max_alt = std::max(max_alt, f.z_m);
        max_pitch = std::max(max_pitch, std::fabs(f.pitch_deg));
        max_yaw_rate = std::max(max_yaw_rate, std::fabs(f.yaw_rate_deg_s));
        return false;
    };
    // Full climb for 3 s, then full forward and full yaw for 2 s (flight time), commanded as the
    // window commands a held stick: one Move, repeated by the link.
    bool watching = false;  // from 1 s into the climb: the take-off's own rise has died down
    auto fly = [&](float pitch, float gaz, float yaw, double seconds) {
        move(0, pitch, gaz, yaw);
        const double from = drone->status().flight.t_s;
        const auto deadline = std::chrono::steady_clock::now() + 20s;
        while (drone->status().flight.t_s < from + seconds) {
            if (std::chrono::steady_clock::now() > deadline) return false;
            if (watching) watch();
            std::this_thread::sleep_for(5ms);
        }
        return true;
    };
    ASSERT_TRUE(fly(0, 1, 0, 1.0));
    watching = true;
    ASSERT_TRUE(fly(0, 1, 0, 3.0));
    ASSERT_TRUE(fly(-1, 0, 1, 2.0));
    EXPECT_LE(max_vz, 0.33) << "control:control_vz_max 300 mm/s";
    EXPECT_GT(max_vz, 0.2) << "the climb never reached its speed";
    EXPECT_LE(max_alt, 1.55) << "control:altitude_max 1500 mm";
    EXPECT_GT(max_alt, 1.3);
    EXPECT_LE(max_pitch, 5.3) << "control:euler_angle_max 5 deg";
    EXPECT_GT(max_pitch, 3.5);
    EXPECT_LE(max_yaw_rate, 42.0) << "control:control_yaw 40 deg/s";
    EXPECT_GT(max_yaw_rate, 30.0);
}

TEST_F(CockpitLive, WhatTheDroneIgnoresIsShownAsIgnored) {
    app::SessionOptions so;
    so.sim_video = false;
    start(so, "thesis_open_hall");
    ASSERT_TRUE(run_until(
        [&] { return snap.connection.state == LinkState::Connected && snap.config.read; }, 15s));
    write("control:euler_angle_max", "0.9");  // beyond the firmware's 30 deg: clamped
    write("video:video_codec", "128");        // MPEG-4: this drone streams H.264 only
    write("control:no_such_key", "1");        // not a key of this firmware
    write("control:outdoor", "TRUE");         // fine: loads the outdoor maxima
    for (const char* k :
         {"control:euler_angle_max", "video:video_codec", "control:no_such_key", "control:outdoor"})
        ASSERT_TRUE(run_until([&] { return settled(k); }, 10s)) << k;
    EXPECT_EQ(last_write("control:euler_angle_max")->state, ConfigWriteState::Ignored);
    EXPECT_NE(last_write("control:euler_angle_max")->detail.find("reports"), std::string::npos);
    EXPECT_EQ(last_write("video:video_codec")->state, ConfigWriteState::Ignored);
    EXPECT_EQ(last_write("control:no_such_key")->state, ConfigWriteState::Ignored);
    EXPECT_NE(last_write("control:no_such_key")->detail.find("no key"), std::string::npos);
    EXPECT_EQ(last_write("control:outdoor")->state, ConfigWriteState::Confirmed);
    // Each said in the log, as a warning.
    bool logged = false;
    for (const auto& m : snap.messages)
        logged |=
            m.level == LogLevel::Warn && m.text.find("video:video_codec") != std::string::npos;
    EXPECT_TRUE(logged);
    // Flat trim on the ground is sent; magnetometer calibration is refused until flying.
    EXPECT_TRUE(control_state(snap, Control::FlatTrim).enabled);
    EXPECT_FALSE(control_state(snap, Control::Calibrate).enabled);
}

TEST_F(CockpitLive, VideoAndNavdataSettingsReachTheStream) {
    start({}, "thesis_pillar_left");
    ASSERT_TRUE(run_until(
        [&] {
            return snap.connection.state == LinkState::Connected && snap.config.read &&
                   !snap.video.bgr.empty();
        },
        20s));
    EXPECT_EQ(snap.video.bgr.cols, 640);
    // The link asks for full navdata at 200 Hz from the start (docs/protocol.md §1.3).
    EXPECT_NEAR(snap.link.expected_navdata_hz, 200.0, 0.1);
    // 720p; full navdata written again is confirmed and keeps the stream at 200 Hz.
    write("video:video_codec", "131");
    write("general:navdata_demo", "FALSE");
    ASSERT_TRUE(run_until([&] { return settled("video:video_codec"); }, 10s));
    EXPECT_EQ(last_write("video:video_codec")->state, ConfigWriteState::Confirmed);
    ASSERT_TRUE(run_until([&] { return snap.video.bgr.cols == 1280; }, 10s))
        << "frames stay " << snap.video.bgr.cols << " wide";
    EXPECT_EQ(snap.video.bgr.rows, 720);
    ASSERT_TRUE(run_until([&] { return settled("general:navdata_demo"); }, 10s));
    EXPECT_EQ(last_write("general:navdata_demo")->state, ConfigWriteState::Confirmed);
    ASSERT_TRUE(run_until(
        [&] { return snap.link.expected_navdata_hz > 150 && snap.link.navdata.rate_hz > 100; },
        10s))
        << snap.link.navdata.rate_hz;
    // Bitrate: 300 kbit/s caps the stream's bytes (the encoder's VBV holds it over a second).
    write("video:video_codec", "129");
    write("video:bitrate", "300");
    ASSERT_TRUE(run_until([&] { return settled("video:bitrate"); }, 10s));
    EXPECT_EQ(last_write("video:bitrate")->state, ConfigWriteState::Confirmed);
    ASSERT_TRUE(run_until(
        [&] {
            return snap.video.bgr.cols == 640 && snap.link.video.bytes_per_s > 0 &&
                   snap.link.video.bytes_per_s < 60'000;
        },
        10s))
        << snap.link.video.bytes_per_s << " B/s";
}

}  // namespace
}  // namespace gs::ui::test
