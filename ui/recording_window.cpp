#include "ui/windows.hpp"

#include "ui/pilot_input.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace gs::ui {

std::string format_bytes(double b) {
    if (!known(b)) return "?";
    const char* units[] = {"B", "kB", "MB", "GB", "TB"};
    int u = 0;
    while (std::fabs(b) >= 1000.0 && u < 4) {
        b /= 1000.0;
        ++u;
    }
    char buf[32];
    // Three significant digits at most ("7.7 kB", "122 kB"): narrow columns stay readable.
    std::snprintf(buf, sizeof buf, u == 0 || std::fabs(b) >= 99.95 ? "%.0f %s" : "%.1f %s", b,
                  units[u]);
    return buf;
}

std::string format_sig(double v, int digits) {
    if (std::isnan(v)) return "-";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    digits = std::max(digits, 1);
    char buf[48];
    if (std::fabs(v) >= std::pow(10.0, digits))
        std::snprintf(buf, sizeof buf, "%.0f", v);  // no exponent for large values
    else
        std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    return buf;
}

std::string format_score(double v, double threshold) {
    if (std::isnan(v)) return "-";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    int decimals = 2;
    if (std::isfinite(threshold) && threshold != 0.0) {
        // Two significant digits of the threshold: 0.3 -> 2 decimals, 0.0013 -> 4, 3.5 -> 1.
        const int mag = static_cast<int>(std::floor(std::log10(std::fabs(threshold))));
        decimals = std::clamp(1 - mag, 0, 6);
    }
    char buf[48];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    // "-0.00" reads as a sign where there is none.
    std::string out = buf;
    if (out[0] == '-' && out.find_first_not_of("-0.") == std::string::npos) out.erase(0, 1);
    return out;
}

std::string format_duration(double s) {
    if (!known(s) || s < 0) return "--:--";
    const long total = static_cast<long>(s);
    char buf[32];
    if (total >= 3600)
        std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", total / 3600, (total / 60) % 60,
                      total % 60);
    else
        std::snprintf(buf, sizeof buf, "%02ld:%04.1f", total / 60,
                      s - static_cast<double>(total / 60 * 60));
    return buf;
}

void RecordingWindow::draw(const GuiSnapshot& s, ViewState& v, Actions& a) {
    if (!ImGui::Begin("Recording", &v.open.recording)) {
        ImGui::End();
        return;
    }
    const RecordingStatus& r = s.recording;
    const std::string key = key_name(v.settings.keymap.key(PilotKey::Record));
    if (r.active) {
        ImGui::PushStyleColor(ImGuiCol_Button, colors::v4(IM_COL32(150, 35, 30, 255)));
        if (ImGui::Button((std::string("Stop recording (") + key + ")").c_str()))
            a.record_stop = true;
        ImGui::PopStyleColor();
        ImGui::SameLine();
        ImGui::TextColored(colors::v4(colors::kBad), "REC %s",
                           format_duration(r.duration_s).c_str());
    } else {
        if (ImGui::Button((std::string("Start recording (") + key + ")").c_str()))
            a.record_start = true;
        ImGui::SameLine();
        ImGui::TextColored(colors::v4(colors::kDim), "idle");
    }
    if (!r.path.empty()) {
        ImGui::TextColored(colors::v4(colors::kDim), "path");
        ImGui::SameLine();
        ImGui::TextUnformatted(r.path.c_str());
    }
    ImGui::Text("%llu frames  %llu navdata", static_cast<unsigned long long>(r.frames),
                static_cast<unsigned long long>(r.navdata));
    ImGui::SameLine();
    ImGui::TextColored(colors::v4(r.drops ? colors::kWarn : colors::kText), "%llu drops",
                       static_cast<unsigned long long>(r.drops));
    ImGui::Text("disk %s", format_bytes(static_cast<double>(r.disk_bytes)).c_str());
    if (known(r.disk_free_bytes)) {
        ImGui::SameLine();
        ImGui::TextColored(colors::v4(r.disk_free_bytes < 1e9 ? colors::kWarn : colors::kDim),
                           "(%s free)", format_bytes(r.disk_free_bytes).c_str());
    }
    if (!r.error.empty()) ImGui::TextColored(colors::v4(colors::kBad), "%s", r.error.c_str());
    ImGui::End();
}

}  // namespace gs::ui
