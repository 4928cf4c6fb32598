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

void VideoWindow::draw(const GuiSnapshot& s, ViewState& v, Actions& a, TextureSource* tex,
                       const char* name, bool fixed) {
    (void)a;
    ImGuiWindowFlags flags = ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoScrollWithMouse;
    if (fixed)
        flags |= ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                 ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoBringToFrontOnFocus |
                 ImGuiWindowFlags_NoSavedSettings;
    const bool visible = ImGui::Begin(name, fixed ? nullptr : &v.open.video, flags);
    {
        const ImVec2 wp = ImGui::GetWindowPos(), ws = ImGui::GetWindowSize();
        v.layout.windows.push_back({name, {wp.x, wp.y, wp.x + ws.x, wp.y + ws.y}});
    }
    if (!visible) {
        ImGui::End();
        return;
    }

    // Layer toggles on one line, frame facts on the right (not in the flight layout: the View
    // menu has the toggles, the picture gets the room).
    OverlayToggles& t = v.settings.overlay;
    bool changed = false;
    if (!fixed) {
        // Each checkbox on the same line as the last when it fits, else on the next one (a narrow
        // window wraps them instead of clipping the last).
        const ImGuiStyle& st = ImGui::GetStyle();
        const float right_edge = ImGui::GetWindowPos().x + ImGui::GetWindowContentRegionMax().x;
        auto same_line_if_fits = [&](const char* next) {
            const float w =
                ImGui::GetFrameHeight() + st.ItemInnerSpacing.x + ImGui::CalcTextSize(next).x;
            if (ImGui::GetItemRectMax().x + st.ItemSpacing.x + w <= right_edge) ImGui::SameLine();
        };
        changed |= ImGui::Checkbox("Regions", &t.regions);
        same_line_if_fits("Trajectories");
        changed |= ImGui::Checkbox("Trajectories", &t.trajectories);
        same_line_if_fits("Centre points");
        changed |= ImGui::Checkbox("Centre points", &t.center_points);
        same_line_if_fits("Boundaries");
        changed |= ImGui::Checkbox("Boundaries", &t.boundaries);
        same_line_if_fits("HUD");
        changed |= ImGui::Checkbox("HUD", &t.hud);
        same_line_if_fits("Undistort");
        // Undistortion preview: the adapter remaps the frame with the calibration in use and moves
        // the overlay onto it, so straight lines come out straight.
        changed |= ImGui::Checkbox("Undistort", &t.undistort);
        const ImVec2 toggles_min = ImGui::GetItemRectMin();
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
            // Right-aligned after the checkboxes when there is room, else on a line of its own
            // (never drawn over the Undistort checkbox).
            const float w = ImGui::CalcTextSize(info).x;
            const ImVec2 toggles_end = ImGui::GetItemRectMax();
            const float right = ImGui::GetWindowContentRegionMax().x - w;
            const float after =
                toggles_end.x - ImGui::GetWindowPos().x + ImGui::GetStyle().ItemSpacing.x;
            if (right >= after) ImGui::SameLine(right);
            ImGui::TextColored(colors::v4(s.video.undistorted ? colors::kInfo : colors::kDim), "%s",
                               info);
            const ImVec2 i0 = ImGui::GetItemRectMin(), i1 = ImGui::GetItemRectMax();
            v.layout.labels.push_back({"video.info", {i0.x, i0.y, i1.x, i1.y}});
            v.layout.labels.push_back(
                {"video.toggles_end",
                 {toggles_end.x, toggles_min.y, toggles_end.x, toggles_end.y}});
        }
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
        const bool stale = s.video.stale;
        for (const auto& r : ov.regions) {
            const ImVec2 b0{p0.x + r.x0 * scale + 1.0f, p0.y + 1.0f};
            const ImVec2 b1{p0.x + r.x1 * scale - 1.0f, p0.y + bar_h};
            // Unknown (too little evidence, stale video, a gap) is grey "no data", never green.
            const bool known_now = r.known && !stale;
            const std::string reason = !r.known ? r.unknown_reason
                                       : stale  ? std::string("video stale")
                                                : std::string();
            // Over the threshold but not (yet) flagged: the classifier waits for its confirmation
            // frames. Neither clear nor unsafe: amber "confirming", never a green bar with a score
            // above its threshold. Still (hovering): nothing approaches, but what stands ahead is
            // not judged. Steel blue "still", never green "clear".
            const RegionShown state =
                region_shown(known_now, r.flagged, r.still, r.score, r.threshold);
            const bool confirming = state == RegionShown::Confirming;
            const bool still = state == RegionShown::Still;
            static constexpr std::uint32_t kBarColours[] = {
                IM_COL32(110, 114, 122, 225), IM_COL32(225, 45, 40, 235),
                IM_COL32(225, 150, 30, 235), IM_COL32(60, 115, 175, 225),
                IM_COL32(40, 185, 80, 215)};
            dl->AddRectFilled(b0, b1, kBarColours[static_cast<std::size_t>(state)], 2.0f);
            // The longest label that fits: "left UNSAFE 0.45 / 0.30", "left 0.45/0.30", "0.45".
            const char* word = shown_word(state);
            const std::string sc = format_score(r.score, r.threshold);
            const std::string th = format_score(r.threshold, r.threshold);
            std::string options[4];
            if (!known_now) {
                options[0] = r.name + " no data";
                options[1] = "no data";
                options[2] = "?";
            } else if (still) {
                // A score of 0 against a threshold says nothing here: the word is the reading.
                options[0] = r.name + " still";
                options[1] = "still";
            } else if (known(r.score)) {
                options[0] = r.name + " " + word + "  " + sc + " / " + th;
                options[1] = r.name + " " + sc + "/" + th;
                options[2] = sc;
            } else {
                options[0] = r.name + " " + word;
                options[1] = word;
            }
            std::string shown;
            for (const auto& o : options) {
                if (o.empty()) continue;
                const ImVec2 ts = ImGui::CalcTextSize(o.c_str());
                if (ts.x < b1.x - b0.x - 6) {
                    dl->AddText({0.5f * (b0.x + b1.x - ts.x), 0.5f * (b0.y + b1.y - ts.y)},
                                IM_COL32(255, 255, 255, 255), o.c_str());
                    shown = o;
                    break;
                }
            }
            if ((!reason.empty() || still) && ImGui::IsMouseHoveringRect(b0, b1) &&
                ImGui::IsWindowHovered(ImGuiHoveredFlags_AllowWhenBlockedByPopup)) {
                const std::string tip = still ? r.name + ": still - " + kStillMeaning
                                              : r.name + ": no data - " + reason;
                ImGui::SetTooltip("%s", tip.c_str());
                v.layout.tooltip = tip;
            }
            LayoutReport::Bar bar;
            bar.name = r.name;
            bar.rect = {b0.x, b0.y, b1.x, b1.y};
            bar.flagged = known_now && r.flagged;
            bar.known = known_now;
            bar.confirming = confirming;
            bar.still = still;
            bar.reason = reason;
            bar.label = shown;
            v.layout.region_bars.push_back(std::move(bar));
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
    // A frozen picture says so: past kStaleAfterMs the newest frame is too old to fly by.
    if (s.video.stale && !s.video.bgr.empty()) {
        char msg[64];
        std::snprintf(msg, sizeof msg, "VIDEO STALE %.1f s", s.video.age_ms / 1000.0);
        const float fs = ImGui::GetFontSize() * 2.0f;
        const ImVec2 ts = ImGui::GetFont()->CalcTextSizeA(fs, FLT_MAX, 0, msg);
        const ImVec2 c{0.5f * (p0.x + p1.x), p0.y + size.y * 0.36f};
        const ImVec2 m0{c.x - ts.x * 0.5f - 14, c.y - ts.y * 0.5f - 8};
        const ImVec2 m1{c.x + ts.x * 0.5f + 14, c.y + ts.y * 0.5f + 8};
        dl->AddRectFilled(p0, p1, IM_COL32(20, 20, 24, 110));
        dl->AddRectFilled(m0, m1, IM_COL32(0, 0, 0, 200), 4.0f);
        dl->AddRect(m0, m1, colors::kWarn, 4.0f, 0, 2.0f);
        dl->AddText(ImGui::GetFont(), fs, {m0.x + 14, m0.y + 8}, colors::kWarn, msg);
        v.layout.video_stale_text = msg;
    }
    // A replay is unmistakable: an orange frame and its name over the picture.
    if (s.connection.state == LinkState::Replay) {
        dl->AddRect(p0, p1, IM_COL32(230, 120, 20, 255), 0.0f, 0, 4.0f);
        const char* tag = "REPLAY";
        const ImVec2 ts = ImGui::CalcTextSize(tag);
        const ImVec2 r0{p1.x - ts.x - 18,
                        p1.y - ts.y - (t.hud ? ImGui::GetFontSize() * 1.9f : 0) - 12};
        dl->AddRectFilled(r0, {r0.x + ts.x + 12, r0.y + ts.y + 6}, IM_COL32(230, 120, 20, 230),
                          3.0f);
        dl->AddText({r0.x + 6, r0.y + 3}, IM_COL32(255, 255, 255, 255), tag);
    }
    ImGui::Dummy(avail);
    ImGui::End();
}

}  // namespace gs::ui
