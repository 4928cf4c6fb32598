// The Calibration window: the camera calibration mode (issue 8) on the live or replayed video.
// Drawing only: it shows what the session's calibration worker reports (GuiSnapshot::calibration)
// and asks for start / capture / undo / reset / auto capture / save through Actions. Whether a
// capture is kept (board found, sharp, adds coverage) is decided by vision::CalibrationSession
// in the worker, never here. The mode runs while the window is open (Gui::frame starts and stops
// it).
#include "ui/windows.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace gs::ui {

namespace {

std::uint32_t board_colour(const CalibrationView& c) {
    if (c.adds_coverage) return colors::kGood;
    if (c.board_found) return colors::kWarn;
    return colors::kBad;  // blurry: corners shown, not usable
}

// Cell colour by how many kept views cover it.
std::uint32_t cell_colour(int n) {
    if (n <= 0) return 0;
    const int a = std::min(200, 70 + 45 * n);
    return IM_COL32(70, 200, 100, a);
}

void draw_coverage_map(const GuiSnapshot& s, ViewState& v, TextureSource* tex) {
    const CalibrationView& c = s.calibration;
    const float iw = c.image_w > 0         ? static_cast<float>(c.image_w)
                     : s.video.bgr.empty() ? 640.0f
                                           : static_cast<float>(s.video.bgr.cols);
    const float ih = c.image_h > 0         ? static_cast<float>(c.image_h)
                     : s.video.bgr.empty() ? 360.0f
                                           : static_cast<float>(s.video.bgr.rows);
    const ImVec2 avail = ImGui::GetContentRegionAvail();
    const float w = std::max(80.0f, std::min(avail.x, ImGui::GetFontSize() * 24.0f));
    const float scale = w / iw;
    const ImVec2 p0 = ImGui::GetCursorScreenPos();
    const ImVec2 p1{p0.x + w, p0.y + ih * scale};
    ImDrawList* dl = ImGui::GetWindowDrawList();
    dl->AddRectFilled(p0, p1, IM_COL32(14, 16, 20, 255));
    // The raw video underneath, dimmed (the map is in raw image pixels: not under the preview).
    const bool raw_video =
        !s.video.bgr.empty() && !s.video.undistorted && static_cast<float>(s.video.bgr.cols) == iw;
    if (tex && raw_video)
        if (ImTextureID id = tex->video_texture(s.video))
            dl->AddImage(id, p0, p1, {0, 0}, {1, 1}, IM_COL32(255, 255, 255, 90));
    if (c.grid_cols > 0 && c.grid_rows > 0 &&
        c.coverage.size() == static_cast<std::size_t>(c.grid_cols * c.grid_rows)) {
        const float cw = w / static_cast<float>(c.grid_cols);
        const float ch = (p1.y - p0.y) / static_cast<float>(c.grid_rows);
        for (int r = 0; r < c.grid_rows; ++r)
            for (int col = 0; col < c.grid_cols; ++col) {
                const int n = c.coverage[static_cast<std::size_t>(r * c.grid_cols + col)];
                const ImVec2 a{p0.x + cw * static_cast<float>(col),
                               p0.y + ch * static_cast<float>(r)};
                const ImVec2 b{a.x + cw, a.y + ch};
                if (n > 0)
                    dl->AddRectFilled({a.x + 1, a.y + 1}, {b.x - 1, b.y - 1}, cell_colour(n));
                dl->AddRect(a, b, IM_COL32(255, 255, 255, 22));
            }
    }
    // Where the board is now (its outer corners), in the same raw pixels.
    const std::size_t n = c.corners.size();
    const auto cols = static_cast<std::size_t>(std::max(1, c.board_cols));
    if (!s.video.undistorted && n >= 4 && n == cols * static_cast<std::size_t>(c.board_rows)) {
        const Point2f q[4] = {c.corners[0], c.corners[cols - 1], c.corners[n - 1],
                              c.corners[n - cols]};
        ImVec2 poly[4];
        for (int i = 0; i < 4; ++i) poly[i] = {p0.x + q[i].x * scale, p0.y + q[i].y * scale};
        dl->AddPolyline(poly, 4, board_colour(c), ImDrawFlags_Closed, 2.0f);
    }
    if (c.views == 0) {
        const char* msg = "coverage map: no views kept yet";
        const ImVec2 ts = ImGui::CalcTextSize(msg);
        dl->AddText({0.5f * (p0.x + p1.x - ts.x), 0.5f * (p0.y + p1.y - ts.y)}, colors::kDim, msg);
    }
    dl->AddRect(p0, p1, IM_COL32(90, 96, 108, 255));
    v.layout.calibration.coverage_map = {p0.x, p0.y, p1.x, p1.y};
    ImGui::Dummy({w, p1.y - p0.y});
}

}  // namespace

int draw_board_corners(ImDrawList* dl, ImVec2 p0, float scale, const CalibrationView& c) {
    const std::size_t n = c.corners.size();
    const auto cols = static_cast<std::size_t>(std::max(1, c.board_cols));
    if (n == 0) return 0;
    const std::uint32_t col = board_colour(c);
    auto at = [&](std::size_t i) {
        return ImVec2{p0.x + c.corners[i].x * scale, p0.y + c.corners[i].y * scale};
    };
    // Rows joined (as cv::drawChessboardCorners does), so a bent row shows the distortion.
    for (std::size_t r = 0; r * cols < n; ++r) {
        for (std::size_t k = 1; k < cols && r * cols + k < n; ++k)
            dl->AddLine(at(r * cols + k - 1), at(r * cols + k), col, 1.5f);
        if (r > 0)
            dl->AddLine(at((r - 1) * cols + cols - 1), at(r * cols), IM_COL32(255, 255, 255, 60),
                        1.0f);
    }
    for (std::size_t i = 0; i < n; ++i) dl->AddCircle(at(i), 3.5f, col, 10, 1.5f);
    dl->AddCircleFilled(at(0), 5.0f, IM_COL32(255, 255, 255, 230));  // the board's origin
    return static_cast<int>(n);
}

void CalibrationWindow::draw(const GuiSnapshot& s, ViewState& v, Actions& a, TextureSource* tex) {
    const bool visible = ImGui::Begin("Calibration", &v.open.calibration);
    {
        const ImVec2 wp = ImGui::GetWindowPos(), ws = ImGui::GetWindowSize();
        v.layout.windows.push_back({"Calibration", {wp.x, wp.y, wp.x + ws.x, wp.y + ws.y}});
    }
    if (!visible) {
        ImGui::End();
        return;
    }
    const CalibrationView& c = s.calibration;
    CalibrationUiState& u = v.calib;
    LayoutReport::Calibration& lc = v.layout.calibration;
    lc.drawn = true;
    lc.views = c.views;
    lc.rms_px = c.rms_px;
    lc.status = c.status;

    // Board: inner corners and square size, as `ardrone-gs calibrate --board 9x6 --square 0.05`.
    const float fw = ImGui::GetFontSize() * 5.5f;
    ImGui::AlignTextToFramePadding();
    ImGui::TextUnformatted("Board");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(fw);
    ImGui::InputInt("##cols", &u.cols);
    ImGui::SameLine();
    ImGui::TextUnformatted("x");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(fw);
    ImGui::InputInt("##rows", &u.rows);
    ImGui::SameLine();
    ImGui::TextColored(colors::v4(colors::kDim), "inner corners");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(fw);
    ImGui::InputFloat("mm squares##square", &u.square_mm, 0, 0, "%.1f");
    u.cols = std::clamp(u.cols, 3, 100);
    u.rows = std::clamp(u.rows, 3, 100);
    u.square_mm = std::clamp(u.square_mm, 1.0f, 2000.0f);
    const bool differs =
        c.active && (u.cols != c.board_cols || u.rows != c.board_rows ||
                     std::fabs(static_cast<double>(u.square_mm) / 1000.0 - c.square_m) > 1e-7);
    if (differs) {
        ImGui::SameLine();
        if (ImGui::Button(c.views > 0 ? "Use this board (forgets the views)" : "Use this board")) {
            a.calibration_start = Actions::CalibrationBoard{
                u.cols, u.rows, static_cast<double>(u.square_mm) / 1000.0};
            u.start_sent = true;
        }
    }

    // What the worker sees in the video now.
    const std::uint32_t scol = !c.active         ? colors::kDim
                               : c.adds_coverage ? colors::kGood
                               : c.board_found   ? colors::kWarn
                                                 : colors::kDim;
    ImGui::TextColored(colors::v4(scol), "%s", c.status.c_str());
    if (c.active && known(c.detect_ms)) {
        ImGui::SameLine();
        ImGui::TextColored(colors::v4(colors::kDim), "(frame %lld, %.0f ms)",
                           static_cast<long long>(c.frame), c.detect_ms);
    }

    // Capture / undo / reset / auto.
    const std::string cap =
        "Capture (" + key_name(v.settings.keymap.key(PilotKey::CalibrationCapture)) + ")";
    if (ImGui::Button(cap.c_str())) a.calibration_capture = true;
    record_button(v, "calibration.capture");
    ImGui::SameLine();
    if (ImGui::Button("Undo last")) a.calibration_undo = true;
    ImGui::SameLine();
    if (ImGui::Button("Reset")) a.calibration_reset = true;
    ImGui::SameLine();
    bool autocap = c.active ? c.auto_capture : u.auto_capture;
    if (ImGui::Checkbox("Auto capture", &autocap)) {
        a.calibration_auto = autocap;
        u.auto_capture = autocap;
    }
    if (!c.last_capture.empty())
        ImGui::TextColored(colors::v4(c.last_capture_kept ? colors::kGood : colors::kWarn), "%s",
                           c.last_capture.c_str());

    // Views and the running error.
    if (known(c.rms_px))
        ImGui::Text("Views %d   RMS error %.3f px", c.views, c.rms_px);
    else
        ImGui::Text("Views %d   RMS error after %d views", c.views, c.min_views);
    ImGui::SameLine();
    ImGui::TextColored(colors::v4(colors::kDim), "  coverage %.0f %%, %d/4 corners",
                       100.0 * c.coverage_fraction, c.corner_regions);

    // Coverage map, with the numbers beside it.
    draw_coverage_map(s, v, tex);
    ImGui::SameLine();
    ImGui::BeginGroup();
    if (c.has_result) {
        ImGui::Text("fx %.1f  fy %.1f", c.fx, c.fy);
        ImGui::Text("cx %.1f  cy %.1f", c.cx, c.cy);
        ImGui::Text("k1 %+.4f  k2 %+.4f", c.dist[0], c.dist[1]);
        ImGui::Text("p1 %+.4f  p2 %+.4f", c.dist[2], c.dist[3]);
        ImGui::Text("k3 %+.4f", c.dist[4]);
    } else {
        ImGui::TextColored(colors::v4(colors::kDim), "no calibration yet");
    }
    if (!c.result_error.empty()) {
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextColored(colors::v4(colors::kWarn), "%s", c.result_error.c_str());
        ImGui::PopTextWrapPos();
    }
    ImGui::EndGroup();

    // Save as the drone's calibration and apply it to the pipeline now.
    const bool can_save = c.active && c.views >= c.min_views;
    ImGui::BeginDisabled(!can_save);
    if (ImGui::Button("Calibrate, save and apply")) a.calibration_save = true;
    ImGui::EndDisabled();
    record_button(v, "calibration.save");
    ImGui::SameLine();
    ImGui::TextColored(colors::v4(colors::kDim), "to %s",
                       c.save_path.empty() ? "(no file configured)" : c.save_path.c_str());
    if (!c.save_error.empty())
        ImGui::TextColored(colors::v4(colors::kBad), "not saved: %s", c.save_error.c_str());
    else if (!c.saved_path.empty())
        ImGui::TextColored(colors::v4(c.applied ? colors::kGood : colors::kWarn), "saved%s",
                           c.applied ? ", applied to the pipeline" : "; applying...");
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextColored(colors::v4(colors::kDim), "in use: %s", c.in_use.c_str());
    ImGui::PopTextWrapPos();
    ImGui::End();
}

}  // namespace gs::ui
