#include "imgui_fixture.hpp"

#include <cfloat>

namespace gs::ui::test {

void ImGuiFixture::SetUp() {
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;
    io.DisplaySize = {1600, 900};
    io.DeltaTime = 1.0f / 60.0f;
    setup_style();
    unsigned char* px = nullptr;
    int w = 0, h = 0;
    io.Fonts->GetTexDataAsRGBA32(&px, &w, &h);
    io.Fonts->SetTexID(reinterpret_cast<ImTextureID>(static_cast<std::uintptr_t>(1)));
}

void ImGuiFixture::TearDown() {
    ImGui::DestroyContext();
}

Actions ImGuiFixture::click(Gui& gui, const GuiSnapshot& s, const char* button, Actions* press) {
    const Rect* r = gui.view().layout.button(button);
    EXPECT_NE(r, nullptr) << button;
    if (!r) return {};
    ImGuiIO& io = ImGui::GetIO();
    io.MousePos = {0.5f * (r->x0 + r->x1), 0.5f * (r->y0 + r->y1)};
    frame(gui, s);
    io.MouseDown[0] = true;
    const Actions pressed = frame(gui, s);
    if (press) *press = pressed;
    io.MouseDown[0] = false;
    const Actions a = frame(gui, s);
    io.MousePos = {-FLT_MAX, -FLT_MAX};
    return a;
}

Actions ImGuiFixture::frame(Gui& gui, const GuiSnapshot& s, InputState in, TextureSource* tex) {
    ImGui::NewFrame();
    Actions a = gui.frame(s, in, tex);
    ImGui::Render();
    last_vertices = ImGui::GetDrawData()->TotalVtxCount;
    return a;
}

}  // namespace gs::ui::test
