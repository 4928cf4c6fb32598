// Pure pieces behind the windows: state bits, control-state names, "why not flying", flight path,
// plot scaling, settings persistence.
#include "support/state_bits.hpp"
#include "ui/demo_snapshot.hpp"
#include "ui/history.hpp"
#include "ui/plot.hpp"
#include "ui/settings.hpp"
#include "ui/windows.hpp"

#include <GLFW/glfw3.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace gs::ui {
namespace {

TEST(DroneStateBits, DecodesProtocolExamples) {
    // In-flight demo example from docs/protocol.md §3.2: bits 0,2,4,5,6,7,10,23-27.
    const DroneStateBits b = DroneStateBits::from_raw(0x0F8004F5u);
    EXPECT_TRUE(b.flying && b.vision_enabled && b.altitude_control && b.user_feedback_start);
    EXPECT_TRUE(b.command_ack && b.camera_ready && b.navdata_demo && b.pic_version_ok);
    EXPECT_FALSE(b.video_enabled || b.emergency || b.battery_low || b.com_watchdog);
    EXPECT_EQ(b.to_raw(), 0x0F8004F5u);
    const DroneStateBits boot = DroneStateBits::from_raw(0x4F800C10u);
    EXPECT_TRUE(boot.navdata_bootstrap && boot.com_watchdog && !boot.flying);
    EXPECT_STREQ(drone_state_bit_names()[31].sdk_name, "EMERGENCY");
    EXPECT_STREQ(drone_state_bit_names()[15].sdk_name, "VBAT_LOW");
}

TEST(CtrlState, NamesMajorAndMinor) {
    EXPECT_EQ(ctrl_state_name(0x00020000u), "LANDED");
    EXPECT_EQ(ctrl_state_name(4u << 16 | 8u), "HOVERING / LOST_COM");
    EXPECT_EQ(ctrl_state_name(3u << 16), "FLYING");
    EXPECT_EQ(ctrl_state_name(6u << 16), "TAKEOFF / GROUND");
    EXPECT_EQ(ctrl_state_name(8u << 16 | 99u), "LANDING / ?99");
    EXPECT_EQ(ctrl_state_name(42u << 16), "UNKNOWN(42)");
}

GuiSnapshot connected_landed(std::uint32_t bits) {
    GuiSnapshot s;
    s.connection.state = LinkState::Connected;
    s.telemetry.valid = true;
    s.telemetry.nav.battery_pct = 80;
    s.telemetry.nav.drone_state = bits;
    s.telemetry.state = DroneStateBits::from_raw(bits);
    return s;
}

bool has(const std::vector<Reason>& rs, const std::string& title, Severity sev) {
    for (const auto& r : rs)
        if (r.title == title && r.severity == sev) return true;
    return false;
}

TEST(WhyNotFlying, ExplainsFromConnectionAndBits) {
    auto rs = explain_not_flying(demo_no_link());
    ASSERT_EQ(rs.size(), 1u);
    EXPECT_EQ(rs[0].severity, Severity::Blocker);
    EXPECT_EQ(rs[0].title, "Not connected");

    rs = explain_not_flying(connected_landed(0x0F800080u));
    EXPECT_TRUE(has(rs, "Ready to take off", Severity::Ok));

    using gs::test::state_bit;
    rs = explain_not_flying(connected_landed(state_bit(gs::test::DroneStateBit::Emergency) |
                                             state_bit(gs::test::DroneStateBit::AnglesOutOfRange) |
                                             state_bit(gs::test::DroneStateBit::Cutout)));
    EXPECT_TRUE(has(rs, "Emergency: motors cut", Severity::Blocker));
    EXPECT_TRUE(has(rs, "Angles out of range", Severity::Blocker));
    EXPECT_TRUE(has(rs, "Motor cut-out", Severity::Blocker));
    EXPECT_FALSE(has(rs, "Ready to take off", Severity::Ok));

    rs = explain_not_flying(connected_landed(1u << 15));
    EXPECT_TRUE(has(rs, "Battery too low (VBAT_LOW)", Severity::Blocker));

    GuiSnapshot low = connected_landed(0);
    low.telemetry.nav.battery_pct = 15;
    rs = explain_not_flying(low);
    EXPECT_TRUE(has(rs, "Battery low", Severity::Warning));
    EXPECT_TRUE(has(rs, "Ready to take off", Severity::Ok));  // a warning does not block

    GuiSnapshot lost = connected_landed(1u << 13);
    lost.connection.state = LinkState::Lost;
    rs = explain_not_flying(lost);
    EXPECT_TRUE(has(rs, "Link lost", Severity::Blocker));
    EXPECT_TRUE(has(rs, "Communication lost (COM_LOST)", Severity::Blocker));
}

NavState nav_at(double t_s, double yaw_deg, double vx, double vy) {
    NavState n;
    n.t_ns = static_cast<TimeNs>(t_s * 1e9);
    n.yaw_deg = yaw_deg;
    n.vx_mps = vx;
    n.vy_mps = vy;
    n.altitude_m = 1.0;
    return n;
}

TEST(FlightPath, IntegratesBodyVelocityRotatedByYaw) {
    TelemetryHistory h;
    // 1 m/s forward heading 0 for 1 s: 1 m along the initial heading.
    for (int i = 0; i <= 10; ++i) h.add(nav_at(0.1 * i, 0.0, 1.0, 0.0));
    EXPECT_NEAR(h.path_x_m(), 1.0, 1e-9);
    EXPECT_NEAR(h.path_y_m(), 0.0, 1e-9);
    // Then heading 90 deg (clockwise: facing right) for 2 s at 0.5 m/s: 1 m to the right.
    for (int i = 11; i <= 30; ++i) h.add(nav_at(0.1 * i, 90.0, 0.5, 0.0));
    EXPECT_NEAR(h.path_x_m(), 1.0, 1e-9);
    EXPECT_NEAR(h.path_y_m(), 1.0, 1e-9);
    // Body-right velocity at heading 90 points backwards (-x).
    for (int i = 31; i <= 40; ++i) h.add(nav_at(0.1 * i, 90.0, 0.0, 1.0));
    EXPECT_NEAR(h.path_x_m(), 0.0, 1e-9);
    // The plotted path is a map: horizontal = right, vertical = forward.
    EXPECT_NEAR(h.path.last_x(), h.path_y_m(), 1e-12);
    EXPECT_NEAR(h.path.last_y(), h.path_x_m(), 1e-12);
}

TEST(FlightPath, GapsAreNotIntegratedAndTimeJumpBackClears) {
    TelemetryHistory h;
    h.add(nav_at(0.0, 0.0, 1.0, 0.0));
    h.add(nav_at(2.0, 0.0, 1.0, 0.0));  // 2 s gap: unknown motion, not 2 m
    EXPECT_EQ(h.path_gaps(), 1u);
    EXPECT_NEAR(h.path_x_m(), 0.0, 1e-12);
    h.add(nav_at(2.1, 0.0, 1.0, 0.0));
    EXPECT_NEAR(h.path_x_m(), 0.1, 1e-9);
    EXPECT_EQ(h.altitude_m.size(), 3u);
    h.add(nav_at(1.0, 0.0, 1.0, 0.0));  // seek back in a replay
    EXPECT_EQ(h.altitude_m.size(), 1u);
    EXPECT_NEAR(h.path_x_m(), 0.0, 1e-12);
}

TEST(PlotScale, NiceTicks) {
    EXPECT_DOUBLE_EQ(nice_step(10.0, 6), 2.0);
    EXPECT_EQ(nice_ticks(0.0, 10.0, 6), (std::vector<double>{0, 2, 4, 6, 8, 10}));
    EXPECT_EQ(nice_ticks(-0.37, 1.2, 5), (std::vector<double>{0.0, 0.5, 1.0}));
    const auto t = nice_ticks(1.0, 1.05, 6);  // centre-scale ratios
    ASSERT_EQ(t.size(), 6u);
    EXPECT_NEAR(t[1] - t[0], 0.01, 1e-12);
    EXPECT_TRUE(nice_ticks(1.0, 1.0, 5).empty());
    EXPECT_EQ(format_tick(0.5, 0.5), "0.5");
    EXPECT_EQ(format_tick(20.0, 10.0), "20");
    EXPECT_EQ(format_tick(1.02, 0.01), "1.02");
}

TEST(PlotScale, AutoscalePadsAndWidensFlatData) {
    const Range r = autoscale(0.0, 10.0, 0.05);
    EXPECT_DOUBLE_EQ(r.lo, -0.5);
    EXPECT_DOUBLE_EQ(r.hi, 10.5);
    const Range flat = autoscale(2.0, 2.0);
    EXPECT_DOUBLE_EQ(flat.lo, 1.5);
    EXPECT_DOUBLE_EQ(flat.hi, 2.5);
    const Range none = autoscale(std::numeric_limits<double>::infinity(),
                                 -std::numeric_limits<double>::infinity());
    EXPECT_DOUBLE_EQ(none.lo, 0.0);
    EXPECT_DOUBLE_EQ(none.hi, 1.0);
}

TEST(RingSeries, KeepsTheNewestInOrder) {
    RingSeries r(3);
    for (int i = 1; i <= 5; ++i) r.push(i, 10 * i);
    ASSERT_EQ(r.size(), 3u);
    EXPECT_EQ(r.x(0), 3);
    EXPECT_EQ(r.y(2), 50);
    EXPECT_EQ(r.last_x(), 5);
}

TEST(Settings, JsonRoundTripKeepsEverything) {
    Settings s;
    s.keymap.key(PilotKey::Emergency) = GLFW_KEY_PAUSE;
    s.keymap.dead_zone = 0.2f;
    s.add_recent("/data/a");
    s.add_recent("/data/b");
    s.add_recent("/data/a");
    s.drone_address = "10.0.0.7";
    s.use_sim = true;
    s.sim_scenario = "obstacle_left";
    s.overlay.trajectories = false;
    s.plot_span_s = 12;
    s.classifier = "thesis_scale";
    s.classifier_presets["indoor"] = {"thesis_scale", {{"scale_threshold", 1.07}}};
    s.classifier_params["thesis_scale"]["window_frames"] = 12;
    EXPECT_EQ(s.recent_datasets, (std::vector<std::string>{"/data/a", "/data/b"}));

    auto back = settings_from_json(settings_to_json(s));
    ASSERT_TRUE(back);
    EXPECT_EQ(back->keymap.keys, s.keymap.keys);
    EXPECT_FLOAT_EQ(back->keymap.dead_zone, 0.2f);
    EXPECT_EQ(back->recent_datasets, s.recent_datasets);
    EXPECT_EQ(back->drone_address, "10.0.0.7");
    EXPECT_TRUE(back->use_sim);
    EXPECT_EQ(back->overlay, s.overlay);
    EXPECT_EQ(back->classifier_presets, s.classifier_presets);
    EXPECT_EQ(back->classifier_params, s.classifier_params);
    EXPECT_DOUBLE_EQ(back->plot_span_s, 12);
}

TEST(Settings, MissingKeysKeepDefaultsWrongTypesAreMalformed) {
    auto s = settings_from_json(R"({"drone_address": "1.2.3.4", "future_key": [1,2]})");
    ASSERT_TRUE(s);
    EXPECT_EQ(s->drone_address, "1.2.3.4");
    EXPECT_EQ(s->keymap.key(PilotKey::Emergency), GLFW_KEY_F12);
    EXPECT_EQ(settings_from_json("{not json").error(), SettingsError::Malformed);
    EXPECT_EQ(settings_from_json(R"({"drone_address": 5})").error(), SettingsError::Malformed);
    EXPECT_EQ(settings_from_json(R"({"keymap": {"keys": {"land": "NoSuchKey"}}})").error(),
              SettingsError::Malformed);
}

TEST(Settings, SaveAndLoadInAConfigDirectory) {
    const auto dir =
        std::filesystem::temp_directory_path() / ("gs_ui_settings_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    const auto file = dir / "nested" / "settings.json";
    EXPECT_EQ(load_settings(file).error(), SettingsError::NotFound);
    Settings s;
    s.add_recent("/x");
    EXPECT_FALSE(save_settings(s, file).has_value());
    auto back = load_settings(file);
    ASSERT_TRUE(back);
    EXPECT_EQ(back->recent_datasets, std::vector<std::string>{"/x"});
    std::filesystem::remove_all(dir);
}

TEST(Settings, ConfigDirFollowsXdg) {
    const char* old = std::getenv("XDG_CONFIG_HOME");
    const std::string saved = old ? old : "";
    ::setenv("XDG_CONFIG_HOME", "/tmp/xdgtest", 1);
    EXPECT_EQ(config_dir(), std::filesystem::path("/tmp/xdgtest/ardrone-gs"));
    if (old)
        ::setenv("XDG_CONFIG_HOME", saved.c_str(), 1);
    else
        ::unsetenv("XDG_CONFIG_HOME");
}

}  // namespace
}  // namespace gs::ui
