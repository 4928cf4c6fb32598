#include "vision/classifier.hpp"
#include "vision/common.hpp"

#include "vision/flow_classifier.hpp"
#include "vision/thesis_classifier.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace gs::vision {

const char* to_string(Region r) {
    switch (r) {
        case Region::Left:
            return "left";
        case Region::Centre:
            return "centre";
        case Region::Right:
            return "right";
    }
    return "?";
}

const char* to_string(UnknownReason r) {
    switch (r) {
        case UnknownReason::None:
            return "measured";
        case UnknownReason::WarmingUp:
            return "warming up: not enough history yet";
        case UnknownReason::TooFewPoints:
            return "too few tracked points";
        case UnknownReason::NoEgoMotion:
            return "no usable velocity or focus of expansion";
        case UnknownReason::Rotating:
            return "rotating too fast";
        case UnknownReason::StaleVideo:
            return "video stale";
        case UnknownReason::Gap:
            return "frames missing";
        case UnknownReason::DamagedFrame:
            return "damaged frame (concealed by the decoder, or the frame that repaired it)";
        case UnknownReason::MotionContradicted:
            return "most points move against the camera motion in use";
    }
    return "?";
}

const PlotSeries* FrameResult::find_series(std::string_view name) const {
    for (const PlotSeries& s : series)
        if (s.name == name) return &s;
    return nullptr;
}

std::unique_ptr<ObstacleClassifier> make_classifier(std::string_view name,
                                                    const CameraCalibration& calib) {
    if (name == "thesis") return std::make_unique<ThesisClassifier>(calib);
    if (name == "flow") return std::make_unique<FlowClassifier>(calib);
    return nullptr;
}

std::vector<std::string_view> classifier_names() {
    return {"thesis", "flow"};
}

TrackingClassifier::TrackingClassifier(const CameraCalibration& calib) : base_calib_(calib) {
    for (Region r : {Region::Left, Region::Right, Region::Centre}) {
        const std::string n = to_string(r);
        s_score_[static_cast<std::size_t>(r)] = add_series(n + ".score");
        s_threshold_[static_cast<std::size_t>(r)] = add_series(n + ".threshold");
    }
}

void TrackingClassifier::reconfigure() {
    if (!calib_.valid()) calib_ = base_calib_;
    tracker_.configure(calib_, tracker_params());
    track_score_.reserve(static_cast<std::size_t>(std::max(1, tracker_params().max_tracks)));
    order_.reserve(static_cast<std::size_t>(std::max(1, tracker_params().max_tracks)));
    result_.traces.reserve(kMaxTraces);
    reset();
}

void TrackingClassifier::apply_params(bool resets) {
    if (resets)
        reconfigure();
    else
        tracker_.set_params(tracker_params());
}

void TrackingClassifier::reset() {
    tracker_.reset();
    have_prev_ = false;
    prev_attitude_ = {};
    for (PlotSeries& s : result_.series) s.points.clear();
    result_.regions = {};
    result_.rejected_steps = 0;
    result_.overlay.clear();
    result_.traces.clear();
    result_.points.clear();
    on_reset();
}

void TrackingClassifier::set_calibration(const CameraCalibration& calib) {
    base_calib_ = calib;
    calib_ = calib;
    reconfigure();
}

std::size_t TrackingClassifier::add_series(std::string name) {
    result_.series.emplace_back(std::move(name), "frame", kSeriesCapacity);
    return result_.series.size() - 1;
}

void TrackingClassifier::plot(std::size_t series, double y) {
    result_.series[series].points.push({static_cast<double>(result_.frame_index), y});
}

Region TrackingClassifier::region_of(float stab_x) const {
    const double mid = calib_.width / 2.0;
    const double band = centre_band_px();
    const auto x = static_cast<double>(stab_x);
    if (x < mid - band) return Region::Left;
    if (x > mid + band) return Region::Right;
    return Region::Centre;
}

cv::Point2f TrackingClassifier::stab_to_raw(cv::Point2f stab) const {
    return calib_.distort_point(tracker_.stabiliser().inverse(stab));
}

const FrameResult& TrackingClassifier::process(const FrameInput& in) {
    const auto t_total = StageClock::now();
    if (in.image.empty()) return result_;
    // A frame no later than the previous one (equal capture times in a dataset, a clock that
    // stepped back) has no time step to measure motion over: it is rejected, the decisions stay
    // as they were, and it never raises an alarm (issue 14 point 3).
    if (have_prev_ && in.t_ns <= prev_t_ns_) {
        ++result_.rejected_steps;
        return result_;
    }
    if (calib_.width != in.image.cols || calib_.height != in.image.rows) {
        calib_ = base_calib_.scaled_to(in.image.cols, in.image.rows);
        tracker_.configure(calib_, tracker_params());
        reset();
    }
    EgoPrior prior;
    prior.rotation =
        wants_derotation() && have_prev_ && prev_attitude_.complete() && in.attitude.complete();
    const cv::Matx33d derot = prior.rotation
                                  ? rotation_homography(calib_, prev_attitude_, in.attitude)
                                  : cv::Matx33d::eye();
    prepare(in, prior);
    tracker_.update(in.image, in.t_ns, in.attitude.roll_deg, derot, prior);
    result_.frame_index = tracker_.frame_index() - 1;
    result_.t_ns = in.t_ns;
    result_.tracks = static_cast<int>(tracker_.tracks().size());
    result_.tracks_added = tracker_.added_last_frame();
    result_.tracks_ended = tracker_.ended_last_frame();

    auto t0 = StageClock::now();
    track_score_.assign(tracker_.tracks().size(), kUnknown);
    std::array<bool, 3> was_unsafe{};
    for (Region r : kRegions) {
        const auto i = static_cast<std::size_t>(r);
        was_unsafe[i] = result_.regions[i].valid && result_.regions[i].unsafe;
    }
    damaged_ = in.concealed || in.repaired;
    classify(in);
    if (damaged_) {
        // Less trust in a damaged frame: it may keep an alarm, not raise one.
        for (Region r : kRegions) {
            RegionDecision& d = result_.regions[static_cast<std::size_t>(r)];
            if (d.unsafe && !was_unsafe[static_cast<std::size_t>(r)]) {
                d.unsafe = false;
                d.valid = false;
                d.approach_only = false;
                d.unknown = UnknownReason::DamagedFrame;
            }
        }
    }
    for (Region r : kRegions) {
        const auto i = static_cast<std::size_t>(r);
        plot(s_score_[i], result_.regions[i].score);
        plot(s_threshold_[i], result_.regions[i].threshold);
    }
    result_.timings.classify_ms = ms_since(t0);

    t0 = StageClock::now();
    fill_traces();
    if (record_points_) fill_points();
    build_overlay();
    result_.timings.overlay_ms = ms_since(t0);

    prev_attitude_ = in.attitude;
    prev_t_ns_ = in.t_ns;
    have_prev_ = true;
    const TrackerTimings& tt = tracker_.timings();
    result_.timings.grey_ms = tt.grey_ms;
    result_.timings.pyramid_ms = tt.pyramid_ms;
    result_.timings.lk_ms = tt.lk_ms;
    result_.timings.geometry_ms = tt.geometry_ms;
    result_.timings.detect_ms = tt.detect_ms;
    result_.timings.total_ms = ms_since(t_total);
    return result_;
}

void TrackingClassifier::set_record_points(bool on) {
    record_points_ = on;
    if (!on) result_.points.clear();
}

std::string_view TrackingClassifier::point_kind(std::size_t i) const {
    return std::isnan(track_score_[i]) ? "unscored" : "scored";
}

void TrackingClassifier::fill_points() {
    const auto& tracks = tracker_.tracks();
    result_.points.resize(tracks.size());  // keeps its capacity: no allocation once grown
    for (std::size_t i = 0; i < tracks.size(); ++i) {
        const Trajectory& t = tracks[i];
        const TrackPoint& now = t.at_back(0);
        PointRecord& p = result_.points[i];
        p.id = t.id;
        p.age = t.length;
        p.region = region_of(now.stab.x);
        p.kind = point_kind(i);
        p.score = track_score_[i];
        p.raw = t.raw;
        p.undist = t.undist;
        p.undist_prev = t.undist_prev;
        p.stab = now.stab;
        p.derot = now.derot;
        p.fb_px = now.fb_px;
        p.structure = t.structure;
    }
}

void TrackingClassifier::fill_traces() {
    const auto& tracks = tracker_.tracks();
    order_.resize(tracks.size());
    for (std::size_t i = 0; i < tracks.size(); ++i) order_[i] = i;
    const std::size_t n = std::min(kMaxTraces, tracks.size());
    // Longest first; ties by id so the selection is deterministic.
    std::partial_sort(order_.begin(), order_.begin() + static_cast<std::ptrdiff_t>(n), order_.end(),
                      [&](std::size_t a, std::size_t b) {
                          if (tracks[a].length != tracks[b].length)
                              return tracks[a].length > tracks[b].length;
                          return tracks[a].id < tracks[b].id;
                      });
    result_.traces.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
        const Trajectory& t = tracks[order_[k]];
        TrajectoryTrace& tr = result_.traces[k];
        tr.id = t.id;
        tr.region = region_of(t.at_back(0).stab.x);
        tr.score = track_score_[order_[k]];
        tr.last_frame = result_.frame_index;
        tr.count = static_cast<int>(t.history_size());
        for (int i = 0; i < tr.count; ++i)
            tr.x[static_cast<std::size_t>(i)] =
                t.at_back(static_cast<std::size_t>(tr.count - 1 - i)).stab.x;
    }
}

DecisionState decision_state(const RegionDecision& d) {
    if (!d.valid) return DecisionState::Unknown;
    if (d.unsafe) return DecisionState::Unsafe;
    return d.approach_only ? DecisionState::Still : DecisionState::Clear;
}

Rgb bar_colour(const RegionDecision& d) {
    static constexpr Rgb kColours[] = {kGrey, kRed, kSteel, kGreen};
    return kColours[static_cast<std::size_t>(decision_state(d))];
}

const char* state_word(const RegionDecision& d) {
    static constexpr const char* kWords[] = {"unknown", "unsafe", "still", "clear"};
    return kWords[static_cast<std::size_t>(decision_state(d))];
}

void TrackingClassifier::build_overlay() {
    Overlay& o = result_.overlay;
    o.clear();
    const auto w = static_cast<float>(calib_.width);
    const auto h = static_cast<float>(calib_.height);
    const auto mid = w / 2.f;
    const auto band = static_cast<float>(centre_band_px());
    constexpr float kBarH = 12.f;
    const float xs[4] = {0.f, mid - band, mid + band, w};
    for (int r = 0; r < 3; ++r) {
        const RegionDecision& d = result_.regions[static_cast<std::size_t>(r)];
        o.bars.push_back({cv::Rect2f(xs[r], 0, xs[r + 1] - xs[r], kBarH), bar_colour(d), true});
    }
    // Region boundaries are vertical in the stabilised image; bent and tilted in the raw one.
    constexpr int kSegments = 12;
    for (float bx : {mid - band, mid + band}) {
        cv::Point2f a = stab_to_raw({bx, 0});
        for (int i = 1; i <= kSegments; ++i) {
            const cv::Point2f b = stab_to_raw({bx, (h - 1) * static_cast<float>(i) / kSegments});
            o.lines.push_back({a, b, kWhite, 1});
            a = b;
        }
    }
    add_overlay_points();
}

}  // namespace gs::vision
