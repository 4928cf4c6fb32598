#include "ui/gui.hpp"

#include <GLFW/glfw3.h>

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

Rect default_window_rect(const char* w, ImVec2 d) {
    const float top = ImGui::GetFrameHeight();  // main menu bar
    const float W = d.x, H = d.y;
    const float L = std::round(W * 0.625f);
    const float R = W - L, half = std::round(R * 0.5f);
    const float video_bottom = top + std::round((H - top) * 0.64f);
    const float conn_h = 196.0f, why_h = 250.0f;
    const std::string n = w;
    if (n == "Video") return {0, top, L, video_bottom};
    if (n == "Plots") return {0, video_bottom, L, H};
    if (n == "Connection") return {L, top, W, top + conn_h};
    if (n == "Why not flying") return {L, top + conn_h, L + half, top + conn_h + why_h};
    if (n == "Recording") return {L + half, top + conn_h, W, top + conn_h + 112};
    if (n == "Replay") return {L + half, top + conn_h + 112, W, top + conn_h + why_h};
    const float mid = top + conn_h + why_h;
    if (n == "Classifier") return {L, mid, L + half, H};
    if (n == "Telemetry") return {L + half, mid, W, mid + std::round((H - mid) * 0.55f)};
    if (n == "Link") return {L + half, mid + std::round((H - mid) * 0.55f), W, H};
    if (n == "Keys") return {W * 0.3f, H * 0.2f, W * 0.3f + 420, H * 0.2f + 440};
    // Over the classifier / telemetry / link column (least needed while calibrating), leaving
    // the video, the connection and the replay controls in view.
    if (n == "Calibration") return {L, mid, W, H};
    return {40, 40, 440, 340};
}

void set_default_layout(const char* window, ImVec2 display) {
    const Rect r = default_window_rect(window, display);
    ImGui::SetNextWindowPos({r.x0, r.y0}, ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize({r.w(), r.h()}, ImGuiCond_FirstUseEver);
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
}

bool Gui::request_close(const GuiSnapshot& s) {
    const bool flying = s.telemetry.state && s.telemetry.state->flying &&
                        s.connection.state == LinkState::Connected;
    if (!flying) return true;
    view_.confirm_quit = true;
    return false;
}

void Gui::draw_menu(const GuiSnapshot& s, Actions& a) {
    if (!ImGui::BeginMainMenuBar()) return;
    if (ImGui::BeginMenu("File")) {
        if (ImGui::MenuItem("Quit", "Ctrl+Q")) {
            if (request_close(s)) a.quit = true;
        }
        ImGui::EndMenu();
    }
    if (ImGui::BeginMenu("View")) {
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
    if (ImGui::BeginMenu("Help")) {
        ImGui::MenuItem("Keys and gamepad", "F1", &view_.open.keys);
        ImGui::EndMenu();
    }
    // Right side: the one line a pilot must always see.
    const char* st = to_string(s.connection.state);
    std::uint32_t col = s.connection.state == LinkState::Connected ? colors::kGood
                        : s.connection.state == LinkState::Replay  ? colors::kInfo
                        : s.connection.state == LinkState::Lost    ? colors::kBad
                                                                   : colors::kWarn;
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s  |  %s  |  Emergency: %s", to_string(s.connection.source),
                  st, key_name(view_.settings.keymap.key(PilotKey::Emergency)).c_str());
    const float w = ImGui::CalcTextSize(buf).x;
    ImGui::SetCursorPosX(ImGui::GetWindowWidth() - w - 16.0f);
    ImGui::TextColored(colors::v4(col), "%s", buf);
    ImGui::EndMainMenuBar();
}

void Gui::draw_quit_dialog(const GuiSnapshot& s, Actions& a) {
    if (view_.confirm_quit) {
        ImGui::OpenPopup("The drone is flying");
        view_.confirm_quit = false;
    }
    const ImVec2 c{ImGui::GetIO().DisplaySize.x * 0.5f, ImGui::GetIO().DisplaySize.y * 0.5f};
    ImGui::SetNextWindowPos(c, ImGuiCond_Appearing, {0.5f, 0.5f});
    view_.quit_dialog_open = false;
    if (ImGui::BeginPopupModal("The drone is flying", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
        view_.quit_dialog_open = true;
        ImGui::TextUnformatted(
            "Closing the ground station now would leave the drone without commands.");
        ImGui::TextUnformatted(
            "Land first? The window closes once the drone reports it has landed.");
        ImGui::Spacing();
        const bool land = ImGui::Button("Land, then quit", {180, 0});
        record_button(view_, "quit.land");
        if (land) {
            a.land = true;
            view_.quit_after_landing = true;
            ImGui::CloseCurrentPopup();
        }
        ImGui::SameLine();
        const bool cancel = ImGui::Button("Cancel", {120, 0});
        record_button(view_, "quit.cancel");
        if (cancel) ImGui::CloseCurrentPopup();
        ImGui::EndPopup();
    }
    if (view_.quit_after_landing) {
        const bool flying = s.telemetry.state && s.telemetry.state->flying &&
                            s.connection.state == LinkState::Connected;
        if (!flying) a.quit = true;
    }
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
    if (s.telemetry.valid) view_.history.add(s.telemetry.nav);

    // Keyboard/gamepad -> pilot input. A focused text field keeps the keys (typing "w" into a
    // path must not fly the drone); the emergency key passes regardless.
    input.text_input_active = io.WantTextInput;
    for (std::size_t k = 0; k < input.keys.size(); ++k)
        if (io.KeysDown[k]) input.keys.set(k);
    const PilotFrame pf = view_.pilot.update(input, view_.settings.keymap);
    view_.last_pilot = pf;
    a.pilot = pf.pilot;
    a.manual = pf.manual;
    a.takeoff = pf.takeoff;
    a.land = pf.land;
    a.emergency = pf.emergency;
    a.flat_trim = pf.flat_trim;
    a.switch_camera = pf.switch_camera;
    if (pf.record_toggle) (s.recording.active ? a.record_stop : a.record_start) = true;
    if (pf.calibration_capture && view_.open.calibration) a.calibration_capture = true;
    a.undistort_preview = view_.settings.overlay.undistort;
    if (!io.WantTextInput && ImGui::IsKeyPressed(GLFW_KEY_F1, false))
        view_.open.keys = !view_.open.keys;
    if (io.KeyCtrl && !io.WantTextInput && ImGui::IsKeyPressed(GLFW_KEY_Q, false)) {
        if (request_close(s)) a.quit = true;
    }

    draw_menu(s, a);
    const ImVec2 d = io.DisplaySize;
    auto place = [&](const char* name) { set_default_layout(name, d); };
    if (view_.open.video) {
        place("Video");
        video_.draw(s, view_, a, tex);
    }
    if (view_.open.plots) {
        place("Plots");
        plots_.draw(s, view_);
    }
    if (view_.open.connection) {
        place("Connection");
        connection_.draw(s, view_, a);
    }
    if (view_.open.why_not_flying) {
        place("Why not flying");
        why_.draw(s, view_);
    }
    if (view_.open.recording) {
        place("Recording");
        recording_.draw(s, view_, a);
    }
    if (view_.open.replay) {
        place("Replay");
        replay_.draw(s, view_, a);
    }
    if (view_.open.classifier) {
        place("Classifier");
        classifier_.draw(s, view_, a);
    }
    if (view_.open.telemetry) {
        place("Telemetry");
        telemetry_.draw(s, view_);
    }
    if (view_.open.link) {
        place("Link");
        link_.draw(s, view_);
    }
    if (view_.open.keys) {
        place("Keys");
        keys_.draw(view_);
    }
    if (view_.open.calibration) {
        place("Calibration");
        calibration_.draw(s, view_, a, tex);
    }
    calibration_mode(s, a);
    draw_quit_dialog(s, a);
    return a;
}

}  // namespace gs::ui
