// Root options of the window entry (--offscreen, --demo, --frames ...) and run_gui().
#ifdef GS_HAVE_GUI

#include "app/command.hpp"
#include "app/gui_entry.hpp"
#include "ui/app_window.hpp"
#include "ui/demo_snapshot.hpp"
#include "ui/settings.hpp"

#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

namespace gs::app {
namespace {

struct GuiOpts {
    bool offscreen = false;
    bool demo = false;
    std::string sim;
    std::string replay;
    int frames = 0;
    int screenshot_every = 0;
    std::string out;
    int width = 1600, height = 900;
};

GuiOpts& opts() {
    static GuiOpts o;
    return o;
}

CommandRegistration reg(-1000, [](CLI::App& root) {
    GuiOpts& o = opts();
    root.add_flag("--offscreen", o.offscreen,
                  "Render the window into an invisible framebuffer and write PNG screenshots "
                  "(needs an X display: use xvfb-run -a on a headless machine)");
    root.add_flag("--demo", o.demo, "Show canned demo data instead of a drone (testing)")
        ->group("");
    root.add_option("--sim", o.sim, "Fly the built-in virtual drone with this scenario");
    root.add_option("--replay", o.replay, "Replay a recorded dataset directory");
    root.add_option("--frames", o.frames, "Stop after N frames (offscreen: required)")
        ->check(CLI::PositiveNumber);
    root.add_option("--screenshot-every", o.screenshot_every,
                    "Offscreen: write a screenshot every K frames (default: only the last)")
        ->check(CLI::PositiveNumber);
    root.add_option("--out", o.out, "Offscreen: directory for the PNG screenshots");
    root.add_option("--width", o.width, "Offscreen window width")
        ->check(CLI::Range(320, 8192))
        ->group("");
    root.add_option("--height", o.height, "Offscreen window height")
        ->check(CLI::Range(240, 8192))
        ->group("");
});

}  // namespace

int run_gui() {
    const GuiOpts& o = opts();
    auto err = [](const std::string& m, int code) {
        std::cerr << "ardrone-gs: " << m << '\n';
        return code;
    };
    if (!o.sim.empty() || !o.replay.empty())
        return err("--sim and --replay are not wired to the window yet in this build; use --demo",
                   2);
    if (o.offscreen && o.out.empty()) return err("--offscreen needs --out DIR", 2);
    if (o.offscreen && o.frames <= 0) return err("--offscreen needs --frames N", 2);
    if (!ui::display_available()) return err(ui::no_display_message(), 3);

    ui::AppOptions ao;
    ao.offscreen = o.offscreen;
    ao.frames = o.frames;
    ao.screenshot_every = o.screenshot_every;
    ao.width = o.width;
    ao.height = o.height;
    if (o.offscreen) {
        std::error_code ec;
        std::filesystem::create_directories(o.out, ec);
        if (ec) return err("cannot create " + o.out + ": " + ec.message(), 2);
        ao.out_dir = o.out;
    } else {
        ao.config_dir = ui::config_dir();
    }

    const bool demo = o.demo;
    auto provide = [demo](ui::GuiSnapshot& s, int frame) {
        if (demo)
            ui::make_demo_snapshot(s, frame);
        else if (frame == 0)
            s = ui::demo_no_link();
    };
    auto consume = [](const ui::Actions&) {};  // wired to the link by the adapter (next step)
    std::string detail;
    auto r = ui::run_window(ao, provide, consume, &detail);
    if (!r) {
        if (r.error() == ui::AppError::NoDisplay) return err(ui::no_display_message(), 3);
        return err(
            std::string(ui::to_string(r.error())) + (detail.empty() ? "" : " (" + detail + ")"), 4);
    }
    if (o.offscreen)
        std::cout << "rendered " << r->frames << " frames, " << r->screenshots.size()
                  << " screenshots in " << o.out << '\n';
    return 0;
}

}  // namespace gs::app

#endif  // GS_HAVE_GUI
