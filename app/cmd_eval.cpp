// `ardrone-gs eval DATASET... --out DIR`: replays each labelled flight through the classifier,
// writes DIR/<flight>/decisions.csv and summary.json, scores every flight as docs/dataset.md's
// "Scoring a flight" says and writes DIR/report.md (thesis-style tables: per flight TP/FP/FN/TN
// and detection distance, per group and overall) and DIR/report.json with the same figures.
// A directory that is not itself a dataset is searched (one level) for flights. A flight with
// frames that cannot be read is scored on the others, listed under "Evaluated with errors" and
// makes the exit status non-zero. On a terminal, progress shows flights and frames done, the
// frame rate and the time left.
#include "app/cli_options.hpp"
#include "app/command.hpp"
#include "app/replay_outputs.hpp"
#include "app/replay_run.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include <unistd.h>

namespace gs::app {
namespace {
namespace fs = std::filesystem;

struct Opts {
    std::vector<std::string> datasets;
    std::string out;
    std::string classifier{vision::kDefaultClassifier};
    std::vector<std::string> set;
    DatasetInputOptions input;  // --calibration, --fps
    std::string split;
    int jobs = 1;
    bool quiet = false;
};

struct FlightResult {
    fs::path path;
    std::string name;
    std::string group;       // labels.json "group" (free key), else the scenario
    std::string split;       // labels.json "split" (free key), else ""
    std::string error;       // non-empty: the flight could not be evaluated
    std::string read_error;  // non-empty: evaluated, but some frames could not be read
    dataset::FlightScore score;
    ReplayStats stats;
    nlohmann::json labels;              // labels.json as read
    std::vector<MissingInput> missing;  // inputs the classifier lacked (issue 14 point 7)
};

bool is_dataset_dir(const fs::path& p) {
    std::error_code ec;
    return fs::exists(p / "flight.json", ec);
}

// The flights named on the command line: datasets, or folders of datasets (sorted by name).
std::vector<fs::path> expand(const std::vector<std::string>& args, std::string& error) {
    std::vector<fs::path> out;
    for (const std::string& a : args) {
        std::error_code ec;
        if (!fs::is_directory(a, ec)) {
            error = a + ": not a directory";
            return {};
        }
        if (is_dataset_dir(a)) {
            out.emplace_back(a);
            continue;
        }
        std::vector<fs::path> found;
        for (const auto& e : fs::directory_iterator(a, ec))
            if (e.is_directory() && is_dataset_dir(e.path())) found.push_back(e.path());
        if (ec) {
            error = a + ": " + ec.message();
            return {};
        }
        if (found.empty()) {
            // Perhaps a thesis-style image folder: open_any_dataset says so if not.
            out.emplace_back(a);
            continue;
        }
        std::sort(found.begin(), found.end());
        out.insert(out.end(), found.begin(), found.end());
    }
    return out;
}

std::string text_or(const nlohmann::json& j, const char* key, const std::string& fallback) {
    if (j.is_object() && j.contains(key) && j[key].is_string()) return j[key].get<std::string>();
    return fallback;
}

// Frames replayed so far over every flight, for the progress line, and the frame counts of the
// flights opened so far (the estimate of the total: their mean times the number of flights).
struct EvalProgress {
    std::atomic<std::int64_t> frames{0};
    std::atomic<std::int64_t> opened_frames{0};
    std::atomic<std::int64_t> opened_flights{0};
    std::function<void()> tick;  // called after each frame (may print)
};

FlightResult evaluate(const fs::path& path, const Opts& o, const fs::path& out,
                      EvalProgress& progress) {
    FlightResult r;
    r.path = path;
    r.name = path.filename().string();
    if (r.name.empty()) r.name = path.parent_path().filename().string();
    auto ds = open_input_dataset(path.string(), o.input);
    if (!ds) {
        r.error = ds.error();
        return r;
    }
    if (!ds->labels()) {
        r.error = path.string() + ": no labels.json: eval needs labelled flights (docs/dataset.md)";
        return r;
    }
    r.labels = nlohmann::json::parse(ds->labels()->json, nullptr, false);
    r.group = text_or(r.labels, "group", to_string(ds->labels()->scenario));
    r.split = text_or(r.labels, "split", "");
    if (!o.split.empty() && r.split != o.split) {
        r.error = "skip";
        return r;
    }
    r.missing = missing_inputs(*ds, o.classifier);
    progress.opened_frames += ds->frame_count();
    ++progress.opened_flights;
    const fs::path dir = out / r.name;
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) {
        r.error = "cannot create " + dir.string() + ": " + ec.message();
        return r;
    }
    ReplaySettings rs;
    rs.classifier = o.classifier;
    rs.set = o.set;
    if (!o.input.calibration.empty()) rs.calibration_file = o.input.calibration;
    auto calib = input_calibration(*ds, o.input);
    if (!calib) {
        r.error = calib.error();
        return r;
    }
    ReplayOutputs outputs(dir, *calib);
    if (auto e = outputs.open_decisions(dir / "decisions.csv")) {
        r.error = *e;
        return r;
    }
    auto st = replay_dataset(*ds, rs, [&](const FrameSample& s, const vision::FrameResult* res) {
        outputs.frame(s, res);
        ++progress.frames;
        if (progress.tick) progress.tick();
    });
    if (!st) {
        r.error = path.string() + ": " + st.error();
        return r;
    }
    if (auto e = outputs.finish({})) {
        r.error = *e;
        return r;
    }
    r.stats = std::move(*st);
    if (r.stats.decode_errors > 0)
        r.read_error = path.string() + ": " + frames_unread_text(r.stats) +
                       " (scored on the frames that could)";
    r.score = dataset::score_flight(ds->labels()->scenario,
                                    ds->label_rows().value_or(std::vector<dataset::LabelRow>{}),
                                    r.stats.flags);
    nlohmann::json j = summary_json(*ds, rs, r.stats);
    j["score"] = score_json(r.score);
    if (auto e = write_json_file(dir / "summary.json", j)) r.error = *e;
    r.stats.flags.clear();
    r.stats.flags.shrink_to_fit();
    return r;
}

std::string dist(const std::optional<double>& d) {
    return d ? fixed(*d, 2) + " m" : "N/A";
}

std::string pct(double v) {
    return std::isfinite(v) ? fixed(100 * v, 1) + " %" : "-";
}

nlohmann::json summary_to_json(const dataset::ScoreSummary& s) {
    auto num = [](double v) {
        return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
    };
    return {{"flights", s.flights},
            {"tp", s.tp},
            {"fp", s.fp},
            {"fn", s.fn},
            {"tn", s.tn},
            {"side_flights", s.side_flights},
            {"side_tp", s.side_tp},
            {"side_tpr", num(s.side_tpr())},
            {"side_wrong_side_alarms", s.side_wrong},
            {"side_mean_detection_m", num(dataset::ScoreSummary::mean(s.side_distances_m))},
            {"side_min_detection_m", num(dataset::ScoreSummary::min(s.side_distances_m))},
            {"centre_flights", s.centre_flights},
            {"centre_tp", s.centre_tp},
            {"centre_tpr", num(s.centre_tpr())},
            {"centre_mean_detection_m", num(dataset::ScoreSummary::mean(s.centre_distances_m))},
            {"centre_min_detection_m", num(dataset::ScoreSummary::min(s.centre_distances_m))},
            {"open_flights", s.open_flights},
            {"open_fp", s.open_fp},
            {"open_fpr", num(s.open_fpr())},
            {"open_fp_involving_centre", s.open_fp_centre}};
}

std::string summary_row(const std::string& name, const dataset::ScoreSummary& s) {
    std::ostringstream o;
    o << "| " << name << " | " << s.flights << " | "
      << (s.side_flights ? std::to_string(s.side_tp) + "/" + std::to_string(s.side_flights) + " (" +
                               pct(s.side_tpr()) + ")"
                         : "-")
      << " | " << (s.side_flights ? std::to_string(s.side_wrong) : "-") << " | "
      << (s.side_flights ? fixed(dataset::ScoreSummary::mean(s.side_distances_m), 2) : "-") << " | "
      << (s.centre_flights ? std::to_string(s.centre_tp) + "/" + std::to_string(s.centre_flights) +
                                 " (" + pct(s.centre_tpr()) + ")"
                           : "-")
      << " | "
      << (s.centre_flights ? fixed(dataset::ScoreSummary::mean(s.centre_distances_m), 2) : "-")
      << " | "
      << fixed(std::min(dataset::ScoreSummary::min(s.side_distances_m),
                        dataset::ScoreSummary::min(s.centre_distances_m)),
               2)
      << " | "
      << (s.open_flights ? std::to_string(s.open_fp) + "/" + std::to_string(s.open_flights) + " (" +
                               pct(s.open_fpr()) + ")"
                         : "-")
      << " |\n";
    return o.str();
}

int run(const Opts& o) {
    std::string err;
    const std::vector<fs::path> flights = expand(o.datasets, err);
    if (!err.empty()) throw fail(err);
    if (flights.empty()) throw fail("no flights to evaluate");
    const fs::path out = o.out;
    std::error_code ec;
    fs::create_directories(out, ec);
    if (ec) throw fail("cannot create " + out.string() + ": " + ec.message());
    {
        // Validate the classifier and overrides once, before any work (--calibration is checked
        // when parsed).
        auto probe = vision::make_classifier(o.classifier, {});
        if (!probe) throw fail("unknown classifier '" + o.classifier + "'");
        if (auto e = apply_overrides(*probe, o.set)) throw fail(*e);
    }

    std::vector<FlightResult> results(flights.size());
    std::atomic<std::size_t> next{0}, done{0};
    std::mutex mu;
    const bool tty = !o.quiet && ::isatty(STDERR_FILENO) == 1;
    const double t0 = wall_seconds();
    double last_print_s = -1;
    EvalProgress progress;
    // "eval: 1 / 3 flights, 212 / 459 frames, 180 frames/s, 2 s left", rewritten in place (under
    // mu). The total is estimated from the flights opened so far.
    auto print_progress = [&](bool always) {
        const double now = wall_seconds();
        if (!always && last_print_s >= 0 && now - last_print_s < 0.2) return;
        last_print_s = now;
        const double el = now - t0;
        const std::size_t d = done.load();
        const std::int64_t f = progress.frames.load();
        const std::int64_t opened = progress.opened_flights.load();
        const double rate = el > 0 ? static_cast<double>(f) / el : 0.0;
        std::cerr << "\reval: " << d << " / " << flights.size() << " flights, " << f;
        if (opened > 0) {
            const double total = static_cast<double>(progress.opened_frames.load()) /
                                 static_cast<double>(opened) * static_cast<double>(flights.size());
            std::cerr << " / " << fixed(total, 0) << " frames, " << fixed(rate, 0) << " frames/s";
            if (rate > 0)
                std::cerr << ", " << fixed(std::max(0.0, total - static_cast<double>(f)) / rate, 0)
                          << " s left";
        } else {
            std::cerr << " frames";
        }
        std::cerr << "\033[K" << std::flush;
    };
    if (tty) {
        progress.tick = [&] {
            std::lock_guard lock(mu);
            print_progress(false);
        };
    }
    auto worker = [&] {
        for (std::size_t i = next++; i < flights.size(); i = next++) {
            results[i] = evaluate(flights[i], o, out, progress);
            ++done;
            if (tty) {
                std::lock_guard lock(mu);
                print_progress(true);
            }
        }
    };
    const int jobs = std::clamp(o.jobs, 1, 16);
    std::vector<std::thread> pool;
    for (int j = 1; j < jobs; ++j) pool.emplace_back(worker);
    worker();
    for (auto& t : pool) t.join();
    if (tty) std::cerr << "\r\033[K" << std::flush;

    // Tables.
    std::map<std::string, dataset::ScoreSummary> groups;
    dataset::ScoreSummary all;
    std::vector<std::string> errors;
    std::int64_t frames = 0;
    double cpu_s = 0;
    nlohmann::json jflights = nlohmann::json::array();
    std::ostringstream per;
    std::set<std::string> missing_notes;  // what the missing inputs cost, once each
    per << "| flight | group | scenario | FP | TP | FN | TN | detection distance | false positive "
           "region | frames |\n|---|---|---|---|---|---|---|---|---|---|\n";
    int evaluated = 0;
    std::vector<std::string> incomplete;  // evaluated, with frames that could not be read
    for (const FlightResult& r : results) {
        if (r.error == "skip") continue;
        if (!r.error.empty()) {
            errors.push_back(r.error);
            continue;
        }
        if (!r.read_error.empty()) incomplete.push_back(r.read_error);
        ++evaluated;
        groups[r.group].add(r.score);
        all.add(r.score);
        frames += r.stats.processed;
        cpu_s += r.stats.cpu_s;
        const dataset::FlightScore& s = r.score;
        std::string notes = s.false_regions_text();
        for (const auto& m : r.missing) notes += (notes.empty() ? "no " : "; no ") + m.input;
        if (s.late_detection_distance_m)
            notes += (notes.empty() ? "" : "; ") +
                     ("late at " + fixed(*s.late_detection_distance_m, 2) + " m");
        per << "| " << r.name << " | " << r.group << " | " << to_string(s.scenario) << " | " << s.fp
            << " | " << s.tp << " | " << s.fn << " | " << s.tn << " | "
            << dist(s.detection_distance_m) << " | " << (notes.empty() ? "N/A" : notes) << " | "
            << r.stats.processed
            << (r.stats.decode_errors
                    ? " (" + std::to_string(r.stats.decode_errors) + " undecodable)"
                    : "")
            << " |\n";
        nlohmann::json jf = score_json(s);
        jf["flight"] = r.name;
        jf["path"] = r.path.string();
        jf["group"] = r.group;
        if (!r.split.empty()) jf["split"] = r.split;
        jf["frames"] = r.stats.processed;
        jf["decode_errors"] = r.stats.decode_errors;
        jf["missing_inputs"] = nlohmann::json::array();
        for (const auto& m : r.missing) {
            jf["missing_inputs"].push_back(
                {{"input", m.input}, {"unknown_share", m.unknown_share}, {"cost", m.cost}});
            missing_notes.insert(m.input + ": " + m.cost);
        }
        jflights.push_back(jf);
    }

    std::ostringstream md;
    md << "# Evaluation: classifier '" << o.classifier << "'\n\n";
    md << evaluated << " flights";
    if (!o.split.empty()) md << " (split '" << o.split << "')";
    md << ", " << frames
       << " frames, scored as docs/dataset.md \"Scoring a flight\" (thesis ch. 6; "
          "detection counts from 0.7 m).\n";
    if (!o.set.empty()) {
        md << "Parameter overrides:";
        for (const auto& s : o.set) md << " `" << s << "`";
        md << "\n";
    }
    md << "\n## Summary\n\n| group | flights | side TP | wrong-side alarms | side mean distance "
          "(m) | "
          "centre TP | centre mean distance (m) | min distance (m) | open-space FP |\n"
          "|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& [g, s] : groups) md << summary_row(g, s);
    md << summary_row("**all**", all);
    md << "\n## Per flight\n\n" << per.str();
    if (!errors.empty()) {
        md << "\n## Not evaluated\n\n";
        for (const auto& e : errors) md << "- " << e << "\n";
    }
    if (!missing_notes.empty()) {
        md << "\n## Inputs the classifier lacked\n\n";
        for (const auto& n : missing_notes) md << "- " << n << "\n";
    }
    if (!incomplete.empty()) {
        md << "\n## Evaluated with errors\n\n";
        for (const auto& e : incomplete) md << "- " << e << "\n";
    }
    md << "\nReplay CPU time " << fixed(cpu_s, 1) << " s ("
       << fixed(cpu_s > 0 ? static_cast<double>(frames) / cpu_s : 0, 0)
       << " frames per CPU second).\n";

    nlohmann::json jr;
    jr["classifier"] = o.classifier;
    jr["overrides"] = o.set;
    if (!o.split.empty()) jr["split"] = o.split;
    jr["flights"] = jflights;
    jr["overall"] = summary_to_json(all);
    nlohmann::json jg = nlohmann::json::object();
    for (const auto& [g, s] : groups) jg[g] = summary_to_json(s);
    jr["groups"] = jg;
    jr["errors"] = errors;
    jr["read_errors"] = incomplete;
    jr["frames"] = frames;
    jr["cpu_s"] = cpu_s;

    {
        std::ofstream f(out / "report.md");
        f << md.str();
        if (!f) throw fail("cannot write " + (out / "report.md").string());
    }
    if (auto e = write_json_file(out / "report.json", jr)) throw fail(*e);

    if (!o.quiet) {
        std::cout << "evaluated " << evaluated << " flights with '" << o.classifier << "': side "
                  << all.side_tp << "/" << all.side_flights << ", centre " << all.centre_tp << "/"
                  << all.centre_flights << ", open-space false positives " << all.open_fp << "/"
                  << all.open_flights << ", wrong-side alarms " << all.side_wrong << "\nwrote "
                  << (out / "report.md").string() << " and report.json\n";
    }
    for (const auto& e : errors) std::cerr << "ardrone-gs: " << e << '\n';
    for (const auto& e : incomplete) std::cerr << "ardrone-gs: " << e << '\n';
    return errors.empty() && incomplete.empty() ? 0 : 1;
}

CommandRegistration reg(31, [](CLI::App& root) {
    auto o = std::make_shared<Opts>();
    auto* sub = root.add_subcommand(
        "eval",
        "Replay labelled flights, score them (docs/dataset.md) and write report.md / report.json");
    sub->add_option("DATASET", o->datasets, "Flight datasets, or folders holding them")->required();
    sub->add_option("--out,-o", o->out, "Output directory (created)")->required();
    add_classifier_options(*sub, o->classifier, o->set);
    add_dataset_input_options(*sub, o->input,
                              "each flight's own (flight.json's or the camera default)");
    sub->add_option("--split", o->split,
                    "Only flights whose labels.json \"split\" is this: tune or test")
        ->check(CLI::IsMember({"tune", "test"}));
    sub->add_option("--jobs,-j", o->jobs, "Flights replayed in parallel")
        ->capture_default_str()
        ->check(CLI::Range(1, 16));
    sub->add_flag("--quiet,-q", o->quiet, "No progress or summary line");
    set_action(*sub, [o] { return run(*o); });
});

}  // namespace
}  // namespace gs::app
