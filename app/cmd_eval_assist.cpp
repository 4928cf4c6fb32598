// `ardrone-gs eval-assist`: the collision-prevention assist flown in closed loop on the virtual
// drone (app/assist_eval.hpp), with and without the assist, and scored.
//   eval-assist --out DIR [--suite default|smoke|FILE] [--speeds 0.6,1.0,1.5,2.0]
//               [--assist on|off|both] [-j N] [--seed S]
// Writes DIR/report.json, DIR/flights.csv, DIR/report.md and DIR/stopping.svg.
#include "app/assist_eval.hpp"
#include "app/cli_options.hpp"
#include "app/command.hpp"
#include "app/pipeline.hpp"
#include "app/replay_outputs.hpp"
#include "app/replay_run.hpp"
#include "drone/sim/rng.hpp"
#include "drone/sim/scenarios.hpp"

#include <unistd.h>
#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>
#include <thread>

namespace gs::app::cmd_eval_assist {
namespace {
namespace fs = std::filesystem;

struct Opts {
    std::string out;
    std::string suite = "default";
    std::string speeds = "0.6,1.0,1.5,2.0";
    std::string assist = "both";
    int jobs = 1;
    std::uint64_t seed = 2027;
    bool quiet = false;
    bool trace = false;
    bool record = false;
    std::string only;
    std::string classifier = "flow";
    std::vector<std::string> set;         // classifier parameters, key=value
    std::vector<std::string> assist_set;  // assist parameters, key=value
    RealismCli realism;
};

std::vector<double> parse_speeds(const std::string& text) {
    std::vector<double> v;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
        char* end = nullptr;
        const double x = std::strtod(item.c_str(), &end);
        if (end == item.c_str() || *end != '\0' || !(x >= 0.1 && x <= 5.0))
            throw fail("--speeds: '" + item + "' is not a speed in 0.1..5 m/s");
        v.push_back(x);
    }
    if (v.empty()) throw fail("--speeds: no speed given");
    return v;
}

// A suite file: one shipped scene name or scene JSON path per line ('#' comments), each flown
// along its start heading: a centre scenario dead ahead, left/right passed, none open.
std::vector<AssistFlightSpec> suite_from_file(const fs::path& file,
                                              const std::vector<double>& speeds,
                                              std::uint64_t seed) {
    std::ifstream in(file);
    if (!in) throw fail("--suite: cannot read " + file.string());
    std::vector<AssistFlightSpec> out;
    std::string line;
    int n = 0;
    while (std::getline(in, line)) {
        ++n;
        const auto a = line.find_first_not_of(" \t\r");
        if (a == std::string::npos || line[a] == '#') continue;
        const std::string name = line.substr(a, line.find_last_not_of(" \t\r") - a + 1);
        auto scene = sim::resolve_scene(name);
        if (!scene)
            throw fail(file.string() + ":" + std::to_string(n) + ": " +
                       sim::to_string(scene.error()));
        for (double v : speeds) {
            AssistFlightSpec f;
            f.scene = *scene;
            f.scene.autopilot.clear();
            f.kind = scene->scenario == "center" ? "ahead"
                     : scene->scenario == "none" ? "open"
                                                 : "side";
            f.obstacle = scene->target_id.empty() ? "none" : scene->target_id;
            f.speed_mps = v;
            f.height_m = std::clamp(scene->start.z_m, 0.5, 2.0);
            f.goal_m = 8.0;
            if (auto t = sim::find_obstacle(*scene, scene->target_id)) {
                const auto h = sim::obstacle_relative(*scene, *t, scene->start.x_m,
                                                      scene->start.y_m, scene->start.yaw_deg);
                f.goal_m = h.distance_m + 2.0;
            }
            f.seed = sim::mix_seed(seed, out.size());
            f.name = scene->name + "-" + fixed(v, 1);
            out.push_back(std::move(f));
        }
    }
    if (out.empty()) throw fail("--suite: " + file.string() + " lists no scene");
    return out;
}

struct Summary {
    int flights = 0, collisions = 0, obstacle_flights = 0, open_flights = 0, nuisance = 0;
    int completed = 0;
    double clearance_sum = 0, clearance_min = 1e9;
    int clearance_n = 0;
    void add(const AssistFlightResult& r) {
        ++flights;
        collisions += r.collided;
        completed += r.completed;
        if (r.kind == "open") {
            ++open_flights;
            nuisance += r.braked;
        } else {
            ++obstacle_flights;
            if (std::isfinite(r.min_clearance_m)) {
                clearance_sum += r.min_clearance_m;
                clearance_min = std::min(clearance_min, r.min_clearance_m);
                ++clearance_n;
            }
        }
    }
    nlohmann::ordered_json json() const {
        nlohmann::ordered_json j;
        j["flights"] = flights;
        j["collisions"] = collisions;
        j["collision_rate"] = flights ? static_cast<double>(collisions) / flights : 0.0;
        j["obstacle_flights"] = obstacle_flights;
        j["obstacle_collision_rate"] =
            obstacle_flights ? static_cast<double>(collisions) / obstacle_flights : 0.0;
        nlohmann::ordered_json c;
        c["mean"] = clearance_n ? clearance_sum / clearance_n : 0.0;
        c["min"] = clearance_n ? clearance_min : 0.0;
        j["min_clearance_m"] = c;
        j["open_flights"] = open_flights;
        j["nuisance_brakes"] = nuisance;
        j["nuisance_brake_rate"] =
            open_flights ? static_cast<double>(nuisance) / open_flights : 0.0;
        j["completed"] = completed;
        return j;
    }
};

std::string pct(int n, int d) {
    return d ? fixed(100.0 * n / d, 0) + " %" : "-";
}

// Stopping distance against speed at the first brake, one dot per braked flight.
std::string stopping_svg(const std::vector<AssistFlightResult>& rs) {
    const double w = 480, h = 320, l = 50, b = 40, r = 20, t = 20;
    const double vmax = 2.5, dmax = 1.5;
    auto X = [&](double v) { return l + (w - l - r) * std::clamp(v / vmax, 0.0, 1.0); };
    auto Y = [&](double d) { return h - b - (h - b - t) * std::clamp(d / dmax, 0.0, 1.0); };
    std::ostringstream s;
    s << "<svg xmlns='http://www.w3.org/2000/svg' width='" << w << "' height='" << h
      << "' font-family='sans-serif' font-size='11'>\n<rect width='100%' height='100%' "
         "fill='white'/>\n";
    s << "<line x1='" << l << "' y1='" << h - b << "' x2='" << w - r << "' y2='" << h - b
      << "' stroke='black'/><line x1='" << l << "' y1='" << t << "' x2='" << l << "' y2='" << h - b
      << "' stroke='black'/>\n";
    for (double v = 0; v <= vmax + 1e-9; v += 0.5)
        s << "<text x='" << X(v) - 8 << "' y='" << h - b + 15 << "'>" << fixed(v, 1) << "</text>\n";
    for (double d = 0; d <= dmax + 1e-9; d += 0.5)
        s << "<text x='" << 15 << "' y='" << Y(d) + 4 << "'>" << fixed(d, 1) << "</text>\n";
    s << "<text x='" << w / 2 - 60 << "' y='" << h - 5 << "'>speed at brake (m/s)</text>\n";
    s << "<text x='12' y='12'>stopping distance (m)</text>\n";
    s << "<line x1='" << l << "' y1='" << Y(0.7) << "' x2='" << w - r << "' y2='" << Y(0.7)
      << "' stroke='grey' stroke-dasharray='4'/><text x='" << w - r - 110 << "' y='" << Y(0.7) - 4
      << "' fill='grey'>thesis: 0.7 m</text>\n";
    for (const auto& x : rs)
        if (x.assist && std::isfinite(x.brake_speed_mps) && std::isfinite(x.stop_distance_m))
            s << "<circle cx='" << X(x.brake_speed_mps) << "' cy='" << Y(x.stop_distance_m)
              << "' r='3' fill='" << (x.collided ? "red" : "steelblue") << "'/>\n";
    s << "</svg>\n";
    return s.str();
}

int run(const Opts& o) {
    const std::vector<double> speeds = parse_speeds(o.speeds);
    auto realism_or = realism_options(o.realism);
    if (!realism_or) throw fail(realism_or.error());
    const sim::RealismOptions realism = *realism_or;
    std::vector<AssistFlightSpec> specs;
    if (o.suite == "default")
        specs = default_assist_suite(speeds, o.seed);
    else if (o.suite == "smoke")
        specs = smoke_assist_suite(speeds, o.seed);
    else
        specs = suite_from_file(o.suite, speeds, o.seed);
    if (!o.only.empty())
        std::erase_if(specs, [&](const AssistFlightSpec& f) {
            return f.name.find(o.only) == std::string::npos;
        });
    if (specs.empty()) throw fail("no flight matches --only " + o.only);
    {
        // Bad --set values are refused before anything flies.
        ObstaclePipeline probe(o.classifier, builtin_calibration(CameraId::Front));
        if (!probe.ok()) throw fail("unknown classifier '" + o.classifier + "'");
        if (auto e = apply_overrides(probe.classifier(), o.set)) throw fail(*e);
    }
    AssistParams assist_params;
    if (auto e = apply_assist_overrides(assist_params, o.assist_set)) throw fail(*e);
    std::vector<bool> modes;
    if (o.assist != "off") modes.push_back(true);
    if (o.assist != "on") modes.push_back(false);

    struct Job {
        std::size_t spec;
        bool assist;
    };
    std::vector<Job> jobs;
    for (bool m : modes)
        for (std::size_t i = 0; i < specs.size(); ++i) jobs.push_back({i, m});
    std::vector<std::optional<AssistFlightResult>> results(jobs.size());
    const fs::path out = o.out;
    std::error_code ec;
    fs::create_directories(out, ec);
    if (ec) throw fail("cannot create " + out.string() + ": " + ec.message());

    std::atomic<std::size_t> next{0};
    std::mutex mu;
    std::vector<std::string> errors;
    const bool tty = !o.quiet && ::isatty(STDERR_FILENO) == 1;
    std::size_t done = 0;
    const auto t0 = std::chrono::steady_clock::now();
    auto worker = [&] {
        for (std::size_t i = next++; i < jobs.size(); i = next++) {
            AssistEvalOptions eo;
            eo.assist = jobs[i].assist;
            eo.classifier = o.classifier;
            eo.set = o.set;
            eo.params = assist_params;
            eo.realism = realism;
            if (o.trace)
                eo.trace_path =
                    (out / (specs[jobs[i].spec].name + (eo.assist ? "-on" : "-off") + ".trace.csv"))
                        .string();
            if (o.record)
                eo.record_dir =
                    (out / (specs[jobs[i].spec].name + (eo.assist ? "-on" : "-off"))).string();
            auto r = fly_assist_flight(specs[jobs[i].spec], eo);
            std::lock_guard lock(mu);
            ++done;
            if (!r) {
                errors.push_back(specs[jobs[i].spec].name + ": " + r.error());
                continue;
            }
            results[i] = *r;
            const double el =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            if (tty) std::cerr << "\r\033[K";
            if (!o.quiet)
                std::cout << "[" << done << "/" << jobs.size() << " " << fixed(el, 0) << " s] "
                          << r->name << " assist " << (r->assist ? "on " : "off") << ": "
                          << (r->collided ? "CRASH into " + r->hit + " at " +
                                                fixed(r->hit_speed_mps, 2) + " m/s"
                              : r->completed ? std::string("completed")
                                             : std::string("stopped"))
                          << (r->braked ? ", braked" : "") << ", clearance "
                          << (std::isfinite(r->min_clearance_m)
                                  ? fixed(r->min_clearance_m, 2) + " m"
                                  : std::string("-"))
                          << std::endl;
            if (tty)
                std::cerr << "eval-assist: " << done << " / " << jobs.size() << " flights, "
                          << fixed(el, 0) << " s" << std::flush;
        }
    };
    std::vector<std::thread> pool;
    for (int j = 1; j < std::clamp(o.jobs, 1, 16); ++j) pool.emplace_back(worker);
    worker();
    for (auto& t : pool) t.join();
    if (tty) std::cerr << "\r\033[K" << std::flush;
    for (const auto& e : errors) std::cerr << "ardrone-gs: eval-assist: " << e << '\n';
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    std::vector<AssistFlightResult> rs;
    for (auto& r : results)
        if (r) rs.push_back(*r);
    Summary on, off;
    std::map<double, std::pair<Summary, Summary>> by_speed;
    for (const auto& r : rs) {
        (r.assist ? on : off).add(r);
        auto& p = by_speed[r.speed_mps];
        (r.assist ? p.first : p.second).add(r);
    }
    nlohmann::ordered_json j;
    j["suite"] = o.suite;
    j["seed"] = o.seed;
    j["classifier"] = o.classifier;
    j["set"] = o.set;
    j["assist_set"] = o.assist_set;
    j["assist_params"] = assist_param_table().to_map(assist_params);
    j["realism"] = realism.any() ? realism.to_json() : nlohmann::json(nullptr);
    j["speeds"] = speeds;
    j["elapsed_s"] = elapsed;
    j["jobs"] = o.jobs;
    if (o.assist != "off") j["assist_on"] = on.json();
    if (o.assist != "on") j["assist_off"] = off.json();
    nlohmann::ordered_json bs = nlohmann::ordered_json::array();
    for (const auto& [v, p] : by_speed) {
        nlohmann::ordered_json e;
        e["speed_mps"] = v;
        if (o.assist != "off") e["assist_on"] = p.first.json();
        if (o.assist != "on") e["assist_off"] = p.second.json();
        bs.push_back(e);
    }
    j["by_speed"] = bs;
    std::ofstream(out / "report.json") << j.dump(2) << '\n';

    std::ofstream csv(out / "flights.csv");
    csv << "name,kind,obstacle,speed_mps,assist,collided,hit,hit_speed_mps,bumps,completed,"
           "braked,interventions,min_clearance_m,brake_speed_mps,stop_distance_m,"
           "brake_clearance_m,brake_ahead_m,brake_ahead_ttc_s,flight_s,frames,unknown_centre_"
           "frames\n";
    auto num = [](double v, int d) { return std::isfinite(v) ? fixed(v, d) : std::string(); };
    for (const auto& r : rs)
        csv << r.name << ',' << r.kind << ',' << r.obstacle << ',' << fixed(r.speed_mps, 2) << ','
            << (r.assist ? "on" : "off") << ',' << r.collided << ',' << r.hit << ','
            << num(r.collided ? r.hit_speed_mps : kUnknown, 3) << ',' << r.bumps << ','
            << r.completed << ',' << r.braked << ',' << r.interventions << ','
            << num(r.min_clearance_m, 3) << ',' << num(r.brake_speed_mps, 3) << ','
            << num(r.stop_distance_m, 3) << ',' << num(r.first_brake_distance_m, 3) << ','
            << num(r.brake_ahead_m, 3) << ',' << num(r.brake_ahead_ttc_s, 2) << ','
            << fixed(r.flight_s, 2) << ',' << r.frames << ',' << r.unknown_centre_frames << '\n';

    std::ofstream svg(out / "stopping.svg");
    svg << stopping_svg(rs);

    std::ostringstream md;
    md << "# Collision-prevention assist, closed loop\n\n"
       << "`ardrone-gs eval-assist --suite " << o.suite << " --speeds " << o.speeds << " --assist "
       << o.assist << " --seed " << o.seed;
    if (o.classifier != "flow") md << " --classifier " << o.classifier;
    for (const auto& kv : o.set) md << " --set " << kv;
    for (const auto& kv : o.assist_set) md << " --assist-set " << kv;
    md << "`: " << rs.size() << " flights in " << fixed(elapsed, 0) << " s (" << o.jobs
       << " jobs).\n\n";
    md << "| | flights | collisions | obstacle flights collided | min clearance mean / min (m) "
          "| nuisance brakes (open) | completed |\n|---|---|---|---|---|---|---|\n";
    auto row = [&](const char* name, const Summary& s) {
        md << "| " << name << " | " << s.flights << " | " << s.collisions << " | "
           << pct(s.collisions, s.obstacle_flights) << " | "
           << (s.clearance_n
                   ? fixed(s.clearance_sum / s.clearance_n, 2) + " / " + fixed(s.clearance_min, 2)
                   : std::string("-"))
           << " | " << s.nuisance << " of " << s.open_flights << " ("
           << pct(s.nuisance, s.open_flights) << ") | " << s.completed << " |\n";
    };
    if (o.assist != "off") row("assist on", on);
    if (o.assist != "on") row("assist off", off);
    md << "\n## By speed\n\n| speed (m/s) | collisions on | collisions off | min clearance on "
          "(m) | nuisance brakes on | mean stopping distance on (m) |\n|---|---|---|---|---|---|\n";
    for (const auto& [v, p] : by_speed) {
        double sum = 0;
        int n = 0;
        for (const auto& r : rs)
            if (r.assist && r.speed_mps == v && std::isfinite(r.stop_distance_m)) {
                sum += r.stop_distance_m;
                ++n;
            }
        md << "| " << fixed(v, 1) << " | " << p.first.collisions << " / " << p.first.flights
           << " | " << p.second.collisions << " / " << p.second.flights << " | "
           << (p.first.clearance_n ? fixed(p.first.clearance_min, 2) : std::string("-")) << " | "
           << p.first.nuisance << " / " << p.first.open_flights << " | "
           << (n ? fixed(sum / n, 2) : std::string("-")) << " |\n";
    }
    md << "\n## Stopping distance against speed\n\n![stopping distance](stopping.svg)\n\n"
          "Distance travelled from the first braking command until the forward speed fell "
          "under 0.05 m/s, against the forward speed then (red: the flight still crashed).\n";
    md << "\n## Worst flights (assist on)\n\n";
    std::vector<const AssistFlightResult*> worst;
    for (const auto& r : rs)
        if (r.assist &&
            (r.collided || (r.kind == "open" && r.braked) ||
             (r.kind != "open" && std::isfinite(r.min_clearance_m) && r.min_clearance_m < 0.3)))
            worst.push_back(&r);
    if (worst.empty()) md << "None: no collision, no nuisance brake, no clearance under 0.3 m.\n";
    for (const auto* r : worst)
        md << "- " << r->name << ": "
           << (r->collided ? "crashed into " + r->hit + " at " + fixed(r->hit_speed_mps, 2) +
                                 " m/s" + (r->braked ? " after braking" : ", never braked")
               : r->kind == "open" ? std::string("braked in open space")
                                   : "clearance " + fixed(r->min_clearance_m, 2) + " m")
           << " (" << r->unknown_centre_frames << " of " << r->frames
           << " frames with the centre unknown)\n";
    std::ofstream(out / "report.md") << md.str();
    if (!o.quiet) std::cout << md.str();
    return errors.empty() ? 0 : 1;
}

CommandRegistration reg(47, [](CLI::App& root) {
    auto o = std::make_shared<Opts>();
    auto* sub = root.add_subcommand(
        "eval-assist",
        "Fly the collision-prevention assist in closed loop on the virtual drone and score it");
    sub->add_option("--out,-o", o->out, "Report directory (report.json, flights.csv, report.md)")
        ->required();
    sub->add_option("--suite", o->suite,
                    "default (16 flights per speed), smoke (3 per speed) or a file listing "
                    "scenes, one per line")
        ->capture_default_str();
    sub->add_option("--speeds", o->speeds, "Comma-separated forward speeds, m/s")
        ->capture_default_str();
    sub->add_option("--assist", o->assist, "Fly with the assist on, off or both")
        ->capture_default_str()
        ->check(CLI::IsMember({"on", "off", "both"}));
    sub->add_option("--jobs,-j", o->jobs, "Flights in parallel")
        ->capture_default_str()
        ->check(CLI::Range(1, 16));
    sub->add_option("--seed", o->seed, "Seed (suite layout, disturbances, sensor noise)")
        ->capture_default_str()
        ->check(unsigned_integer());
    sub->add_flag("--quiet,-q", o->quiet, "No per-flight lines or summary");
    sub->add_flag("--trace", o->trace,
                  "Also write DIR/<flight>-on|off.trace.csv: every AT cycle of every flight");
    sub->add_flag("--record", o->record,
                  "Also write DIR/<flight>-on|off/: each flight as a dataset, to replay (what "
                  "the classifier saw, with the ground truth)");
    sub->add_option("--only", o->only, "Only the flights whose name contains this");
    add_classifier_options(*sub, o->classifier, o->set);
    sub->add_option("--assist-set", o->assist_set,
                    "Override an assist parameter, KEY=VALUE (repeatable; `params --assist` "
                    "lists them)");
    add_realism_options(*sub, o->realism,
                        "Fly with the camera, link and estimator of a real AR.Drone 2 (as "
                        "`generate --realism`: rolling shutter, blur, exposure steps, flicker, "
                        "vignetting, noise, lost slices, 1 Mbit/s, late and drifting navdata, "
                        "plain walls, a glossy floor, a person crossing); the options below change "
                        "one effect");
    set_action(*sub, [o] { return run(*o); });
});

}  // namespace
}  // namespace gs::app::cmd_eval_assist
