// The buttons of the flight controls that the windows share (ui/windows.hpp): disabled with the
// reason from control_state, which the layout report records and the tooltip shows.
#include "ui/controls.hpp"
#include "ui/windows.hpp"

namespace gs::ui {

void note_disabled(ViewState& v, const char* id, const ControlState& cs) {
    if (cs.enabled) return;
    v.layout.disabled.push_back({id, cs.why});
    if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
        ImGui::SetTooltip("%s", cs.why.c_str());
}

void command_button(ViewState& v, const GuiSnapshot& s, const char* id, const std::string& label,
                    Control c, bool& out) {
    const ControlState cs = control_state(s, c);
    if (!cs.enabled) ImGui::BeginDisabled();
    if (ImGui::Button((label + "##" + id).c_str())) out = true;
    if (!cs.enabled) ImGui::EndDisabled();
    record_button(v, id);
    note_disabled(v, id, cs);
}

}  // namespace gs::ui
