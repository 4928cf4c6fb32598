// The whole window drawn on a bare ImGui context against canned snapshots.
#include "imgui_fixture.hpp"
#include "ui/demo_snapshot.hpp"

#include <GLFW/glfw3.h>

#include <cmath>

namespace gs::ui::test {
namespace {

using GuiHeadless = ImGuiFixture;

TEST_F(GuiHeadless, DrawsDemoNoLinkAndNoVideoSnapshots) {
    Gui gui;
    GuiSnapshot demo;
    for (int f = 0; f < 3; ++f) {
        make_demo_snapshot(demo, f);
        frame(gui, demo);
        EXPECT_GT(last_vertices, 1000);
    }
    for (const GuiSnapshot& s : {demo_no_link(), demo_no_video(), GuiSnapshot{}}) {
        for (int f = 0; f < 2; ++f) {
            const Actions a = frame(gui, s);
            EXPECT_GT(last_vertices, 1000);
            EXPECT_FALSE(a.takeoff || a.land || a.emergency || a.quit);
            EXPECT_FALSE(a.pilot.any());
        }
    }
}

TEST_F(GuiHeadless, RegionBarsFollowTheClassifierFlags) {
    Gui gui;
    GuiSnapshot s;
    make_demo_snapshot(s, 10);  // left flagged
    frame(gui, s);
    const LayoutReport& l = gui.view().layout;
    ASSERT_EQ(l.region_bars.size(), 3u);
    EXPECT_EQ(l.region_bars[0].name, "left");
    EXPECT_TRUE(l.region_bars[0].flagged);
    EXPECT_FALSE(l.region_bars[1].flagged);
    EXPECT_FALSE(l.region_bars[2].flagged);
    // Bars tile the image width in thirds, left to right, at the image top.
    const Rect& img = l.video_image;
    ASSERT_GT(img.w(), 100.0f);
    EXPECT_NEAR(img.w() / img.h(), 640.0f / 360.0f, 0.01f);  // aspect-correct
    for (std::size_t i = 0; i < 3; ++i) {
        const Rect& b = l.region_bars[i].rect;
        EXPECT_NEAR(b.x0, img.x0 + img.w() * static_cast<float>(i) / 3.0f, 1.5f);
        EXPECT_NEAR(b.x1, img.x0 + img.w() * static_cast<float>(i + 1) / 3.0f, 1.5f);
        EXPECT_NEAR(b.y0, img.y0, 1.5f);
    }

    DemoOptions o;
    o.flag_left = false;
    o.flag_right = true;
    make_demo_snapshot(s, 11, o);
    frame(gui, s);
    EXPECT_FALSE(gui.view().layout.region_bars[0].flagged);
    EXPECT_TRUE(gui.view().layout.region_bars[2].flagged);

    gui.view().settings.overlay.regions = false;  // layer toggled off: no bars drawn
    frame(gui, s);
    EXPECT_TRUE(gui.view().layout.region_bars.empty());
}

TEST_F(GuiHeadless, BatteryGaugeShowsTheNavdataValue) {
    Gui gui;
    GuiSnapshot s;
    for (double pct : {67.0, 12.0, 100.0, 0.0}) {
        DemoOptions o;
        o.battery_pct = pct;
        make_demo_snapshot(s, 5, o);
        frame(gui, s);
        const LayoutReport& l = gui.view().layout;
        const float inner = l.battery_outline.w() - 4.0f;
        ASSERT_GT(inner, 10.0f);
        EXPECT_NEAR(l.battery_fill.w() / inner, pct / 100.0, 0.01) << pct;
        char want[16];
        std::snprintf(want, sizeof want, "%.0f%%", pct);
        EXPECT_EQ(l.battery_text, want);
        EXPECT_EQ(l.battery_warning, pct < 20.0) << pct;
        EXPECT_EQ(l.battery_color, pct < 20.0   ? colors::kBad
                                   : pct < 40.0 ? colors::kWarn
                                                : colors::kGood);
    }
    // Unknown battery: no fill, no number, no false "low" alarm.
    make_demo_snapshot(s, 6);
    s.telemetry.nav.battery_pct = kUnknown;
    frame(gui, s);
    EXPECT_EQ(gui.view().layout.battery_text, "---%");
    EXPECT_FLOAT_EQ(gui.view().layout.battery_fill.w(), 0.0f);
    EXPECT_FALSE(gui.view().layout.battery_warning);
}

TEST_F(GuiHeadless, VideoTextureIsRequestedOnlyWhenThereIsAFrame) {
    Gui gui;
    CountingTexture tex;
    frame(gui, demo_no_video(), {}, &tex);
    EXPECT_EQ(tex.calls, 0);
    GuiSnapshot s;
    make_demo_snapshot(s, 3);
    frame(gui, s, {}, &tex);
    EXPECT_EQ(tex.calls, 1);
    EXPECT_EQ(tex.last_index, 3);
}

TEST_F(GuiHeadless, HeldKeyBecomesPilotInputAndFocusLossHovers) {
    Gui gui;
    GuiSnapshot s;
    make_demo_snapshot(s, 1);
    ImGui::GetIO().KeysDown[GLFW_KEY_W] = true;
    Actions a = frame(gui, s);
    EXPECT_FLOAT_EQ(a.pilot.pitch, -gui.view().settings.keymap.keyboard_gain);  // forward
    EXPECT_TRUE(a.manual);
    InputState unfocused;
    unfocused.window_focused = false;
    a = frame(gui, s, unfocused);
    EXPECT_FALSE(a.pilot.any());
    // Focus back with W still reported down (its key-up was lost): still hover.
    a = frame(gui, s);
    EXPECT_FALSE(a.pilot.any());
    ImGui::GetIO().KeysDown[GLFW_KEY_W] = false;
    frame(gui, s);
    ImGui::GetIO().KeysDown[GLFW_KEY_W] = true;
    a = frame(gui, s);
    EXPECT_LT(a.pilot.pitch, 0.0f);
}

TEST_F(GuiHeadless, EmergencyKeyGivesOneEmergencyAction) {
    Gui gui;
    GuiSnapshot s;
    make_demo_snapshot(s, 1);
    ImGui::GetIO().KeysDown[GLFW_KEY_ESCAPE] = true;
    EXPECT_TRUE(frame(gui, s).emergency);
    EXPECT_FALSE(frame(gui, s).emergency);  // held: not repeated
}

TEST_F(GuiHeadless, ClosingWhileFlyingAsksFirst) {
    Gui gui;
    GuiSnapshot flying;
    make_demo_snapshot(flying, 1);
    ASSERT_TRUE(flying.telemetry.state->flying);
    EXPECT_FALSE(gui.request_close(flying));
    const Actions a = frame(gui, flying);
    EXPECT_FALSE(a.quit);
    EXPECT_TRUE(gui.view().quit_dialog_open);
    EXPECT_TRUE(gui.request_close(demo_no_link()));
}

TEST_F(GuiHeadless, RecordKeyTogglesAgainstTheRecordingState) {
    Gui gui;
    GuiSnapshot s;
    make_demo_snapshot(s, 1);  // recording active
    ImGui::GetIO().KeysDown[GLFW_KEY_R] = true;
    Actions a = frame(gui, s);
    EXPECT_TRUE(a.record_stop);
    EXPECT_FALSE(a.record_start);
    ImGui::GetIO().KeysDown[GLFW_KEY_R] = false;
    frame(gui, s);
    s.recording.active = false;
    ImGui::GetIO().KeysDown[GLFW_KEY_R] = true;
    a = frame(gui, s);
    EXPECT_TRUE(a.record_start);
}

}  // namespace
}  // namespace gs::ui::test
