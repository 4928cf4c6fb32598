#include "ui/windows.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

namespace gs::ui {

namespace {

// "+0.42 cm" style numbers (`decimals` after the point, a sign when `sign`); "-" when unknown.
std::string signed_num(double v, double scale, int decimals, const char* unit, bool sign = true) {
    if (!known(v)) return "-";
    char b[48];
    std::snprintf(b, sizeof b, sign ? "%+.*f %s" : "%.*f %s", decimals, v * scale, unit);
    return b;
}

// The bottom camera's visual odometry: this sample's estimate and how it was found, then the
// integrated pose against the navdata's over the same samples.
void odometry_readout(const OdometryView& o, const GuiSnapshot& s) {
    ImGui::TextColored(colors::v4(colors::kInfo), "Visual odometry (bottom camera)");
    if (!o.active) {
        ImGui::TextColored(colors::v4(colors::kDim),
                           s.video.bgr.empty() ? "waiting for video" : "waiting for a frame");
        return;
    }
    const ImGuiTableFlags tf = ImGuiTableFlags_SizingFixedFit | ImGuiTableFlags_RowBg;
    if (!ImGui::BeginTable("odometry", 2, tf)) return;
    ImGui::TableSetupColumn("what", ImGuiTableColumnFlags_WidthFixed);
    ImGui::TableSetupColumn("value", ImGuiTableColumnFlags_WidthStretch);
    // One row: a label, then the value wrapped inside its cell (the window may be narrow).
    auto row = [](const char* label, std::uint32_t col, const std::string& text) {
        ImGui::TableNextRow();
        ImGui::TableSetColumnIndex(0);
        ImGui::TextColored(colors::v4(colors::kDim), "%s", label);
        ImGui::TableSetColumnIndex(1);
        ImGui::PushStyleColor(ImGuiCol_Text, colors::v4(col));
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextUnformatted(text.c_str());
        ImGui::PopTextWrapPos();
        ImGui::PopStyleColor();
    };
    const bool first = o.sample == 0;
    row("sample", colors::kDim,
        std::to_string(o.sample) + ", " + format_sig(o.ms, 2) + " ms (mean " +
            format_sig(o.ms_mean, 2) + " ms)");
    row("status",
        o.valid ? colors::kGood
        : first ? colors::kDim
                : colors::kWarn,
        o.status + " (" + std::to_string(o.inliers) + " inliers / " + std::to_string(o.tracked) +
            " tracked / " + std::to_string(o.corners) + " corners)");
    std::string per = "dx " + signed_num(o.dx_m, 100, 2, "cm") + "  dy " +
                      signed_num(o.dy_m, 100, 2, "cm") + "  dyaw " +
                      signed_num(o.dyaw_deg, 1, 2, "deg");
    if (o.spike_zeroed) per += "  (spike: zeroed)";
    if (o.rotation_gated) per += "  (rotating: translation gated)";
    row("per sample", o.spike_zeroed || o.rotation_gated ? colors::kWarn : colors::kText, per);
    row("navdata", colors::kDim,
        "dyaw " + signed_num(o.dyaw_navdata_deg, 1, 2, "deg") + ", floor " +
            signed_num(o.distance_m, 1, 2, "m", false));
    row("path", colors::kText,
        "x " + signed_num(o.x_m, 1, 2, "m") + "  y " + signed_num(o.y_m, 1, 2, "m") + "  yaw " +
            signed_num(o.yaw_deg, 1, 1, "deg", false));
    if (known(o.nav_x_m) && known(o.x_m))
        row("navdata path", colors::kDim,
            "x " + signed_num(o.nav_x_m, 1, 2, "m") + "  y " + signed_num(o.nav_y_m, 1, 2, "m") +
                "  apart " +
                signed_num(std::hypot(o.x_m - o.nav_x_m, o.y_m - o.nav_y_m), 100, 1, "cm", false));
    row("samples", o.invalid > 0 ? colors::kWarn : colors::kDim,
        std::to_string(o.samples) + ": " + std::to_string(o.invalid) + " without estimate, " +
            std::to_string(o.spike_samples) + " spike-zeroed, " + std::to_string(o.gated_samples) +
            " gated");
    ImGui::EndTable();
}

}  // namespace

void ClassifierWindow::draw(const GuiSnapshot& s, ViewState& v, Actions& a) {
    if (!ImGui::Begin("Classifier", &v.open.classifier)) {
        ImGui::End();
        return;
    }
    const ClassifierOutput& c = s.classifier;
    if (s.odometry.active || s.video.camera == "bottom") {
        odometry_readout(s.odometry, s);
        ImGui::Separator();
    }
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
    if (!c.not_running.empty()) {
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextColored(colors::v4(colors::kWarn), "Obstacle classifier %s.",
                           c.not_running.c_str());
        ImGui::PopTextWrapPos();
    }
    // Decisions.
    for (const auto& d : c.decisions) {
        const bool stale = s.video.stale;
        const bool measured = d.known && !stale;
        // The region bar's states ("confirming" amber, "still" steel blue), in text colours.
        const RegionShown state = region_shown(measured, d.flagged, d.still, d.score, d.threshold);
        const bool still = state == RegionShown::Still;
        static constexpr std::uint32_t kTextColours[] = {colors::kDim, colors::kBad, colors::kWarn,
                                                         colors::kStill, colors::kGood};
        ImGui::TextColored(colors::v4(kTextColours[static_cast<std::size_t>(state)]), "%-7s %-7s",
                           d.name.c_str(), shown_word(state));
        ImGui::SameLine();
        if (still) {
            ImGui::TextColored(colors::v4(colors::kDim), "nothing approaching");
            if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", kStillMeaning);
        } else if (!measured)
            ImGui::TextColored(colors::v4(colors::kDim), "%s",
                               stale ? "video stale" : d.unknown_reason.c_str());
        else if (known(d.score)) {
            ImGui::TextColored(colors::v4(colors::kDim), "%s / %s",
                               format_score(d.score, d.threshold).c_str(),
                               format_score(d.threshold, d.threshold).c_str());
            if (d.flagged && known(d.edge_m)) {
                ImGui::SameLine();
                ImGui::TextColored(colors::v4(colors::kDim), "edge %+.2f m", d.edge_m);
                if (ImGui::IsItemHovered())
                    ImGui::SetTooltip(
                        "How far beside the flight line the obstacle's inner edge is, toward "
                        "this side (negative: across the line), from the points rated unsafe");
            }
        } else
            ImGui::TextColored(colors::v4(colors::kDim), "score -");
    }
    ImGui::Separator();

    // Parameters, drawn from the generic list; drag to tune live, right-click to reset one.
    // The name column is as wide as the longest name when the sliders keep room to be dragged;
    // in a narrow window each name goes on its own line above its slider. Hovering a name shows
    // its description.
    float name_w = 0;
    for (const auto& p : c.params) name_w = std::max(name_w, ImGui::CalcTextSize(p.name.c_str()).x);
    const float min_slider = ImGui::GetFontSize() * 10;
    const float avail = ImGui::GetContentRegionAvail().x;
    name_w = std::clamp(name_w, ImGui::GetFontSize() * 4, std::max(avail - min_slider, 1.0f));
    bool any_changed = false;
    const float value_w = ImGui::CalcTextSize("-0.0000").x;
    // Names in full: beside their slider when the window is wide enough, else above it.
    float longest = 0;
    for (const auto& p : c.params)
        longest = std::max(longest, ImGui::CalcTextSize(p.name.c_str()).x);
    const bool two_lines = longest + value_w + ImGui::GetFontSize() * 7 > avail;
    const int slider_col = two_lines ? 0 : 1, value_col = slider_col + 1;
    if (ImGui::BeginTable("params", two_lines ? 2 : 3,
                          ImGuiTableFlags_SizingFixedFit | ImGuiTableFlags_RowBg)) {
        if (!two_lines) ImGui::TableSetupColumn("name", ImGuiTableColumnFlags_WidthFixed, name_w);
        ImGui::TableSetupColumn("slider", ImGuiTableColumnFlags_WidthStretch);
        ImGui::TableSetupColumn("value", ImGuiTableColumnFlags_WidthFixed, value_w);
        for (const auto& p : c.params) {
            ImGui::TableNextRow();
            ImGui::TableSetColumnIndex(0);
            const bool modified = p.value != p.default_value;
            ImGui::TextColored(colors::v4(modified ? colors::kWarn : colors::kText), "%s",
                               p.name.c_str());
            if (ImGui::IsItemHovered()) {
                ImGui::BeginTooltip();
                ImGui::PushTextWrapPos(ImGui::GetFontSize() * 24);
                ImGui::TextUnformatted(p.name.c_str());
                if (!p.description.empty())
                    ImGui::TextColored(colors::v4(colors::kDim), "%s", p.description.c_str());
                ImGui::TextColored(colors::v4(colors::kDim), "default %g, range [%g, %g]",
                                   p.default_value, p.min, p.max);
                ImGui::PopTextWrapPos();
                ImGui::EndTooltip();
            }
            if (two_lines) ImGui::TableNextRow();
            ImGui::TableSetColumnIndex(slider_col);
            ImGui::SetNextItemWidth(-FLT_MIN);
            ImGui::PushID(p.name.c_str());
            bool changed = false;
            double val = p.value;
            // The value in its own column: a slider's handle never covers it.
            if (p.integer) {
                int iv = static_cast<int>(p.value);
                changed = ImGui::SliderInt("##v", &iv, static_cast<int>(p.min),
                                           static_cast<int>(p.max), "");
                val = iv;
            } else {
                changed =
                    ImGui::SliderScalar("##v", ImGuiDataType_Double, &val, &p.min, &p.max, "");
            }
            if (ImGui::BeginPopupContextItem("reset")) {
                if (ImGui::MenuItem("Reset to default")) {
                    val = p.default_value;
                    changed = true;
                }
                ImGui::EndPopup();
            }
            ImGui::PopID();
            ImGui::TableSetColumnIndex(value_col);
            ImGui::TextUnformatted(p.integer ? std::to_string(static_cast<long long>(val)).c_str()
                                             : format_sig(val, 3).c_str());
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
