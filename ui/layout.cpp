#include "ui/layout.hpp"

#include <imgui_internal.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace gs::ui {

float menu_bar_height() {
    return ImGui::GetFrameHeight();
}

float status_bar_height() {
    // Row 1: the flight buttons (1.9 frame heights); row 2: banners and the latest message.
    const ImGuiStyle& st = ImGui::GetStyle();
    return std::round(ImGui::GetFrameHeight() * 1.9f + ImGui::GetTextLineHeightWithSpacing() +
                      st.WindowPadding.y * 2.0f + st.ItemSpacing.y + 2.0f);
}

float content_top() {
    return menu_bar_height() + status_bar_height();
}

float plot_strip_height(ImVec2 d) {
    const float top = content_top();
    return std::round(std::clamp((d.y - top) * 0.2f, 110.0f, 200.0f));
}

namespace {

Rect flight_rect(const std::string& n, ImVec2 d) {
    const float top = content_top();
    const float strip = plot_strip_height(d);
    if (n == "Flight video") return {0, top, d.x, d.y - strip};
    if (n == "Plot strip") return {0, d.y - strip, d.x, d.y};
    return {};
}

}  // namespace

Rect default_window_rect(const char* w, ImVec2 d, LayoutMode mode) {
    const std::string n = w;
    const float top = content_top();
    const float W = d.x, H = d.y;
    if (mode == LayoutMode::Flight) {
        const Rect r = flight_rect(n, d);
        if (r.w() > 0) return r;
    }
    const float fs = ImGui::GetFontSize();
    const float video_bottom = top + std::round((H - top) * 0.64f);
    // The video window as wide as its 16:9 picture at that height (title bar, toggles and frame
    // line above it), the rest to the panels: a short screen wastes no width around the video.
    const float picture_h = video_bottom - top - ImGui::GetFrameHeight() * 3.2f;
    const float L = std::round(std::clamp(picture_h * 16.0f / 9.0f + 20.0f, W * 0.45f, W * 0.625f));
    const float half = std::round((W - L) * 0.5f);
    // Right column: the connection (source, pilot input) at the top, then "why not flying" beside
    // recording over replay, then the classifier beside telemetry over link.
    const float conn_h = std::round(fs * 10.2f);
    const float row2_top = top + conn_h;
    const float row2_h = std::round(std::max((H - row2_top) * 0.42f, fs * 15.5f));
    const float row3_top = std::min(row2_top + row2_h, H - fs * 6.0f);
    const float rec_h = std::round(fs * 5.6f);
    if (n == "Video") return {0, top, L, video_bottom};
    if (n == "Plots") return {0, video_bottom, L, H};
    if (n == "Connection") return {L, top, W, row2_top};
    if (n == "Why not flying") return {L, row2_top, L + half, row3_top};
    if (n == "Recording") return {L + half, row2_top, W, row2_top + rec_h};
    if (n == "Replay") return {L + half, row2_top + rec_h, W, row3_top};
    if (n == "Classifier") return {L, row3_top, L + half, H};
    const float tel_bottom = row3_top + std::round((H - row3_top) * 0.5f);
    if (n == "Telemetry") return {L + half, row3_top, W, tel_bottom};
    if (n == "Link") return {L + half, tel_bottom, W, H};
    // Over the classifier / telemetry / link column (least needed while calibrating), leaving
    // the video, the connection and the replay controls in view.
    if (n == "Calibration") return {L, row3_top, W, H};
    // Helper windows float over the video, sized for their content, inside the viewport.
    const float cw = std::min(W - 40.0f, fs * 40.0f);
    const float ch = std::min(H - top - 20.0f, fs * 33.0f);
    if (n == "Keys" || n == "Drone settings" || n == "Messages")
        return {std::round((W - cw) * 0.5f), top + 10.0f, std::round((W + cw) * 0.5f),
                top + 10.0f + ch};
    return {40, top + 10, 440, top + 310};
}

Rect keep_inside(const Rect& r, ImVec2 d, float top) {
    const float w = std::clamp(r.w(), 60.0f, d.x);
    const float h = std::clamp(r.h(), 40.0f, std::max(40.0f, d.y - top));
    Rect o;
    o.x0 = std::clamp(r.x0, 0.0f, std::max(0.0f, d.x - w));
    o.y0 = std::clamp(r.y0, top, std::max(top, d.y - h));
    o.x1 = o.x0 + w;
    o.y1 = o.y0 + h;
    return o;
}

void end_layout_frame(ViewState& v) {
    v.drawn_layout = v.settings.layout;
    if (v.reset_layout_frames > 0) --v.reset_layout_frames;
}

void place_window(const char* name, ImVec2 d, ViewState& v) {
    const LayoutMode mode = v.settings.layout;
    const Rect def = default_window_rect(name, d, mode);
    const float top = content_top();
    const bool fixed = mode == LayoutMode::Flight && (std::string_view(name) == "Flight video" ||
                                                      std::string_view(name) == "Plot strip");
    if (fixed || v.reset_layout_frames > 0) {
        ImGui::SetNextWindowPos({def.x0, def.y0}, ImGuiCond_Always);
        ImGui::SetNextWindowSize({def.w(), def.h()}, ImGuiCond_Always);
        v.window_display.insert_or_assign(std::string(name), d);
        return;
    }
    const ImGuiWindow* w = ImGui::FindWindowByName(name);
    if (!w) {  // never seen, not in imgui.ini either
        ImGui::SetNextWindowPos({def.x0, def.y0}, ImGuiCond_FirstUseEver);
        ImGui::SetNextWindowSize({def.w(), def.h()}, ImGuiCond_FirstUseEver);
        return;
    }
    Rect r{w->Pos.x, w->Pos.y, w->Pos.x + w->SizeFull.x, w->Pos.y + w->SizeFull.y};
    // The viewport changed since this window was placed (a resize, or it was hidden meanwhile):
    // it keeps its place relative to the viewport (a window at the right edge stays there),
    // below the fixed bars, which do not scale.
    auto seen = v.window_display.find(std::string_view(name));
    if (seen == v.window_display.end()) seen = v.window_display.emplace(name, d).first;
    const ImVec2 was = seen->second;
    const bool rescaled = was.x > 0 && was.y > top && (was.x != d.x || was.y != d.y);
    if (rescaled) {
        const float sx = d.x / was.x, sy = (d.y - top) / (was.y - top);
        r.x0 *= sx;
        r.x1 *= sx;
        r.y0 = top + (r.y0 - top) * sy;
        r.y1 = top + (r.y1 - top) * sy;
    }
    seen->second = d;
    const Rect in = keep_inside(r, d, top);
    const bool moved = std::fabs(in.x0 - w->Pos.x) > 0.5f || std::fabs(in.y0 - w->Pos.y) > 0.5f;
    const bool resized =
        std::fabs(in.w() - w->SizeFull.x) > 0.5f || std::fabs(in.h() - w->SizeFull.y) > 0.5f;
    if (moved || rescaled) ImGui::SetNextWindowPos({in.x0, in.y0}, ImGuiCond_Always);
    if (resized || rescaled) ImGui::SetNextWindowSize({in.w(), in.h()}, ImGuiCond_Always);
}

}  // namespace gs::ui
