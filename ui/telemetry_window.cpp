#include "ui/windows.hpp"

#include <cstdio>

namespace gs::ui {

namespace {
// Table rows; the values of a stale sample are drawn dimmed: they are what the drone said then.
struct Rows {
    bool stale = false;
    void row(const char* name, const char* value, std::uint32_t col = colors::kText) const {
        ImGui::TableNextRow();
        ImGui::TableSetColumnIndex(0);
        ImGui::TextColored(colors::v4(colors::kDim), "%s", name);
        ImGui::TableSetColumnIndex(1);
        ImGui::TextColored(colors::v4(stale ? colors::kDim : col), "%s", value);
    }
    void num(const char* name, double v, int decimals, bool sign = false) const {
        char buf[64];
        if (known(v))
            std::snprintf(buf, sizeof buf, sign ? "%+.*f" : "%.*f", decimals, v);
        else
            std::snprintf(buf, sizeof buf, "unknown");
        row(name, buf, known(v) ? colors::kText : colors::kDim);
    }
};
}  // namespace

void TelemetryWindow::draw(const GuiSnapshot& s, ViewState& v) {
    if (!ImGui::Begin("Telemetry", &v.open.telemetry)) {
        ImGui::End();
        return;
    }
    const Telemetry& t = s.telemetry;
    // Say what the values are: none yet, or the last ones received before the navdata stopped.
    std::string& note = v.layout.telemetry_note;
    if (!t.valid) {
        note = "No navdata received.";
    } else if (t.stale) {
        char buf[128];
        std::snprintf(buf, sizeof buf,
                      "STALE %.1f s: no navdata since; the values below are the last received.",
                      t.age_ms / 1000.0);
        note = buf;
    }
    if (!note.empty()) {  // wrapped: a narrow window must not cut it off
        ImGui::PushStyleColor(ImGuiCol_Text, colors::v4(colors::kWarn));
        ImGui::TextWrapped("%s", note.c_str());
        ImGui::PopStyleColor();
    }
    const Rows r{t.valid && t.stale};
    const ImGuiTableFlags tf =
        ImGuiTableFlags_RowBg | ImGuiTableFlags_BordersInnerV | ImGuiTableFlags_SizingStretchProp;
    if (ImGui::CollapsingHeader("State", ImGuiTreeNodeFlags_DefaultOpen) &&
        ImGui::BeginTable("state", 2, tf)) {
        const NavState& n = t.nav;
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.3f s", static_cast<double>(n.t_ns) * 1e-9);
        r.row("time", t.valid ? buf : "unknown");
        if (n.seq) {
            std::snprintf(buf, sizeof buf, "%u", *n.seq);
            r.row("seq", buf);
        }
        r.row("ctrl_state", t.ctrl_state.empty() ? "unknown" : t.ctrl_state.c_str());
        r.num("roll_deg", n.roll_deg, 2, true);
        r.num("pitch_deg", n.pitch_deg, 2, true);
        r.num("yaw_deg", n.yaw_deg, 2, true);
        r.num("altitude_m", n.altitude_m, 3);
        r.num("vx_mps", n.vx_mps, 3, true);
        r.num("vy_mps", n.vy_mps, 3, true);
        r.num("vz_mps", n.vz_mps, 3, true);
        r.num("battery_pct", n.battery_pct, 0);
        ImGui::EndTable();
    }
    if (t.state && ImGui::CollapsingHeader("drone_state bits")) {
        const std::uint32_t raw = t.state->to_raw();
        ImGui::Text("0x%08X", raw);
        if (ImGui::BeginTable("bits", 3, tf)) {
            for (const auto& b : drone_state_bit_names()) {
                const bool on = ((raw >> b.bit) & 1u) != 0;
                ImGui::TableNextRow();
                ImGui::TableSetColumnIndex(0);
                ImGui::TextColored(colors::v4(colors::kDim), "%2d", b.bit);
                ImGui::TableSetColumnIndex(1);
                ImGui::TextColored(colors::v4(on ? colors::kText : colors::kDim), "%s", b.sdk_name);
                ImGui::TableSetColumnIndex(2);
                ImGui::TextColored(colors::v4(on ? colors::kGood : colors::kDim), "%s",
                                   on ? "1" : "0");
            }
            ImGui::EndTable();
        }
    }
    // Every navdata field, grouped by option.
    std::size_t i = 0;
    while (i < t.fields.size()) {
        const std::string& group = t.fields[i].group;
        std::size_t j = i;
        while (j < t.fields.size() && t.fields[j].group == group) ++j;
        if (ImGui::CollapsingHeader(group.c_str()) && ImGui::BeginTable(group.c_str(), 2, tf)) {
            for (std::size_t k = i; k < j; ++k)
                r.row(t.fields[k].name.c_str(), t.fields[k].value.c_str());
            ImGui::EndTable();
        }
        i = j;
    }
    ImGui::End();
}

}  // namespace gs::ui
