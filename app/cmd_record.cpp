// `ardrone-gs record`: connects to a drone (a real one at an address, or an in-process virtual
// drone on loopback ephemeral ports), records a dataset until N seconds, the end of the virtual
// drone's scripted flight or Ctrl-C, and optionally runs the obstacle pipeline on the recorded
// frames (DIR/live_decisions.csv: the decisions replay must reproduce).
#include "app/cli_options.hpp"
#include "app/command.hpp"
#include "app/pipeline.hpp"
#include "app/replay_run.hpp"
#include "drone/dataset/csv.hpp"
#include "drone/link/drone_link.hpp"
#include "drone/protocol/ports.hpp"
#include "drone/record/recorder.hpp"
#include "drone/sim/loopback.hpp"
#include "drone/sim/scenarios.hpp"
#include "vision/classifier.hpp"

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <thread>

namespace gs::app::cmd_record {
namespace {

std::atomic<bool> g_stop{false};
extern "C" void on_record_signal(int) {
    g_stop = true;
}

struct Opts {
    std::string drone;
    std::string sim;
    bool autopilot = false;
    std::string out;
    double seconds = 0;
    std::string classifier;
    std::string calibration;
    double connect_timeout_s = 10;
    bool quiet = false;
    int port_base = 0;             // --drone: ports BASE (navdata), +1 video, +2 AT, +5 control
    std::string navdata = "full";  // full (200 Hz) or demo (15 Hz)
    std::string stats;             // a JSON file with the recorder's and the link's counters
};

// What `record --stats FILE` writes at the end: the recorder's counters and the link's, so a
// soak (scripts/soak.sh) can check them against the dataset.
std::string stats_json(const record::RecorderStatus& st, const link::LinkStatus& ls,
                       std::uint64_t accepted_at_start, const std::string& why) {
    nlohmann::ordered_json j;
    j["dataset"] = st.path;
    j["why"] = why;
    j["duration_s"] = st.duration_s;
    j["recorder"] = {{"frames", st.frames},
                     {"navdata", st.navdata},
                     {"navdata_accepted", st.navdata_accepted},
                     {"navdata_link_span", st.navdata_link_span},
                     {"at", st.at},
                     {"drops", st.drops},
                     {"dropped_link", st.dropped_link},
                     {"dropped_writer", st.dropped_writer},
                     {"dropped_tap", st.dropped_tap},
                     {"dropped_reference_lost", st.dropped_reference_lost},
                     {"dropped_no_picture", st.dropped_no_picture},
                     {"dropped_not_h264", st.dropped_not_h264},
                     {"dropped_cut_by_reset", st.dropped_cut_by_reset},
                     {"concealed", st.concealed},
                     {"frames_skipped", st.frames_skipped},
                     {"video_connections", st.video_connections},
                     {"write_errors", st.write_errors},
                     {"error", st.error}};
    j["link"] = {{"navdata_datagrams", ls.navdata.datagrams},
                 {"navdata_accepted", ls.navdata.accepted},
                 {"navdata_accepted_while_recording", ls.navdata.accepted - accepted_at_start},
                 {"checksum_failures", ls.navdata.checksum_failures},
                 {"out_of_order", ls.machine.out_of_order},
                 {"sequence_gaps", ls.machine.sequence_gaps},
                 {"drone_restarts", ls.machine.drone_restarts},
                 {"link_losses", ls.machine.link_losses},
                 {"video_connects", ls.video.connects},
                 {"video_decoded", ls.video.decoded},
                 {"video_concealed", ls.video.concealed},
                 {"video_repaired", ls.video.repaired},
                 {"video_idr_waits", ls.video.idr_waits},
                 {"video_cut_by_reset", ls.video.cut_by_reset},
                 {"video_clock_frozen", ls.video.clock_frozen}};
    return j.dump(2) + "\n";
}

std::string megabytes(std::uint64_t bytes) {
    char b[32];
    std::snprintf(b, sizeof b, "%.1f MB", static_cast<double>(bytes) / 1e6);
    return b;
}

// The live pipeline: every recorded frame, in dataset order, as replay will read it.
struct LiveDecisions {
    std::uint64_t frames = 0;
    std::string error;
};

LiveDecisions run_pipeline(const std::string& name, const CameraCalibration& calib,
                           BoundedQueue<FrameSample>& frames, const std::filesystem::path& file) {
    LiveDecisions r;
    ObstaclePipeline pipeline(name, calib);
    std::FILE* f = std::fopen(file.c_str(), "w");
    if (f == nullptr) {
        r.error = "cannot create " + file.string();
        while (frames.pop_for(std::chrono::milliseconds(50)) || !frames.closed()) {
        }
        return r;
    }
    std::fputs(decisions_csv_header().c_str(), f);
    while (true) {
        auto s = frames.pop_for(std::chrono::milliseconds(50));
        if (!s) {
            if (frames.closed()) break;
            continue;
        }
        const vision::FrameResult& res = pipeline.process(*s);
        std::fputs(decisions_csv_row(s->index, s->t_ns, &res).c_str(), f);
        std::fflush(f);  // whole lines, so a killed recording keeps what was decided
        ++r.frames;
    }
    std::fclose(f);
    return r;
}

int run(const Opts& o) {
    if (!o.classifier.empty()) {
        CameraCalibration probe;
        if (!vision::make_classifier(o.classifier, probe)) {
            std::string names;
            for (auto n : vision::classifier_names())
                names += (names.empty() ? "" : ", ") + std::string(n);
            throw fail("unknown classifier '" + o.classifier + "' (one of: " + names + ")", 2);
        }
    }
    // The calibration recorded in flight.json and used for the live decisions: FILE when given
    // (checked before connecting), else the camera default.
    record::RecorderOptions ro;
    if (!o.calibration.empty()) {
        auto c = load_calibration_for(o.calibration, ro.writer.width, ro.writer.height);
        if (!c) throw fail(c.error(), 2);
        ro.writer.calibration = *c;
    } else if (auto c = default_calibration(CameraId::Front, assets_dir())) {
        ro.writer.calibration = c->scaled_to(ro.writer.width, ro.writer.height);
    }
    std::unique_ptr<sim::VirtualDrone> drone;
    link::LinkConfig lc;
    if (!o.sim.empty()) {
        auto scene = sim::resolve_scene(o.sim);
        if (!scene) throw fail(sim::to_string(scene.error()));
        sim::VirtualDroneOptions vo = sim::loopback_options(std::move(*scene));
        vo.autopilot = o.autopilot;
        drone = std::make_unique<sim::VirtualDrone>(std::move(vo));
        auto started = drone->start();
        if (!started) throw fail("cannot start the virtual drone: " + started.error().message);
        lc = sim::link_config(*drone);
    } else {
        lc.drone_address = o.drone;
        if (o.port_base != 0) protocol::DronePorts::from_base(o.port_base).apply_to(lc);
    }
    lc.setup.navdata_demo = o.navdata == "demo";
    std::signal(SIGINT, on_record_signal);
    std::signal(SIGTERM, on_record_signal);

    link::DroneLink link(lc);
    if (auto s = link.start(); !s) throw fail("cannot start the link: " + s.error().message);
    const auto t_connect = std::chrono::steady_clock::now();
    const auto connect_limit = std::chrono::duration<double>(o.connect_timeout_s);
    while (link.state() != link::ConnectionState::Connected) {
        if (g_stop) return 130;
        if (std::chrono::steady_clock::now() - t_connect > connect_limit) {
            const auto st = link.status();
            char b[32];
            std::snprintf(b, sizeof b, "%.1f", o.connect_timeout_s);
            throw fail("no connection to the drone at " + lc.drone_address + " within " + b +
                       " s (link " + std::string(link::to_string(st.state)) +
                       (st.reason.empty() ? "" : ": " + st.reason) + ")");
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }

    // Frames start a little after the link is up (the video port connects on its own); a
    // recording that starts before them would begin with navdata only.
    while (!link.video().latest() && !g_stop &&
           std::chrono::steady_clock::now() - t_connect < 2 * connect_limit) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    if (!link.video().latest()) std::cerr << "ardrone-gs: record: no video yet, recording anyway\n";

    if (drone) ro.writer.source = "simulated (virtual drone, scene " + drone->scene().name + ")";
    if (!o.classifier.empty()) ro.frame_tap = 4096;
    const std::uint64_t accepted_at_start = link.status().navdata.accepted;
    record::Recorder rec(link, drone.get());
    if (auto s = rec.start(o.out, ro); !s)
        throw fail("cannot record to " + o.out + ": " + s.error().message);
    std::cout << "recording to " << o.out << (o.seconds > 0 ? "" : " (Ctrl-C stops)") << std::endl;

    LiveDecisions live;
    std::thread pipeline;
    if (!o.classifier.empty()) {
        pipeline = std::thread([&] {
            live = run_pipeline(o.classifier, ro.writer.calibration.value_or(CameraCalibration{}),
                                *rec.frames(), std::filesystem::path(o.out) / "live_decisions.csv");
        });
    }

    const bool tty = isatty(STDOUT_FILENO) && !o.quiet;
    const auto t0 = std::chrono::steady_clock::now();
    std::string why = "stopped";
    while (true) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        const double elapsed =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (g_stop) {
            why = "interrupted";
            break;
        }
        if (o.seconds > 0 && elapsed >= o.seconds) {
            why = "time is up";
            break;
        }
        if (drone && o.autopilot && drone->status().autopilot_done) {
            why = "scripted flight done";
            break;
        }
        // The disk failed: the recorder stopped itself (the link flies on, unaffected).
        if (const auto st = rec.status(); !st.recording && st.disk_full) {
            why = "disk full";
            break;
        }
        if (tty) {
            const auto st = rec.status();
            std::printf("\r%6.1f s  %-12s  frames %6llu  navdata %7llu  drops %llu  %s   ",
                        st.duration_s, link::to_string(link.state()),
                        static_cast<unsigned long long>(st.frames),
                        static_cast<unsigned long long>(st.navdata),
                        static_cast<unsigned long long>(st.drops), megabytes(st.bytes).c_str());
            std::fflush(stdout);
        }
    }
    if (tty) std::printf("\n");
    const record::RecorderStatus st = rec.stop();
    if (pipeline.joinable()) pipeline.join();
    const link::LinkStatus link_status = link.status();
    link.stop();
    if (drone) drone->stop();

    char line[512];
    std::snprintf(
        line, sizeof line,
        "recorded %s (%s): %.1f s, %llu frames, %llu navdata, %llu drops (link %llu, disk %llu, "
        "pipeline %llu, reference lost %llu, no picture %llu, cut by a reset %llu, not H.264 "
        "%llu), %llu concealed, %s, recorder CPU %.1f %%",
        st.path.c_str(), why.c_str(), st.duration_s, static_cast<unsigned long long>(st.frames),
        static_cast<unsigned long long>(st.navdata), static_cast<unsigned long long>(st.drops),
        static_cast<unsigned long long>(st.dropped_link),
        static_cast<unsigned long long>(st.dropped_writer),
        static_cast<unsigned long long>(st.dropped_tap),
        static_cast<unsigned long long>(st.dropped_reference_lost),
        static_cast<unsigned long long>(st.dropped_no_picture),
        static_cast<unsigned long long>(st.dropped_cut_by_reset),
        static_cast<unsigned long long>(st.dropped_not_h264),
        static_cast<unsigned long long>(st.concealed), megabytes(st.bytes).c_str(),
        st.duration_s > 0 ? st.cpu_ms / (st.duration_s * 10.0) : 0.0);
    std::cout << line << std::endl;
    if (!o.classifier.empty()) {
        std::cout << "live decisions: " << live.frames << " frames (" << o.classifier << ") in "
                  << (std::filesystem::path(o.out) / "live_decisions.csv").string() << std::endl;
        if (!live.error.empty()) throw fail(live.error);
    }
    if (!o.stats.empty()) {
        std::ofstream f(o.stats, std::ios::trunc);
        f << stats_json(st, link_status, accepted_at_start, why);
        if (!f) throw fail("cannot write " + o.stats);
    }
    if (st.disk_full) throw fail(st.error);
    if (!st.error.empty()) throw fail("recording incomplete: " + st.error);
    return 0;
}

CommandRegistration reg(45, [](CLI::App& root) {
    auto o = std::make_shared<Opts>();
    auto* sub = root.add_subcommand(
        "record", "Record a flight as a dataset (from a drone or the virtual drone)");
    auto* drone = sub->add_option(
        "--drone", o->drone, "Address of a real AR.Drone 2 (standard ports), e.g. 192.168.1.1");
    auto* simopt = sub->add_option("--sim", o->sim,
                                   "Record an in-process virtual drone flying this scenario "
                                   "(shipped name or scene JSON), on loopback");
    drone->excludes(simopt);
    auto* ap =
        sub->add_flag("--autopilot", o->autopilot,
                      "With --sim: fly the scenario's scripted flight, stop when it is done");
    ap->needs(simopt);
    sub->add_option("--out", o->out, "Dataset directory to create (new or empty)")->required();
    sub->add_option("--seconds", o->seconds, "Stop after this many seconds (0: until Ctrl-C)")
        ->check(number_in(0, std::numeric_limits<double>::infinity(), "a time in seconds"));
    sub->add_option("--classifier", o->classifier,
                    "Also run this obstacle classifier live: DIR/live_decisions.csv");
    add_calibration_option(*sub, o->calibration,
                           "the front camera default: recorded in flight.json and used by "
                           "--classifier");
    sub->add_option("--connect-timeout", o->connect_timeout_s, "Seconds to wait for the connection")
        ->capture_default_str()
        ->check(number_in(0.1, 3600, "a time in seconds"));
    sub->add_flag("--quiet", o->quiet, "No progress line");
    sub->add_option("--port-base", o->port_base,
                    "With --drone: ports BASE (navdata), +1 (video), +2 (AT), +5 (control), as "
                    "`sim --port-base` serves them")
        ->check(CLI::Range(1024, 65000))
        ->needs(drone);
    sub->add_option("--navdata", o->navdata,
                    "Navdata mode asked of the drone: full (200 Hz, the default) or demo (15 Hz)")
        ->capture_default_str()
        ->check(CLI::IsMember({"full", "demo"}));
    sub->add_option("--stats", o->stats,
                    "Write the recorder's and the link's counters to this JSON file at the end")
        ->check(output_file());
    set_action(*sub, [o] {
        if (o->drone.empty() && o->sim.empty())
            throw fail("record needs --drone ADDR or --sim SCENARIO", 2);
        return run(*o);
    });
});

}  // namespace
}  // namespace gs::app::cmd_record
