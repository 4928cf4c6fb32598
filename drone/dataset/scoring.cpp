#include "drone/dataset/scoring.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace gs::dataset {

std::string FlightScore::false_regions_text() const {
    std::string s;
    for (std::size_t r = 0; r < 3; ++r) {
        if (!false_regions[r]) continue;
        if (!s.empty()) s += '+';
        s += kRegionNames[r];
    }
    return s;
}

FlightScore score_flight(Scenario scenario, const std::vector<LabelRow>& labels,
                         const std::vector<RegionFlags>& flags, const ScoringRules& rules) {
    FlightScore sc;
    sc.scenario = scenario;
    sc.frames = static_cast<int>(flags.size());

    // labels.csv rows by frame (files need not list every frame, nor in order).
    std::unordered_map<std::int64_t, double> distance;
    distance.reserve(labels.size());
    for (const LabelRow& l : labels) distance[l.frame] = l.distance_m;

    int target = -1, opposite = -1;  // region indices
    if (scenario == Scenario::Left) target = 0, opposite = 2;
    if (scenario == Scenario::Right) target = 2, opposite = 0;
    if (scenario == Scenario::Center) target = 1;

    bool false_positive = false;
    for (std::size_t i = 0; i < flags.size(); ++i) {
        const auto frame = static_cast<std::int64_t>(i);
        const RegionFlags& f = flags[i];
        if (scenario == Scenario::None) {
            ++sc.scored_frames;
            for (std::size_t r = 0; r < 3; ++r) {
                if (!f[r]) continue;
                ++sc.flagged_frames[r];
                sc.false_regions[r] = true;
                if (!sc.first_false_frame) sc.first_false_frame = frame;
                false_positive = true;
            }
            continue;
        }
        const auto it = distance.find(frame);
        const double d = it == distance.end() ? kUnknown : it->second;
        if (!known(d) || d < 0) {
            ++sc.unscored_frames;
            continue;
        }
        ++sc.scored_frames;
        for (int r = 0; r < 3; ++r) {
            if (!f[static_cast<std::size_t>(r)]) continue;
            ++sc.flagged_frames[static_cast<std::size_t>(r)];
            if (r == target) {
                if (d >= rules.min_detection_distance_m) {
                    if (!sc.detection_frame) {
                        sc.detection_frame = frame;
                        sc.detection_distance_m = d;
                    }
                } else if (!sc.late_detection_distance_m) {
                    sc.late_detection_distance_m = d;
                }
            } else if (r == opposite) {
                sc.false_regions[static_cast<std::size_t>(r)] = true;
                if (!sc.first_false_frame) sc.first_false_frame = frame;
                false_positive = true;
            } else {
                ++sc.other_flag_frames[static_cast<std::size_t>(r)];
            }
        }
    }

    if (scenario == Scenario::None) {
        (false_positive ? sc.fp : sc.tn) = 1;
    } else {
        (sc.detection_frame ? sc.tp : sc.fn) = 1;
        if (false_positive) sc.fp = 1;
        if (sc.detection_frame) sc.late_detection_distance_m.reset();
    }
    return sc;
}

void ScoreSummary::add(const FlightScore& s) {
    ++flights;
    tp += s.tp;
    fp += s.fp;
    fn += s.fn;
    tn += s.tn;
    switch (s.scenario) {
        case Scenario::Left:
        case Scenario::Right:
            ++side_flights;
            side_tp += s.tp;
            side_wrong += s.fp;
            if (s.detection_distance_m) side_distances_m.push_back(*s.detection_distance_m);
            break;
        case Scenario::Center:
            ++centre_flights;
            centre_tp += s.tp;
            if (s.detection_distance_m) centre_distances_m.push_back(*s.detection_distance_m);
            break;
        case Scenario::None:
            ++open_flights;
            open_fp += s.fp;
            open_fp_centre += s.false_regions[1] ? 1 : 0;
            break;
    }
}

double ScoreSummary::mean(const std::vector<double>& v) {
    if (v.empty()) return kUnknown;
    double s = 0;
    for (double x : v) s += x;
    return s / static_cast<double>(v.size());
}

double ScoreSummary::min(const std::vector<double>& v) {
    if (v.empty()) return kUnknown;
    return *std::min_element(v.begin(), v.end());
}

}  // namespace gs::dataset
