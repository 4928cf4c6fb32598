// Root options of the window entry (--offscreen, --demo, --frames ...) and run_gui().
#ifdef GS_HAVE_GUI

#include "app/command.hpp"
#include "app/gui_adapter.hpp"
#include "app/gui_entry.hpp"
#include "app/session.hpp"
#include "drone/dataset/dataset.hpp"
#include "drone/sim/scenarios.hpp"
#include "ui/app_window.hpp"
#include "ui/demo_snapshot.hpp"
#include "ui/settings.hpp"

#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <thread>

namespace gs::app {
namespace {

struct GuiOpts {
    bool offscreen = false;
    bool demo = false;
    std::string sim;
    std::string replay;
    bool autopilot = false;
    std::string classifier;
    std::string camera;
    int frames = 0;
    int screenshot_every = 0;
    std::string out;
    int width = 1600, height = 900;
    bool calibration_window = false;
    bool auto_capture = false;
    bool undistort_preview = false;
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
    root.add_flag("--demo", o.demo,
                  "Show the window with canned demo data: no drone, virtual drone or dataset "
                  "needed (a quick look, e.g. offscreen on a machine without a display)");
    root.add_option("--sim", o.sim,
                    "Fly the built-in virtual drone in this scenario (the default, with "
                    "'warehouse', when neither --sim nor --replay is given)");
    root.add_option("--replay", o.replay, "Replay a recorded dataset directory")->excludes("--sim");
    root.add_flag("--autopilot", o.autopilot,
                  "Virtual drone: fly the scenario's scripted flight (manual keys still land "
                  "and emergency-stop it)");
    root.add_option("--classifier", o.classifier, "Obstacle classifier (thesis, flow)");
    root.add_option("--camera", o.camera,
                    "Drone or virtual drone: the camera to show once connected (bottom: visual "
                    "odometry instead of the obstacle classifier; C switches in the window)")
        ->check(CLI::IsMember({"front", "bottom"}));
    root.add_option("--frames", o.frames, "Stop after N frames (offscreen: required)")
        ->check(CLI::PositiveNumber);
    root.add_option("--screenshot-every", o.screenshot_every,
                    "Offscreen: write a screenshot every K frames (default: only the last)")
        ->check(CLI::PositiveNumber);
    root.add_option("--out", o.out, "Offscreen: directory for the PNG screenshots");
    root.add_flag("--calibration-window", o.calibration_window,
                  "Open the Calibration window (camera calibration mode: show a 9x6 chessboard, "
                  "press K to capture views, then save and apply)");
    root.add_flag("--auto-capture", o.auto_capture,
                  "Calibration window: capture every view that adds coverage (implies "
                  "--calibration-window)");
    root.add_flag("--undistort-preview", o.undistort_preview,
                  "Start with the video window showing the undistorted image");
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
    if (o.offscreen && o.out.empty()) return err("--offscreen needs --out DIR", 2);
    if (o.offscreen && o.frames <= 0) return err("--offscreen needs --frames N", 2);
    // Bad names fail here, before a window opens.
    const std::string scenario = o.sim.empty() ? "warehouse" : o.sim;
    if (o.replay.empty() && !o.demo) {
        if (auto sc = sim::resolve_scene(scenario); !sc) return err(sim::to_string(sc.error()), 2);
    }
    if (!o.replay.empty()) {
        if (auto d = dataset::Dataset::open(o.replay); !d)
            return err("cannot replay " + o.replay + ": " + to_string(d.error()), 2);
    }
    if (!o.classifier.empty()) {
        if (!vision::make_classifier(o.classifier, CameraCalibration{}))
            return err("unknown classifier '" + o.classifier + "'", 2);
    }
    if (!ui::display_available()) return err(ui::no_display_message(), 3);

    ui::AppOptions ao;
    ao.offscreen = o.offscreen;
    ao.frames = o.frames;
    ao.screenshot_every = o.screenshot_every;
    ao.width = o.width;
    ao.height = o.height;
    const bool calibrating = o.calibration_window || o.auto_capture;
    ao.open_calibration = calibrating;
    ao.calibration_auto_capture = o.auto_capture;
    ao.undistort_preview = o.undistort_preview;
    if (o.offscreen) {
        std::error_code ec;
        std::filesystem::create_directories(o.out, ec);
        if (ec) return err("cannot create " + o.out + ": " + ec.message(), 2);
        ao.out_dir = o.out;
    } else {
        ao.config_dir = ui::config_dir();
    }

    SessionOptions so;
    if (!o.classifier.empty()) so.classifier = o.classifier;
    // Offscreen replay is lock-stepped: window frame k shows dataset frame k, classified, so a
    // screenshot does not depend on how fast the machine renders.
    const bool lockstep = o.offscreen && !o.replay.empty();
    so.replay_lockstep = lockstep;
    // The calibration mode saves the drone's calibration in the user's config directory (an
    // offscreen run keeps it beside its screenshots, never touching the user's).
    so.calibration_file =
        (o.offscreen ? std::filesystem::path(o.out) : ui::config_dir()) / "calibration_front.json";
    if (lockstep) {
        // ... and, lock-stepped, the calibration mode checks every frame (see provide()).
        so.calibration_interval_ms = 0;
        so.calibration_auto_interval_ms = 0;
    }
    Session session(so);
    GuiAdapter adapter(session);
    adapter.set_sim_autopilot(o.autopilot);
    if (o.camera == "bottom") adapter.set_start_camera(1);
    if (!o.demo) {
        if (!o.replay.empty())
            session.request(OpenReplay{o.replay});
        else
            session.request(StartSim{scenario, o.autopilot});
    }

    const bool demo = o.demo;
    const bool offscreen_live = o.offscreen && !demo && o.replay.empty();
    const auto t0 = std::chrono::steady_clock::now();
    // Lock-stepped calibration mode: wait (bounded) until its worker has checked replay frame
    // `f` (and auto-captured it), so screenshot k shows frame k's board and views.
    auto wait_calibration = [&](std::int64_t f) {
        if (!calibrating || f < 0) return;
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
        const std::uint64_t id = session.source().latest().value_or(SourceInfo{}).id;
        while (std::chrono::steady_clock::now() < deadline) {
            const auto m = session.calibration_mode().latest();
            if (m && m->active && m->frame == f && m->source_id == id) return;
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
    };
    auto provide = [&](ui::GuiSnapshot& s, int frame) {
        if (demo) {
            ui::make_demo_snapshot(s, frame);
            return;
        }
        if (lockstep) {
            // Ask for dataset frame `frame` and wait (bounded) until it is classified.
            const auto before = session.frames_processed();
            const auto info = session.replay().latest();
            const bool more = !info || !info->open || info->frame + 1 < info->frame_count;
            // The mode starts after window frame 0: let it check the frame on screen first.
            if (frame > 0 && info) wait_calibration(info->frame);
            if (more && session.request(ReplayStep{1})) {
                const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
                while (session.frames_processed() == before &&
                       std::chrono::steady_clock::now() < deadline)
                    std::this_thread::sleep_for(std::chrono::milliseconds(1));
                if (frame > 0)
                    if (const auto now = session.replay().latest()) wait_calibration(now->frame);
            }
        } else if (offscreen_live) {
            // Live sources run in real time: 30 window frames per second, so --frames N covers
            // N/30 s of flight whatever the renderer's speed.
            std::this_thread::sleep_until(t0 + std::chrono::microseconds(33'333) * frame);
        }
        adapter.fill(s);
    };
    auto consume = [&](const ui::Actions& a) { adapter.consume(a); };
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
