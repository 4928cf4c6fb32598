// Indicators that tell the truth (issue 13, points 5, 6, 7 and 9), on a bare ImGui context:
// unknown regions are grey "no data" with the reason, stale video says so, the status bar shows
// the source, the flight state, battery, link, REC and the latest message, advice fits the cause
// and controls that cannot act are disabled with the reason.
#include "imgui_fixture.hpp"
#include "support/state_bits.hpp"
#include "ui/controls.hpp"
#include "ui/demo_snapshot.hpp"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <string>

namespace gs::ui::test {
namespace {

class CockpitIndicators : public ImGuiFixture {
protected:
    static GuiSnapshot sim_flying() {
        GuiSnapshot s;
        make_demo_snapshot(s, 1);
        s.connection.source = SourceKind::Sim;
        s.connection.scenario = "warehouse";
        return s;
    }
    static bool has_reason(const std::vector<Reason>& rs, const std::string& title) {
        return std::any_of(rs.begin(), rs.end(), [&](const Reason& r) { return r.title == title; });
    }
    static bool drawn_window(const Gui& gui, const std::string& name) {
        for (const auto& [n, r] : gui.view().layout.windows)
            if (n == name) return true;
        return false;
    }
    // The centre measured (known, not flagged) at `score` against 0.30, on its bar and in the
    // Classifier window's list alike; `still`: judged for approaching things only.
    static void measure_centre(GuiSnapshot& s, double score, bool still = false) {
        RegionBar& centre = s.classifier.overlay.regions[1];
        RegionDecision& d = s.classifier.decisions[1];
        centre.known = d.known = true;
        centre.flagged = d.flagged = false;
        centre.score = d.score = score;
        centre.threshold = d.threshold = 0.30;
        centre.still = d.still = still;
    }
    // Hovers the mouse over `r` for two frames, then takes it away: the tooltip is in the layout.
    void hover(Gui& gui, const GuiSnapshot& s, const Rect& r) {
        ImGui::GetIO().MousePos = {0.5f * (r.x0 + r.x1), 0.5f * (r.y0 + r.y1)};
        frame(gui, s);
        frame(gui, s);
        ImGui::GetIO().MousePos = {-FLT_MAX, -FLT_MAX};
    }
    static std::string disabled_why(const Gui& gui, const std::string& id) {
        for (const auto& [n, why] : gui.view().layout.disabled)
            if (n == id) return why;
        return {};
    }
};

// Point 5: a region with too little evidence is unknown, grey, "no data", the reason on hover.
TEST_F(CockpitIndicators, UnknownRegionIsGreyNoDataWithTheReasonAsTooltip) {
    Gui gui;
    GuiSnapshot s = sim_flying();
    RegionBar& centre = s.classifier.overlay.regions[1];
    centre.known = false;
    centre.unknown_reason = "too few tracked points";
    s.classifier.decisions[1].known = false;
    s.classifier.decisions[1].unknown_reason = "too few tracked points";
    frame(gui, s);
    const auto& bars = gui.view().layout.region_bars;
    ASSERT_EQ(bars.size(), 3u);
    EXPECT_FALSE(bars[1].known);
    EXPECT_FALSE(bars[1].flagged);
    EXPECT_NE(bars[1].label.find("no data"), std::string::npos) << bars[1].label;
    EXPECT_EQ(bars[1].label.find("clear"), std::string::npos);
    EXPECT_TRUE(bars[0].known);
    EXPECT_TRUE(bars[0].flagged);  // the demo's left obstacle
    // Hovering the grey bar says why.
    hover(gui, s, bars[1].rect);
    EXPECT_NE(gui.view().layout.tooltip.find("too few tracked points"), std::string::npos)
        << gui.view().layout.tooltip;
}

// A still camera (hovering) sees nothing static approach, whatever stands ahead: its regions are
// steel blue "still", never green "clear", the tooltip says what is and is not judged, and an
// approaching thing still turns the bar red.
TEST_F(CockpitIndicators, AStillCameraRegionIsStillNotClearWithItsMeaningAsTooltip) {
    Gui gui;
    GuiSnapshot s = sim_flying();
    measure_centre(s, 0, true);
    frame(gui, s);
    const auto& bars = gui.view().layout.region_bars;
    ASSERT_EQ(bars.size(), 3u);
    EXPECT_TRUE(bars[1].known);
    EXPECT_TRUE(bars[1].still);
    EXPECT_FALSE(bars[1].flagged);
    EXPECT_NE(bars[1].label.find("still"), std::string::npos) << bars[1].label;
    EXPECT_EQ(bars[1].label.find("clear"), std::string::npos) << bars[1].label;
    EXPECT_FALSE(bars[2].still) << "only the region marked still";
    hover(gui, s, bars[1].rect);
    EXPECT_NE(gui.view().layout.tooltip.find("not seen until the drone moves"), std::string::npos)
        << gui.view().layout.tooltip;
    // A hand coming at the still camera: unsafe, red, not "still".
    RegionBar& centre = s.classifier.overlay.regions[1];
    centre.flagged = true;
    centre.score = 0.6;
    frame(gui, s);
    EXPECT_TRUE(gui.view().layout.region_bars[1].flagged);
    EXPECT_FALSE(gui.view().layout.region_bars[1].still);
    EXPECT_NE(gui.view().layout.region_bars[1].label.find("UNSAFE"), std::string::npos);
}

// Point 5: a score over its threshold that the classifier has not confirmed yet (it waits a few
// frames) is neither clear nor unsafe: an amber "confirming" bar, never green.
TEST_F(CockpitIndicators, AScoreOverItsThresholdNotYetConfirmedIsNeverClear) {
    Gui gui;
    GuiSnapshot s = sim_flying();
    measure_centre(s, 0.47);
    RegionBar& centre = s.classifier.overlay.regions[1];
    frame(gui, s);
    const auto& bars = gui.view().layout.region_bars;
    ASSERT_EQ(bars.size(), 3u);
    EXPECT_TRUE(bars[1].known);
    EXPECT_FALSE(bars[1].flagged);
    EXPECT_TRUE(bars[1].confirming);
    EXPECT_EQ(bars[1].label.find("clear"), std::string::npos) << bars[1].label;
    // Under the threshold it is clear again; flagged it is unsafe, not "confirming".
    centre.score = 0.12;
    frame(gui, s);
    EXPECT_FALSE(gui.view().layout.region_bars[1].confirming);
    centre.score = 0.47;
    centre.flagged = true;
    frame(gui, s);
    EXPECT_FALSE(gui.view().layout.region_bars[1].confirming);
    EXPECT_TRUE(gui.view().layout.region_bars[1].flagged);
}

// Point 6: stale video says so over the picture and no region stays "clear".
TEST_F(CockpitIndicators, StaleVideoShowsAnOverlayAndTurnsEveryRegionUnknown) {
    Gui gui;
    GuiSnapshot s = sim_flying();
    s.video.stale = true;
    s.video.age_ms = 1556;
    s.video.fps = 0;
    frame(gui, s);
    const LayoutReport& l = gui.view().layout;
    EXPECT_EQ(l.video_stale_text, "VIDEO STALE 1.6 s");
    for (const auto& b : l.region_bars) {
        EXPECT_FALSE(b.known) << b.name;
        EXPECT_FALSE(b.flagged) << b.name;
        EXPECT_EQ(b.reason, "video stale");
    }
    EXPECT_NE(std::find(l.status.banners.begin(), l.status.banners.end(), "VIDEO STALE"),
              l.status.banners.end());
    EXPECT_NE(l.status.video.find("STALE 1.6 s"), std::string::npos) << l.status.video;
    // Fresh again: the bars are the classifier's.
    s.video.stale = false;
    s.video.age_ms = 20;
    frame(gui, s);
    EXPECT_TRUE(gui.view().layout.video_stale_text.empty());
    EXPECT_TRUE(gui.view().layout.region_bars[0].known);
}

// Stale navdata: the Telemetry window and the HUD say their values are the last received and how
// old they are, instead of showing them as the drone's state now; none at all says so too.
TEST_F(CockpitIndicators, StaleNavdataIsShownAsTheLastReceivedInTelemetryAndTheHud) {
    Gui gui;
    GuiSnapshot s = sim_flying();
    ASSERT_TRUE(s.telemetry.valid);
    s.telemetry.age_ms = 40;
    s.telemetry.stale = false;
    frame(gui, s);
    ASSERT_TRUE(drawn_window(gui, "Telemetry"));
    EXPECT_TRUE(gui.view().layout.telemetry_note.empty()) << gui.view().layout.telemetry_note;
    EXPECT_TRUE(gui.view().layout.hud_stale_text.empty());
    s.telemetry.age_ms = 3420;
    s.telemetry.stale = true;
    frame(gui, s);
    EXPECT_EQ(gui.view().layout.telemetry_note,
              "STALE 3.4 s: no navdata since; the values below are the last received.");
    // The HUD's horizon, heading, speeds and altitude are dimmed under a label saying so.
    EXPECT_EQ(gui.view().layout.hud_stale_text, "NAVDATA STALE 3.4 s");
    s.telemetry = Telemetry{};
    frame(gui, s);
    EXPECT_EQ(gui.view().layout.telemetry_note, "No navdata received.");
}

// Point 7: the status bar a QGroundControl user recognises.
TEST_F(CockpitIndicators, StatusBarShowsSourceStateBatteryLinkRecAndTheLatestMessage) {
    Gui gui;
    GuiSnapshot s = sim_flying();
    s.link.expected_navdata_hz = 200;
    frame(gui, s);
    const LayoutReport::Status& st = gui.view().layout.status;
    EXPECT_EQ(st.source, "VIRTUAL DRONE");
    EXPECT_EQ(st.state, "FLYING");  // the demo's ctrl_state major 3
    EXPECT_EQ(st.battery, "67 %");
    EXPECT_NE(st.link.find("Hz"), std::string::npos) << st.link;
    EXPECT_NE(st.rec.find("REC 00:42"), std::string::npos) << st.rec;
    EXPECT_NE(st.rec.find("~/flights/2026-11-22_0640"), std::string::npos) << st.rec;
    EXPECT_EQ(st.message, "recording to ~/flights/2026-11-22_0640");
    const std::uint32_t sim_color = st.source_color;

    // Each source its own colour; a replay unmistakable and its state marked as recorded.
    s.connection.source = SourceKind::Replay;
    s.connection.state = LinkState::Replay;
    s.telemetry.nav.ctrl_state = 4u << 16;  // HOVERING in the recording
    frame(gui, s);
    EXPECT_EQ(gui.view().layout.status.source, "REPLAY");
    EXPECT_EQ(gui.view().layout.status.state, "HOVERING (recorded)");
    EXPECT_NE(gui.view().layout.status.source_color, sim_color);
    s.connection.source = SourceKind::Drone;
    s.connection.state = LinkState::Connected;
    frame(gui, s);
    EXPECT_EQ(gui.view().layout.status.source, "LIVE DRONE");
    EXPECT_NE(gui.view().layout.status.source_color, sim_color);

    // A low battery is a banner.
    s.telemetry.nav.battery_pct = 12;
    frame(gui, s);
    const auto& banners = gui.view().layout.status.banners;
    EXPECT_NE(std::find(banners.begin(), banners.end(), "LOW BATTERY 12 % - land now"),
              banners.end());

    // The log is one click away, scrolled to the newest line.
    for (int i = 0; i < 150; ++i)
        s.messages.push_back({"message " + std::to_string(i), LogLevel::Info, 1.0 + i});
    frame(gui, s);
    EXPECT_EQ(gui.view().layout.status.message, "message 149");
    click(gui, s, "status.log");
    EXPECT_TRUE(gui.view().open.messages);
    for (int i = 0; i < 3; ++i) frame(gui, s);
    EXPECT_EQ(gui.view().layout.messages_shown, static_cast<int>(s.messages.size()));
    EXPECT_TRUE(gui.view().layout.messages_at_end);
}

// Point 9: advice that fits the cause.
TEST_F(CockpitIndicators, ACommandedCutOutIsNoMotorFault) {
    GuiSnapshot s;
    make_demo_snapshot(s, 1);
    // EMERGENCY + CUTOUT, as the drone sets them.
    const std::uint32_t cut = gs::test::state_bit(gs::test::DroneStateBit::Emergency) |
                              gs::test::state_bit(gs::test::DroneStateBit::Cutout);
    s.telemetry.nav.drone_state = cut;
    s.telemetry.state = DroneStateBits::from_raw(cut);
    s.telemetry.emergency_commanded = true;
    auto rs = explain_not_flying(s);
    EXPECT_TRUE(has_reason(rs, "Emergency: motors cut by the pilot"));
    EXPECT_FALSE(has_reason(rs, "Motor cut-out")) << "no propeller advice after a commanded cut";
    s.telemetry.emergency_commanded = false;
    rs = explain_not_flying(s);
    EXPECT_TRUE(has_reason(rs, "Emergency: motors cut"));
    EXPECT_TRUE(has_reason(rs, "Motor cut-out"));
}

TEST_F(CockpitIndicators, ControlsThatCannotActAreDisabledWithTheReason) {
    Gui gui;
    // A replay: no drone to take off, land or cut.
    GuiSnapshot replay = sim_flying();
    replay.connection.source = SourceKind::Replay;
    replay.connection.state = LinkState::Replay;
    frame(gui, replay);
    EXPECT_NE(disabled_why(gui, "flight.takeoff").find("replay"), std::string::npos);
    EXPECT_NE(disabled_why(gui, "flight.land").find("replay"), std::string::npos);
    EXPECT_FALSE(click(gui, replay, "flight.takeoff").takeoff);
    InputState t;
    t.pressed.set(GLFW_KEY_T);
    const Actions a = frame(gui, replay, t);
    EXPECT_FALSE(a.takeoff);
    ASSERT_FALSE(a.notes.empty());
    EXPECT_NE(a.notes.back().find("take-off refused: this is a replay"), std::string::npos)
        << a.notes.back();

    // Landed on the virtual drone: land is disabled, take-off and the emergency are not.
    GuiSnapshot landed = sim_flying();
    const std::uint32_t bits = 0x0F800080u;  // landed, threads on, no fault
    landed.telemetry.nav.drone_state = bits;
    landed.telemetry.state = DroneStateBits::from_raw(bits);
    landed.telemetry.nav.ctrl_state = 2u << 16;
    frame(gui, landed);
    EXPECT_NE(disabled_why(gui, "flight.land").find("on the ground"), std::string::npos);
    EXPECT_TRUE(disabled_why(gui, "flight.takeoff").empty());
    EXPECT_TRUE(disabled_why(gui, "flight.emergency").empty());
    EXPECT_EQ(control_state(landed, Control::Calibrate).enabled, false);
    EXPECT_EQ(control_state(landed, Control::FlatTrim).enabled, true);

    // Flying: take-off is disabled; land, the emergency and calibration are not.
    GuiSnapshot flying = sim_flying();
    frame(gui, flying);
    EXPECT_EQ(disabled_why(gui, "flight.takeoff"), "already flying");
    EXPECT_TRUE(disabled_why(gui, "flight.land").empty());
    EXPECT_TRUE(control_state(flying, Control::Calibrate).enabled);
    EXPECT_FALSE(control_state(flying, Control::FlatTrim).enabled);
    // Link lost: the emergency and land still go.
    flying.connection.state = LinkState::Lost;
    EXPECT_TRUE(control_state(flying, Control::Emergency).enabled);
    EXPECT_TRUE(control_state(flying, Control::Land).enabled);
    EXPECT_FALSE(control_state(flying, Control::Takeoff).enabled);
}

}  // namespace
}  // namespace gs::ui::test
