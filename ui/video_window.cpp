#include "ui/windows.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace gs::ui {

namespace {
ImVec2 lerp_img(ImVec2 p0, float sx, float sy, Point2f p) {
    return {p0.x + p.x * sx, p0.y + p.y * sy};
}
}  // namespace

void VideoWindow::draw(const GuiSnapshot& s, ViewState& v, Actions& a, TextureSource* tex) {
    (void)a;
    const bool visible = ImGui::Begin(
        "Video", &v.open.video, ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse);
    {
        const ImVec2 wp = ImGui::GetWindowPos(), ws = ImGui::GetWindowSize();
        v.layout.windows.push_back({"Video", {wp.x, wp.y, wp.x + ws.x, wp.y + ws.y}});
    }
    if (!visible) {
        ImGui::End();
        return;
    }

    // Layer toggles on one line, frame facts on the right.
    OverlayToggles& t = v.settings.overlay;
    bool changed = false;
    changed |= ImGui::Checkbox("Regions", &t.regions);
    ImGui::SameLine();
    changed |= ImGui::Checkbox("Trajectories", &t.trajectories);
    ImGui::SameLine();
    changed |= ImGui::Checkbox("Centre points", &t.center_points);
    ImGui::SameLine();
    changed |= ImGui::Checkbox("Boundaries", &t.boundaries);
    ImGui::SameLine();
    changed |= ImGui::Checkbox("HUD", &t.hud);
    ImGui::SameLine();
    // Undistortion preview: the adapter remaps the frame with the calibration in use and moves
    // the overlay onto it, so straight lines come out straight.
    changed |= ImGui::Checkbox("Undistort", &t.undistort);
    if (changed) v.settings_dirty = true;
    v.layout.undistorted = s.video.undistorted;
    {
        char info[192];
        const char* und = s.video.undistorted ? " | undistorted" : "";
        if (s.video.bgr.empty())
            std::snprintf(info, sizeof info, "%s camera | no frame", s.video.camera.c_str());
        else if (t.undistort && !s.video.undistorted && !s.video.undistort_note.empty())
            std::snprintf(info, sizeof info, "%s camera | frame %lld | raw: %s",
                          s.video.camera.c_str(), static_cast<long long>(s.video.index),
                          s.video.undistort_note.c_str());
        else
            std::snprintf(info, sizeof info, "%s camera | %dx%d | frame %lld%s",
                          s.video.camera.c_str(), s.video.bgr.cols, s.video.bgr.rows,
                          static_cast<long long>(s.video.index), und);
        const float w = ImGui::CalcTextSize(info).x;
        ImGui::SameLine(std::max(ImGui::GetCursorPosX(), ImGui::GetWindowContentRegionMax().x - w));
        ImGui::TextColored(colors::v4(s.video.undistorted ? colors::kInfo : colors::kDim), "%s",
                           info);
    }

    // Aspect-correct image area, centred.
    const ImVec2 avail = ImGui::GetContentRegionAvail();
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    const float img_w = s.video.bgr.empty() ? 640.0f : static_cast<float>(s.video.bgr.cols);
    const float img_h = s.video.bgr.empty() ? 360.0f : static_cast<float>(s.video.bgr.rows);
    const float scale = std::max(0.01f, std::min(avail.x / img_w, avail.y / img_h));
    const ImVec2 size{img_w * scale, img_h * scale};
    const ImVec2 p0{std::floor(origin.x + (avail.x - size.x) * 0.5f),
                    std::floor(origin.y + (avail.y - size.y) * 0.5f)};
    const ImVec2 p1{p0.x + size.x, p0.y + size.y};
    v.layout.video_image = {p0.x, p0.y, p1.x, p1.y};
    ImDrawList* dl = ImGui::GetWindowDrawList();

    ImTextureID id = (tex && !s.video.bgr.empty()) ? tex->video_texture(s.video) : nullptr;
    if (id) {
        dl->AddImage(id, p0, p1);
    } else {
        dl->AddRectFilled(p0, p1, IM_COL32(18, 20, 24, 255));
        const char* msg = s.video.bgr.empty() ? "NO VIDEO" : "video texture unavailable";
        const float fs = ImGui::GetFontSize() * 1.8f;
        const ImVec2 ts = ImGui::GetFont()->CalcTextSizeA(fs, FLT_MAX, 0, msg);
        dl->AddText(ImGui::GetFont(), fs, {0.5f * (p0.x + p1.x - ts.x), p0.y + size.y * 0.68f},
                    colors::kDim, msg);
    }

    // Classifier overlay in image pixels, scaled with the image.
    const Overlay& ov = s.classifier.overlay;
    dl->PushClipRect(p0, p1, true);
    if (t.boundaries) {
        for (const auto& l : ov.boundaries)
            dl->AddLine(lerp_img(p0, scale, scale, l.a), lerp_img(p0, scale, scale, l.b), l.rgba,
                        l.thickness);
    }
    if (t.trajectories) {
        std::vector<ImVec2> pts;
        for (const auto& tr : ov.trajectories) {
            pts.clear();
            for (const auto& p : tr.points) pts.push_back(lerp_img(p0, scale, scale, p));
            if (pts.size() >= 2)
                dl->AddPolyline(pts.data(), static_cast<int>(pts.size()), tr.rgba, 0, tr.thickness);
            if (!pts.empty()) dl->AddCircleFilled(pts.back(), tr.thickness + 1.0f, tr.rgba);
        }
    }
    if (t.center_points) {
        for (const auto& p : ov.center_points)
            dl->AddCircleFilled(lerp_img(p0, scale, scale, p.p), p.radius, p.rgba);
    }
    if (t.regions && !ov.regions.empty()) {
        const float bar_h = std::max(16.0f, size.y * 0.04f);
        for (const auto& r : ov.regions) {
            const ImVec2 b0{p0.x + r.x0 * scale + 1.0f, p0.y + 1.0f};
            const ImVec2 b1{p0.x + r.x1 * scale - 1.0f, p0.y + bar_h};
            const std::uint32_t col =
                r.flagged ? IM_COL32(225, 45, 40, 235) : IM_COL32(40, 185, 80, 215);
            dl->AddRectFilled(b0, b1, col, 2.0f);
            char lbl[96];
            if (known(r.score))
                std::snprintf(lbl, sizeof lbl, "%s %s  %s / %s", r.name.c_str(),
                              r.flagged ? "UNSAFE" : "clear", format_sig(r.score).c_str(),
                              format_sig(r.threshold).c_str());
            else
                std::snprintf(lbl, sizeof lbl, "%s %s", r.name.c_str(),
                              r.flagged ? "UNSAFE" : "clear");
            const ImVec2 ts = ImGui::CalcTextSize(lbl);
            if (ts.x < b1.x - b0.x - 4)
                dl->AddText({0.5f * (b0.x + b1.x - ts.x), 0.5f * (b0.y + b1.y - ts.y)},
                            IM_COL32(255, 255, 255, 255), lbl);
            v.layout.region_bars.push_back({r.name, {b0.x, b0.y, b1.x, b1.y}, r.flagged});
        }
    }
    // Calibration mode: the detected board over the video, and what a capture would do.
    const CalibrationView& cal = s.calibration;
    if (cal.active) {
        v.layout.calibration.corners_drawn = draw_board_corners(dl, p0, scale, cal);
        const std::string key = key_name(v.settings.keymap.key(PilotKey::CalibrationCapture));
        char msg[224];
        std::snprintf(msg, sizeof msg, "CALIBRATION  %s  |  %d views%s%s", cal.status.c_str(),
                      cal.views, cal.adds_coverage ? "  |  press " : "",
                      cal.adds_coverage ? key.c_str() : "");
        const ImVec2 ts = ImGui::CalcTextSize(msg);
        // Above the HUD's bottom strip (fs * 1.9 high, ui/hud.cpp) when the HUD is on.
        const float above = t.hud ? ImGui::GetFontSize() * 1.9f : 0.0f;
        const ImVec2 b0{p0.x + 8, p1.y - above - ts.y - 14};
        dl->AddRectFilled(b0, {b0.x + ts.x + 12, b0.y + ts.y + 6}, IM_COL32(0, 0, 0, 170), 3.0f);
        dl->AddText({b0.x + 6, b0.y + 3},
                    cal.adds_coverage ? colors::kGood
                    : cal.board_found ? colors::kWarn
                                      : colors::kText,
                    msg);
    }
    dl->PopClipRect();

    if (t.hud) hud.draw(dl, p0, p1, s, v);
    ImGui::Dummy(avail);
    ImGui::End();
}

}  // namespace gs::ui
