#pragma once
// Headless ImGui for window tests: a context with a display size and a built font atlas, no
// GLFW and no GL (imgui's example_null, v1.86). One frame = NewFrame, Gui::frame, Render.

#include "ui/gui.hpp"

#include <gtest/gtest.h>

namespace gs::ui::test {

class ImGuiFixture : public ::testing::Test {
protected:
    void SetUp() override;
    void TearDown() override;
    // Draws one frame of `gui` and returns its actions.
    Actions frame(Gui& gui, const GuiSnapshot& s, InputState in = {}, TextureSource* tex = nullptr);
    // A left click at the centre of a button the window reported in its layout: hover, press,
    // release (ImGui buttons fire on release). Returns the actions of the release frame (and
    // those of the press frame in `press`, when given).
    Actions click(Gui& gui, const GuiSnapshot& s, const char* button, Actions* press = nullptr);
    int last_vertices = 0;
};

// Counts calls and hands back a fake texture id.
class CountingTexture final : public TextureSource {
public:
    ImTextureID video_texture(const VideoFrame& f) override {
        ++calls;
        last_index = f.index;
        return reinterpret_cast<ImTextureID>(static_cast<std::uintptr_t>(7));
    }
    int calls = 0;
    std::int64_t last_index = -1;
};

}  // namespace gs::ui::test
