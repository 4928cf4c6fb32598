#pragma once
// Scoring a labelled flight exactly as docs/dataset.md's "Scoring a flight" (the thesis' chapter 6)
// says, and summing flights into the thesis-style tables. Pure: decisions and labels in, counts
// out. A region is flagged at a frame when the classifier reported it unsafe at that frame.
//
// - left / right flights: TP when that side is flagged at a frame whose distance_m >= 0.7 m,
//   FN otherwise; the detection distance is distance_m at the first such frame. A flag on the
//   opposite side is a FP. Frames with distance_m below 0 (obstacle passed) are not scored.
// - center flights: TP when the centre is flagged at a frame with distance_m >= 0.7, else FN.
// - none flights: any flag in any region at any frame is a FP, otherwise a TN.
// Frames of obstacle flights without a distance (empty labels.csv field) are not scored either:
// nothing says where the obstacle is. They are counted (unscored_frames) so it is visible.

#include "drone/dataset/dataset.hpp"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace gs::dataset {

// What the classifier reported at one frame: left, center, right unsafe.
using RegionFlags = std::array<bool, 3>;
inline constexpr std::array<const char*, 3> kRegionNames{"left", "center", "right"};

struct ScoringRules {
    double min_detection_distance_m = 0.7;  // the AR.Drone's stopping distance (thesis §5.2)
};

struct FlightScore {
    Scenario scenario = Scenario::None;
    int tp = 0, fp = 0, fn = 0, tn = 0;
    // First frame at which the target region was flagged early enough, and its distance.
    std::optional<std::int64_t> detection_frame;
    std::optional<double> detection_distance_m;
    // The target region flagged only closer than the stopping distance (an FN): where.
    std::optional<double> late_detection_distance_m;
    // Regions that raised the false positive (the opposite side, or any region of a none flight).
    std::array<bool, 3> false_regions{};
    std::optional<std::int64_t> first_false_frame;
    // Flags that the rules neither reward nor punish (the centre during a side flight, the sides
    // during a centre flight), for information.
    std::array<int, 3> other_flag_frames{};
    std::array<int, 3> flagged_frames{};  // scored frames each region was flagged at
    int frames = 0;
    int scored_frames = 0;
    int unscored_frames = 0;  // passed (distance < 0) or without a distance

    std::string false_regions_text() const;  // "right", "center+right", "" when none
};

// Scores one flight. `labels` is labels.csv (may be empty for a none flight); rows are matched to
// decisions by frame index. Frames with no label row count as without a distance.
FlightScore score_flight(Scenario scenario, const std::vector<LabelRow>& labels,
                         const std::vector<RegionFlags>& flags, const ScoringRules& rules = {});

// Sums over a set of flights (per scenario group and overall).
struct ScoreSummary {
    int flights = 0;
    int tp = 0, fp = 0, fn = 0, tn = 0;
    int side_flights = 0, side_tp = 0, side_wrong = 0;  // left + right flights
    int centre_flights = 0, centre_tp = 0;
    int open_flights = 0, open_fp = 0;
    int open_fp_centre = 0;  // open flights whose false positive involved the centre
    std::vector<double> side_distances_m, centre_distances_m;

    void add(const FlightScore& s);
    static double rate(int num, int den) { return den > 0 ? double(num) / den : kUnknown; }
    double side_tpr() const { return rate(side_tp, side_flights); }
    double centre_tpr() const { return rate(centre_tp, centre_flights); }
    double open_fpr() const { return rate(open_fp, open_flights); }
    static double mean(const std::vector<double>& v);
    static double min(const std::vector<double>& v);
};

}  // namespace gs::dataset
