// `ardrone-gs generate`: labelled obstacle flights rendered offline by the virtual drone.
//   generate --scene thesis_pillar_left --out DIR [--speed 1.0] [--seed N] [--frames N]
//   generate --suite --out DIR [--split tune|test] [--jobs N] [--shard K/N]   (the 82 flights
//   of thesis table 5.1; every core by default; a shard renders every N-th flight)
#include "app/cli_options.hpp"
#include "app/command.hpp"
#include "app/replay_outputs.hpp"
#include "drone/sim/obstacle_flights.hpp"
#include "drone/sim/scenarios.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <thread>

namespace gs::app::cmd_generate {
namespace {
namespace fs = std::filesystem;

struct Opts {
    std::string out;
    std::string scene;
    bool suite = false;
    std::string split;
    std::string only;
    double speed = 1.0;
    double height = 0;
    double max_seconds = 30;
    std::uint64_t seed = 2026;
    int jobs = 1;
    Shard shard;
    int bitrate_kbps = 1500;
    RealismCli realism;
    bool quiet = false;
};

int run(const Opts& o) {
    std::vector<sim::ObstacleFlightInfo> flights;
    if (o.suite) {
        auto suite = sim::thesis_suite(o.seed);
        for (std::size_t i = 0; i < suite.size(); ++i) {
            auto& f = suite[i];
            if (!o.shard.holds(i)) continue;
            if (!o.split.empty() && f.split != o.split) continue;
            if (!o.only.empty() && f.name.find(o.only) == std::string::npos) continue;
            flights.push_back(std::move(f));
        }
        if (flights.empty()) throw fail("no suite flight matches");
    } else {
        auto scene = sim::resolve_scene(o.scene);
        if (!scene) throw fail(sim::to_string(scene.error()));
        if (scene->scenario != "none" && scene->target_id.empty())
            throw fail(o.scene + ": the scene names no target obstacle");
        sim::ObstacleFlightInfo f = sim::scenario_flight(*scene, o.speed, o.seed);
        if (o.height > 0) f.params.height_m = o.height;
        flights.push_back(std::move(f));
    }
    auto realism_or = realism_options(o.realism);
    if (!realism_or) throw fail(realism_or.error());
    const sim::RealismOptions realism = *realism_or;
    for (auto& f : flights) {
        f.params.max_record_s = o.max_seconds;
        f.params.bitrate_bps = o.bitrate_kbps * 1000;
        f.params.realism = realism;
    }

    const fs::path out = o.out;
    std::atomic<std::size_t> next{0};
    std::mutex mu;
    std::vector<std::string> errors;
    const bool tty = !o.quiet && ::isatty(STDERR_FILENO) == 1;
    std::size_t done = 0;
    auto worker = [&] {
        for (std::size_t i = next++; i < flights.size(); i = next++) {
            const auto& f = flights[i];
            const fs::path dir = o.suite ? out / f.name : out;
            auto r = sim::write_obstacle_flight(dir, f);
            std::lock_guard lock(mu);
            ++done;
            if (!r) {
                errors.push_back(f.name + ": " + r.error());
                continue;
            }
            if (tty) std::cerr << "\r\033[K";
            if (!o.quiet)
                std::cout << dir.string() << ": " << f.scenario << ", " << r->frames << " frames ("
                          << fixed(r->duration_s, 1) << " s at " << fixed(f.params.speed_mps, 2)
                          << " m/s), target " << fixed(r->start_distance_m, 2) << " -> "
                          << fixed(r->end_distance_m, 2) << " m; render "
                          << fixed(r->render_ms / std::max(1, r->frames), 1) << " ms/frame, encode "
                          << fixed(r->encode_ms / std::max(1, r->frames), 1) << " ms/frame"
                          << (f.params.realism.any()
                                  ? ", realism " +
                                        fixed(r->realism_ms / std::max(1, r->frames), 1) +
                                        " ms/frame, " + std::to_string(r->slices_lost) +
                                        " slices lost"
                                  : std::string())
                          << "\n";
            if (tty)
                std::cerr << "generate: " << done << " / " << flights.size() << " flights"
                          << std::flush;
        }
    };
    std::vector<std::thread> pool;
    const int jobs = std::clamp(o.jobs, 1, static_cast<int>(flights.size()));
    for (int j = 1; j < jobs; ++j) pool.emplace_back(worker);
    worker();
    for (auto& t : pool) t.join();
    if (tty) std::cerr << "\r\033[K" << std::flush;
    for (const auto& e : errors) std::cerr << "ardrone-gs: " << e << '\n';
    return errors.empty() ? 0 : 1;
}

CommandRegistration reg(45, [](CLI::App& root) {
    auto o = std::make_shared<Opts>();
    auto* sub = root.add_subcommand(
        "generate", "Render labelled obstacle flights offline with the virtual drone (datasets)");
    sub->add_option("--out,-o", o->out,
                    "Dataset directory to create (with --suite: a folder of flights)")
        ->required();
    auto* scene = sub->add_option(
        "--scene", o->scene, "A scenario (assets/scenes: thesis_pillar_left, ...) or scene JSON");
    auto* suite = sub->add_flag("--suite", o->suite,
                                "The 82-flight evaluation suite mirroring thesis table 5.1");
    scene->excludes(suite);
    sub->add_option("--split", o->split, "With --suite: only the tune or test flights")
        ->check(CLI::IsMember({"tune", "test"}))
        ->needs(suite);
    sub->add_option("--only", o->only, "With --suite: only flights whose name contains this")
        ->needs(suite);
    sub->add_option("--speed", o->speed, "With --scene: forward speed in m/s")
        ->capture_default_str()
        ->check(CLI::Range(0.1, 5.0));
    sub->add_option("--height", o->height,
                    "With --scene: flight height in m (default: the scene's)")
        ->check(CLI::Range(0.3, 3.0));
    sub->add_option("--max-seconds", o->max_seconds, "Longest recording per flight")
        ->capture_default_str()
        ->check(CLI::Range(1.0, 600.0));
    sub->add_option("--seed", o->seed, "Seed (suite layout, sensor noise)")
        ->capture_default_str()
        ->check(unsigned_integer());
    sub->add_option("--bitrate", o->bitrate_kbps, "H.264 bitrate in kbit/s")
        ->capture_default_str()
        ->check(CLI::Range(100, 20000));
    add_jobs_option(*sub, o->jobs, "Flights rendered");
    add_shard_option(*sub, o->shard,
                     "With --suite: only every N-th flight of the suite (the K-th part of N, K "
                     "from 1), to render the suite on several machines into one folder")
        ->needs(suite);
    add_realism_options(*sub, o->realism,
                        "Film the flights as a real AR.Drone 2 camera, link and estimator would "
                        "(drone/sim/realism.hpp: 25 ms rolling shutter, 12 ms exposure, 15 % "
                        "exposure steps, 3 % flicker, 30 % vignetting, 1.5 % noise, 2 % lost "
                        "slices, navdata 30 +- 10 ms late with drifting biases; half the walls "
                        "plain, a floor reflecting 20 %, blurred by 1.5 deg; one person crossing "
                        "the path ahead at 1.3 m/s); the options below change one effect");
    sub->add_flag("--quiet,-q", o->quiet, "No per-flight lines");
    set_action(*sub, [o, scene, suite] {
        if (scene->count() == 0 && suite->count() == 0) throw fail("give --scene NAME or --suite");
        return run(*o);
    });
});

}  // namespace
}  // namespace gs::app::cmd_generate
