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

namespace gs::app::cmd_eval {
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
    Shard shard;
    bool merge = false;  // DATASET... are shard output folders to combine
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
    {
        const nlohmann::json labels = nlohmann::json::parse(ds->labels()->json, nullptr, false);
        r.group = text_or(labels, "group", to_string(ds->labels()->scenario));
        r.split = text_or(labels, "split", "");
    }
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
    // Keep only what the report needs: a flight's result is a few hundred bytes whatever its
    // length, so memory stays flat in the number of flights.
    r.stats.flags = {};
    r.stats.params = {};
    r.stats.first_error = {};
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

// What a report says about the run that made it (the same for every shard of one batch).
struct RunHeader {
    std::string classifier;
    std::vector<std::string> set;
    std::string split;
    DatasetInputOptions input;
};

// The report's figures in one place: report.md and report.json from the flights' results in
// batch order (those not evaluated here, `nullopt`, are left out). A shard's report and a merged
// one are written by this same function, so a merge of all shards equals the single run.
void write_report(const std::vector<std::optional<FlightResult>>& results, const RunHeader& h,
                  const Shard& shard, const fs::path& out, bool quiet, int& exit_code) {
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
    for (const auto& slot : results) {
        if (!slot) continue;
        const FlightResult& r = *slot;
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
    md << "# Evaluation: classifier '" << h.classifier << "'\n\n";
    md << evaluated << " flights";
    if (!h.split.empty()) md << " (split '" << h.split << "')";
    if (!shard.whole())
        md << " (shard " << shard.k << "/" << shard.n << ": every " << shard.n
           << "-th flight; `eval --merge` combines the shards)";
    md << ", " << frames
       << " frames, scored as docs/dataset.md \"Scoring a flight\" (thesis ch. 6; "
          "detection counts from 0.7 m).\n";
    if (!h.set.empty()) {
        md << "Parameter overrides:";
        for (const auto& s : h.set) md << " `" << s << "`";
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
    jr["classifier"] = h.classifier;
    jr["overrides"] = h.set;
    if (!h.split.empty()) jr["split"] = h.split;
    if (!shard.whole()) jr["shard"] = {{"k", shard.k}, {"n", shard.n}};
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

    if (!quiet) {
        std::cout << "evaluated " << evaluated << " flights with '" << h.classifier << "'";
        if (!shard.whole()) std::cout << " (shard " << shard.k << "/" << shard.n << ")";
        std::cout << ": side " << all.side_tp << "/" << all.side_flights << ", centre "
                  << all.centre_tp << "/" << all.centre_flights << ", open-space false positives "
                  << all.open_fp << "/" << all.open_flights << ", wrong-side alarms "
                  << all.side_wrong << "\nwrote " << (out / "report.md").string()
                  << " and report.json\n";
    }
    for (const auto& e : errors) std::cerr << "ardrone-gs: " << e << '\n';
    for (const auto& e : incomplete) std::cerr << "ardrone-gs: " << e << '\n';
    exit_code = errors.empty() && incomplete.empty() ? 0 : 1;
}

// ---- Shards: partial.json holds each flight's result in full, to be merged later. ----

constexpr const char* kPartialFormat = "ardrone-gs eval partial";
constexpr int kPartialVersion = 1;

// FNV-1a over the batch's flight names in order: shards of one batch agree on it, so a merge
// of shards run over different folders (or a different --split) is refused.
std::string batch_fingerprint(const std::vector<fs::path>& flights) {
    std::uint64_t h = 1469598103934665603ULL;
    for (const fs::path& f : flights) {
        const std::string name = f.filename().string() + '\n';
        for (unsigned char c : name) {
            h ^= c;
            h *= 1099511628211ULL;
        }
    }
    std::ostringstream o;
    o << std::hex << h;
    return o.str();
}

nlohmann::json header_json(const RunHeader& h, const Shard& shard, std::size_t total,
                           const std::string& fingerprint) {
    return {{"format", kPartialFormat},   {"version", kPartialVersion},
            {"classifier", h.classifier}, {"overrides", h.set},
            {"split", h.split},           {"calibration", h.input.calibration},
            {"fps", h.input.fps},         {"shard", {{"k", shard.k}, {"n", shard.n}}},
            {"flights_in_batch", total},  {"batch_fingerprint", fingerprint}};
}

template <class T>
nlohmann::json opt_json(const std::optional<T>& v) {
    return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}
template <class T>
std::optional<T> json_opt(const nlohmann::json& j) {
    if (j.is_null()) return std::nullopt;
    return j.get<T>();
}

nlohmann::json result_json(std::size_t index, const FlightResult& r) {
    const dataset::FlightScore& s = r.score;
    nlohmann::json missing = nlohmann::json::array();
    for (const auto& m : r.missing)
        missing.push_back({{"input", m.input},
                           {"columns", m.columns},
                           {"unknown_share", m.unknown_share},
                           {"cost", m.cost}});
    return {{"index", index},
            {"name", r.name},
            {"path", r.path.string()},
            {"group", r.group},
            {"split", r.split},
            {"error", r.error},
            {"read_error", r.read_error},
            {"processed", r.stats.processed},
            {"decode_errors", r.stats.decode_errors},
            {"cpu_s", r.stats.cpu_s},
            {"missing", missing},
            {"score",
             {{"scenario", to_string(s.scenario)},
              {"tp", s.tp},
              {"fp", s.fp},
              {"fn", s.fn},
              {"tn", s.tn},
              {"detection_frame", opt_json(s.detection_frame)},
              {"detection_distance_m", opt_json(s.detection_distance_m)},
              {"late_detection_distance_m", opt_json(s.late_detection_distance_m)},
              {"false_regions", s.false_regions},
              {"first_false_frame", opt_json(s.first_false_frame)},
              {"other_flag_frames", s.other_flag_frames},
              {"flagged_frames", s.flagged_frames},
              {"frames", s.frames},
              {"scored_frames", s.scored_frames},
              {"unscored_frames", s.unscored_frames}}}};
}

FlightResult result_from_json(const nlohmann::json& j) {
    FlightResult r;
    r.name = j.at("name").get<std::string>();
    r.path = j.at("path").get<std::string>();
    r.group = j.at("group").get<std::string>();
    r.split = j.at("split").get<std::string>();
    r.error = j.at("error").get<std::string>();
    r.read_error = j.at("read_error").get<std::string>();
    r.stats.processed = j.at("processed").get<std::int64_t>();
    r.stats.decode_errors = j.at("decode_errors").get<std::int64_t>();
    r.stats.cpu_s = j.at("cpu_s").get<double>();
    for (const auto& m : j.at("missing"))
        r.missing.push_back({m.at("input").get<std::string>(), m.at("columns").get<std::string>(),
                             m.at("unknown_share").get<double>(), m.at("cost").get<std::string>()});
    const nlohmann::json& s = j.at("score");
    dataset::FlightScore& f = r.score;
    const std::string scenario = s.at("scenario").get<std::string>();
    bool known = false;
    for (auto c : {dataset::Scenario::Left, dataset::Scenario::Center, dataset::Scenario::Right,
                   dataset::Scenario::None})
        if (to_string(c) == scenario) {
            f.scenario = c;
            known = true;
        }
    if (!known) throw std::runtime_error("unknown scenario '" + scenario + "'");
    f.tp = s.at("tp").get<int>();
    f.fp = s.at("fp").get<int>();
    f.fn = s.at("fn").get<int>();
    f.tn = s.at("tn").get<int>();
    f.detection_frame = json_opt<std::int64_t>(s.at("detection_frame"));
    f.detection_distance_m = json_opt<double>(s.at("detection_distance_m"));
    f.late_detection_distance_m = json_opt<double>(s.at("late_detection_distance_m"));
    f.false_regions = s.at("false_regions").get<std::array<bool, 3>>();
    f.first_false_frame = json_opt<std::int64_t>(s.at("first_false_frame"));
    f.other_flag_frames = s.at("other_flag_frames").get<std::array<int, 3>>();
    f.flagged_frames = s.at("flagged_frames").get<std::array<int, 3>>();
    f.frames = s.at("frames").get<int>();
    f.scored_frames = s.at("scored_frames").get<int>();
    f.unscored_frames = s.at("unscored_frames").get<int>();
    return r;
}

// `eval --merge DIR... --out OUT`: the shards' partial.json combined, checked to be the parts of
// one batch (same classifier, overrides, split, inputs, flights; every part exactly once), and
// the report written as the single run would have; each flight's folder is copied into OUT.
int run_merge(const Opts& o) {
    const fs::path out = o.out;
    std::optional<nlohmann::json> first;
    std::vector<std::optional<FlightResult>> results;
    std::vector<bool> seen_parts;
    RunHeader h;
    for (const std::string& d : o.datasets) {
        const fs::path file = fs::path(d) / "partial.json";
        std::ifstream f(file);
        if (!f)
            throw fail(file.string() + ": cannot read (is " + d + " an `eval --shard` output?)");
        nlohmann::json j = nlohmann::json::parse(f, nullptr, false);
        if (j.is_discarded() || !j.is_object() || j.value("format", "") != kPartialFormat)
            throw fail(file.string() + ": not an eval partial report");
        if (j.value("version", 0) != kPartialVersion)
            throw fail(file.string() + ": partial report version " +
                       std::to_string(j.value("version", 0)) + ", this program reads " +
                       std::to_string(kPartialVersion));
        try {
            nlohmann::json head = j;
            head.erase("shard");
            head.erase("flights");
            const int n = j.at("shard").at("n").get<int>();
            const int k = j.at("shard").at("k").get<int>();
            if (!first) {
                first = head;
                const auto total = head.at("flights_in_batch").get<std::size_t>();
                if (total > 10'000'000) throw fail(file.string() + ": implausible batch size");
                results.resize(total);
                seen_parts.assign(static_cast<std::size_t>(n), false);
                h.classifier = head.at("classifier").get<std::string>();
                h.set = head.at("overrides").get<std::vector<std::string>>();
                h.split = head.at("split").get<std::string>();
                h.input.calibration = head.at("calibration").get<std::string>();
                h.input.fps = head.at("fps").get<double>();
            } else if (head != *first) {
                throw fail(file.string() +
                           ": a shard of another batch (classifier, overrides, split, inputs or "
                           "flights differ from " +
                           o.datasets.front() + "'s)");
            }
            if (n != static_cast<int>(seen_parts.size()) || k < 1 || k > n)
                throw fail(file.string() + ": shard " + std::to_string(k) + "/" +
                           std::to_string(n) + " does not match the others' count " +
                           std::to_string(seen_parts.size()));
            if (seen_parts[static_cast<std::size_t>(k - 1)])
                throw fail(file.string() + ": shard " + std::to_string(k) + "/" +
                           std::to_string(n) + " given twice");
            seen_parts[static_cast<std::size_t>(k - 1)] = true;
            const Shard shard{k, n};
            for (const auto& jf : j.at("flights")) {
                const auto i = jf.at("index").get<std::size_t>();
                if (i >= results.size() || !shard.holds(i) || results[i])
                    throw fail(file.string() + ": flight index " + std::to_string(i) +
                               " does not belong to shard " + std::to_string(k) + "/" +
                               std::to_string(n));
                results[i] = result_from_json(jf);
            }
            // Each flight's own outputs (decisions.csv, summary.json) beside the merged report.
            std::error_code ec;
            if (!fs::equivalent(d, out, ec))
                for (const auto& jf : j.at("flights")) {
                    const std::string name = jf.at("name").get<std::string>();
                    const fs::path src = fs::path(d) / name;
                    if (!fs::is_directory(src, ec)) continue;
                    fs::create_directories(out / name, ec);
                    fs::copy(src, out / name,
                             fs::copy_options::recursive | fs::copy_options::overwrite_existing,
                             ec);
                    if (ec)
                        throw fail("cannot copy " + src.string() + " to " + out.string() + ": " +
                                   ec.message());
                }
        } catch (const nlohmann::json::exception& e) {
            throw fail(file.string() + ": malformed partial report (" + e.what() + ")");
        } catch (const CLI::Error&) {
            throw;
        } catch (const std::runtime_error& e) {
            throw fail(file.string() + ": " + e.what());
        }
    }
    std::string missing;
    for (std::size_t k = 0; k < seen_parts.size(); ++k)
        if (!seen_parts[k])
            missing += (missing.empty() ? "" : ", ") + std::to_string(k + 1) + "/" +
                       std::to_string(seen_parts.size());
    if (!missing.empty()) throw fail("shards missing from the merge: " + missing);
    int code = 0;
    write_report(results, h, Shard{}, out, o.quiet, code);
    return code;
}

int run(const Opts& o) {
    const fs::path out = o.out;
    std::error_code ec;
    fs::create_directories(out, ec);
    if (ec) throw fail("cannot create " + out.string() + ": " + ec.message());
    if (o.merge) return run_merge(o);

    std::string err;
    const std::vector<fs::path> flights = expand(o.datasets, err);
    if (!err.empty()) throw fail(err);
    if (flights.empty()) throw fail("no flights to evaluate");
    {
        // Validate the classifier and overrides once, before any work (--calibration is checked
        // when parsed).
        auto probe = vision::make_classifier(o.classifier, {});
        if (!probe) throw fail("unknown classifier '" + o.classifier + "'");
        if (auto e = apply_overrides(*probe, o.set)) throw fail(*e);
    }
    // This shard's flights, in batch order.
    std::vector<std::size_t> mine;
    for (std::size_t i = 0; i < flights.size(); ++i)
        if (o.shard.holds(i)) mine.push_back(i);

    std::vector<std::optional<FlightResult>> results(flights.size());
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
        std::cerr << "\reval: " << d << " / " << mine.size() << " flights, " << f;
        if (opened > 0) {
            const double total = static_cast<double>(progress.opened_frames.load()) /
                                 static_cast<double>(opened) * static_cast<double>(mine.size());
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
    // Each worker takes the next flight and writes its result into that flight's slot: the
    // report reads the slots in batch order, so it does not depend on --jobs or on timing.
    auto worker = [&] {
        for (std::size_t m = next++; m < mine.size(); m = next++) {
            const std::size_t i = mine[m];
            results[i] = evaluate(flights[i], o, out, progress);
            ++done;
            if (tty) {
                std::lock_guard lock(mu);
                print_progress(true);
            }
        }
    };
    const int jobs = std::clamp(o.jobs, 1, static_cast<int>(std::max<std::size_t>(1, mine.size())));
    std::vector<std::thread> pool;
    for (int j = 1; j < jobs; ++j) pool.emplace_back(worker);
    worker();
    for (auto& t : pool) t.join();
    if (tty) std::cerr << "\r\033[K" << std::flush;

    const RunHeader h{o.classifier, o.set, o.split, o.input};
    if (!o.shard.whole()) {
        nlohmann::json p = header_json(h, o.shard, flights.size(), batch_fingerprint(flights));
        p["flights"] = nlohmann::json::array();
        for (std::size_t i : mine) p["flights"].push_back(result_json(i, *results[i]));
        if (auto e = write_json_file(out / "partial.json", p)) throw fail(*e);
    }
    int code = 0;
    write_report(results, h, o.shard, out, o.quiet, code);
    return code;
}

CommandRegistration reg(31, [](CLI::App& root) {
    auto o = std::make_shared<Opts>();
    auto* sub = root.add_subcommand(
        "eval",
        "Replay labelled flights, score them (docs/dataset.md) and write report.md / report.json");
    sub->add_option("DATASET", o->datasets,
                    "Flight datasets, or folders holding them (with --merge: `eval --shard` "
                    "output folders)")
        ->required();
    sub->add_option("--out,-o", o->out, "Output directory (created)")->required();
    add_classifier_options(*sub, o->classifier, o->set);
    add_dataset_input_options(*sub, o->input,
                              "each flight's own (flight.json's or the camera default)");
    sub->add_option("--split", o->split,
                    "Only flights whose labels.json \"split\" is this: tune or test")
        ->check(CLI::IsMember({"tune", "test"}));
    add_jobs_option(*sub, o->jobs, "Flights replayed");
    auto* shard = add_shard_option(
        *sub, o->shard,
        "Evaluate only every N-th flight (the K-th part of N, K from 1) and write partial.json "
        "beside the part's report, for `eval --merge`");
    sub->add_flag("--merge", o->merge,
                  "Combine the partial reports in the DATASET folders (the outputs of every "
                  "`--shard K/N` of one batch) into the report a single run writes")
        ->excludes(shard);
    sub->add_flag("--quiet,-q", o->quiet, "No progress or summary line");
    set_action(*sub, [o] { return run(*o); });
});

}  // namespace
}  // namespace gs::app::cmd_eval
