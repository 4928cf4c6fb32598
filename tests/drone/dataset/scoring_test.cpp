// Scoring a flight as docs/dataset.md "Scoring a flight" says, on hand-made label/decision sequences.
#include "drone/dataset/scoring.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace gs {
namespace {

using namespace dataset;

std::vector<LabelRow> labels(const std::vector<double>& d) {
    std::vector<LabelRow> v;
    for (std::size_t i = 0; i < d.size(); ++i)
        v.push_back({static_cast<std::int64_t>(i), d[i], d[i] == d[i] ? -0.5 : kUnknown});
    return v;
}

constexpr RegionFlags kNone{false, false, false};
constexpr RegionFlags kL{true, false, false};
constexpr RegionFlags kC{false, true, false};
constexpr RegionFlags kR{false, false, true};

TEST(Scoring, LeftFlightDetectedAtTheFirstFlagAtOrBeyondTheStoppingDistance) {
    const auto l = labels({5, 4, 3, 2, 1, 0.5, -0.5});
    const FlightScore s =
        score_flight(Scenario::Left, l, {kNone, kNone, kNone, kL, kL, kL, kNone});
    EXPECT_EQ(s.tp, 1);
    EXPECT_EQ(s.fn, 0);
    EXPECT_EQ(s.fp, 0);
    EXPECT_EQ(s.tn, 0);
    ASSERT_TRUE(s.detection_distance_m);
    EXPECT_DOUBLE_EQ(*s.detection_distance_m, 2.0);
    EXPECT_EQ(*s.detection_frame, 3);
    EXPECT_FALSE(s.late_detection_distance_m);
    EXPECT_EQ(s.flagged_frames[0], 3);
    EXPECT_EQ(s.scored_frames, 6);
    EXPECT_EQ(s.unscored_frames, 1);  // the obstacle passed
}

TEST(Scoring, ExactlyTheStoppingDistanceCounts) {
    const FlightScore s =
        score_flight(Scenario::Center, labels({1.5, 0.7, 0.5}), {kNone, kC, kC});
    EXPECT_EQ(s.tp, 1);
    EXPECT_DOUBLE_EQ(*s.detection_distance_m, 0.7);
}

TEST(Scoring, FlaggedOnlyTooLateIsAMissWithItsDistanceReported) {
    const FlightScore s = score_flight(
        Scenario::Right, labels({3, 2, 1, 0.6, 0.3}), {kNone, kNone, kNone, kR, kR});
    EXPECT_EQ(s.tp, 0);
    EXPECT_EQ(s.fn, 1);
    EXPECT_FALSE(s.detection_distance_m);
    ASSERT_TRUE(s.late_detection_distance_m);
    EXPECT_DOUBLE_EQ(*s.late_detection_distance_m, 0.6);
}

TEST(Scoring, OppositeSideIsAFalsePositiveButNotOncePassedAndTheCentreIsNeither) {
    // Right flagged while the obstacle is ahead: a wrong-side alarm.
    FlightScore s = score_flight(Scenario::Left, labels({4, 3, 2, -0.2}),
                                                   {kR, kNone, kL, kNone});
    EXPECT_EQ(s.tp, 1);
    EXPECT_EQ(s.fp, 1);
    EXPECT_TRUE(s.false_regions[2]);
    EXPECT_EQ(s.false_regions_text(), "right");
    EXPECT_EQ(*s.first_false_frame, 0);
    // Right flagged only after passing: not scored.
    s = score_flight(Scenario::Left, labels({4, 3, 2, -0.2}),
                              {kNone, kNone, kL, kR});
    EXPECT_EQ(s.fp, 0);
    // Centre flagged during a side flight: neither rewarded nor punished, but counted.
    s = score_flight(Scenario::Left, labels({4, 3, 2, 1}),
                              {kC, kC, kNone, kNone});
    EXPECT_EQ(s.fp, 0);
    EXPECT_EQ(s.fn, 1);
    EXPECT_EQ(s.other_flag_frames[1], 2);
}

TEST(Scoring, OpenSpaceAnyFlagAnywhereIsAFalsePositive) {
    const std::vector<LabelRow> none;
    FlightScore s =
        score_flight(Scenario::None, none, {kNone, kNone, kNone});
    EXPECT_EQ(s.tn, 1);
    EXPECT_EQ(s.fp, 0);
    EXPECT_EQ(s.scored_frames, 3);
    s = score_flight(Scenario::None, none,
                              {kNone, kC, RegionFlags{false, true, true}});
    EXPECT_EQ(s.tn, 0);
    EXPECT_EQ(s.fp, 1);
    EXPECT_EQ(s.false_regions_text(), "center+right");
    EXPECT_EQ(*s.first_false_frame, 1);
}

TEST(Scoring, FramesWithoutADistanceAreNotScored) {
    // labels.csv lists only frames 1 and 2; frame 0 has an empty distance.
    std::vector<LabelRow> l{{0, kUnknown, kUnknown}, {2, 2.5, 0.5}};
    const FlightScore s = score_flight(Scenario::Right, l, {kR, kR, kR});
    EXPECT_EQ(s.unscored_frames, 2);  // frame 0 (empty) and frame 1 (no row)
    EXPECT_EQ(s.tp, 1);
    EXPECT_EQ(*s.detection_frame, 2);
}

TEST(Scoring, SummaryRatesAndDistances) {
    ScoreSummary sum;
    sum.add(
        score_flight(Scenario::Left, labels({3, 2}), {kL, kNone}));  // TP at 3
    sum.add(
        score_flight(Scenario::Right, labels({3, 2}), {kL, kR}));  // TP at 2 + FP
    sum.add(score_flight(Scenario::Right, labels({3, 2}), {kNone, kNone}));  // FN
    sum.add(
        score_flight(Scenario::Center, labels({2, 1}), {kNone, kC}));  // TP at 1
    sum.add(score_flight(Scenario::None, {}, {kNone, kNone}));         // TN
    sum.add(score_flight(Scenario::None, {}, {kNone, kC}));  // FP centre
    EXPECT_EQ(sum.flights, 6);
    EXPECT_EQ(sum.side_flights, 3);
    EXPECT_EQ(sum.side_tp, 2);
    EXPECT_EQ(sum.side_wrong, 1);
    EXPECT_DOUBLE_EQ(sum.side_tpr(), 2.0 / 3.0);
    EXPECT_DOUBLE_EQ(ScoreSummary::mean(sum.side_distances_m), 2.5);
    EXPECT_DOUBLE_EQ(ScoreSummary::min(sum.side_distances_m), 2.0);
    EXPECT_DOUBLE_EQ(sum.centre_tpr(), 1.0);
    EXPECT_DOUBLE_EQ(sum.open_fpr(), 0.5);
    EXPECT_EQ(sum.open_fp_centre, 1);
    EXPECT_EQ(sum.tp, 3);
    EXPECT_EQ(sum.fn, 1);
    EXPECT_EQ(sum.fp, 2);
    EXPECT_EQ(sum.tn, 1);
    EXPECT_TRUE(std::isnan(ScoreSummary().side_tpr()));
}

}  // namespace
}  // namespace gs
