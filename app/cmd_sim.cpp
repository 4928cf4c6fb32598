// `ardrone-gs sim`: the virtual AR.Drone 2, standalone. It listens on the real ports (AT 5556,
// navdata 5554, video 5555, control 5559) of a loopback address, so any AR.Drone client can fly
// it: this ground station, node-ar-drone, the official SDK examples.
#include "app/cli_options.hpp"
#include "app/command.hpp"
#include "drone/protocol/ports.hpp"
#include "drone/sim/scenarios.hpp"
#include "drone/sim/virtual_drone.hpp"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace gs::app::cmd_sim {
namespace {

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) {
    g_stop = true;
}

struct Opts {
    std::string bind = "127.0.0.1";
    std::string scenario = "warehouse";
    bool autopilot = false;
    double seconds = 0;
    int port_base = 0;  // 0: the standard ports
    bool quiet = false;
    bool json_status = false;  // one JSON line of the simulator's state per 200 ms on stdout
    // Fault knobs (issue 14 point 14): a faulty link anyone can reproduce.
    sim::NavdataFaults navdata;
    std::uint64_t seed = 1;
    double video_reset_every_s = 0;  // 0: never
    bool video_reset_in_idr = false;
    std::vector<std::string> blackouts;  // "AT:DURATION" seconds, repeatable
    std::string blackout_every;          // "PERIOD:DURATION" seconds
    std::vector<double> reboot_at_s;
    double reboot_every_s = 0;
    int boot_ms = 3000;
    double video_stall_every_s = 0;
    int video_stall_ms = 1500;
};

// "A:B" as two non-negative numbers of seconds.
std::optional<std::pair<double, double>> parse_pair(const std::string& text) {
    const auto colon = text.find(':');
    if (colon == std::string::npos) return std::nullopt;
    try {
        std::size_t n1 = 0, n2 = 0;
        const std::string a = text.substr(0, colon), b = text.substr(colon + 1);
        const double x = std::stod(a, &n1), y = std::stod(b, &n2);
        if (n1 != a.size() || n2 != b.size() || !(x >= 0) || !(y > 0) || !std::isfinite(x) ||
            !std::isfinite(y))
            return std::nullopt;
        return std::pair{x, y};
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

CLI::Validator seconds_pair(const std::string& what) {
    return CLI::Validator(
        [what](std::string& text) -> std::string {
            if (!parse_pair(text))
                return "expected " + what +
                       " as two numbers of seconds A:B "
                       "(B > 0), got '" +
                       text + "'";
            return {};
        },
        "A:B", what);
}

// When each scheduled fault is due, from the start of the run (seconds), re-armed for the
// periodic ones.
struct FaultSchedule {
    struct Item {
        double at_s;
        double period_s;  // 0: once
        sim::Fault fault;
    };
    std::vector<Item> items;

    explicit FaultSchedule(const Opts& o) {
        for (const auto& b : o.blackouts) {
            auto p = parse_pair(b);
            items.push_back({p->first, 0, sim::FaultBlackout{static_cast<int>(p->second * 1000)}});
        }
        if (auto p = parse_pair(o.blackout_every); p)
            items.push_back(
                {p->first, p->first, sim::FaultBlackout{static_cast<int>(p->second * 1000)}});
        for (double t : o.reboot_at_s) items.push_back({t, 0, sim::FaultReboot{o.boot_ms}});
        if (o.reboot_every_s > 0)
            items.push_back({o.reboot_every_s, o.reboot_every_s, sim::FaultReboot{o.boot_ms}});
        if (o.video_reset_every_s > 0)
            items.push_back({o.video_reset_every_s, o.video_reset_every_s,
                             sim::FaultVideoReset{o.video_reset_in_idr}});
        if (o.video_stall_every_s > 0)
            items.push_back({o.video_stall_every_s, o.video_stall_every_s,
                             sim::FaultVideoStall{o.video_stall_ms}});
    }
    // Injects every fault due at `elapsed_s`.
    void run(double elapsed_s, sim::VirtualDrone& drone) {
        for (auto& it : items) {
            while (it.at_s >= 0 && elapsed_s >= it.at_s) {
                drone.inject(it.fault);
                it.at_s = it.period_s > 0 ? it.at_s + it.period_s : -1;
            }
        }
    }
};

int run(const Opts& o) {
    auto scene = sim::resolve_scene(o.scenario);
    if (!scene) throw fail(sim::to_string(scene.error()));
    sim::VirtualDroneOptions vo;
    vo.bind_address = o.bind;
    vo.scene = std::move(*scene);
    vo.autopilot = o.autopilot;
    vo.core.faults = o.navdata;
    vo.core.seed = o.seed;
    if (o.port_base != 0) protocol::DronePorts::from_base(o.port_base).apply_to(vo);
    sim::VirtualDrone drone(std::move(vo));
    auto started = drone.start();
    if (!started) throw fail("cannot start the virtual drone: " + started.error().message);
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    if (!o.quiet)
        std::cout << "virtual AR.Drone 2 '" << drone.scene().name << "' on " << o.bind << ": AT "
                  << drone.at_port() << ", navdata " << drone.navdata_port() << ", video "
                  << drone.video_port() << ", control " << drone.control_port()
                  << (o.autopilot ? " (autopilot)" : "") << "; Ctrl-C stops" << std::endl;
    const bool tty = isatty(STDOUT_FILENO) && !o.quiet;
    FaultSchedule schedule(o);
    const auto t0 = std::chrono::steady_clock::now();
    while (!g_stop) {
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
        const double elapsed =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (o.seconds > 0 && elapsed >= o.seconds) break;
        schedule.run(elapsed, drone);
        if (o.json_status) {
            const auto st = drone.status();
            std::printf(
                "{\"t_s\":%.3f,\"ctrl\":\"%s\",\"x_m\":%.4f,\"y_m\":%.4f,\"z_m\":%.4f,"
                "\"yaw_deg\":%.3f,\"vx_mps\":%.4f,\"battery_pct\":%.3f,"
                "\"drone_state\":%u,\"navdata_sent\":%llu,\"video_frames\":%llu,"
                "\"at_commands\":%llu,\"collisions\":%llu,\"bumps\":%llu}\n",
                elapsed, sim::to_string(st.flight.major), st.flight.x_m, st.flight.y_m,
                st.flight.z_m, st.flight.yaw_deg, st.flight.vx_body_mps(), st.flight.battery_pct,
                st.drone_state, static_cast<unsigned long long>(st.counters.navdata_sent),
                static_cast<unsigned long long>(st.video_frames_sent),
                static_cast<unsigned long long>(st.counters.at_commands),
                static_cast<unsigned long long>(st.counters.collisions),
                static_cast<unsigned long long>(st.counters.bumps));
            std::fflush(stdout);
        } else if (tty) {
            const auto st = drone.status();
            std::printf(
                "\r%6.1f s  %-9s  x %6.2f y %6.2f z %5.2f m  yaw %7.1f  battery %5.1f %%  "
                "navdata %llu  video %llu frames  crashes %llu bumps %llu   ",
                elapsed, sim::to_string(st.flight.major), st.flight.x_m, st.flight.y_m,
                st.flight.z_m, st.flight.yaw_deg, st.flight.battery_pct,
                static_cast<unsigned long long>(st.counters.navdata_sent),
                static_cast<unsigned long long>(st.video_frames_sent),
                static_cast<unsigned long long>(st.counters.collisions),
                static_cast<unsigned long long>(st.counters.bumps));
            std::fflush(stdout);
        }
    }
    if (tty) std::printf("\n");
    const auto st = drone.status();
    if (!st.last_error.empty()) std::cerr << "ardrone-gs: sim: " << st.last_error << '\n';
    drone.stop();
    if (!o.quiet) {
        const auto& c = st.counters;
        std::printf(
            "sim: navdata sent %llu, dropped %llu, reordered %llu, duplicated %llu, corrupted "
            "%llu; video frames %llu, resets %llu, clients %llu; reboots %llu\n",
            static_cast<unsigned long long>(c.navdata_sent),
            static_cast<unsigned long long>(c.navdata_dropped),
            static_cast<unsigned long long>(c.navdata_reordered),
            static_cast<unsigned long long>(c.navdata_duplicated),
            static_cast<unsigned long long>(c.navdata_corrupted),
            static_cast<unsigned long long>(st.video_frames_sent),
            static_cast<unsigned long long>(st.video_resets),
            static_cast<unsigned long long>(st.video_clients),
            static_cast<unsigned long long>(c.reboots));
        std::printf("sim: collisions %llu (motors cut), bumps %llu\n",
                    static_cast<unsigned long long>(c.collisions),
                    static_cast<unsigned long long>(c.bumps));
        for (const auto& e : st.collisions)
            std::printf(
                "sim: %s at %.2f s: %s %s at x %.2f y %.2f z %.2f m, %.2f m/s (%.2f m/s into it)\n",
                e.crash ? "crash" : "bump", e.t_s, sim::to_string(e.kind), e.what.c_str(), e.x_m,
                e.y_m, e.z_m, e.speed_mps, e.approach_mps);
    }
    return 0;
}

CommandRegistration reg(40, [](CLI::App& root) {
    auto o = std::make_shared<Opts>();
    auto* sub =
        root.add_subcommand("sim", "Run the virtual AR.Drone 2 on loopback (real protocols)");
    sub->add_option("--bind", o->bind, "Address to listen on")->capture_default_str();
    sub->add_option(
           "--scenario", o->scenario,
           "Shipped scenario name (" +
               [] {
                   std::string s;
                   for (const auto& n : sim::list_scenes()) s += (s.empty() ? "" : ", ") + n;
                   return s;
               }() +
               ") or a scene JSON file")
        ->capture_default_str();
    sub->add_flag("--autopilot", o->autopilot, "Fly the scenario's scripted flight");
    sub->add_option("--seconds", o->seconds, "Stop after this many seconds (0: until Ctrl-C)")
        ->check(number_in(0, std::numeric_limits<double>::infinity(), "a time in seconds"));
    sub->add_option(
           "--port-base", o->port_base,
           "Use ports BASE (navdata), +1 (video), +2 (AT), +5 (control) instead of 5554...")
        ->check(CLI::Range(1024, 65000));
    sub->add_flag("--quiet", o->quiet, "No banner, status line or closing counters");
    const auto probability = number_in(0, 1, "a probability");
    sub->add_option("--loss", o->navdata.loss, "Navdata datagrams not sent (probability)")
        ->check(probability)
        ->group("Faults");
    sub->add_option("--reorder", o->navdata.reorder,
                    "Navdata datagrams held back and sent after the next one (probability)")
        ->check(probability)
        ->group("Faults");
    sub->add_option("--duplicate", o->navdata.duplicate,
                    "Navdata datagrams sent twice (probability)")
        ->check(probability)
        ->group("Faults");
    sub->add_option("--corrupt", o->navdata.corrupt_checksum,
                    "Navdata datagrams with a wrong checksum (probability)")
        ->check(probability)
        ->group("Faults");
    sub->add_option("--fault-seed", o->seed, "Seed of the navdata fault generator")
        ->check(unsigned_integer())
        ->capture_default_str()
        ->group("Faults");
    sub->add_option("--video-reset-every", o->video_reset_every_s,
                    "Reset the video TCP connection mid-frame every S seconds")
        ->check(number_in(0.1, 1e6, "a period in seconds"))
        ->group("Faults");
    sub->add_flag("--video-reset-in-idr", o->video_reset_in_idr,
                  "Cut the video inside an IDR frame (the next connection starts with P-frames)")
        ->group("Faults");
    sub->add_option("--video-stall-every", o->video_stall_every_s,
                    "Stop sending video for --video-stall-ms every S seconds")
        ->check(number_in(0.1, 1e6, "a period in seconds"))
        ->group("Faults");
    sub->add_option("--video-stall-ms", o->video_stall_ms, "Length of a video stall")
        ->check(CLI::Range(1, 60000))
        ->capture_default_str()
        ->group("Faults");
    sub->add_option("--blackout", o->blackouts,
                    "No navdata at all from AT seconds for DURATION seconds (AT:DURATION, "
                    "repeatable)")
        ->check(seconds_pair("a blackout"))
        ->group("Faults");
    sub->add_option("--blackout-every", o->blackout_every,
                    "A blackout of DURATION seconds every PERIOD seconds (PERIOD:DURATION)")
        ->check(seconds_pair("a blackout period"))
        ->group("Faults");
    sub->add_option("--reboot-at", o->reboot_at_s, "Reboot the drone at S seconds (repeatable)")
        ->check(number_in(0, 1e6, "a time in seconds"))
        ->group("Faults");
    sub->add_option("--reboot-every", o->reboot_every_s, "Reboot the drone every S seconds")
        ->check(number_in(1, 1e6, "a period in seconds"))
        ->group("Faults");
    sub->add_option("--boot-ms", o->boot_ms, "How long a reboot keeps the drone down")
        ->check(CLI::Range(0, 60000))
        ->capture_default_str()
        ->group("Faults");
    sub->add_flag(
        "--json-status", o->json_status,
        "Print the simulator's state as one JSON line every 200 ms (for tests and tools)");
    set_action(*sub, [o] { return run(*o); });
});

}  // namespace
}  // namespace gs::app::cmd_sim
