// `ardrone-gs replay DATASET --out DIR`: the obstacle pipeline over a recorded (or imported, or
// rendered) flight without a display. Writes DIR/decisions.csv (one row per frame),
// DIR/summary.json (frames, decode errors, timing, flagged frames per region; the flight's score
// when it is labelled), with --video DIR/overlay.mp4 (the frames with the overlay drawn;
// --undistort shows the undistorted image) and with --plots PNG plots of the classifier's series in
// DIR/plots/, with --points DIR/points.csv (every tracked point per frame). Frames that cannot be
// read leave their decisions.csv row empty and make the exit status non-zero (the outputs for the
// other frames are still written).
#include "app/cli_options.hpp"
#include "app/command.hpp"
#include "app/replay_outputs.hpp"
#include "app/replay_run.hpp"
#include "drone/dataset/thesis.hpp"

#include <nlohmann/json.hpp>

#include <fstream>
#include <iostream>
#include <memory>

namespace gs::app::cmd_replay {
namespace {
namespace fs = std::filesystem;

struct Opts {
    std::string dataset;
    std::string out;
    std::string classifier{vision::kDefaultClassifier};
    DatasetInputOptions input;  // --calibration, --fps
    std::vector<std::string> set;
    bool video = false;
    bool undistort = false;
    bool plots = false;
    bool points = false;
    bool quiet = false;
    bool force = false;
    bool strict = false;
};

// What a replay writes into --out: a folder holding only these may be written over.
constexpr std::initializer_list<const char*> kReplayOutputs = {
    "decisions.csv", "summary.json", "overlay.mp4", "plots", "points.csv"};

int run(const Opts& o) {
    if (auto e = check_output_dir(o.out, kReplayOutputs, o.force)) throw fail(*e);
    auto ds = open_input_dataset(o.dataset, o.input);
    if (!ds) throw fail(ds.error());
    for (const auto& w : ds->warnings())
        std::cerr << "ardrone-gs: " << o.dataset << ": " << w << '\n';
    const auto missing = missing_inputs(*ds, o.classifier);
    for (const auto& m : missing)
        std::cerr << "ardrone-gs: " << o.dataset << ": note: " << to_string(m) << '\n';
    const fs::path out = o.out;
    std::error_code ec;
    fs::create_directories(out, ec);
    if (ec) throw fail("cannot create " + out.string() + ": " + ec.message());

    ReplaySettings rs;
    rs.classifier = o.classifier;
    if (!o.input.calibration.empty()) rs.calibration_file = o.input.calibration;
    rs.set = o.set;
    rs.record_points = o.points;

    // One calibration for the whole run: the classifier and the undistorted video alike.
    auto calib = input_calibration(*ds, o.input);
    if (!calib) throw fail(calib.error());
    ReplayOutputs outputs(out, *calib);
    if (auto e = outputs.open_decisions(out / "decisions.csv")) throw fail(*e);
    if (o.video) {
        if (auto e = outputs.open_video(out / "overlay.mp4", ds->info(), o.undistort))
            throw fail(*e);
    }
    if (o.plots) outputs.enable_plots();
    if (o.points) {
        if (auto e = outputs.open_points(out / "points.csv")) throw fail(*e);
    }

    Progress progress("replay " + fs::path(o.dataset).filename().string(), ds->frame_count(),
                      !o.quiet);
    auto stats = replay_dataset(
        *ds, rs, [&](const FrameSample& s, const vision::FrameResult* r) { outputs.frame(s, r); },
        &progress);
    if (!stats) throw fail(o.dataset + ": " + stats.error());
    if (auto e = outputs.finish(o.plots ? out / "plots" : fs::path())) throw fail(*e);

    nlohmann::json j = summary_json(*ds, rs, *stats);
    j["missing_inputs"] = nlohmann::json::array();
    for (const auto& m : missing)
        j["missing_inputs"].push_back({{"input", m.input},
                                       {"columns", m.columns},
                                       {"unknown_share", m.unknown_share},
                                       {"cost", m.cost}});
    if (ds->labels()) {
        const dataset::FlightScore sc = dataset::score_flight(
            ds->labels()->scenario, ds->label_rows().value_or(std::vector<dataset::LabelRow>{}),
            stats->flags);
        j["score"] = score_json(sc);
    }
    if (auto e = write_json_file(out / "summary.json", j)) throw fail(*e);

    if (!o.quiet) {
        std::cout << "replayed " << stats->processed << " of " << stats->frames << " frames of "
                  << o.dataset << " with '" << rs.classifier << "' in " << fixed(stats->wall_s, 2)
                  << " s (" << fixed(stats->processed / std::max(stats->wall_s, 1e-9), 0)
                  << " frames/s); flagged frames: left " << stats->flagged[0] << ", center "
                  << stats->flagged[1] << ", right " << stats->flagged[2];
        if (stats->concealed > 0)
            std::cout << "; " << stats->concealed << " frames decoded with concealed damage";
        if (stats->rejected_steps > 0)
            std::cout << "; " << stats->rejected_steps
                      << " frames not after the previous one in time (skipped by the classifier)";
        std::cout << "\nwrote " << (out / "decisions.csv").string() << ", summary.json"
                  << (o.video ? ", overlay.mp4" : "") << (o.plots ? ", plots/" : "")
                  << (o.points ? ", points.csv" : "") << '\n';
    }
    // The outputs hold every frame that could be read; a frame that could not is still an error.
    if (stats->decode_errors > 0)
        throw fail(o.dataset + ": " + frames_unread_text(*stats) +
                   " (their decisions.csv rows are empty; summary.json counts them)");
    // Every frame produced a picture: damage the decoder concealed is a success unless --strict.
    if (o.strict && stats->concealed > 0)
        throw fail(o.dataset + ": " + std::to_string(stats->concealed) + " of " +
                   std::to_string(stats->frames) +
                   " frames were decoded with concealed damage (--strict)");
    return 0;
}

CommandRegistration reg(30, [](CLI::App& root) {
    auto o = std::make_shared<Opts>();
    auto* sub = root.add_subcommand(
        "replay",
        "Run the obstacle classifier over a dataset headless: decisions.csv, summary.json");
    sub->add_option(
           "DATASET", o->dataset,
           "Dataset directory (docs/dataset.md), or a thesis-style image folder with its IMU "
           "text file")
        ->required();
    sub->add_option("--out,-o", o->out,
                    "Output directory (created; a folder holding other files than a replay's "
                    "outputs is refused without --force)")
        ->required()
        ->check(output_directory());
    sub->add_flag("--force", o->force, "Write into --out even when it holds other files");
    sub->add_flag("--strict", o->strict,
                  "Exit non-zero on any video damage, concealed frames included (by default "
                  "only frames with no picture at all are an error)");
    add_classifier_options(*sub, o->classifier, o->set);
    add_dataset_input_options(*sub, o->input,
                              "flight.json's or the camera default, by the classifier and the "
                              "--undistort video alike");
    sub->add_flag("--video", o->video, "Also write overlay.mp4: the frames with the overlay");
    sub->add_flag("--undistort", o->undistort,
                  "With --video: show the undistorted image (straight lines come out straight)")
        ->needs("--video");
    sub->add_flag("--plots", o->plots, "Also write PNG plots of the classifier's series (plots/)");
    sub->add_flag("--points", o->points,
                  "Also write points.csv: every tracked point of every frame, where it is and "
                  "how the classifier judged it (region, kind, score)");
    sub->add_flag("--quiet,-q", o->quiet, "No progress or summary line");
    set_action(*sub, [o] { return run(*o); });
});

}  // namespace
}  // namespace gs::app::cmd_replay
