#pragma once
// A dataset replayed headless through the obstacle pipeline, as fast as possible: the same
// DatasetSource the window plays and the same ObstaclePipeline, so a flight decides the same on
// every run and wherever it is played. Shared by `replay` and `eval`.

#include "app/pipeline.hpp"
#include "drone/dataset/dataset.hpp"
#include "drone/dataset/scoring.hpp"
#include "vision/classifier.hpp"

#include <cstdint>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace gs::app {

// decisions.csv (the replay contract of issue #5 and `record`'s live_decisions.csv).
std::string decisions_csv_header();
// One row; a frame that could not be decoded (result null) has empty decision, score and state
// fields. The state is vision::state_word: unsafe, still, clear or unknown (the 0 in the decision
// column of an unknown region means "not flagged", not "clear").
std::string decisions_csv_row(std::int64_t frame, TimeNs t_ns, const vision::FrameResult* result);

struct ReplaySettings {
    std::string classifier{vision::kDefaultClassifier};
    std::optional<std::string> calibration_file;  // overrides flight.json / the default
    std::vector<std::string> set;                 // classifier parameter overrides key=value
    bool record_points = false;                   // FrameResult::points filled (replay --points)
};

// The calibration in `file` (--calibration FILE), scaled to `width` x `height`, the size of the
// frames it is used on. The error names the file and the problem.
[[nodiscard]] Expected<CameraCalibration, std::string> load_calibration_for(const std::string& file,
                                                                            int width, int height);
// What a replay of `dataset` uses, for the classifier and every output alike: the settings'
// calibration file when given, else the dataset's (flight.json's or the camera default).
[[nodiscard]] Expected<CameraCalibration, std::string> replay_calibration(
    const dataset::Dataset& dataset, const ReplaySettings& settings);

// Parses key=value overrides and applies them; the error names the first bad one.
[[nodiscard]] std::optional<std::string> apply_overrides(vision::ObstacleClassifier& c,
                                                         const std::vector<std::string>& set);

struct ReplayStats {
    std::int64_t frames = 0;          // rows in frames.csv
    std::int64_t processed = 0;       // frames through the classifier
    std::int64_t decode_errors = 0;   // frames that could not be read (skipped, row left empty)
    std::int64_t concealed = 0;       // frames decoded with concealed damage (kept, less trusted)
    std::int64_t repaired = 0;        // intra frames that replaced concealed damage (less trusted)
    std::int64_t rejected_steps = 0;  // frames whose time was not after the previous one's
    std::string first_error;
    std::array<std::int64_t, 3> flagged{};  // frames each region was reported unsafe
    // Frames each region had no measured decision (RegionDecision::valid false), in all and by
    // vision::UnknownReason (indexed by its value).
    std::array<std::int64_t, 3> unknown{};
    // Judged only for approaching things (a still camera: vision::RegionDecision::approach_only).
    std::array<std::int64_t, 3> still{};
    std::array<std::array<std::int64_t, vision::kUnknownReasonCount>, 3> unknown_by_reason{};
    double wall_s = 0, cpu_s = 0;  // whole replay, this thread
    // Per frame, milliseconds: reading (decode) and classifying.
    double read_ms_p50 = 0, read_ms_p99 = 0, classify_ms_p50 = 0, classify_ms_p99 = 0;
    double classify_ms_mean = 0;
    std::vector<dataset::RegionFlags> flags;  // per frame, for scoring
    vision::ParamMap params;                  // the classifier's parameters as run
};

// An input the classifier uses that the dataset lacks (issue 14 point 7), and what that costs.
struct MissingInput {
    std::string input;         // "velocity", "altitude", "attitude (pitch, yaw)", "roll"
    std::string columns;       // the frames.csv columns that are absent or empty
    double unknown_share = 1;  // share of frames where it is unknown (1: all)
    std::string cost;          // what the classifier cannot do without it
};
// The inputs `classifier` uses that are unknown in more than 10 % of `dataset`'s frames.
std::vector<MissingInput> missing_inputs(const dataset::Dataset& dataset,
                                         std::string_view classifier);
// "no velocity (vx_mps, vy_mps, vz_mps) in 100 % of frames: ..." for a message line.
std::string to_string(const MissingInput& m);

// "3 of 153 frames could not be read (first: ...)": the error a run with unreadable frames ends on.
std::string frames_unread_text(const ReplayStats& st);

// What the caller sees for each frame (result null when the frame could not be decoded).
using ReplayFrameFn =
    std::function<void(const FrameSample& sample, const vision::FrameResult* result)>;

// Progress on a terminal: "label: frames done / total, rate, time left", rewritten in place;
// silent when stderr is not a terminal (CI logs) or when disabled.
class Progress {
public:
    Progress(std::string label, std::int64_t total, bool enabled);
    void update(std::int64_t done);
    void finish();

private:
    std::string label_;
    std::int64_t total_;
    bool enabled_;
    double t0_s_;
    double last_print_s_ = -1;
};

// Replays `dataset` through a fresh pipeline. Errors: unknown classifier, bad override, no
// frames, calibration file unreadable. Decode errors are counted, not fatal.
[[nodiscard]] Expected<ReplayStats, std::string> replay_dataset(const dataset::Dataset& dataset,
                                                                const ReplaySettings& settings,
                                                                const ReplayFrameFn& on_frame,
                                                                Progress* progress = nullptr);

// Thread CPU time in seconds (the honest number on a shared machine).
double thread_cpu_seconds();
double wall_seconds();

}  // namespace gs::app
