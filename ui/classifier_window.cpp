#include "ui/windows.hpp"

#include <cstdio>
#include <cstring>

namespace gs::ui {

void ClassifierWindow::draw(const GuiSnapshot& s, ViewState& v, Actions& a) {
    if (!ImGui::Begin("Classifier", &v.open.classifier)) {
        ImGui::End();
        return;
    }
    const ClassifierOutput& c = s.classifier;
    // Picker.
    ImGui::SetNextItemWidth(-FLT_MIN);
    if (ImGui::BeginCombo("##classifier", c.active.empty() ? "(none)" : c.active.c_str())) {
        for (const auto& name : c.available) {
            if (ImGui::Selectable(name.c_str(), name == c.active) && name != c.active) {
                a.classifier_select = name;
                v.settings.classifier = name;
                v.settings_dirty = true;
            }
        }
        ImGui::EndCombo();
    }
    // Decisions.
    for (const auto& d : c.decisions) {
        const std::uint32_t col = d.flagged ? colors::kBad : colors::kGood;
        ImGui::TextColored(colors::v4(col), "%-7s %-6s", d.name.c_str(),
                           d.flagged ? "UNSAFE" : "clear");
        ImGui::SameLine();
        if (known(d.score))
            ImGui::TextColored(colors::v4(colors::kDim), "score %.3f / thr %.3f", d.score,
                               d.threshold);
        else
            ImGui::TextColored(colors::v4(colors::kDim), "score -");
    }
    ImGui::Separator();

    // Parameters, drawn from the generic list; drag to tune live, right-click to reset one.
    bool any_changed = false;
    if (ImGui::BeginTable("params", 2, ImGuiTableFlags_SizingStretchProp | ImGuiTableFlags_RowBg)) {
        ImGui::TableSetupColumn("name", ImGuiTableColumnFlags_WidthStretch, 0.45f);
        ImGui::TableSetupColumn("value", ImGuiTableColumnFlags_WidthStretch, 0.55f);
        for (const auto& p : c.params) {
            ImGui::TableNextRow();
            ImGui::TableSetColumnIndex(0);
            const bool modified = p.value != p.default_value;
            ImGui::TextColored(colors::v4(modified ? colors::kWarn : colors::kText), "%s",
                               p.name.c_str());
            if (ImGui::IsItemHovered() && !p.description.empty()) {
                ImGui::BeginTooltip();
                ImGui::PushTextWrapPos(ImGui::GetFontSize() * 24);
                ImGui::TextUnformatted(p.description.c_str());
                ImGui::TextColored(colors::v4(colors::kDim), "default %g, range [%g, %g]",
                                   p.default_value, p.min, p.max);
                ImGui::PopTextWrapPos();
                ImGui::EndTooltip();
            }
            ImGui::TableSetColumnIndex(1);
            ImGui::SetNextItemWidth(-FLT_MIN);
            ImGui::PushID(p.name.c_str());
            bool changed = false;
            double val = p.value;
            if (p.integer) {
                int iv = static_cast<int>(p.value);
                changed =
                    ImGui::SliderInt("##v", &iv, static_cast<int>(p.min), static_cast<int>(p.max));
                val = iv;
            } else {
                changed =
                    ImGui::SliderScalar("##v", ImGuiDataType_Double, &val, &p.min, &p.max, "%.4g");
            }
            if (ImGui::BeginPopupContextItem("reset")) {
                if (ImGui::MenuItem("Reset to default")) {
                    val = p.default_value;
                    changed = true;
                }
                ImGui::EndPopup();
            }
            ImGui::PopID();
            if (changed) {
                a.param_changes.emplace_back(p.name, val);
                v.settings.classifier_params[c.active][p.name] = val;
                any_changed = true;
            }
        }
        ImGui::EndTable();
    }
    if (any_changed) v.settings_dirty = true;
    if (c.params.empty()) ImGui::TextColored(colors::v4(colors::kDim), "No tunable parameters.");

    if (ImGui::Button("Reset all")) {
        for (const auto& p : c.params)
            if (p.value != p.default_value) a.param_changes.emplace_back(p.name, p.default_value);
        v.settings.classifier_params.erase(c.active);
        v.settings_dirty = true;
    }
    // Presets: the window owns them (settings file); loading one is a batch of param changes.
    ImGui::Separator();
    ImGui::SetNextItemWidth(ImGui::GetFontSize() * 8);
    ImGui::InputTextWithHint("##preset", "preset name", v.preset_name.data(), v.preset_name.size());
    ImGui::SameLine();
    if (ImGui::Button("Save preset") && v.preset_name[0] != 0) {
        ClassifierPreset pr;
        pr.classifier = c.active;
        for (const auto& p : c.params) pr.params[p.name] = p.value;
        v.settings.classifier_presets[v.preset_name.data()] = pr;
        v.settings_dirty = true;
    }
    std::string to_delete;
    for (const auto& [name, pr] : v.settings.classifier_presets) {
        ImGui::PushID(name.c_str());
        if (ImGui::SmallButton("Load")) {
            if (pr.classifier != c.active && !pr.classifier.empty())
                a.classifier_select = pr.classifier;
            for (const auto& [pn, pv] : pr.params) a.param_changes.emplace_back(pn, pv);
        }
        ImGui::SameLine();
        if (ImGui::SmallButton("x")) to_delete = name;
        ImGui::SameLine();
        ImGui::Text("%s", name.c_str());
        ImGui::SameLine();
        ImGui::TextColored(colors::v4(colors::kDim), "(%s)", pr.classifier.c_str());
        ImGui::PopID();
    }
    if (!to_delete.empty()) {
        v.settings.classifier_presets.erase(to_delete);
        v.settings_dirty = true;
    }
    ImGui::End();
}

}  // namespace gs::ui
