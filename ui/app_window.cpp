#include "ui/app_window.hpp"

#include "ui/gl_texture.hpp"
#include "ui/gui.hpp"
#include "ui/key_latch.hpp"

#include <GL/gl.h>
#include <GL/glext.h>
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>

namespace gs::ui {

const char* to_string(AppError e) {
    switch (e) {
        case AppError::NoDisplay:
            return "no display";
        case AppError::GlfwInit:
            return "GLFW could not initialise";
        case AppError::WindowCreate:
            return "could not create an OpenGL 3.3 window";
        case AppError::OpenGl:
            return "OpenGL setup failed";
        case AppError::Screenshot:
            return "could not write a screenshot";
    }
    return "?";
}

WindowSize initial_window_size(int work_w, int work_h, WindowSize fallback) {
    if (work_w <= 0 || work_h <= 0) return fallback;
    constexpr int kDecorations = 40;  // title bar and borders the window manager adds
    return {work_w, std::max(240, work_h - kDecorations)};
}

bool display_available() {
    const char* x = std::getenv("DISPLAY");
    const char* w = std::getenv("WAYLAND_DISPLAY");
    return (x && *x) || (w && *w);
}

std::string no_display_message() {
    return "no display found (DISPLAY and WAYLAND_DISPLAY are unset), so the window cannot open.\n"
           "  Headless use: the subcommands work without a display (ardrone-gs --help lists "
           "them).\n"
           "  Window without a screen: xvfb-run -a ardrone-gs --offscreen --demo --frames 30 "
           "--screenshot-every 10 --out shots/";
}

namespace {

std::string g_glfw_error;
void glfw_error(int code, const char* text) {
    g_glfw_error = "GLFW error " + std::to_string(code) + ": " + (text ? text : "");
}

// The framebuffer-object entry points (GL 3.0) through GLFW's loader; the 1.x calls
// (glReadPixels, textures) come straight from libGL.
struct Fbo {
    PFNGLGENFRAMEBUFFERSPROC GenFramebuffers = nullptr;
    PFNGLBINDFRAMEBUFFERPROC BindFramebuffer = nullptr;
    PFNGLFRAMEBUFFERTEXTURE2DPROC FramebufferTexture2D = nullptr;
    PFNGLCHECKFRAMEBUFFERSTATUSPROC CheckFramebufferStatus = nullptr;
    PFNGLDELETEFRAMEBUFFERSPROC DeleteFramebuffers = nullptr;
    GLuint fbo = 0, color = 0;
    int w = 0, h = 0;

    bool create(int width, int height) {
        GenFramebuffers =
            reinterpret_cast<PFNGLGENFRAMEBUFFERSPROC>(glfwGetProcAddress("glGenFramebuffers"));
        BindFramebuffer =
            reinterpret_cast<PFNGLBINDFRAMEBUFFERPROC>(glfwGetProcAddress("glBindFramebuffer"));
        FramebufferTexture2D = reinterpret_cast<PFNGLFRAMEBUFFERTEXTURE2DPROC>(
            glfwGetProcAddress("glFramebufferTexture2D"));
        CheckFramebufferStatus = reinterpret_cast<PFNGLCHECKFRAMEBUFFERSTATUSPROC>(
            glfwGetProcAddress("glCheckFramebufferStatus"));
        DeleteFramebuffers = reinterpret_cast<PFNGLDELETEFRAMEBUFFERSPROC>(
            glfwGetProcAddress("glDeleteFramebuffers"));
        if (!GenFramebuffers || !BindFramebuffer || !FramebufferTexture2D ||
            !CheckFramebufferStatus || !DeleteFramebuffers)
            return false;
        w = width;
        h = height;
        glGenTextures(1, &color);
        glBindTexture(GL_TEXTURE_2D, color);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        GenFramebuffers(1, &fbo);
        BindFramebuffer(GL_FRAMEBUFFER, fbo);
        FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color, 0);
        const bool ok = CheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
        BindFramebuffer(GL_FRAMEBUFFER, 0);
        return ok;
    }
    void destroy() {
        if (fbo) DeleteFramebuffers(1, &fbo);
        if (color) glDeleteTextures(1, &color);
        fbo = color = 0;
    }
};

nlohmann::json rect_json(const Rect& r) {
    return {r.x0, r.y0, r.x1, r.y1};
}

bool write_screenshot(const std::filesystem::path& png, int w, int h, const LayoutReport& layout,
                      std::vector<unsigned char>& pixels) {
    pixels.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
    cv::Mat rgba(h, w, CV_8UC4, pixels.data());
    cv::Mat bgr, flipped;
    cv::cvtColor(rgba, bgr, cv::COLOR_RGBA2BGR);
    cv::flip(bgr, flipped, 0);  // GL rows start at the bottom
    if (!cv::imwrite(png.string(), flipped)) return false;

    nlohmann::json j;
    j["width"] = w;
    j["height"] = h;
    j["video_image"] = rect_json(layout.video_image);
    j["region_bars"] = nlohmann::json::array();
    for (const auto& b : layout.region_bars)
        j["region_bars"].push_back({{"name", b.name},
                                    {"rect", rect_json(b.rect)},
                                    {"flagged", b.flagged},
                                    {"confirming", b.confirming},
                                    {"still", b.still},
                                    {"known", b.known},
                                    {"reason", b.reason},
                                    {"label", b.label}});
    j["battery"] = {{"outline", rect_json(layout.battery_outline)},
                    {"fill", rect_json(layout.battery_fill)},
                    {"text", layout.battery_text},
                    {"warning", layout.battery_warning},
                    {"color_rgba", layout.battery_color}};
    const LayoutReport::Calibration& c = layout.calibration;
    j["calibration"] = {{"drawn", c.drawn},
                        {"corners_drawn", c.corners_drawn},
                        {"coverage_map", rect_json(c.coverage_map)},
                        {"views", c.views},
                        {"rms_px", known(c.rms_px) ? nlohmann::json(c.rms_px) : nlohmann::json()},
                        {"status", c.status}};
    j["undistorted"] = layout.undistorted;
    j["clock_s"] = layout.clock_s;
    j["video_index"] = layout.video_index;
    j["layout"] = layout.layout_mode;
    j["video_stale"] = layout.video_stale_text;
    j["replay_notes"] = layout.replay_notes;
    const LayoutReport::Status& st = layout.status;
    j["status"] = {{"source", st.source},   {"state", st.state},     {"activity", st.activity},
                   {"battery", st.battery}, {"link", st.link},       {"video", st.video},
                   {"rec", st.rec},         {"message", st.message}, {"banners", st.banners},
                   {"assist", st.assist}};
    j["assist"] = {{"toggle", layout.assist.toggle},
                   {"banner", layout.assist.banner},
                   {"hud", layout.assist.hud}};
    nlohmann::json disabled = nlohmann::json::object();
    for (const auto& [id, why] : layout.disabled) disabled[id] = why;
    j["disabled"] = disabled;
    nlohmann::json buttons = nlohmann::json::object();
    for (const auto& [name, r] : layout.buttons) buttons[name] = rect_json(r);
    j["buttons"] = buttons;
    nlohmann::json wins = nlohmann::json::object();
    for (const auto& [name, r] : layout.windows) wins[name] = rect_json(r);
    j["windows"] = wins;
    std::filesystem::path js = png;
    js.replace_extension(".json");
    std::ofstream out(js);
    out << j.dump(2) << '\n';
    return static_cast<bool>(out);
}

// Every key event, latched until the next frame reads it (ImGui 1.86 keeps only the current
// state, so a tap between two frames would be lost). Installed before ImGui's backend, which
// chains to it.
void key_callback(GLFWwindow* win, int key, int /*scancode*/, int action, int /*mods*/) {
    auto* latch = static_cast<KeyLatch*>(glfwGetWindowUserPointer(win));
    if (!latch) return;
    latch->on_key(key, action == GLFW_PRESS     ? KeyLatch::Event::Press
                       : action == GLFW_RELEASE ? KeyLatch::Event::Release
                                                : KeyLatch::Event::Repeat);
}

InputState poll_input(GLFWwindow* win, KeyLatch& latch) {
    InputState in;
    latch.take(in);
    in.window_focused = glfwGetWindowAttrib(win, GLFW_FOCUSED) == GLFW_TRUE;
    for (int jid = GLFW_JOYSTICK_1; jid <= GLFW_JOYSTICK_LAST; ++jid) {
        GLFWgamepadstate st;
        if (glfwJoystickIsGamepad(jid) && glfwGetGamepadState(jid, &st)) {
            in.gamepad.connected = true;
            for (std::size_t i = 0; i < in.gamepad.axes.size(); ++i)
                in.gamepad.axes[i] = st.axes[i];
            for (std::size_t i = 0; i < in.gamepad.buttons.size(); ++i)
                in.gamepad.buttons[i] = st.buttons[i] == GLFW_PRESS;
            break;
        }
    }
    return in;
}

}  // namespace

Expected<RunResult, AppError> run_window(const AppOptions& opt, const SnapshotProvider& provide,
                                         const ActionsConsumer& consume,
                                         std::string* error_detail) {
    RunResult result;
    auto fail = [&](AppError e) -> Expected<RunResult, AppError> {
        if (error_detail) *error_detail = g_glfw_error;
        return Unexpected{e};
    };
    if (!display_available()) return fail(AppError::NoDisplay);
    glfwSetErrorCallback(glfw_error);
    if (!glfwInit()) return fail(AppError::GlfwInit);
    struct GlfwGuard {
        ~GlfwGuard() { glfwTerminate(); }
    } glfw_guard;

    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    if (opt.offscreen) glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
    // On screen, the window fills the monitor's work area (the desktop minus its panels) and is
    // maximised: a small screen never has its controls off the edges, a big one is used.
    int width = opt.width, height = opt.height;
    bool maximize = false;
    int wa_x = 0, wa_y = 0, wa_w = 0, wa_h = 0;  // the work area
    if (!opt.offscreen) {
        if (GLFWmonitor* mon = glfwGetPrimaryMonitor()) {
            glfwGetMonitorWorkarea(mon, &wa_x, &wa_y, &wa_w, &wa_h);
            const WindowSize fit = initial_window_size(wa_w, wa_h, {width, height});
            maximize = wa_w > 0 && wa_h > 0;
            width = fit.width;
            height = fit.height;
        }
    }
    GLFWwindow* win = glfwCreateWindow(width, height, opt.title.c_str(), nullptr, nullptr);
    if (!win) return fail(AppError::WindowCreate);
    if (maximize) glfwMaximizeWindow(win);
    glfwMakeContextCurrent(win);
    glfwSwapInterval(opt.offscreen ? 0 : 1);
    KeyLatch latch;
    glfwSetWindowUserPointer(win, &latch);
    glfwSetKeyCallback(win, key_callback);  // before ImGui's backend, which chains to it

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    std::string ini_path;
    Settings settings;
    const std::filesystem::path settings_file =
        opt.config_dir.empty() ? std::filesystem::path{} : opt.config_dir / "settings.json";
    if (!opt.config_dir.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(opt.config_dir, ec);
        ini_path = (opt.config_dir / "imgui.ini").string();
        io.IniFilename = ini_path.c_str();
        if (auto loaded = load_settings(settings_file)) settings = *loaded;
    } else {
        io.IniFilename = nullptr;
    }
    setup_style();
    if (!ImGui_ImplGlfw_InitForOpenGL(win, true) || !ImGui_ImplOpenGL3_Init("#version 330 core")) {
        ImGui::DestroyContext();
        glfwDestroyWindow(win);
        return fail(AppError::OpenGl);
    }

    Fbo fbo;
    if (opt.offscreen && !fbo.create(opt.width, opt.height)) {
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
        glfwDestroyWindow(win);
        return fail(AppError::OpenGl);
    }

    bool ok = true;
    {
        Gui gui(settings);
        if (opt.open_calibration) {
            gui.view().open.calibration = true;
            gui.view().calib.auto_capture = opt.calibration_auto_capture;
        }
        if (opt.undistort_preview) gui.view().settings.overlay.undistort = true;
        if (opt.layout) gui.view().settings.layout = *opt.layout;
        GlVideoTexture video_tex;
        GuiSnapshot snap;
        std::vector<unsigned char> pixels;
        auto last = std::chrono::steady_clock::now();
        for (int frame = 0; opt.frames <= 0 || frame < opt.frames; ++frame) {
            glfwPollEvents();
            if (!opt.offscreen && glfwGetWindowAttrib(win, GLFW_ICONIFIED)) {
                glfwWaitEventsTimeout(
                    0.05);  // minimised: keep the loop (and commands) alive, draw nothing
            }
            provide(snap, frame);
            ImGui_ImplOpenGL3_NewFrame();
            ImGui_ImplGlfw_NewFrame();
            if (opt.offscreen) {
                // Deterministic frames: fixed size and step, whatever the invisible window says.
                io.DisplaySize = {static_cast<float>(opt.width), static_cast<float>(opt.height)};
                io.DisplayFramebufferScale = {1.0f, 1.0f};
                io.DeltaTime = 1.0f / 30.0f;
                io.MousePos = {-FLT_MAX, -FLT_MAX};
            }
            ImGui::NewFrame();
            Actions a = gui.frame(snap, poll_input(win, latch), &video_tex);
            if (glfwWindowShouldClose(win)) {
                if (gui.request_close(snap))
                    a.quit = true;
                else
                    glfwSetWindowShouldClose(win, GLFW_FALSE);
            }
            ImGui::Render();

            int fw = opt.width, fh = opt.height;
            if (opt.offscreen)
                fbo.BindFramebuffer(GL_FRAMEBUFFER, fbo.fbo);
            else
                glfwGetFramebufferSize(win, &fw, &fh);
            glViewport(0, 0, fw, fh);
            glClearColor(0.05f, 0.055f, 0.065f, 1.0f);
            glClear(GL_COLOR_BUFFER_BIT);
            ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
            ++result.frames;

            if (opt.offscreen) {
                const bool last_frame = opt.frames > 0 && frame == opt.frames - 1;
                const bool every =
                    opt.screenshot_every > 0 && (frame + 1) % opt.screenshot_every == 0;
                if (every || (last_frame && opt.screenshot_every <= 0)) {
                    char name[64];
                    std::snprintf(name, sizeof name, "frame_%06d.png", frame + 1);
                    const std::filesystem::path png = opt.out_dir / name;
                    if (!write_screenshot(png, opt.width, opt.height, gui.view().layout, pixels)) {
                        ok = false;
                        break;
                    }
                    result.screenshots.push_back(png);
                }
                fbo.BindFramebuffer(GL_FRAMEBUFFER, 0);
            } else {
                glfwSwapBuffers(win);
            }
            const auto now = std::chrono::steady_clock::now();
            const double ms = std::chrono::duration<double, std::milli>(now - last).count();
            last = now;
            ViewState& vs = gui.view();
            vs.ui_frame_ms = known(vs.ui_frame_ms) ? 0.9 * vs.ui_frame_ms + 0.1 * ms : ms;
            vs.ui_fps = vs.ui_frame_ms > 0 ? 1000.0 / vs.ui_frame_ms : kUnknown;

            consume(a);
            if (a.quit) break;
            if (!settings_file.empty() && gui.view().settings_dirty && frame % 120 == 0) {
                (void)save_settings(gui.view().settings, settings_file);  // best effort, retried
                gui.view().settings_dirty = false;
            }
        }
        if (!settings_file.empty()) {
            if (auto e = save_settings(gui.view().settings, settings_file))
                std::fprintf(stderr, "ardrone-gs: %s: %s\n", settings_file.c_str(), to_string(*e));
        }
    }
    if (opt.offscreen) fbo.destroy();
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
    glfwDestroyWindow(win);
    if (!ok) return fail(AppError::Screenshot);
    result.detail = g_glfw_error;
    return result;
}

}  // namespace gs::ui
