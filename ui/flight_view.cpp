// The flight layout: what a pilot looks at while flying. The video with its overlay and HUD fills
// the window between the status bar and a compact plot strip; nothing else competes for the
// screen. F2 (or View -> Engineering layout) brings every panel back, where it was.
#include "ui/layout.hpp"
#include "ui/windows.hpp"

namespace gs::ui {

void FlightView::draw(const GuiSnapshot& s, ViewState& v, Actions& a, TextureSource* tex) {
    const ImVec2 d = ImGui::GetIO().DisplaySize;
    place_window("Flight video", d, v);
    video.draw(s, v, a, tex, "Flight video", /*fixed=*/true);

    place_window("Plot strip", d, v);
    constexpr ImGuiWindowFlags kStrip =
        ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
        ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoScrollbar |
        ImGuiWindowFlags_NoScrollWithMouse | ImGuiWindowFlags_NoBringToFrontOnFocus |
        ImGuiWindowFlags_NoSavedSettings;
    if (ImGui::Begin("Plot strip", nullptr, kStrip)) {
        const ImVec2 wp = ImGui::GetWindowPos(), ws = ImGui::GetWindowSize();
        v.layout.windows.push_back({"Plot strip", {wp.x, wp.y, wp.x + ws.x, wp.y + ws.y}});
        plots.draw_strip(s, v);
    }
    ImGui::End();
}

}  // namespace gs::ui
