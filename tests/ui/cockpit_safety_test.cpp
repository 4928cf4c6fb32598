// The cockpit's safety rules on a bare ImGui context (issue 13, points 1, 2 and 4):
//  - Escape closes menus and dialogs and never touches the drone; the emergency key works with a
//    menu open and while a text field has the keyboard; a saved keymap that bound Escape is
//    migrated and the user is told;
//  - every action that would stop commanding a flying drone asks first ("Land, then ..." /
//    "Cancel");
//  - a key pressed and released inside one frame is acted on exactly once.
#include "imgui_fixture.hpp"
#include "ui/demo_snapshot.hpp"
#include "ui/key_latch.hpp"

#include <GLFW/glfw3.h>

#include <cstdio>

namespace gs::ui::test {
namespace {

class CockpitSafety : public ImGuiFixture {
protected:
    // Hover, press, release at the centre of a reported rectangle; the release frame's actions
    // (with the flight commands of the press frame: those act on the press through a menu).
    Actions click(Gui& gui, const GuiSnapshot& s, const char* button) {
        Actions press;
        Actions a = ImGuiFixture::click(gui, s, button, &press);
        EXPECT_FALSE((press.emergency && a.emergency) || (press.land && a.land))
            << button << ": acted on both press and release";
        a.emergency = a.emergency || press.emergency;
        a.land = a.land || press.land;
        return a;
    }
    // One frame in which `key` was pressed and released (a latched tap).
    Actions tap(Gui& gui, const GuiSnapshot& s, int key) {
        InputState in;
        in.pressed.set(static_cast<std::size_t>(key));
        return frame(gui, s, in);
    }
    static bool touches_drone(const Actions& a) {
        return a.emergency || a.land || a.takeoff || a.flat_trim || a.switch_camera ||
               a.disconnect || a.connect || a.replay_open || a.quit || a.pilot.any();
    }
    static GuiSnapshot flying() {
        GuiSnapshot s;
        make_demo_snapshot(s, 1);
        return s;
    }
};

TEST_F(CockpitSafety, EscapeIsNoPilotKeyTheEmergencyKeyIsF12) {
    const Keymap km = Keymap::defaults();
    EXPECT_EQ(km.key(PilotKey::Emergency), GLFW_KEY_F12);
    for (std::size_t i = 0; i < kPilotKeyCount; ++i)
        EXPECT_NE(km.key(static_cast<PilotKey>(i)), GLFW_KEY_ESCAPE)
            << description(static_cast<PilotKey>(i));
    PilotMapper m;
    InputState esc;
    esc.keys.set(GLFW_KEY_ESCAPE);
    esc.pressed.set(GLFW_KEY_ESCAPE);
    const PilotFrame f = m.update(esc, km);
    EXPECT_FALSE(f.emergency || f.land || f.takeoff || f.manual);
}

TEST_F(CockpitSafety, EscapeClosesTheViewMenuAndNothingElse) {
    Gui gui;
    const GuiSnapshot s = flying();
    frame(gui, s);
    EXPECT_EQ(gui.view().layout.popups_open, 0);
    click(gui, s, "menu.view");
    ASSERT_EQ(gui.view().layout.popups_open, 1) << "the View menu did not open";
    const Actions a = tap(gui, s, GLFW_KEY_ESCAPE);
    EXPECT_FALSE(touches_drone(a));
    EXPECT_EQ(gui.view().layout.popups_open, 0) << "Escape left the menu open";
    EXPECT_FALSE(touches_drone(frame(gui, s)));
}

TEST_F(CockpitSafety, EscapeCancelsTheDroneIsFlyingDialog) {
    Gui gui;
    const GuiSnapshot s = flying();
    ASSERT_FALSE(gui.request_close(s));
    for (int i = 0; i < 3; ++i) frame(gui, s);
    ASSERT_TRUE(gui.view().quit_dialog_open);
    const Actions a = tap(gui, s, GLFW_KEY_ESCAPE);
    EXPECT_FALSE(touches_drone(a));
    for (int i = 0; i < 3; ++i) EXPECT_FALSE(touches_drone(frame(gui, s)));
    EXPECT_FALSE(gui.view().quit_dialog_open);
    EXPECT_FALSE(gui.view().leave_asked.pending());
    EXPECT_FALSE(gui.view().quit_after_landing);
}

TEST_F(CockpitSafety, EmergencyKeyWorksWithAMenuOpen) {
    Gui gui;
    const GuiSnapshot s = flying();
    frame(gui, s);
    click(gui, s, "menu.view");
    ASSERT_EQ(gui.view().layout.popups_open, 1);
    EXPECT_TRUE(tap(gui, s, GLFW_KEY_F12).emergency);
}

TEST_F(CockpitSafety, EmergencyKeyWorksWhileATextFieldIsFocusedOtherKeysType) {
    Gui gui;
    const GuiSnapshot s = flying();
    frame(gui, s);
    click(gui, s, "replay.path");
    frame(gui, s);
    ASSERT_TRUE(ImGui::GetIO().WantTextInput) << "the replay path field did not take the keys";
    const Actions t = tap(gui, s, GLFW_KEY_T);
    EXPECT_FALSE(t.takeoff) << "typing 't' into a path took off";
    EXPECT_TRUE(tap(gui, s, GLFW_KEY_F12).emergency);
}

TEST_F(CockpitSafety, SavedKeymapBindingEscapeToEmergencyIsMigratedAndTheUserTold) {
    auto loaded = settings_from_json(
        R"({"keymap": {"keys": {"emergency": "Escape", "land": "Escape", "record": "F12"}}})");
    ASSERT_TRUE(loaded);
    EXPECT_EQ(loaded->keymap.key(PilotKey::Emergency), GLFW_KEY_F12);
    EXPECT_EQ(loaded->keymap.key(PilotKey::Land), GLFW_KEY_L);
    EXPECT_EQ(loaded->keymap.key(PilotKey::Record), kNoKey) << "F12 would record and cut";
    ASSERT_EQ(loaded->notices.size(), 3u);
    // A typing key is no emergency key either (it would fire while typing a path).
    auto space = settings_from_json(R"({"keymap": {"keys": {"emergency": "Space"}}})");
    ASSERT_TRUE(space);
    EXPECT_EQ(space->keymap.key(PilotKey::Emergency), GLFW_KEY_F12);
    EXPECT_EQ(space->notices.size(), 1u);
    auto fine = settings_from_json(R"({"keymap": {"keys": {"emergency": "Pause"}}})");
    ASSERT_TRUE(fine);
    EXPECT_EQ(fine->keymap.key(PilotKey::Emergency), GLFW_KEY_PAUSE);
    EXPECT_TRUE(fine->notices.empty());
    // An unbound action survives a round trip.
    auto back = settings_from_json(settings_to_json(*loaded));
    ASSERT_TRUE(back);
    EXPECT_EQ(back->keymap.key(PilotKey::Record), kNoKey);
    EXPECT_TRUE(back->notices.empty());

    // The window tells the user (a notice window and the message log) and saves the change.
    Gui gui(*loaded);
    EXPECT_TRUE(gui.view().settings_dirty);
    const GuiSnapshot s = flying();
    const Actions a = frame(gui, s);
    EXPECT_EQ(a.notes.size(), 3u);
    bool shown = false;
    for (const auto& [name, r] : gui.view().layout.windows) shown |= name == "Settings changed";
    EXPECT_TRUE(shown);
    frame(gui, s);
    click(gui, s, "notice.ok");
    EXPECT_TRUE(gui.view().notices.empty());
    EXPECT_TRUE(frame(gui, s).notes.empty());
}

TEST_F(CockpitSafety, APressAndReleaseInsideOneFrameActsExactlyOnce) {
    Gui gui;
    GuiSnapshot s;
    make_demo_snapshot(s, 1);
    KeyLatch latch;
    auto latched_frame = [&] {
        InputState in;
        latch.take(in);
        return frame(gui, s, in);
    };
    for (int key : {GLFW_KEY_T, GLFW_KEY_C, GLFW_KEY_F12, GLFW_KEY_L}) {
        latch.on_key(key, KeyLatch::Event::Press);
        latch.on_key(key, KeyLatch::Event::Release);
        const Actions a = latched_frame();
        EXPECT_EQ(a.takeoff, key == GLFW_KEY_T) << key_name(key);
        EXPECT_EQ(a.switch_camera, key == GLFW_KEY_C) << key_name(key);
        EXPECT_EQ(a.emergency, key == GLFW_KEY_F12) << key_name(key);
        EXPECT_EQ(a.land, key == GLFW_KEY_L) << key_name(key);
        const Actions b = latched_frame();
        EXPECT_FALSE(b.takeoff || b.switch_camera || b.emergency || b.land) << "acted twice";
    }
    // A press held across frames (auto-repeat events included) is still one press.
    latch.on_key(GLFW_KEY_T, KeyLatch::Event::Press);
    EXPECT_TRUE(latched_frame().takeoff);
    latch.on_key(GLFW_KEY_T, KeyLatch::Event::Repeat);
    EXPECT_FALSE(latched_frame().takeoff);
    latch.on_key(GLFW_KEY_T, KeyLatch::Event::Release);
    EXPECT_FALSE(latched_frame().takeoff);
    // A movement tap inside one frame moves for that frame, then hovers.
    latch.on_key(GLFW_KEY_W, KeyLatch::Event::Press);
    latch.on_key(GLFW_KEY_W, KeyLatch::Event::Release);
    EXPECT_LT(latched_frame().pilot.pitch, 0.0f);
    EXPECT_FALSE(latched_frame().pilot.any());
    // F1 tapped inside one frame opens the key help.
    latch.on_key(GLFW_KEY_F1, KeyLatch::Event::Press);
    latch.on_key(GLFW_KEY_F1, KeyLatch::Event::Release);
    latched_frame();
    EXPECT_TRUE(gui.view().open.keys);
    EXPECT_EQ(latch.presses(), 7u);
}

// Ctrl+Q as a fast typist (or xdotool) sends it: Ctrl down, Q down, Q up, Ctrl up, all inside one
// frame. By the frame Ctrl is no longer held, yet the chord asks to quit (the drone is flying).
TEST_F(CockpitSafety, ACtrlQChordInsideOneFrameAsksToQuit) {
    Gui gui;
    const GuiSnapshot s = flying();
    KeyLatch latch;
    auto latched_frame = [&] {
        InputState in;
        latch.take(in);
        return frame(gui, s, in);
    };
    // Q alone is no quit.
    latch.on_key(GLFW_KEY_Q, KeyLatch::Event::Press);
    latch.on_key(GLFW_KEY_Q, KeyLatch::Event::Release);
    latched_frame();
    latched_frame();
    EXPECT_FALSE(gui.view().quit_dialog_open);
    latch.on_key(GLFW_KEY_LEFT_CONTROL, KeyLatch::Event::Press);
    latch.on_key(GLFW_KEY_Q, KeyLatch::Event::Press);
    latch.on_key(GLFW_KEY_Q, KeyLatch::Event::Release);
    latch.on_key(GLFW_KEY_LEFT_CONTROL, KeyLatch::Event::Release);
    const Actions a = latched_frame();
    EXPECT_FALSE(a.quit);  // flying: it asks first
    for (int i = 0; i < 2; ++i) EXPECT_FALSE(touches_drone(latched_frame()));
    EXPECT_TRUE(gui.view().quit_dialog_open);
}

// Point 2: every way of leaving a flying drone asks, and "Land, then ..." does it once landed.
TEST_F(CockpitSafety, DisconnectWhileFlyingAsksLandThenDisconnect) {
    Gui gui;
    const GuiSnapshot s = flying();
    frame(gui, s);
    const Actions a = click(gui, s, "connection.disconnect");
    EXPECT_FALSE(a.disconnect) << "disconnected a flying drone without asking";
    for (int i = 0; i < 2; ++i) frame(gui, s);
    ASSERT_TRUE(gui.view().quit_dialog_open);
    EXPECT_EQ(gui.view().leave_asked.kind, LeaveKind::Disconnect);
    const Actions land = click(gui, s, "leave.land");
    EXPECT_TRUE(land.land);
    EXPECT_FALSE(land.disconnect);
    for (int i = 0; i < 3; ++i) EXPECT_FALSE(frame(gui, s).disconnect) << "still flying";
    GuiSnapshot landed = s;
    landed.telemetry.state->flying = false;
    EXPECT_TRUE(frame(gui, landed).disconnect);
    EXPECT_FALSE(frame(gui, landed).disconnect) << "disconnect requested twice";
}

TEST_F(CockpitSafety, OpeningAReplayWhileFlyingAsksAndCancelKeepsTheLink) {
    Gui gui;
    std::snprintf(gui.view().replay_path.data(), gui.view().replay_path.size(), "%s",
                  "/data/flight_1");
    const GuiSnapshot s = flying();
    frame(gui, s);
    const Actions a = click(gui, s, "replay.open");  // the path field holds a dataset path
    EXPECT_FALSE(a.replay_open.has_value()) << "opened a replay over a flying drone";
    for (int i = 0; i < 2; ++i) frame(gui, s);
    ASSERT_EQ(gui.view().leave_asked.kind, LeaveKind::OpenReplay);
    const Actions c = click(gui, s, "leave.cancel");
    EXPECT_FALSE(c.replay_open || c.land || c.disconnect);
    for (int i = 0; i < 3; ++i) {
        const Actions b = frame(gui, s);
        EXPECT_FALSE(b.replay_open || b.land);
    }
    EXPECT_FALSE(gui.view().quit_dialog_open);
    GuiSnapshot landed = s;
    landed.telemetry.state->flying = false;
    EXPECT_FALSE(frame(gui, landed).replay_open.has_value()) << "a cancelled request came back";
}

TEST_F(CockpitSafety, SwitchingScenarioWhileFlyingAsksLandedDoesNotLinkLostOffersNow) {
    Gui gui;
    GuiSnapshot s = flying();
    s.connection.source = SourceKind::Sim;
    s.connection.scenario = "warehouse";
    s.connection.scenarios = {"warehouse", "thesis_pillar_left"};
    gui.view().settings.use_sim = true;
    gui.view().settings.sim_scenario = "warehouse";
    auto pick = [&](const GuiSnapshot& snap) {
        frame(gui, snap);
        click(gui, snap, "connection.scenario");
        frame(gui, snap);  // a popup settles its place over its first frames
        frame(gui, snap);
        return click(gui, snap, "scenario.thesis_pillar_left");
    };
    Actions a = pick(s);
    EXPECT_FALSE(a.connect.has_value()) << "switched scenario under a flying drone";
    EXPECT_EQ(gui.view().settings.sim_scenario, "thesis_pillar_left") << "the pick did not land";
    frame(gui, s);
    ASSERT_EQ(gui.view().leave_asked.kind, LeaveKind::Connect);
    EXPECT_EQ(gui.view().leave_asked.connect.scenario, "thesis_pillar_left");
    click(gui, s, "leave.cancel");

    // Landed: no question.
    GuiSnapshot landed = s;
    landed.telemetry.state->flying = false;
    gui.view().settings.sim_scenario = "warehouse";
    a = pick(landed);
    ASSERT_TRUE(a.connect.has_value());
    EXPECT_EQ(a.connect->scenario, "thesis_pillar_left");

    // Flying with the link lost: asked too, and "now" is offered (it cannot be told to land).
    GuiSnapshot lost = s;
    lost.connection.state = LinkState::Lost;
    frame(gui, lost);
    a = click(gui, lost, "connection.disconnect");
    EXPECT_FALSE(a.disconnect);
    frame(gui, lost);
    ASSERT_NE(gui.view().layout.button("leave.now"), nullptr);
    EXPECT_TRUE(click(gui, lost, "leave.now").disconnect);
}

// The status bar's buttons stay clickable whatever is open: a menu, the flying question.
TEST_F(CockpitSafety, EmergencyButtonWorksWithAMenuOrTheQuestionOpen) {
    Gui gui;
    const GuiSnapshot s = flying();
    frame(gui, s);
    click(gui, s, "menu.view");
    ASSERT_EQ(gui.view().layout.popups_open, 1);
    EXPECT_TRUE(click(gui, s, "flight.emergency").emergency);
    ASSERT_FALSE(gui.request_close(s));
    for (int i = 0; i < 3; ++i) frame(gui, s);
    ASSERT_TRUE(gui.view().quit_dialog_open);
    EXPECT_TRUE(click(gui, s, "flight.emergency").emergency);
    EXPECT_TRUE(click(gui, s, "flight.land").land);
    EXPECT_TRUE(gui.view().quit_dialog_open) << "the question stays until answered";
}

TEST_F(CockpitSafety, TakingOffAgainCancelsWhatWaitedForTheLanding) {
    Gui gui;
    const GuiSnapshot s = flying();
    ASSERT_FALSE(gui.request_close(s));
    for (int i = 0; i < 3; ++i) frame(gui, s);
    EXPECT_TRUE(click(gui, s, "quit.land").land);
    EXPECT_TRUE(gui.view().quit_after_landing);
    const Actions t = tap(gui, s, GLFW_KEY_T);
    EXPECT_TRUE(t.takeoff);
    EXPECT_FALSE(gui.view().leave_after_landing.pending());
    GuiSnapshot landed = s;
    landed.telemetry.state->flying = false;
    EXPECT_FALSE(frame(gui, landed).quit);
}

}  // namespace
}  // namespace gs::ui::test
