#include "ui/windows.hpp"

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
    if (!c.reason.empty()) {
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
        if (ImGui::BeginCombo("##scenario", cur)) {
            for (const auto& sc : c.scenarios)
                if (ImGui::Selectable(sc.c_str(), sc == st.sim_scenario)) {
                    st.sim_scenario = sc;
                    v.settings_dirty = true;
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
    } else if (ImGui::Button("Disconnect", {btn_w, 0})) {
        a.disconnect = true;
    }
    ImGui::Separator();

    // Flight controls. Emergency is large, red and always in the same place.
    const Keymap& km = st.keymap;
    auto label = [&](const char* text, PilotKey k) {
        return std::string(text) + " (" + key_name(km.key(k)) + ")";
    };
    const float h = ImGui::GetFrameHeight() * 1.6f;
    const float w = (ImGui::GetContentRegionAvail().x - ImGui::GetStyle().ItemSpacing.x * 2) / 3.0f;
    if (ImGui::Button(label("Take off", PilotKey::Takeoff).c_str(), {w, h})) a.takeoff = true;
    ImGui::SameLine();
    if (ImGui::Button(label("Land", PilotKey::Land).c_str(), {w, h})) a.land = true;
    ImGui::SameLine();
    ImGui::PushStyleColor(ImGuiCol_Button, colors::v4(IM_COL32(170, 30, 25, 255)));
    ImGui::PushStyleColor(ImGuiCol_ButtonHovered, colors::v4(IM_COL32(215, 45, 35, 255)));
    ImGui::PushStyleColor(ImGuiCol_ButtonActive, colors::v4(IM_COL32(240, 70, 50, 255)));
    if (ImGui::Button(label("EMERGENCY", PilotKey::Emergency).c_str(), {w, h})) a.emergency = true;
    ImGui::PopStyleColor(3);
    if (ImGui::Button(label("Flat trim", PilotKey::FlatTrim).c_str())) a.flat_trim = true;
    ImGui::SameLine();
    if (ImGui::Button(label("Camera", PilotKey::SwitchCamera).c_str())) a.switch_camera = true;
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
        "Keyboard (works when the window has focus; text fields keep the keys except "
        "emergency). Losing focus makes the drone hover.");
    if (ImGui::BeginTable("keys", 2, ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingStretchProp)) {
        for (std::size_t i = 0; i < kPilotKeyCount; ++i) {
            const auto k = static_cast<PilotKey>(i);
            ImGui::TableNextRow();
            ImGui::TableSetColumnIndex(0);
            ImGui::TextColored(colors::v4(k == PilotKey::Emergency ? colors::kBad : colors::kInfo),
                               "%s", key_name(v.settings.keymap.key(k)).c_str());
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
    ImGui::TextColored(colors::v4(colors::kDim),
                       "F1 toggles this window. Ctrl+Q quits (asks to land first).");
    ImGui::End();
}

}  // namespace gs::ui
