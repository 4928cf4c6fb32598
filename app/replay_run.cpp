#include "app/replay_run.hpp"

#include "drone/dataset/csv.hpp"
#include "drone/dataset/dataset_source.hpp"
#include "drone/dataset/video_frames.hpp"

#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <iostream>

namespace gs::app {

std::string decisions_csv_header() {
    return "frame,t_ms,left,center,right,left_score,center_score,right_score,left_state,"
           "center_state,right_state\n";
}

std::string decisions_csv_row(std::int64_t frame, TimeNs t_ns, const vision::FrameResult* res) {
    std::string line = std::to_string(frame) + ',' + dataset::csv::format_ms(t_ns);
    for (auto reg : vision::kRegions)
        line += res == nullptr ? "," : (res->region(reg).unsafe ? ",1" : ",0");
    for (auto reg : vision::kRegions)
        line += ',' + (res == nullptr ? std::string()
                                      : dataset::csv::format_number(res->region(reg).score));
    for (auto reg : vision::kRegions) {
        line += ',';
        if (res != nullptr) line += vision::state_word(res->region(reg));
    }
    line += '\n';
    return line;
}

std::optional<std::string> apply_overrides(vision::ObstacleClassifier& c,
                                           const std::vector<std::string>& set) {
    for (const std::string& kv : set) {
        const auto o = vision::parse_param_override(kv);
        if (!o) return "--set " + kv + ": " + o.error();
        const std::string& key = o->key;
        const vision::ParamStatus st = c.set_param(key, o->value);
        if (st == vision::ParamStatus::UnknownName) {
            std::string names;
            for (const auto& p : c.params()) names += (names.empty() ? "" : ", ") + p.name;
            return "--set " + kv + ": " + std::string(c.name()) + " has no parameter '" + key +
                   "' (it has: " + names + ")";
        }
        if (st == vision::ParamStatus::OutOfRange) {
            for (const auto& p : c.params())
                if (p.name == key)
                    return "--set " + kv + ": out of range [" +
                           vision::format_param_value(p.min, p.type) + ", " +
                           vision::format_param_value(p.max, p.type) + "]";
        }
        if (st != vision::ParamStatus::Ok) return "--set " + kv + ": " + vision::to_string(st);
    }
    return std::nullopt;
}

Expected<CameraCalibration, std::string> load_calibration_for(const std::string& file, int width,
                                                              int height) {
    auto c = load_calibration_file(file);
    if (!c) return Unexpected(to_string(c.error()));
    return c->scaled_to(width, height);
}

Expected<CameraCalibration, std::string> replay_calibration(const dataset::Dataset& dataset,
                                                            const ReplaySettings& settings) {
    if (!settings.calibration_file) return dataset.calibration();
    return load_calibration_for(*settings.calibration_file, dataset.info().width,
                                dataset.info().height);
}

std::vector<MissingInput> missing_inputs(const dataset::Dataset& dataset,
                                         std::string_view classifier) {
    struct Need {
        const char* input;
        const char* columns;
        std::vector<double NavState::*> fields;
        const char* cost;
    };
    const bool flow = classifier != "thesis";
    std::vector<Need> needs;
    if (flow) {
        needs.push_back({"velocity",
                         "vx_mps, vy_mps, vz_mps",
                         {&NavState::vx_mps, &NavState::vy_mps, &NavState::vz_mps},
                         "the focus of expansion and the flight corridor cannot be placed: every "
                         "tracked point is judged by its time to contact alone, so walls, floor "
                         "and anything near the image edges can raise alarms"});
        needs.push_back({"altitude",
                         "altitude_m",
                         {&NavState::altitude_m},
                         "the floor cannot be told from an obstacle in the corridor"});
        needs.push_back({"attitude (pitch, yaw)",
                         "pitch_deg, yaw_deg",
                         {&NavState::pitch_deg, &NavState::yaw_deg},
                         "the flow of pitching and turning is not removed: a rotation can read "
                         "as expansion"});
    }
    needs.push_back({"roll",
                     "roll_deg",
                     {&NavState::roll_deg},
                     flow ? "the flow of rolling is not removed"
                          : "the image is not rotated by the roll (thesis §3.2): banking reads as "
                            "sideways flow"});
    std::vector<MissingInput> out;
    const auto& rows = dataset.frames();
    if (rows.empty()) return out;
    for (const Need& n : needs) {
        std::size_t unknown = 0;
        for (const dataset::FrameRow& r : rows) {
            bool any_unknown = false;
            for (auto f : n.fields) any_unknown |= !std::isfinite(r.nav.*f);
            unknown += any_unknown ? 1 : 0;
        }
        const double share = static_cast<double>(unknown) / static_cast<double>(rows.size());
        if (share > 0.1) out.push_back({n.input, n.columns, share, n.cost});
    }
    return out;
}

std::string to_string(const MissingInput& m) {
    char pct[16];
    std::snprintf(pct, sizeof pct, "%.0f %%", m.unknown_share * 100);
    return "no " + m.input + " (" + m.columns + ") in " + pct + " of the frames: " + m.cost;
}

std::string frames_unread_text(const ReplayStats& st) {
    return std::to_string(st.decode_errors) + " of " + std::to_string(st.frames) +
           " frames could not be read (first: " + st.first_error + ")";
}

double thread_cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

double wall_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

Progress::Progress(std::string label, std::int64_t total, bool enabled)
    : label_(std::move(label)),
      total_(total),
      enabled_(enabled && ::isatty(STDERR_FILENO) == 1),
      t0_s_(wall_seconds()) {}

void Progress::update(std::int64_t done) {
    if (!enabled_) return;
    const double now = wall_seconds();
    if (last_print_s_ >= 0 && now - last_print_s_ < 0.2 && done < total_) return;
    last_print_s_ = now;
    const double el = now - t0_s_;
    const double rate = el > 0 ? static_cast<double>(done) / el : 0;
    const double left = rate > 0 ? static_cast<double>(total_ - done) / rate : 0;
    char b[256];
    std::snprintf(b, sizeof b, "\r%s: %lld / %lld frames, %.0f frames/s, %.0f s left   ",
                  label_.c_str(), static_cast<long long>(done), static_cast<long long>(total_),
                  rate, left);
    std::cerr << b << std::flush;
}

void Progress::finish() {
    if (enabled_ && last_print_s_ >= 0) std::cerr << "\r\033[K" << std::flush;
}

namespace {

double percentile(std::vector<double>& v, double q) {
    if (v.empty()) return 0;
    const auto k = static_cast<std::size_t>(std::lround(q * static_cast<double>(v.size() - 1)));
    std::nth_element(v.begin(), v.begin() + static_cast<long>(k), v.end());
    return v[k];
}

}  // namespace

Expected<ReplayStats, std::string> replay_dataset(const dataset::Dataset& dataset,
                                                  const ReplaySettings& settings,
                                                  const ReplayFrameFn& on_frame,
                                                  Progress* progress) {
    GS_TRY_ASSIGN(auto calib, replay_calibration(dataset, settings));
    ObstaclePipeline pipeline(settings.classifier, calib);
    if (!pipeline.ok()) {
        std::string names;
        for (auto n : vision::classifier_names())
            names += (names.empty() ? "" : ", ") + std::string(n);
        return Unexpected("unknown classifier '" + settings.classifier + "' (" + names + ")");
    }
    if (auto e = apply_overrides(pipeline.classifier(), settings.set)) return Unexpected(*e);
    pipeline.classifier().set_record_points(settings.record_points);

    auto store = dataset::open_frames(dataset);
    if (!store) return Unexpected(to_string(store.error()));

    // The source takes its own copy of the dataset (it owns what it plays).
    dataset::DatasetSource source(dataset, std::move(*store), SteadyClock::instance(),
                                  Pacing::fastest());

    ReplayStats st;
    st.params = pipeline.classifier().params_to_map();
    st.frames = dataset.frame_count();
    st.flags.assign(static_cast<std::size_t>(st.frames), dataset::RegionFlags{});
    std::vector<double> read_ms, classify_ms;
    read_ms.reserve(static_cast<std::size_t>(st.frames));
    classify_ms.reserve(static_cast<std::size_t>(st.frames));
    const double wall0 = wall_seconds(), cpu0 = thread_cpu_seconds();

    FrameSample sample;
    NavState nav;
    while (true) {
        while (source.next_nav(nav) == SourceStatus::Sample) {
        }
        const std::int64_t index = source.position();
        const double t0 = wall_seconds();
        const SourceStatus s = source.next(sample);
        const double t1 = wall_seconds();
        if (s == SourceStatus::End) break;
        if (s == SourceStatus::Error) {
            ++st.decode_errors;
            if (st.first_error.empty()) st.first_error = source.last_error();
            FrameSample blank;
            blank.index = index;
            blank.t_ns = dataset.frames()[static_cast<std::size_t>(index)].nav.t_ns;
            blank.nav = dataset.frames()[static_cast<std::size_t>(index)].nav;
            if (on_frame) on_frame(blank, nullptr);
            if (progress) progress->update(index + 1);
            continue;
        }
        if (s != SourceStatus::Sample) break;  // fastest pacing: never NotYet or Paused
        const vision::FrameResult& res = pipeline.process(sample);
        const double t2 = wall_seconds();
        st.concealed += sample.concealed ? 1 : 0;
        st.repaired += sample.repaired ? 1 : 0;
        st.rejected_steps = res.rejected_steps;
        read_ms.push_back((t1 - t0) * 1e3);
        classify_ms.push_back((t2 - t1) * 1e3);
        ++st.processed;
        dataset::RegionFlags& f = st.flags[static_cast<std::size_t>(sample.index)];
        for (std::size_t r = 0; r < 3; ++r) {
            const vision::RegionDecision& d = res.regions[r];
            f[r] = d.unsafe;
            st.flagged[r] += f[r] ? 1 : 0;
            st.still[r] += vision::decision_state(d) == vision::DecisionState::Still ? 1 : 0;
            if (!d.valid) {
                ++st.unknown[r];
                const auto why = static_cast<std::size_t>(d.unknown);
                if (why < st.unknown_by_reason[r].size()) ++st.unknown_by_reason[r][why];
            }
        }
        if (on_frame) on_frame(sample, &res);
        if (progress) progress->update(sample.index + 1);
    }
    st.wall_s = wall_seconds() - wall0;
    st.cpu_s = thread_cpu_seconds() - cpu0;
    double sum = 0;
    for (double v : classify_ms) sum += v;
    st.classify_ms_mean = classify_ms.empty() ? 0 : sum / static_cast<double>(classify_ms.size());
    st.read_ms_p50 = percentile(read_ms, 0.5);
    st.read_ms_p99 = percentile(read_ms, 0.99);
    st.classify_ms_p50 = percentile(classify_ms, 0.5);
    st.classify_ms_p99 = percentile(classify_ms, 0.99);
    if (progress) progress->finish();
    return st;
}

}  // namespace gs::app
