// The status bar: fixed under the menu bar, the full width of the window, never scrolled, moved
// or closed. Row 1: the source (LIVE DRONE / VIRTUAL DRONE / REPLAY, each its own colour), the
// flight state, the battery, the link's quality and age, the video's rate and age, REC with its
// elapsed time and dataset; on the right Take off, Land and EMERGENCY, always there. Row 2: the
// banners (low battery, link lost, emergency, stale video) and the latest message, the log one
// click away. What a QGroundControl user looks for in its toolbar.
#include "ui/controls.hpp"
#include "ui/layout.hpp"
#include "ui/windows.hpp"

#include <imgui_internal.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace gs::ui {

namespace {

constexpr ImGuiWindowFlags kFixed = ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize |
                                    ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoScrollbar |
                                    ImGuiWindowFlags_NoScrollWithMouse |
                                    ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings |
                                    ImGuiWindowFlags_NoFocusOnAppearing;

// A filled rounded badge with centred text, as one item (hover-able).
void badge(const char* text, std::uint32_t bg, std::uint32_t fg, float h, float pad = 10.0f) {
    const ImVec2 ts = ImGui::CalcTextSize(text);
    const ImVec2 p = ImGui::GetCursorScreenPos();
    const ImVec2 sz{ts.x + pad * 2, h};
    ImDrawList* dl = ImGui::GetWindowDrawList();
    dl->AddRectFilled(p, {p.x + sz.x, p.y + sz.y}, bg, 4.0f);
    dl->AddText({p.x + pad, p.y + (h - ts.y) * 0.5f}, fg, text);
    ImGui::Dummy(sz);
}

// Label (dim) and value (coloured) on one line, vertically centred in a row of height h.
void field(const char* label, const char* value, std::uint32_t col, float h) {
    const ImVec2 p = ImGui::GetCursorScreenPos();
    const ImVec2 ls = ImGui::CalcTextSize(label), vs = ImGui::CalcTextSize(value);
    ImDrawList* dl = ImGui::GetWindowDrawList();
    const float y = p.y + (h - ls.y) * 0.5f;
    dl->AddText({p.x, y}, colors::kDim, label);
    dl->AddText({p.x + ls.x + 5.0f, y}, col, value);
    ImGui::Dummy({ls.x + 5.0f + vs.x, h});
}

float field_width(const char* label, const char* value) {
    return ImGui::CalcTextSize(label).x + 5.0f + ImGui::CalcTextSize(value).x;
}

// Four signal bars, `q` of them lit.
void quality_bars(int q, std::uint32_t col, float h) {
    const ImVec2 p = ImGui::GetCursorScreenPos();
    ImDrawList* dl = ImGui::GetWindowDrawList();
    const float bw = 4.0f, gap = 2.0f, full = h * 0.55f, base = p.y + (h + full) * 0.5f;
    for (int i = 0; i < 4; ++i) {
        const float bh = full * static_cast<float>(i + 1) / 4.0f;
        const float x = p.x + static_cast<float>(i) * (bw + gap);
        dl->AddRectFilled({x, base - bh}, {x + bw, base}, i < q ? col : IM_COL32(70, 74, 82, 255));
    }
    ImGui::Dummy({4 * (bw + gap), h});
}

std::uint32_t level_color(LogLevel l) {
    switch (l) {
        case LogLevel::Ok:
            return colors::kGood;
        case LogLevel::Warn:
            return colors::kWarn;
        case LogLevel::Error:
            return colors::kBad;
        case LogLevel::Info:
            break;
    }
    return colors::kText;
}

// A flight button; disabled with the reason as tooltip. Returns true when clicked. With
// `through_popups`, a press on it while a menu or combo is open acts at once (ImGui would spend
// that click closing the menu): one click lands or cuts the motors, whatever is open.
bool flight_button(ViewState& v, const char* id, const std::string& label, ImVec2 size,
                   const ControlState& cs, std::uint32_t color = 0, bool through_popups = false) {
    const bool popup_open = GImGui->OpenPopupStack.Size > 0;
    if (!cs.enabled) ImGui::BeginDisabled();
    if (color) {
        const ImVec4 c = colors::v4(color);
        auto lit = [&](float k) {
            return ImVec4{std::min(1.0f, c.x * k), std::min(1.0f, c.y * k), std::min(1.0f, c.z * k),
                          c.w};
        };
        ImGui::PushStyleColor(ImGuiCol_Button, c);
        ImGui::PushStyleColor(ImGuiCol_ButtonHovered, lit(1.25f));
        ImGui::PushStyleColor(ImGuiCol_ButtonActive, lit(1.45f));
    }
    bool clicked = ImGui::Button((label + "##" + id).c_str(), size);
    if (color) ImGui::PopStyleColor(3);
    if (!cs.enabled) ImGui::EndDisabled();
    record_button(v, id);
    if (through_popups && popup_open && ImGui::IsMouseClicked(ImGuiMouseButton_Left) &&
        ImGui::IsMouseHoveringRect(ImGui::GetItemRectMin(), ImGui::GetItemRectMax()))
        clicked = true;
    note_disabled(v, id, cs);
    return clicked && cs.enabled;
}

}  // namespace

void StatusBar::draw(const GuiSnapshot& s, ViewState& v, Actions& a) {
    const ImVec2 d = ImGui::GetIO().DisplaySize;
    const float top = menu_bar_height(), h = status_bar_height();
    ImGui::SetNextWindowPos({0, top}, ImGuiCond_Always);
    ImGui::SetNextWindowSize({d.x, h}, ImGuiCond_Always);
    ImGui::PushStyleVar(ImGuiStyleVar_WindowRounding, 0.0f);
    ImGui::PushStyleColor(ImGuiCol_WindowBg, colors::v4(IM_COL32(24, 27, 32, 255)));
    const bool visible = ImGui::Begin("##status_bar", nullptr, kFixed);
    ImGui::PopStyleColor();
    ImGui::PopStyleVar();
    {
        const ImVec2 wp = ImGui::GetWindowPos(), ws = ImGui::GetWindowSize();
        v.layout.windows.push_back({"Status bar", {wp.x, wp.y, wp.x + ws.x, wp.y + ws.y}});
    }
    if (!visible) {
        ImGui::End();
        return;
    }
    LayoutReport::Status& out = v.layout.status;
    const Keymap& km = v.settings.keymap;
    const float fs = ImGui::GetFontSize();
    const float row_h = std::round(ImGui::GetFrameHeight() * 1.9f);
    const float sp = ImGui::GetStyle().ItemSpacing.x;
    char buf[256];

    // ---- Right: the flight buttons, sized first so nothing can push them off -------------
    const ControlState take = control_state(s, Control::Takeoff);
    const ControlState land = control_state(s, Control::Land);
    const ControlState emer = control_state(s, Control::Emergency);
    const bool in_emergency = s.telemetry.state && s.telemetry.state->emergency;
    auto with_key = [&](const char* text, PilotKey k) {
        const std::string key = key_name(km.key(k));
        return key.empty() ? std::string(text) : std::string(text) + " (" + key + ")";
    };
    const std::string take_l = with_key("Take off", PilotKey::Takeoff);
    const std::string land_l = with_key("Land", PilotKey::Land);
    const std::string emer_l =
        with_key(in_emergency ? "RESET EMERGENCY" : "EMERGENCY", PilotKey::Emergency);
    const float pad = ImGui::GetStyle().FramePadding.x * 2 + fs * 0.8f;
    const float bw_take = ImGui::CalcTextSize(take_l.c_str()).x + pad;
    const float bw_land = ImGui::CalcTextSize(land_l.c_str()).x + pad;
    const float bw_emer = std::max(ImGui::CalcTextSize(emer_l.c_str()).x + pad, fs * 9.5f);
    const float buttons_w = bw_take + bw_land + bw_emer + sp * 2 + fs;
    const float x_right = ImGui::GetWindowContentRegionMax().x - buttons_w;

    // ---- Left: source, state, battery, link, video, REC (dropped from the end if narrow) ---
    const float x0 = ImGui::GetCursorPosX();
    const SourceBadge sb = source_badge(s);
    badge(sb.text.c_str(), sb.background, IM_COL32(255, 255, 255, 255), row_h);
    out.source = sb.text;
    out.source_color = sb.background;
    if (ImGui::IsItemHovered()) {
        const ConnectionInfo& c = s.connection;
        std::string tip = c.state == LinkState::Replay  ? "Replaying " + c.address
                          : c.source == SourceKind::Sim ? "Virtual drone, scenario " + c.scenario
                                                        : "Drone at " + c.address;
        if (!c.activity.empty()) tip += "\n" + c.activity;
        ImGui::SetTooltip("%s", tip.c_str());
    }
    ImGui::SameLine(0, sp * 1.5f);
    const FlightStateView fsv = flight_state(s);
    {
        const float big = fs * 1.3f;
        const ImVec2 p = ImGui::GetCursorScreenPos();
        const ImVec2 ts = ImGui::GetFont()->CalcTextSizeA(big, FLT_MAX, 0, fsv.text.c_str());
        ImGui::GetWindowDrawList()->AddText(
            ImGui::GetFont(), big, {p.x, p.y + (row_h - ts.y) * 0.5f}, fsv.color, fsv.text.c_str());
        ImGui::Dummy({ts.x, row_h});
    }
    out.state = fsv.text;
    // The assist's toggle: always there with a source, one click switches it (and only a click
    // on it: Escape and clicks elsewhere leave it as it is).
    if (s.assist.available) {
        ImGui::SameLine(0, sp * 1.5f);
        const std::string key = key_name(km.key(PilotKey::AssistToggle));
        const std::string label = std::string(s.assist.enabled ? "ASSIST ON" : "ASSIST OFF") +
                                  (key.empty() ? "" : " (" + key + ")");
        const ImVec4 c =
            colors::v4(s.assist.enabled ? IM_COL32(30, 120, 60, 255) : IM_COL32(150, 100, 20, 255));
        ImGui::PushStyleColor(ImGuiCol_Button, c);
        ImGui::PushStyleColor(ImGuiCol_ButtonHovered,
                              ImVec4{std::min(1.0f, c.x * 1.25f), std::min(1.0f, c.y * 1.25f),
                                     std::min(1.0f, c.z * 1.25f), 1.0f});
        const float y = ImGui::GetCursorPosY();
        ImGui::SetCursorPosY(y + (row_h - ImGui::GetFrameHeight()) * 0.5f);
        if (ImGui::Button((label + "##assist").c_str())) a.assist_toggle = true;
        ImGui::PopStyleColor(2);
        record_button(v, "status.assist");
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip(
                "Collision assist: brakes and blocks moves toward obstacles the classifier "
                "reports.\nClick or %s: on / off. Hold %s: bypass it.%s",
                key.c_str(), key_name(km.key(PilotKey::AssistOverride)).c_str(),
                s.assist.dry_run ? "\nReplay: a dry run, nothing is sent." : "");
        out.assist = label;
        v.layout.assist.toggle = label;
    }
    if (!s.connection.activity.empty()) {
        ImGui::SameLine(0, sp * 1.5f);
        const std::string act = s.connection.activity;
        if (ImGui::GetCursorPosX() + ImGui::CalcTextSize(act.c_str()).x < x_right) {
            field("", act.c_str(), colors::kWarn, row_h);
            out.activity = act;
        }
    }

    // Where the last field ends (window coordinates): after an item ImGui's cursor sits at the
    // start of the next line until SameLine, so GetCursorPosX() would say there is always room.
    auto line_end = [] { return ImGui::GetItemRectMax().x - ImGui::GetWindowPos().x; };
    auto fits = [&](float w) { return line_end() + sp * 2 + w < x_right; };
    // Battery.
    const Telemetry& t = s.telemetry;
    const double bat = t.valid ? t.nav.battery_pct : kUnknown;
    const bool bat_low =
        (known(bat) && bat < t.battery_low_pct) || (t.state && t.state->battery_low);
    if (known(bat))
        std::snprintf(buf, sizeof buf, "%.0f %%", bat);
    else
        std::snprintf(buf, sizeof buf, "---");
    out.battery = buf;
    if (fits(field_width("BAT", buf))) {
        ImGui::SameLine(0, sp * 2);
        field("BAT", buf,
              !known(bat) ? colors::kDim
              : bat_low   ? colors::kBad
              : bat < 40  ? colors::kWarn
                          : colors::kGood,
              row_h);
    }
    // Link: quality bars, navdata rate and age.
    const bool live =
        s.connection.state == LinkState::Connected || s.connection.state == LinkState::Lost;
    if (live) {
        const int q = link_quality(s);
        const StreamHealth& n = s.link.navdata;
        if (s.connection.state == LinkState::Lost)
            std::snprintf(buf, sizeof buf, "LOST %.1f s", n.age_ms / 1000.0);
        else if (known(n.rate_hz) && known(n.age_ms))
            std::snprintf(buf, sizeof buf, "%.0f Hz  %.0f ms", n.rate_hz, n.age_ms);
        else
            std::snprintf(buf, sizeof buf, "---");
        out.link = buf;
        const std::uint32_t col = q >= 3 ? colors::kGood : q == 2 ? colors::kWarn : colors::kBad;
        if (fits(field_width("LINK", buf) + 30)) {
            ImGui::SameLine(0, sp * 2);
            field("LINK", "", col, row_h);
            ImGui::SameLine(0, 2);
            quality_bars(q, col, row_h);
            ImGui::SameLine(0, 5);
            field("", buf, col, row_h);
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip(
                    "navdata %.1f of %.0f packets/s expected, newest %.0f ms ago",
                    known(n.rate_hz) ? n.rate_hz : 0.0,
                    known(s.link.expected_navdata_hz) ? s.link.expected_navdata_hz : 15.0,
                    known(n.age_ms) ? n.age_ms : 0.0);
        }
    }
    // Video: rate and age of the newest frame.
    if (s.connection.state != LinkState::Disconnected) {
        const VideoFrame& vf = s.video;
        if (vf.bgr.empty())
            std::snprintf(buf, sizeof buf, "none");
        else if (vf.stale)
            std::snprintf(buf, sizeof buf, "STALE %.1f s", vf.age_ms / 1000.0);
        else if (known(vf.age_ms))
            std::snprintf(buf, sizeof buf, "%.0f fps  %.0f ms", known(vf.fps) ? vf.fps : 0.0,
                          vf.age_ms);
        else
            std::snprintf(buf, sizeof buf, "%.0f fps", known(vf.fps) ? vf.fps : 0.0);
        out.video = buf;
        if (fits(field_width("VIDEO", buf))) {
            ImGui::SameLine(0, sp * 2);
            field("VIDEO", buf, vf.stale || vf.bgr.empty() ? colors::kWarn : colors::kText, row_h);
        }
    }
    // REC: elapsed time and where it goes.
    if (s.recording.active) {
        const std::string dur = format_duration(s.recording.duration_s);
        out.rec = "REC " + dur + " " + s.recording.path;
        const float need = field_width("REC", dur.c_str()) + 16;
        if (fits(need)) {
            ImGui::SameLine(0, sp * 2);
            const ImVec2 p = ImGui::GetCursorScreenPos();
            ImGui::GetWindowDrawList()->AddCircleFilled({p.x + 6, p.y + row_h * 0.5f}, 6.0f,
                                                        colors::kBad);
            ImGui::Dummy({14, row_h});
            ImGui::SameLine(0, 4);
            field("REC", dur.c_str(), colors::kBad, row_h);
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip("recording to %s", s.recording.path.c_str());
            // The dataset path, cut to the room left.
            const float room = x_right - line_end() - sp * 4;
            std::string path = s.recording.path;
            if (room > fs * 4) {
                while (path.size() > 4 && ImGui::CalcTextSize(path.c_str()).x > room)
                    path = "..." + path.substr(std::min<std::size_t>(path.size(), 8));
                ImGui::SameLine(0, sp);
                field("", path.c_str(), colors::kDim, row_h);
            }
        }
    }
    {
        // The left block as drawn (screen coordinates), for the layout checks: it must end
        // before the flight buttons begin.
        const ImVec2 w = ImGui::GetWindowPos();
        v.layout.labels.push_back({"status.left",
                                   {w.x + x0, ImGui::GetItemRectMin().y, ImGui::GetItemRectMax().x,
                                    ImGui::GetItemRectMax().y}});
    }

    // ---- The flight buttons -----------------------------------------------------------------
    ImGui::SameLine(std::max(x_right + fs, ImGui::GetCursorPosX() + sp));
    const float by = ImGui::GetCursorPosY();
    if (flight_button(v, "flight.takeoff", take_l, {bw_take, row_h}, take)) a.takeoff = true;
    ImGui::SameLine();
    ImGui::SetCursorPosY(by);
    if (flight_button(v, "flight.land", land_l, {bw_land, row_h}, land, IM_COL32(40, 95, 160, 255),
                      true))
        a.land = true;
    ImGui::SameLine();
    ImGui::SetCursorPosY(by);
    if (flight_button(v, "flight.emergency", emer_l, {bw_emer, row_h}, emer,
                      IM_COL32(185, 30, 25, 255), true))
        a.emergency = true;
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(in_emergency ? "The drone is in emergency: press once to reset it"
                                       : "Cuts the motors at once: the drone falls");

    // ---- Row 2: banners, the latest message, the log -----------------------------------------
    std::vector<std::pair<std::string, std::uint32_t>> banners;
    if (bat_low) {
        std::snprintf(buf, sizeof buf, "LOW BATTERY %s - land now",
                      known(bat) ? (std::to_string(static_cast<int>(bat)) + " %").c_str() : "");
        banners.push_back({buf, colors::kBad});
    }
    if (s.connection.state == LinkState::Lost) banners.push_back({"LINK LOST", colors::kBad});
    if (in_emergency)
        banners.push_back(
            {t.emergency_commanded ? "EMERGENCY (commanded)" : "EMERGENCY", colors::kBad});
    if (s.video.stale) banners.push_back({"VIDEO STALE", colors::kWarn});
    std::size_t assist_at = SIZE_MAX;  // the assist's banner among them
    if (s.assist.available && (s.assist.acting || s.assist.unknown || s.assist.confirming ||
                               s.assist.override_held || !s.assist.enabled)) {
        assist_at = banners.size();
        banners.push_back({s.assist.line, s.assist.acting ? colors::kBad : colors::kWarn});
    }
    if (v.leave_after_landing.pending())
        banners.push_back({std::string("LANDING, THEN ") + leave_verb(v.leave_after_landing.kind),
                           colors::kWarn});
    std::snprintf(buf, sizeof buf, "Log (%zu)", s.messages.size());
    const float log_w = ImGui::CalcTextSize(buf).x + ImGui::GetStyle().FramePadding.x * 2;
    const float log_x = ImGui::GetWindowContentRegionMax().x - log_w;
    if (assist_at != SIZE_MAX) {
        // The banners end before the Log button: an assist line too long for the room left (a
        // small window, a side's steering with a brake pending) is said in its action words
        // ("STEERING LEFT; BRAKE PENDING"), cut short only if even they do not fit; the whole
        // line is the banner's tooltip and in the HUD.
        const float item_sp = ImGui::GetStyle().ItemSpacing.x;
        float others = 0;
        for (std::size_t i = 0; i < banners.size(); ++i)
            if (i != assist_at)
                others += ImGui::CalcTextSize(banners[i].first.c_str()).x + 16.0f + item_sp;
        if (v.leave_after_landing.pending())
            others +=
                ImGui::CalcTextSize("Cancel").x + ImGui::GetStyle().FramePadding.x * 2 + item_sp;
        const float room = log_x - ImGui::GetCursorPosX() - others - 16.0f - sp * 2;
        std::string& text = banners[assist_at].first;
        if (ImGui::CalcTextSize(text.c_str()).x > room && !s.assist.brief.empty())
            text = s.assist.brief;
        if (ImGui::CalcTextSize(text.c_str()).x > room) {
            while (text.size() > 1 && ImGui::CalcTextSize((text + "...").c_str()).x > room)
                text.pop_back();
            text += "...";
        }
        v.layout.assist.banner = text;
    }
    const float row2_h = ImGui::GetTextLineHeight() + 2.0f;
    for (std::size_t i = 0; i < banners.size(); ++i) {
        const auto& [text, col] = banners[i];
        badge(text.c_str(), col, IM_COL32(255, 255, 255, 255), row2_h, 8.0f);
        if (i == assist_at) {
            if (ImGui::IsItemHovered() && text != s.assist.line)
                ImGui::SetTooltip("%s", s.assist.line.c_str());
            const ImVec2 r0 = ImGui::GetItemRectMin(), r1 = ImGui::GetItemRectMax();
            v.layout.labels.push_back({"status.assist_banner", {r0.x, r0.y, r1.x, r1.y}});
        }
        out.banners.push_back(text);
        ImGui::SameLine();
    }
    if (v.leave_after_landing.pending()) {
        if (ImGui::SmallButton("Cancel##leave")) {
            a.notes.push_back(std::string("cancelled: ") + leave_verb(v.leave_after_landing.kind) +
                              " after landing");
            v.leave_after_landing = {};
            v.quit_after_landing = false;
        }
        ImGui::SameLine();
    }
    const float msg_room = log_x - ImGui::GetCursorPosX() - sp * 2;
    if (!s.messages.empty() && msg_room > fs * 3) {
        const LogLine& m = s.messages.back();
        std::string text = m.text;
        const float room = msg_room;
        if (ImGui::CalcTextSize(text.c_str()).x > room) {
            while (text.size() > 1 && ImGui::CalcTextSize((text + "...").c_str()).x > room)
                text.pop_back();
            text += "...";
        }
        ImGui::TextColored(colors::v4(level_color(m.level)), "%s", text.c_str());
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", m.text.c_str());
        if (ImGui::IsItemClicked()) {
            v.open.messages = true;
            v.messages_scroll_to_end = true;
        }
        out.message = m.text;
        ImGui::SameLine();
    }
    ImGui::SetCursorPosX(log_x);
    if (ImGui::SmallButton(buf)) {
        v.open.messages = !v.open.messages;
        v.messages_scroll_to_end = v.open.messages;
    }
    record_button(v, "status.log");
    ImGui::End();
}

}  // namespace gs::ui
