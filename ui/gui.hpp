#pragma once
// Gui: one ground-station frame. Call between ImGui::NewFrame() and ImGui::Render(): it draws
// every window from the snapshot, maps keyboard/gamepad to pilot input, and returns the Actions.
// No GLFW or GL in here, so tests run it on a bare ImGui context.

#include "ui/actions.hpp"
#include "ui/snapshot.hpp"
#include "ui/view_state.hpp"
#include "ui/windows.hpp"

namespace gs::ui {

// Fonts (DejaVu Sans when installed, else ImGui's default) and the dark cockpit style.
// Call once after ImGui::CreateContext(), before the font atlas is built.
void setup_style(float scale = 1.0f);

class Gui {
public:
    explicit Gui(Settings settings = {});

    // Draws one frame. `input` carries window focus and the gamepad; held keys are added from
    // io.KeysDown and text_input_active from io.WantTextInput. `tex` may be null (no video texture:
    // a placeholder is drawn).
    Actions frame(const GuiSnapshot& s, InputState input, TextureSource* tex);

    // The user asked to close the window (title-bar X, Ctrl+Q). Returns true when it may close
    // now; when the drone is flying it opens the "land first?" dialog and returns false.
    bool request_close(const GuiSnapshot& s);

    // True while a drone is in the air that this window commands (or commanded until its link
    // was lost): leaving it (quit, disconnect, replay, another source) asks first.
    static bool commanding_flying_drone(const GuiSnapshot& s);

    ViewState& view() { return view_; }
    const ViewState& view() const { return view_; }

private:
    void draw_menu(const GuiSnapshot& s, Actions& a);
    void read_ui_keys(const InputState& in, Actions& a, const GuiSnapshot& s);
    void handle_escape();
    // Requests in `a` that would stop commanding a flying drone wait behind the question.
    void guard_leaving(const GuiSnapshot& s, Actions& a);
    void draw_leave_dialog(const GuiSnapshot& s, Actions& a);
    void finish_leaving(const GuiSnapshot& s, Actions& a);
    void draw_notices();
    void hold_back_unavailable(const GuiSnapshot& s, Actions& a);
    void calibration_mode(const GuiSnapshot& s, Actions& a);

    ViewState view_;
    bool notices_logged_ = false;
    VideoWindow video_;
    TelemetryWindow telemetry_;
    LinkWindow link_;
    WhyNotFlyingWindow why_;
    PlotsWindow plots_;
    ClassifierWindow classifier_;
    RecordingWindow recording_;
    ReplayWindow replay_;
    ConnectionWindow connection_;
    KeysWindow keys_;
    CalibrationWindow calibration_;
    StatusBar status_;
    MessagesWindow messages_;
    DroneSettingsWindow settings_;
    FlightView flight_;
};

}  // namespace gs::ui
