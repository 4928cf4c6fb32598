// Drone -> Settings. Each setting shows the value the drone reported (its configuration read
// back over the control port) and what became of the last change: sent, confirmed by the
// read-back, ignored (the drone reports another value or has no such key), refused, no answer.
// A change is sent when the control is released, once, as the link's SetConfig (CONFIG_IDS +
// CONFIG, then the read-back). Values the firmware bounds are bounded here.
#include "ui/controls.hpp"
#include "ui/windows.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace gs::ui {

namespace {

enum class Kind { Number, Bool, Choice };
struct Choice {
    const char* value;  // as the drone prints it
    const char* label;
};
struct Spec {
    const char* label;
    const char* key;
    Kind kind;
    double min = 0, max = 0;  // in display units (firmware bounds)
    double scale = 1;         // display = drone value * scale
    bool integer = false;     // the drone stores an integer
    int decimals = 1;         // shown with this many decimals
    const char* unit = "";
    const char* help = "";
    const Choice* choices = nullptr;
    int n_choices = 0;
};

constexpr double kDeg = 57.29577951308232;
constexpr Choice kCodecs[] = {{"129", "H.264 360p (640x360)"}, {"131", "H.264 720p (1280x720)"}};
constexpr Choice kNavdata[] = {{"TRUE", "demo, 15 Hz"}, {"FALSE", "full, 200 Hz"}};

// docs/protocol.md section 5.4: keys, units and the firmware's ranges.
const Spec kSpecs[] = {
    {"Max altitude", "control:altitude_max", Kind::Number, 0.5, 5.0, 0.001, true, 1, "m",
     "control:altitude_max (mm). The drone will not climb above it. Firmware range 0.5-5 m."},
    {"Max tilt", "control:euler_angle_max", Kind::Number, 1.0, 30.0, kDeg, false, 0, "deg",
     "control:euler_angle_max (rad): the tilt a full stick or key gives, hence the speed. "
     "Firmware range 0-30 deg."},
    {"Max vertical speed", "control:control_vz_max", Kind::Number, 0.2, 2.0, 0.001, false, 2, "m/s",
     "control:control_vz_max (mm/s) for full climb or descent. Range 0.2-2 m/s."},
    {"Max yaw rate", "control:control_yaw", Kind::Number, 40.0, 350.0, kDeg, false, 0, "deg/s",
     "control:control_yaw (rad/s) for a full turn command. Range 40-350 deg/s."},
    {"Outdoor flight", "control:outdoor", Kind::Bool, 0, 0, 1, false, 0, "",
     "control:outdoor: the outdoor control tuning (wind estimation); the drone loads its "
     "outdoor_* maxima."},
    {"Outdoor hull", "control:flight_without_shell", Kind::Bool, 0, 0, 1, false, 0, "",
     "control:flight_without_shell: flying with the outdoor hull (no bumpers)."},
    {"Video stream", "video:video_codec", Kind::Choice, 0, 0, 1, false, 0, "",
     "video:video_codec: the live stream's resolution (H.264 only: the ground station decodes "
     "nothing else).",
     kCodecs, 2},
    {"Video bitrate", "video:bitrate", Kind::Number, 250, 4000, 1, true, 0, "kbit/s",
     "video:bitrate (kbit/s): the encoder's target. Range 250-4000."},
    {"Navdata rate", "general:navdata_demo", Kind::Choice, 0, 0, 1, false, 0, "",
     "general:navdata_demo: demo navdata at 15 Hz, or every option at 200 Hz.", kNavdata, 2},
};

std::string drone_value(const Spec& sp, double display) {
    char buf[48];
    const double v = display / sp.scale;
    if (sp.integer)
        std::snprintf(buf, sizeof buf, "%d", static_cast<int>(std::lround(v)));
    else
        std::snprintf(buf, sizeof buf, "%.7g", v);
    return buf;
}

std::optional<double> number(const std::string* v) {
    if (!v) return std::nullopt;
    char* end = nullptr;
    const double d = std::strtod(v->c_str(), &end);
    if (end == v->c_str() || !std::isfinite(d)) return std::nullopt;
    return d;
}

std::uint32_t state_color(ConfigWriteState s) {
    switch (s) {
        case ConfigWriteState::Confirmed:
            return colors::kGood;
        case ConfigWriteState::Pending:
            return colors::kDim;
        case ConfigWriteState::Ignored:
            return colors::kWarn;
        default:
            return colors::kBad;
    }
}

}  // namespace

void DroneSettingsWindow::draw(const GuiSnapshot& s, ViewState& v, Actions& a) {
    if (!ImGui::Begin("Drone settings", &v.open.drone_settings)) {
        ImGui::End();
        return;
    }
    {
        const ImVec2 wp = ImGui::GetWindowPos(), ws = ImGui::GetWindowSize();
        v.layout.windows.push_back({"Drone settings", {wp.x, wp.y, wp.x + ws.x, wp.y + ws.y}});
    }
    const DroneConfigView& c = s.config;
    if (!c.available) {
        ImGui::TextColored(colors::v4(colors::kWarn), "%s",
                           s.connection.state == LinkState::Replay
                               ? "A replay has no drone to configure."
                               : "Connect to the drone to read and change its settings.");
    } else if (!c.read) {
        ImGui::TextColored(colors::v4(colors::kDim), "Reading the configuration...");
    }
    const bool can_write = c.available && c.read;
    const float fs = ImGui::GetFontSize();
    if (ImGui::BeginTable("settings", 3,
                          ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingStretchProp)) {
        ImGui::TableSetupColumn("setting", ImGuiTableColumnFlags_WidthFixed, fs * 9.0f);
        ImGui::TableSetupColumn("value", ImGuiTableColumnFlags_WidthStretch, 2.0f);
        ImGui::TableSetupColumn("drone", ImGuiTableColumnFlags_WidthStretch, 1.4f);
        for (const Spec& sp : kSpecs) {
            ImGui::PushID(sp.key);
            ImGui::TableNextRow();
            ImGui::TableSetColumnIndex(0);
            ImGui::TextUnformatted(sp.label);
            if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", sp.help);
            const std::string* cur = c.get(sp.key);
            const ConfigWrite* w = c.last_write(sp.key);
            // While a write is on its way the control shows what was asked, not the old value.
            const std::string* shown = w && w->state == ConfigWriteState::Pending ? &w->value : cur;
            ImGui::TableSetColumnIndex(1);
            if (!can_write || !shown) ImGui::BeginDisabled();
            std::optional<std::pair<std::string, std::string>> write;
            switch (sp.kind) {
                case Kind::Number: {
                    auto& edit = v.settings_edits[sp.key];
                    const auto dv = number(shown);
                    if (!v.settings_editing.count(sp.key))
                        edit = dv ? static_cast<float>(*dv * sp.scale) : static_cast<float>(sp.min);
                    const float width = ImGui::GetContentRegionAvail().x - fs * 6.5f;
                    ImGui::SetNextItemWidth(std::max(width, fs * 5.0f));
                    ImGui::SliderFloat("##v", &edit, static_cast<float>(sp.min),
                                       static_cast<float>(sp.max), "",
                                       ImGuiSliderFlags_AlwaysClamp);
                    if (ImGui::IsItemActive()) v.settings_editing.insert(sp.key);
                    if (ImGui::IsItemDeactivated()) v.settings_editing.erase(sp.key);
                    if (ImGui::IsItemDeactivatedAfterEdit())
                        write = {{sp.key, drone_value(sp, static_cast<double>(edit))}};
                    ImGui::SameLine();
                    // Beside the slider, never under its handle.
                    ImGui::Text("%.*f %s", sp.decimals, static_cast<double>(edit), sp.unit);
                    break;
                }
                case Kind::Bool: {
                    bool on = shown && *shown == "TRUE";
                    if (ImGui::Checkbox("##v", &on)) write = {{sp.key, on ? "TRUE" : "FALSE"}};
                    break;
                }
                case Kind::Choice: {
                    const char* label = shown ? shown->c_str() : "?";
                    for (int i = 0; i < sp.n_choices; ++i)
                        if (shown && *shown == sp.choices[i].value) label = sp.choices[i].label;
                    ImGui::SetNextItemWidth(-FLT_MIN);
                    if (ImGui::BeginCombo("##v", label)) {
                        for (int i = 0; i < sp.n_choices; ++i) {
                            const bool sel = shown && *shown == sp.choices[i].value;
                            if (ImGui::Selectable(sp.choices[i].label, sel) && !sel)
                                write = {{sp.key, sp.choices[i].value}};
                        }
                        ImGui::EndCombo();
                    }
                    break;
                }
            }
            if (!can_write || !shown) ImGui::EndDisabled();
            if (write && can_write) a.config_writes.push_back(*write);
            // What the drone says, and what became of the last change.
            ImGui::TableSetColumnIndex(2);
            if (w && w->state != ConfigWriteState::Confirmed) {
                std::string txt = to_string(w->state);
                ImGui::TextColored(colors::v4(state_color(w->state)), "%s", txt.c_str());
                if (ImGui::IsItemHovered())
                    ImGui::SetTooltip("%s = %s: %s%s%s", w->key.c_str(), w->value.c_str(),
                                      txt.c_str(), w->detail.empty() ? "" : "\n",
                                      w->detail.c_str());
                v.layout.setting_status.push_back({sp.key, txt});
            } else if (cur) {
                ImGui::TextColored(colors::v4(w ? colors::kGood : colors::kDim), "%s%s",
                                   w ? "confirmed " : "", cur->c_str());
                v.layout.setting_status.push_back({sp.key, w ? "confirmed" : "read"});
            } else {
                ImGui::TextColored(colors::v4(colors::kDim), "-");
            }
            ImGui::PopID();
        }
        ImGui::EndTable();
    }
    ImGui::Spacing();
    if (!c.available) ImGui::BeginDisabled();
    if (ImGui::Button("Read from the drone")) a.config_read = true;
    if (!c.available) ImGui::EndDisabled();
    ImGui::SameLine();
    command_button(v, s, "settings.flat_trim", "Flat trim", Control::FlatTrim, a.flat_trim);
    ImGui::SameLine();
    command_button(v, s, "settings.calibrate", "Calibrate magnetometer", Control::Calibrate,
                   a.calibrate_magnetometer);
    ImGui::TextColored(colors::v4(colors::kDim),
                       "Flat trim: landed, on level ground. Magnetometer: in flight, the drone "
                       "turns a full circle.");
    ImGui::End();
}

}  // namespace gs::ui
