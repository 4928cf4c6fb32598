// The live pipeline end to end, as the window runs it (without drawing): the session connects to
// a virtual drone, which flies its scenario's scripted flight (take off, fly past the pillar),
// and classifies every frame the link decodes. Measures, over the flight:
//  - latency from the last byte of a frame's video arriving to its decision being published
//    (the session's PipelineOutput::latency_ms), percentiles;
//  - the AT command period (every gap between two sends), percentiles and the share outside
//    30 +- 3 ms;
//  - navdata and video rates, frames classified, frames the pipeline could not keep up with.
//
// Usage: bench_live_bench [seconds=20] [scenario=thesis_pillar_left] [classifier=flow]
//                         [external=PATH_TO_ardrone-gs] [load=N]
// With external=..., the virtual drone runs as its own process (`ardrone-gs sim`, standard ports
// on 127.0.0.1), as a real drone would be outside the ground station; otherwise it runs inside
// the session's process (what `ardrone-gs` does by default), rendering and encoding its video
// on the same two cores. load=N adds N threads spinning at normal priority (a window drawing
// with software OpenGL, a build on the same machine ...).

#include "app/session.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

using namespace gs;
using namespace std::chrono_literals;

namespace {

double quantile(std::vector<double> v, double q) {
    if (v.empty()) return kUnknown;
    std::sort(v.begin(), v.end());
    const auto i = static_cast<std::size_t>(
        std::clamp(q * static_cast<double>(v.size() - 1), 0.0, static_cast<double>(v.size() - 1)));
    return v[i];
}

std::string arg(int argc, char** argv, const char* key, const char* fallback) {
    const std::string k = std::string(key) + "=";
    for (int i = 1; i < argc; ++i)
        if (std::string(argv[i]).rfind(k, 0) == 0) return std::string(argv[i]).substr(k.size());
    return fallback;
}

}  // namespace

int main(int argc, char** argv) {
    const double seconds = std::atof(arg(argc, argv, "seconds", "20").c_str());
    const std::string scenario = arg(argc, argv, "scenario", "thesis_pillar_left");
    const std::string external = arg(argc, argv, "external", "");
    app::SessionOptions so;
    so.classifier = arg(argc, argv, "classifier", "flow");

    pid_t sim_pid = -1;
    if (!external.empty()) {
        sim_pid = fork();
        if (sim_pid == 0) {
            execl(external.c_str(), external.c_str(), "sim", "--scenario", scenario.c_str(),
                  "--autopilot", static_cast<char*>(nullptr));
            std::perror("exec");
            _exit(127);
        }
        std::this_thread::sleep_for(1500ms);  // the sim renders its first frames
    }

    std::atomic<bool> spin{true};
    std::vector<std::thread> hogs;
    for (int i = 0; i < std::atoi(arg(argc, argv, "load", "0").c_str()); ++i)
        hogs.emplace_back([&spin] {
            volatile double x = 0;
            while (spin.load(std::memory_order_relaxed)) x = x + 1;
        });

    app::Session session(so);
    if (external.empty())
        session.request(app::StartSim{scenario, /*autopilot=*/true});
    else
        session.request(app::ConnectDrone{"127.0.0.1"});

    std::vector<double> latency_ms;
    std::uint64_t gen = 0;
    std::shared_ptr<const app::PipelineOutput> out;
    std::uint64_t dropped = 0;
    const auto t0 = std::chrono::steady_clock::now();
    const auto t_end = t0 + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < t_end) {
        if (session.output().read_if_newer(gen, out) && out) {
            if (std::isfinite(out->latency_ms)) latency_ms.push_back(out->latency_ms);
            dropped = out->frames_dropped;
        }
        while (auto m = session.next_message()) std::printf("  session: %s\n", m->c_str());
        std::this_thread::sleep_for(1ms);
    }
    const auto src = session.source().latest();
    if (!src || !src->link) {
        std::fprintf(stderr, "no link: %s\n", src ? src->error.c_str() : "no source");
        return 1;
    }
    const link::LinkStatus st = src->link->status();
    const link::AtStats& at = st.at;

    std::printf("live pipeline, %s, %.0f s, classifier %s, virtual drone %s\n", scenario.c_str(),
                seconds, so.classifier.c_str(),
                external.empty() ? "in-process" : "as its own process");
    std::printf(
        "  link: %s; navdata %.0f Hz (%llu accepted); video %.1f fps, %llu decoded, "
        "%llu decode errors, %llu IDR waits\n",
        link::to_string(st.state), st.navdata.rate_hz,
        static_cast<unsigned long long>(st.navdata.accepted), st.video.fps,
        static_cast<unsigned long long>(st.video.decoded),
        static_cast<unsigned long long>(st.video.decode_errors),
        static_cast<unsigned long long>(st.video.idr_waits));
    std::printf(
        "  classified %zu frames seen by the bench, %llu the pipeline did not keep up "
        "with\n",
        latency_ms.size(), static_cast<unsigned long long>(dropped));
    std::printf(
        "  last video byte -> decision published (ms): p50 %.2f  p90 %.2f  p99 %.2f  "
        "max %.2f\n",
        quantile(latency_ms, 0.5), quantile(latency_ms, 0.9), quantile(latency_ms, 0.99),
        quantile(latency_ms, 1.0));
    std::printf("  AT sender %s\n", at.realtime ? "real-time (SCHED_FIFO)" : "normal priority");
    std::printf(
        "  AT period (ms, 1 ms bins, upper edge): p1 %.0f  p50 %.0f  p99 %.0f  max %.2f; "
        "%llu of %llu gaps outside 30 +- 3 ms (%.2f %%)\n",
        at.period_ms_quantile(0.01), at.period_ms_quantile(0.5), at.period_ms_quantile(0.99),
        at.period_ms_max, static_cast<unsigned long long>(at.periods_off_by_3ms),
        static_cast<unsigned long long>(at.periods),
        at.periods
            ? 100.0 * static_cast<double>(at.periods_off_by_3ms) / static_cast<double>(at.periods)
            : 0.0);
    spin = false;
    for (auto& t : hogs) t.join();
    if (sim_pid > 0) {
        kill(sim_pid, SIGTERM);
        waitpid(sim_pid, nullptr, 0);
    }
    return 0;
}
