// `ardrone-gs sim`: the virtual AR.Drone 2, standalone. It listens on the real ports (AT 5556,
// navdata 5554, video 5555, control 5559) of a loopback address, so any AR.Drone client can fly
// it: this ground station, node-ar-drone, the official SDK examples.
#include "app/command.hpp"
#include "drone/sim/scenarios.hpp"
#include "drone/sim/virtual_drone.hpp"

#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <memory>
#include <thread>

namespace gs::app {
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
};

int run(const Opts& o) {
    auto scene = sim::resolve_scene(o.scenario);
    if (!scene) throw fail(sim::to_string(scene.error()));
    sim::VirtualDroneOptions vo;
    vo.bind_address = o.bind;
    vo.scene = std::move(*scene);
    vo.autopilot = o.autopilot;
    if (o.port_base != 0) {
        vo.navdata_port = static_cast<std::uint16_t>(o.port_base);
        vo.video_port = static_cast<std::uint16_t>(o.port_base + 1);
        vo.at_port = static_cast<std::uint16_t>(o.port_base + 2);
        vo.control_port = static_cast<std::uint16_t>(o.port_base + 5);
    }
    sim::VirtualDrone drone(std::move(vo));
    auto started = drone.start();
    if (!started) throw fail("cannot start the virtual drone: " + started.error().message);
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    std::cout << "virtual AR.Drone 2 '" << drone.scene().name << "' on " << o.bind << ": AT "
              << drone.at_port() << ", navdata " << drone.navdata_port() << ", video "
              << drone.video_port() << ", control " << drone.control_port()
              << (o.autopilot ? " (autopilot)" : "") << "; Ctrl-C stops" << std::endl;
    const bool tty = isatty(STDOUT_FILENO) && !o.quiet;
    const auto t0 = std::chrono::steady_clock::now();
    while (!g_stop) {
        std::this_thread::sleep_for(std::chrono::milliseconds(200));
        const double elapsed =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (o.seconds > 0 && elapsed >= o.seconds) break;
        if (o.json_status) {
            const auto st = drone.status();
            std::printf(
                "{\"t_s\":%.3f,\"ctrl\":\"%s\",\"x_m\":%.4f,\"y_m\":%.4f,\"z_m\":%.4f,"
                "\"yaw_deg\":%.3f,\"vx_mps\":%.4f,\"battery_pct\":%.3f,"
                "\"drone_state\":%u,\"navdata_sent\":%llu,\"video_frames\":%llu,"
                "\"at_commands\":%llu}\n",
                elapsed, sim::to_string(st.flight.major), st.flight.x_m, st.flight.y_m,
                st.flight.z_m, st.flight.yaw_deg, st.flight.vx_body_mps(), st.flight.battery_pct,
                st.drone_state, static_cast<unsigned long long>(st.counters.navdata_sent),
                static_cast<unsigned long long>(st.video_frames_sent),
                static_cast<unsigned long long>(st.counters.at_commands));
            std::fflush(stdout);
        } else if (tty) {
            const auto st = drone.status();
            std::printf(
                "\r%6.1f s  %-9s  x %6.2f y %6.2f z %5.2f m  yaw %7.1f  battery %5.1f %%  "
                "navdata %llu  video %llu frames   ",
                elapsed, sim::to_string(st.flight.major), st.flight.x_m, st.flight.y_m,
                st.flight.z_m, st.flight.yaw_deg, st.flight.battery_pct,
                static_cast<unsigned long long>(st.counters.navdata_sent),
                static_cast<unsigned long long>(st.video_frames_sent));
            std::fflush(stdout);
        }
    }
    if (tty) std::printf("\n");
    const auto st = drone.status();
    if (!st.last_error.empty()) std::cerr << "ardrone-gs: sim: " << st.last_error << '\n';
    drone.stop();
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
        ->check(CLI::NonNegativeNumber);
    sub->add_option(
           "--port-base", o->port_base,
           "Use ports BASE (navdata), +1 (video), +2 (AT), +5 (control) instead of 5554...")
        ->check(CLI::Range(1024, 65000));
    sub->add_flag("--quiet", o->quiet, "No status line");
    sub->add_flag(
        "--json-status", o->json_status,
        "Print the simulator's state as one JSON line every 200 ms (for tests and tools)");
    set_action(*sub, [o] { return run(*o); });
});

}  // namespace
}  // namespace gs::app
