#include "ui/windows.hpp"

#include "ui/controls.hpp"
#include "ui/pilot_input.hpp"

#include <cstdio>
#include <cstring>

namespace gs::ui {

namespace {
// Small centred bar for one pilot axis in [-1, 1].
void axis_bar(const char* name, float val) {
    ImDrawList* dl = ImGui::GetWindowDrawList();
    const float fs = ImGui::GetFontSize();
    const ImVec2 p = ImGui::GetCursorScreenPos();
    const float lw = fs * 2.6f, w = fs * 5.0f, h = fs * 0.8f;
    dl->AddText({p.x, p.y}, colors::kDim, name);
    const ImVec2 b0{p.x + lw, p.y + (fs - h) * 0.5f + 1}, b1{b0.x + w, b0.y + h};
    dl->AddRectFilled(b0, b1, IM_COL32(40, 42, 48, 255));
    const float mid = 0.5f * (b0.x + b1.x);
    const float x = mid + val * w * 0.5f;
    dl->AddRectFilled({std::min(mid, x), b0.y}, {std::max(mid, x), b1.y}, colors::kInfo);
    dl->AddLine({mid, b0.y - 1}, {mid, b1.y + 1}, IM_COL32(255, 255, 255, 120));
    ImGui::Dummy({lw + w + 4, fs});
}
}  // namespace

void ConnectionWindow::draw(const GuiSnapshot& s, ViewState& v, Actions& a) {
    if (!ImGui::Begin("Connection", &v.open.connection)) {
        ImGui::End();
        return;
    }
    const ConnectionInfo& c = s.connection;
    const std::uint32_t col = c.state == LinkState::Connected ? colors::kGood
                              : c.state == LinkState::Replay  ? colors::kInfo
                              : c.state == LinkState::Lost    ? colors::kBad
                                                              : colors::kWarn;
    ImGui::TextColored(colors::v4(col), "%s", to_string(c.state));
    ImGui::SameLine();
    if (c.state != LinkState::Disconnected) {
        if (c.source == SourceKind::Sim)
            ImGui::TextColored(colors::v4(colors::kDim), "virtual drone, scenario %s",
                               c.scenario.c_str());
        else
            ImGui::TextColored(colors::v4(colors::kDim), "%s %s", to_string(c.source),
                               c.address.c_str());
    }
    if (!c.activity.empty()) {
        ImGui::SameLine();
        ImGui::TextColored(colors::v4(colors::kWarn), "- %s", c.activity.c_str());
    } else if (!c.reason.empty()) {
        ImGui::SameLine();
        ImGui::TextColored(colors::v4(colors::kDim), "- %s", c.reason.c_str());
    }

    // Source choice and connect/disconnect.
    Settings& st = v.settings;
    // The choice follows the source actually connected (the window may have been started on the
    // virtual drone from the command line), so Disconnect + Connect comes back to the same one.
    const bool live = c.state != LinkState::Disconnected && c.state != LinkState::Replay;
    if (live && (c.source == SourceKind::Sim) != st.use_sim) {
        st.use_sim = c.source == SourceKind::Sim;
        if (st.use_sim) st.sim_scenario = c.scenario;
        v.settings_dirty = true;
    }
    int src = st.use_sim ? 1 : 0;
    if (ImGui::RadioButton("Drone", &src, 0)) {
        st.use_sim = false;
        v.settings_dirty = true;
    }
    ImGui::SameLine();
    if (ImGui::RadioButton("Virtual drone", &src, 1)) {
        st.use_sim = true;
        v.settings_dirty = true;
    }
    ImGui::SameLine();
    const float btn_w = ImGui::GetFontSize() * 6.5f;
    ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x - btn_w -
                            ImGui::GetStyle().ItemSpacing.x);
    if (!st.use_sim) {
        if (ImGui::InputText("##addr", v.drone_address.data(), v.drone_address.size())) {
            st.drone_address = v.drone_address.data();
            v.settings_dirty = true;
        }
    } else {
        const char* cur = st.sim_scenario.empty() ? "(default)" : st.sim_scenario.c_str();
        const bool open = ImGui::BeginCombo("##scenario", cur);
        if (!open) record_button(v, "connection.scenario");
        if (open) {
            for (const auto& sc : c.scenarios) {
                if (ImGui::Selectable(sc.c_str(), sc == st.sim_scenario)) {
                    // Picking another scenario while the virtual drone runs switches to it (the
                    // window asks first when the drone is flying).
                    const bool running_other = c.source == SourceKind::Sim &&
                                               c.state != LinkState::Disconnected &&
                                               c.state != LinkState::Replay && sc != c.scenario;
                    if (running_other) a.connect = ConnectRequest{true, {}, sc};
                    st.sim_scenario = sc;
                    v.settings_dirty = true;
                }
                record_button(v, ("scenario." + sc).c_str());
            }
            ImGui::EndCombo();
        }
    }
    ImGui::SameLine();
    const bool connected = c.state != LinkState::Disconnected && c.state != LinkState::Replay;
    if (!connected) {
        if (ImGui::Button("Connect", {btn_w, 0})) {
            ConnectRequest r;
            r.sim = st.use_sim;
            r.address = st.drone_address.empty() ? "192.168.1.1" : st.drone_address;
            r.scenario = st.sim_scenario;
            a.connect = r;
        }
        record_button(v, "connection.connect");
    } else {
        if (ImGui::Button("Disconnect", {btn_w, 0})) a.disconnect = true;
        record_button(v, "connection.disconnect");
    }
    ImGui::Separator();

    // Take off, Land and EMERGENCY live in the status bar (always on screen); here the ground
    // checks and the camera, each disabled with its reason when it cannot act now.
    const Keymap& km = st.keymap;
    auto label = [&](const char* text, PilotKey k) {
        const std::string key = key_name(km.key(k));
        return key.empty() ? std::string(text) : std::string(text) + " (" + key + ")";
    };
    command_button(v, s, "connection.flat_trim", label("Flat trim", PilotKey::FlatTrim),
                   Control::FlatTrim, a.flat_trim);
    ImGui::SameLine();
    command_button(v, s, "connection.camera", label("Camera", PilotKey::SwitchCamera),
                   Control::SwitchCamera, a.switch_camera);
    ImGui::SameLine();
    if (ImGui::Button("Settings...")) v.open.drone_settings = true;
    ImGui::SameLine();
    if (ImGui::Button("Keys...")) v.open.keys = true;

    // What the pilot input currently commands.
    const PilotFrame& pf = v.last_pilot;
    ImGui::BeginGroup();
    axis_bar("roll", pf.pilot.roll);
    axis_bar("pitch", pf.pilot.pitch);
    ImGui::EndGroup();
    ImGui::SameLine();
    ImGui::BeginGroup();
    axis_bar("gaz", pf.pilot.gaz);
    axis_bar("yaw", pf.pilot.yaw);
    ImGui::EndGroup();
    ImGui::SameLine();
    ImGui::TextColored(colors::v4(pf.manual ? colors::kInfo : colors::kDim),
                       pf.manual ? "MANUAL" : "hover");
    ImGui::End();
}

void KeysWindow::draw(ViewState& v) {
    if (!ImGui::Begin("Keys", &v.open.keys)) {
        ImGui::End();
        return;
    }
    ImGui::TextWrapped(
        "Keyboard (works when the window has focus; text fields keep the keys except the "
        "emergency key, which works in every state). Losing focus makes the drone hover.");
    if (ImGui::BeginTable("keys", 2, ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingStretchProp)) {
        for (std::size_t i = 0; i < kPilotKeyCount; ++i) {
            const auto k = static_cast<PilotKey>(i);
            ImGui::TableNextRow();
            ImGui::TableSetColumnIndex(0);
            const int code = v.settings.keymap.key(k);
            ImGui::TextColored(colors::v4(k == PilotKey::Emergency ? colors::kBad : colors::kInfo),
                               "%s", code == kNoKey ? "(none)" : key_name(code).c_str());
            ImGui::TableSetColumnIndex(1);
            ImGui::TextUnformatted(description(k));
        }
        ImGui::EndTable();
    }
    ImGui::Separator();
    ImGui::TextWrapped(
        "Gamepad (mode 2): left stick yaw / climb, right stick roll / pitch, "
        "A take off, B land, Back EMERGENCY, X flat trim, Y camera, Start record. "
        "A held key overrides the stick on its axis.");
    ImGui::PushStyleColor(ImGuiCol_Text, colors::v4(colors::kDim));
    ImGui::TextWrapped(
        "F1 toggles this window, F2 the flight / engineering layout. Escape closes menus and "
        "dialogs and does nothing to the drone. Ctrl+Q quits (asks to land first when flying).");
    ImGui::PopStyleColor();
    v.layout.keys_clipped = ImGui::GetScrollMaxY() > 0.0f || ImGui::GetScrollMaxX() > 0.0f;
    ImGui::End();
}

}  // namespace gs::ui
