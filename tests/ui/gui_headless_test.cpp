// The whole window drawn on a bare ImGui context against canned snapshots.
#include "imgui_fixture.hpp"
#include "ui/demo_snapshot.hpp"

#include <GLFW/glfw3.h>

#include <cmath>

namespace gs::ui::test {
namespace {

class GuiHeadless : public ImGuiFixture {};

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
    ImGui::GetIO().KeysDown[GLFW_KEY_F12] = true;
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

TEST_F(GuiHeadless, LandThenQuitSendsLandAndQuitsOnlyOnceLanded) {
    Gui gui;
    GuiSnapshot flying;
    make_demo_snapshot(flying, 1);
    ASSERT_TRUE(flying.telemetry.state->flying);
    ASSERT_EQ(flying.connection.state, LinkState::Connected);
    EXPECT_FALSE(gui.request_close(flying));
    for (int i = 0; i < 3; ++i) EXPECT_FALSE(frame(gui, flying).quit);  // the dialog settles
    ASSERT_TRUE(gui.view().quit_dialog_open);
    const Actions a = click(gui, flying, "quit.land");
    EXPECT_TRUE(a.land);
    EXPECT_FALSE(a.quit);
    EXPECT_TRUE(gui.view().quit_after_landing);
    // Still flying: the window stays, the dialog is gone, no second land.
    for (int i = 0; i < 5; ++i) {
        const Actions b = frame(gui, flying);
        EXPECT_FALSE(b.quit);
        EXPECT_FALSE(b.land);
        EXPECT_FALSE(gui.view().quit_dialog_open);
    }
    // Navdata says landed: now it closes.
    GuiSnapshot landed = flying;
    landed.telemetry.state->flying = false;
    EXPECT_TRUE(frame(gui, landed).quit);
}

TEST_F(GuiHeadless, CancelInTheQuitDialogKeepsFlyingAndTheWindowOpen) {
    Gui gui;
    GuiSnapshot flying;
    make_demo_snapshot(flying, 1);
    EXPECT_FALSE(gui.request_close(flying));
    for (int i = 0; i < 3; ++i) frame(gui, flying);
    const Actions a = click(gui, flying, "quit.cancel");
    EXPECT_FALSE(a.land);
    EXPECT_FALSE(a.quit);
    EXPECT_FALSE(gui.view().quit_after_landing);
    EXPECT_FALSE(frame(gui, flying).quit);
    EXPECT_FALSE(gui.view().quit_dialog_open);
    GuiSnapshot landed = flying;
    landed.telemetry.state->flying = false;
    EXPECT_FALSE(frame(gui, landed).quit) << "cancelled: landing later does not close";
}

TEST_F(GuiHeadless, CalibrationWindowStartsTheModeCapturesOnKAndStopsWhenClosed) {
    Gui gui;
    GuiSnapshot s;
    make_demo_snapshot(s, 2);
    ImGui::GetIO().KeysDown[GLFW_KEY_K] = true;
    EXPECT_FALSE(frame(gui, s).calibration_capture) << "K does nothing while the window is closed";
    ImGui::GetIO().KeysDown[GLFW_KEY_K] = false;
    gui.view().open.calibration = true;
    Actions a = frame(gui, s);
    ASSERT_TRUE(a.calibration_start);
    EXPECT_EQ(a.calibration_start->cols, 9);
    EXPECT_EQ(a.calibration_start->rows, 6);
    EXPECT_DOUBLE_EQ(a.calibration_start->square_m, 0.05);
    EXPECT_FALSE(frame(gui, s).calibration_start) << "asked once, not every frame";
    // The mode runs: the board over the video, the status, the coverage map.
    s.calibration.active = true;
    s.calibration.frame = s.video.index;
    s.calibration.board_found = s.calibration.adds_coverage = true;
    s.calibration.status = "board found: +12 cells, capture it";
    for (int r = 0; r < 6; ++r)
        for (int c = 0; c < 9; ++c)
            s.calibration.corners.push_back(
                {200.0f + 25.0f * static_cast<float>(c), 100.0f + 25.0f * static_cast<float>(r)});
    s.calibration.grid_cols = 16;
    s.calibration.grid_rows = 9;
    s.calibration.coverage.assign(16 * 9, 0);
    s.calibration.coverage[20] = 2;
    s.calibration.image_w = 640;
    s.calibration.image_h = 360;
    s.calibration.views = 4;
    s.calibration.rms_px = 0.21;
    a = frame(gui, s);
    EXPECT_FALSE(a.calibration_start);
    const LayoutReport& l = gui.view().layout;
    EXPECT_TRUE(l.calibration.drawn);
    EXPECT_EQ(l.calibration.corners_drawn, 54);
    EXPECT_GT(l.calibration.coverage_map.w(), 100.0f);
    EXPECT_NEAR(l.calibration.coverage_map.w() / l.calibration.coverage_map.h(), 640.0 / 360.0,
                0.02);
    EXPECT_EQ(l.calibration.views, 4);
    ASSERT_NE(l.button("calibration.capture"), nullptr);
    ASSERT_NE(l.button("calibration.save"), nullptr);
    // K captures (one edge per press).
    ImGui::GetIO().KeysDown[GLFW_KEY_K] = true;
    EXPECT_TRUE(frame(gui, s).calibration_capture);
    EXPECT_FALSE(frame(gui, s).calibration_capture);
    ImGui::GetIO().KeysDown[GLFW_KEY_K] = false;
    frame(gui, s);
    // The capture and save buttons.
    EXPECT_TRUE(click(gui, s, "calibration.capture").calibration_capture);
    EXPECT_TRUE(click(gui, s, "calibration.save").calibration_save);
    // Closing the window stops the mode (once).
    gui.view().open.calibration = false;
    EXPECT_TRUE(frame(gui, s).calibration_stop);
    EXPECT_FALSE(frame(gui, s).calibration_stop);
    // The undistortion toggle is a level the adapter reads every frame.
    gui.view().settings.overlay.undistort = true;
    EXPECT_TRUE(frame(gui, s).undistort_preview);
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
