#include "ui/gui.hpp"

#include "ui/controls.hpp"

#include <GLFW/glfw3.h>
#include <imgui_internal.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

namespace gs::ui {

namespace colors {
ImVec4 v4(std::uint32_t c) {
    return ImGui::ColorConvertU32ToFloat4(c);
}
}  // namespace colors

void setup_style(float scale) {
    ImGuiIO& io = ImGui::GetIO();
    const char* font = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
    std::error_code ec;
    if (std::filesystem::exists(font, ec))
        io.Fonts->AddFontFromFileTTF(font, 15.0f * scale);
    else
        io.Fonts->AddFontDefault();

    ImGui::StyleColorsDark();
    ImGuiStyle& st = ImGui::GetStyle();
    st.WindowRounding = 0.0f;  // tiled windows read as one docked cockpit
    st.WindowBorderSize = 1.0f;
    st.FrameRounding = 3.0f;
    st.GrabRounding = 3.0f;
    st.TabRounding = 3.0f;
    st.WindowPadding = {8, 6};
    st.FramePadding = {6, 3};
    st.ItemSpacing = {8, 4};
    st.ScrollbarSize = 12.0f;
    ImVec4* c = st.Colors;
    c[ImGuiCol_WindowBg] = ImVec4(0.075f, 0.082f, 0.094f, 1.0f);
    c[ImGuiCol_ChildBg] = ImVec4(0.06f, 0.065f, 0.075f, 1.0f);
    c[ImGuiCol_TitleBg] = ImVec4(0.10f, 0.11f, 0.13f, 1.0f);
    c[ImGuiCol_TitleBgActive] = ImVec4(0.14f, 0.17f, 0.22f, 1.0f);
    c[ImGuiCol_MenuBarBg] = ImVec4(0.10f, 0.11f, 0.13f, 1.0f);
    c[ImGuiCol_Border] = ImVec4(0.22f, 0.24f, 0.28f, 1.0f);
    c[ImGuiCol_FrameBg] = ImVec4(0.14f, 0.15f, 0.18f, 1.0f);
    c[ImGuiCol_Header] = ImVec4(0.18f, 0.24f, 0.32f, 1.0f);
    c[ImGuiCol_TableHeaderBg] = ImVec4(0.13f, 0.15f, 0.18f, 1.0f);
    if (scale != 1.0f) st.ScaleAllSizes(scale);
}

Gui::Gui(Settings settings) {
    view_.settings = std::move(settings);
    auto copy = [](auto& dst, const std::string& src) {
        std::memset(dst.data(), 0, dst.size());
        std::memcpy(dst.data(), src.data(), std::min(src.size(), dst.size() - 1));
    };
    copy(view_.drone_address, view_.settings.drone_address);
    if (!view_.settings.recent_datasets.empty())
        copy(view_.replay_path, view_.settings.recent_datasets.front());
    // What loading the settings changed (a keymap that bound Escape ...): told once, and saved
    // so that it is not told again.
    view_.notices = std::move(view_.settings.notices);
    view_.settings.notices.clear();
    if (!view_.notices.empty()) view_.settings_dirty = true;
}

// Keys the window itself answers (not the pilot's): Escape, F1, Ctrl+Q. Edges come from the
// latched presses, so a tap between two frames counts too.
void Gui::read_ui_keys(const InputState& in, Actions& a, const GuiSnapshot& s) {
    const ImGuiIO& io = ImGui::GetIO();
    const std::bitset<512> presses = in.pressed | (in.keys & ~view_.ui_prev_keys);
    view_.ui_prev_keys = in.keys;
    if (!in.window_focused) return;
    auto pressed = [&](int k) { return presses.test(static_cast<std::size_t>(k)); };
    // Escape while typing belongs to the text field (it cancels the edit).
    if (pressed(GLFW_KEY_ESCAPE) && !io.WantTextInput) handle_escape();
    if (io.WantTextInput) return;
    if (pressed(kHelpKey)) view_.open.keys = !view_.open.keys;
    if (pressed(kLayoutKey)) {
        view_.settings.layout = view_.settings.layout == LayoutMode::Flight
                                    ? LayoutMode::Engineering
                                    : LayoutMode::Flight;
        view_.settings_dirty = true;
    }
    const bool ctrl =
        in.keys.test(GLFW_KEY_LEFT_CONTROL) || in.keys.test(GLFW_KEY_RIGHT_CONTROL) || io.KeyCtrl;
    if (((ctrl && pressed(GLFW_KEY_Q)) || in.pressed_with_ctrl.test(GLFW_KEY_Q)) &&
        request_close(s))
        a.quit = true;
}

// Escape closes what is open, one level per press, and never touches the drone: an open menu,
// combo or dialog first (a dialog's question is cancelled), else the focused helper window.
void Gui::handle_escape() {
    ImGuiContext& g = *GImGui;
    if (g.OpenPopupStack.Size > 0) {
        ImGui::ClosePopupToLevel(0, true);
        return;
    }
    if (view_.leave_asked.pending()) {  // "The drone is flying": Escape is Cancel
        view_.leave_asked = {};
        return;
    }
    const ImGuiWindow* focused = g.NavWindow ? g.NavWindow->RootWindow : nullptr;
    const std::string name = focused ? focused->Name : "";
    if (name == "Keys" && view_.open.keys) {
        view_.open.keys = false;
    } else if (name == "Drone settings" && view_.open.drone_settings) {
        view_.open.drone_settings = false;
    } else if (name == "Messages" && view_.open.messages) {
        view_.open.messages = false;
    } else if (!view_.notices.empty()) {
        view_.notices.clear();
    } else if (view_.open.keys) {
        view_.open.keys = false;
    }
}

// A key for a control that cannot act now is not sent; the log says why. Land and the emergency
// always go (control_state never holds them back while a link exists).
void Gui::hold_back_unavailable(const GuiSnapshot& s, Actions& a) {
    auto hold = [&](bool& flag, Control c) {
        if (!flag) return;
        const ControlState cs = control_state(s, c);
        if (cs.enabled) return;
        flag = false;
        a.notes.push_back(std::string(to_string(c)) + " refused: " + cs.why);
    };
    hold(a.takeoff, Control::Takeoff);
    hold(a.flat_trim, Control::FlatTrim);
    hold(a.switch_camera, Control::SwitchCamera);
    hold(a.record_start, Control::Record);
}

// Told once, until acknowledged (OK or Escape); not modal: the flight controls stay usable.
void Gui::draw_notices() {
    if (view_.notices.empty()) return;
    const ImVec2 d = ImGui::GetIO().DisplaySize;
    ImGui::SetNextWindowPos({d.x * 0.5f, d.y * 0.3f}, ImGuiCond_Appearing, {0.5f, 0.0f});
    bool open = true;
    if (ImGui::Begin("Settings changed", &open,
                     ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse)) {
        const ImVec2 wp = ImGui::GetWindowPos(), ws = ImGui::GetWindowSize();
        view_.layout.windows.push_back(
            {"Settings changed", {wp.x, wp.y, wp.x + ws.x, wp.y + ws.y}});
        ImGui::TextColored(colors::v4(colors::kWarn),
                           "Your saved settings were changed to keep the drone safe:");
        for (const auto& n : view_.notices) ImGui::BulletText("%s", n.c_str());
        ImGui::TextColored(colors::v4(colors::kDim),
                           "Emergency: %s. Escape closes menus and "
                           "dialogs and does nothing to the drone.",
                           key_name(view_.settings.keymap.key(PilotKey::Emergency)).c_str());
        if (ImGui::Button("OK")) open = false;
        record_button(view_, "notice.ok");
    }
    ImGui::End();
    if (!open) view_.notices.clear();
}

void Gui::draw_menu(const GuiSnapshot& s, Actions& a) {
    if (!ImGui::BeginMainMenuBar()) return;
    if (ImGui::BeginMenu("File")) {
        const bool live = s.connection.state != LinkState::Disconnected &&
                          s.connection.state != LinkState::Replay;
        if (ImGui::MenuItem("Open replay", nullptr, false, view_.replay_path[0] != 0))
            a.replay_open = std::string(view_.replay_path.data());
        if (ImGui::BeginMenu("Recent datasets", !view_.settings.recent_datasets.empty())) {
            for (const auto& p : view_.settings.recent_datasets)
                if (ImGui::MenuItem(p.c_str())) a.replay_open = p;
            ImGui::EndMenu();
        }
        ImGui::Separator();
        if (ImGui::MenuItem("Disconnect", nullptr, false,
                            live || s.connection.state == LinkState::Replay))
            a.disconnect = true;
        ImGui::Separator();
        if (ImGui::MenuItem("Quit", "Ctrl+Q")) {
            if (request_close(s)) a.quit = true;
        }
        ImGui::EndMenu();
    }
    const bool view_open = ImGui::BeginMenu("View");
    if (!view_open) record_button(view_, "menu.view");  // the header (tests click it)
    if (view_open) {
        OpenWindows& o = view_.open;
        ImGui::MenuItem("Video", nullptr, &o.video);
        ImGui::MenuItem("Plots", nullptr, &o.plots);
        ImGui::MenuItem("Connection", nullptr, &o.connection);
        ImGui::MenuItem("Why not flying", nullptr, &o.why_not_flying);
        ImGui::MenuItem("Recording", nullptr, &o.recording);
        ImGui::MenuItem("Replay", nullptr, &o.replay);
        ImGui::MenuItem("Classifier", nullptr, &o.classifier);
        ImGui::MenuItem("Telemetry", nullptr, &o.telemetry);
        ImGui::MenuItem("Link", nullptr, &o.link);
        ImGui::MenuItem("Calibration", nullptr, &o.calibration);
        ImGui::MenuItem("Messages", nullptr, &o.messages);
        ImGui::Separator();
        const bool flight = view_.settings.layout == LayoutMode::Flight;
        const std::string lk = key_name(kLayoutKey);
        if (ImGui::MenuItem("Flight layout", lk.c_str(), flight) && !flight) {
            view_.settings.layout = LayoutMode::Flight;
            view_.settings_dirty = true;
        }
        if (ImGui::MenuItem("Engineering layout", lk.c_str(), !flight) && flight) {
            view_.settings.layout = LayoutMode::Engineering;
            view_.settings_dirty = true;
        }
        const bool reset = ImGui::MenuItem("Reset layout");
        record_button(view_, "menu.reset_layout");
        if (reset) {
            // Every window back to its default place and size, the default ones open again.
            view_.reset_layout_frames = 2;
            const OpenWindows keep = view_.open;
            view_.open = OpenWindows{};
            view_.open.calibration = keep.calibration;
            view_.open.drone_settings = keep.drone_settings;
        }
        ImGui::Separator();
        OverlayToggles& t = view_.settings.overlay;
        bool changed = false;
        changed |= ImGui::MenuItem("Overlay: region bar", nullptr, &t.regions);
        changed |= ImGui::MenuItem("Overlay: trajectories", nullptr, &t.trajectories);
        changed |= ImGui::MenuItem("Overlay: centre band points", nullptr, &t.center_points);
        changed |= ImGui::MenuItem("Overlay: region boundaries", nullptr, &t.boundaries);
        changed |= ImGui::MenuItem("HUD", nullptr, &t.hud);
        changed |= ImGui::MenuItem("Undistorted video", nullptr, &t.undistort);
        if (changed) view_.settings_dirty = true;
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("Drone")) {
        ImGui::MenuItem("Settings", nullptr, &view_.open.drone_settings);
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("Help")) {
        ImGui::MenuItem("Keys and gamepad", "F1", &view_.open.keys);
        ImGui::EndMenu();
    }
    ImGui::EndMainMenuBar();
}

// The calibration mode runs while its window is open: started (with the board typed in the
// window) when it opens, stopped when it closes. K captures only while it is open.
void Gui::calibration_mode(const GuiSnapshot& s, Actions& a) {
    CalibrationUiState& u = view_.calib;
    if (view_.open.calibration) {
        u.stop_sent = false;
        if (s.calibration.active) {
            u.start_sent = false;
        } else if (!u.start_sent) {
            a.calibration_start = Actions::CalibrationBoard{
                u.cols, u.rows, static_cast<double>(u.square_mm) / 1000.0};
            if (u.auto_capture) a.calibration_auto = true;
            u.start_sent = true;
        }
    } else {
        u.start_sent = false;
        if (!s.calibration.active) {
            u.stop_sent = false;
        } else if (!u.stop_sent) {
            a.calibration_stop = true;
            u.stop_sent = true;
        }
    }
}

Actions Gui::frame(const GuiSnapshot& s, InputState input, TextureSource* tex) {
    Actions a;
    ImGuiIO& io = ImGui::GetIO();
    view_.layout = LayoutReport{};
    view_.layout.clock_s = static_cast<double>(s.now_ns) * 1e-9;
    view_.layout.video_index = s.video.bgr.empty() ? -1 : s.video.index;
    view_.layout.layout_mode = to_string(view_.settings.layout);
    if (s.telemetry.valid) view_.history.add(s.telemetry.nav);
    if (!view_.notices.empty() && !notices_logged_) {
        for (const auto& n : view_.notices) a.notes.push_back("settings changed: " + n);
        notices_logged_ = true;
    }

    // Keyboard/gamepad -> pilot input. A focused text field keeps the keys (typing "w" into a
    // path must not fly the drone); the emergency key passes regardless (it types nothing).
    input.text_input_active = io.WantTextInput;
    for (std::size_t k = 0; k < input.keys.size(); ++k)
        if (io.KeysDown[k]) input.keys.set(k);
    read_ui_keys(input, a, s);
    const PilotFrame pf = view_.pilot.update(input, view_.settings.keymap);
    view_.last_pilot = pf;
    a.pilot = pf.pilot;
    a.manual = pf.manual;
    a.takeoff = pf.takeoff;
    a.land = pf.land;
    a.emergency = pf.emergency;
    a.flat_trim = pf.flat_trim;
    a.switch_camera = pf.switch_camera;
    a.assist_toggle = pf.assist_toggle;
    a.assist_override = pf.assist_override;
    if (pf.record_toggle) (s.recording.active ? a.record_stop : a.record_start) = true;
    if (pf.calibration_capture && view_.open.calibration) a.calibration_capture = true;
    a.undistort_preview = view_.settings.overlay.undistort;

    draw_menu(s, a);
    const ImVec2 d = io.DisplaySize;
    status_.draw(s, view_, a);
    auto place = [&](const char* name) { place_window(name, d, view_); };
    // Where each window was drawn this frame (the offscreen JSON and the tests read it).
    auto report = [&](const char* name) {
        const ImGuiWindow* w = ImGui::FindWindowByName(name);
        if (!w || !w->Active) return;
        for (const auto& [n, r] : view_.layout.windows)
            if (n == name) return;  // the window reported itself
        view_.layout.windows.push_back(
            {name, {w->Pos.x, w->Pos.y, w->Pos.x + w->Size.x, w->Pos.y + w->Size.y}});
    };
    if (view_.settings.layout == LayoutMode::Flight) {
        flight_.draw(s, view_, a, tex);
    } else {
        if (view_.open.video) {
            place("Video");
            video_.draw(s, view_, a, tex);
            report("Video");
        }
        if (view_.open.plots) {
            place("Plots");
            plots_.draw(s, view_);
            report("Plots");
        }
        if (view_.open.connection) {
            place("Connection");
            connection_.draw(s, view_, a);
            report("Connection");
        }
        if (view_.open.why_not_flying) {
            place("Why not flying");
            why_.draw(s, view_);
            report("Why not flying");
        }
        if (view_.open.recording) {
            place("Recording");
            recording_.draw(s, view_, a);
            report("Recording");
        }
        if (view_.open.replay) {
            place("Replay");
            replay_.draw(s, view_, a);
            report("Replay");
        }
        if (view_.open.classifier) {
            place("Classifier");
            classifier_.draw(s, view_, a);
            report("Classifier");
        }
        if (view_.open.telemetry) {
            place("Telemetry");
            telemetry_.draw(s, view_);
            report("Telemetry");
        }
        if (view_.open.link) {
            place("Link");
            link_.draw(s, view_);
            report("Link");
        }
        if (view_.open.calibration) {
            place("Calibration");
            calibration_.draw(s, view_, a, tex);
            report("Calibration");
        }
    }
    // Helpers float over either layout.
    if (view_.open.keys) {
        place("Keys");
        keys_.draw(view_);
        report("Keys");
    }
    if (view_.open.drone_settings) {
        place("Drone settings");
        settings_.draw(s, view_, a);
        report("Drone settings");
    }
    if (view_.open.messages) {
        place("Messages");
        messages_.draw(s, view_);
        report("Messages");
    }
    end_layout_frame(view_);
    hold_back_unavailable(s, a);
    calibration_mode(s, a);
    draw_notices();
    guard_leaving(s, a);
    draw_leave_dialog(s, a);
    finish_leaving(s, a);
    {
        const ImGuiContext& g = *GImGui;
        view_.layout.popups_open = g.OpenPopupStack.Size;
    }
    return a;
}

}  // namespace gs::ui
