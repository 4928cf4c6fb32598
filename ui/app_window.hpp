#pragma once
// The real window: GLFW + OpenGL 3.3 core + the ImGui GLFW/OpenGL3 backends around Gui, and an
// offscreen mode that renders the same frames into an invisible window's framebuffer object and
// writes PNG screenshots (plus a JSON of where the key widgets were laid out) for pixel checks
// under Xvfb. The only file that touches GLFW/GL directly besides the video texture.

#include "drone/core/clock.hpp"
#include "drone/core/expected.hpp"
#include "ui/actions.hpp"
#include "ui/settings.hpp"
#include "ui/snapshot.hpp"

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace gs::ui {

struct AppOptions {
    bool offscreen = false;
    int width = 1600, height = 900;  // window size (the offscreen framebuffer size)
    int frames = 0;                  // stop after this many frames (0 = until the window closes)
    int screenshot_every = 0;        // offscreen: write a PNG every K frames (0 = only the last)
    std::filesystem::path out_dir;   // offscreen: where PNG + JSON go
    // Window layout (imgui.ini) and settings.json live here; empty = no persistence (offscreen
    // runs use none, so screenshots never depend on a user's saved layout).
    std::filesystem::path config_dir;
    std::string title = "ardrone-gs";
    // Start with the Calibration window open (auto capture on or not), with the undistortion
    // preview on.
    bool open_calibration = false;
    bool calibration_auto_capture = false;
    bool undistort_preview = false;
};

enum class AppError { NoDisplay, GlfwInit, WindowCreate, OpenGl, Screenshot };
const char* to_string(AppError e);

struct RunResult {
    int frames = 0;
    std::vector<std::filesystem::path> screenshots;
    std::string detail;  // GLFW's last error text, if any
};

// Fills the snapshot for the frame about to be drawn. `frame` counts from 0.
using SnapshotProvider = std::function<void(GuiSnapshot& out, int frame)>;
// Receives what the user asked for in that frame (called once per frame, on the UI thread:
// it must only enqueue, never block).
using ActionsConsumer = std::function<void(const Actions& a)>;

// True when an X11 or Wayland display is named in the environment.
bool display_available();
// What to tell a user with no display.
std::string no_display_message();

[[nodiscard]] Expected<RunResult, AppError> run_window(const AppOptions& opt,
                                                       const SnapshotProvider& provide,
                                                       const ActionsConsumer& consume,
                                                       std::string* error_detail = nullptr);

}  // namespace gs::ui
