// Root options of the window entry (--offscreen, --demo, --frames ...) and run_gui().
#ifdef GS_HAVE_GUI

#include "app/command.hpp"
#include "app/gui_adapter.hpp"
#include "app/gui_entry.hpp"
#include "app/session.hpp"
#include "drone/core/clock.hpp"
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
    std::string layout;
    std::string assist = "on";
    float hold_forward = 0;
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
    root.add_option("--layout", o.layout,
                    "Start in this layout: flight (the video fills the window) or engineering "
                    "(every panel); F2 switches. Default: the one used last")
        ->check(CLI::IsMember({"flight", "engineering"}));
    root.add_option("--assist", o.assist,
                    "The collision-prevention assist between the pilot and the drone: on (the "
                    "default) or off; B (gamepad right bumper) switches it in the window, Left "
                    "Shift (left bumper) held bypasses it")
        ->check(CLI::IsMember({"on", "off"}));
    root.add_option(
            "--hold-forward", o.hold_forward,
            "Virtual drone, tests: a scripted pilot takes off and holds forward at this "
            "fraction of the maximum tilt (0.3 ~ 1.1 m/s), through the assist like the keys")
        ->check(CLI::Range(0.0f, 1.0f))
        ->excludes("--replay");
    root.add_option("--width", o.width, "Offscreen window width")
        ->check(CLI::Range(320, 8192))
        ->group("");
    root.add_option("--height", o.height, "Offscreen window height")
        ->check(CLI::Range(240, 8192))
        ->group("");
});

// Lock-step on a live source: the simulated clock moves to window frame k's time (k/30 s after
// the frame the virtual drone came up on), then the frame waits (bounded) until the drone has
// run everything due by then and the ground has caught up: the link has the drone's newest
// navdata and the session has classified the newest video frame. Screenshot k is then the
// flight at k/30 s, the same on any machine. A wait that runs out is said on stderr.
class LockstepLive {
public:
    LockstepLive(Session& session, FakeClock& clock) : session_(session), clock_(clock) {}

    void frame(int frame) {
        // The drone comes up first (building the scene takes real time, not flight time), with
        // the link's video connection, so that the flight's first frame is window frame 0's.
        if (first_ < 0) {
            const bool up = until(
                [&] {
                    src_ = session_.source().latest().value_or(SourceInfo{});
                    return src_.opens_handled > 0 &&
                           (src_.virtual_drone != nullptr || src_.kind == SessionSource::None);
                },
                std::chrono::seconds(60), "the virtual drone to start");
            if (!up || !src_.virtual_drone || !src_.link) return;
            if (src_.link->config_used().video)
                (void)until([&] { return src_.virtual_drone->video_client_connected(); },
                            std::chrono::seconds(10), "the video connection");
            first_ = frame;
        }
        sim::VirtualDrone& drone = *src_.virtual_drone;
        link::DroneLink& lk = *src_.link;
        const TimeNs t = static_cast<TimeNs>(frame - first_) * 1'000'000'000LL / 30;
        clock_.set(t);
        if (!drone.wait_reached(t, std::chrono::seconds(10))) {
            warn("the virtual drone");
            return;
        }
        const std::uint32_t nav_seq = drone.navdata_sequence();
        (void)until(
            [&] {
                const auto n = lk.navdata().latest();
                return nav_seq == 0 || (n && n->seq >= nav_seq) ||
                       lk.state() == link::ConnectionState::Bootstrapping;
            },
            std::chrono::seconds(10), "navdata");
        const std::uint32_t sent = drone.last_frame_number();
        if (sent == 0) return;
        // The newest frame sent, received and classified (a frame the decoder had to skip,
        // waiting for a key frame, is not waited for).
        (void)until(
            [&] {
                const auto v = lk.video().latest();
                const link::LinkStatus st = lk.status();
                const bool all_in = st.video.pave_frames >= drone.video_frames_sent();
                return v ? (v->frame_number >= sent || all_in) : all_in;
            },
            std::chrono::seconds(10), "the video frame");
        const auto got = lk.video().latest();
        if (!got) return;
        (void)until(
            [&] {
                const auto o = session_.output().latest();
                return o && *o && (*o)->source_id == src_.id &&
                       (*o)->frame.frame_number >= got->frame_number;
            },
            std::chrono::seconds(10), "the classifier");
    }

private:
    template <class Pred>
    bool until(const Pred& pred, std::chrono::milliseconds limit, const char* what) {
        const auto deadline = std::chrono::steady_clock::now() + limit;
        while (!pred()) {
            if (std::chrono::steady_clock::now() > deadline) {
                warn(what);
                return false;
            }
            std::this_thread::sleep_for(std::chrono::microseconds(200));
        }
        return true;
    }
    void warn(const char* what) {
        if (++warnings_ <= 5)
            std::cerr << "ardrone-gs: lock-step: waited in vain for " << what
                      << "; this frame may lag the flight\n";
    }

    Session& session_;
    FakeClock& clock_;
    SourceInfo src_;
    int first_ = -1;  // the window frame the flight's clock starts on
    int warnings_ = 0;
};

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
    if (!o.layout.empty())
        ao.layout = o.layout == "flight" ? ui::LayoutMode::Flight : ui::LayoutMode::Engineering;
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
    // Offscreen on a live source: everything (the virtual drone, the link, the session, the
    // window) runs on one simulated clock that advances 1/30 s per window frame, so that frame
    // k shows the flight at k/30 s whatever the machine's speed (see provide()).
    const bool offscreen_live = o.offscreen && !o.demo && o.replay.empty();
    FakeClock sim_clock(0);
    Clock& clock = offscreen_live ? static_cast<Clock&>(sim_clock) : SteadyClock::instance();
    Session session(so, clock);
    GuiAdapter adapter(session, clock);
    adapter.set_sim_autopilot(o.autopilot);
    adapter.set_assist(o.assist != "off");
    adapter.set_hold_forward(o.hold_forward);
    if (o.camera == "bottom") adapter.set_start_camera(1);
    if (!o.demo) {
        if (!o.replay.empty())
            session.request(OpenReplay{o.replay});
        else
            session.request(StartSim{scenario, o.autopilot});
    }

    const bool demo = o.demo;
    LockstepLive live_lockstep(session, sim_clock);
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
            live_lockstep.frame(frame);
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
