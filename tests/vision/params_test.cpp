#include "vision/classifier.hpp"
#include "vision/flow_classifier.hpp"
#include "vision/thesis_classifier.hpp"

#include <gtest/gtest.h>

#include <set>

using namespace gs::vision;
using gs::CameraCalibration;

namespace {
CameraCalibration calib() {
    return CameraCalibration::ideal(640, 360, 60);
}
double value_of(const ObstacleClassifier& c, std::string_view n) {
    double v = -1;
    EXPECT_TRUE(c.get_param(n, v)) << n;
    return v;
}
}  // namespace

TEST(Params, FactoryKnowsBothClassifiers) {
    for (std::string_view n : classifier_names()) {
        auto c = make_classifier(n, calib());
        ASSERT_NE(c, nullptr) << n;
        EXPECT_EQ(c->name(), n);
    }
    EXPECT_EQ(make_classifier("nope", calib()), nullptr);
    EXPECT_NE(make_classifier(kDefaultClassifier, calib()), nullptr);
}

TEST(Params, ThesisDefaultsAreTheThesisValues) {
    auto c = make_classifier("thesis", calib());
    EXPECT_EQ(value_of(*c, "centre_band_px"), 80);
    EXPECT_EQ(value_of(*c, "slope_window"), 30);
    EXPECT_EQ(value_of(*c, "edge_scale"), 3);
    EXPECT_EQ(value_of(*c, "centre_scale"), 1);
    EXPECT_EQ(value_of(*c, "cluster_distance_px"), 20);
    EXPECT_EQ(value_of(*c, "cluster_slope_diff"), 0.5);
    EXPECT_EQ(value_of(*c, "cluster_min_size"), 8);
    EXPECT_EQ(value_of(*c, "slope_threshold"), 3.5);
    EXPECT_EQ(value_of(*c, "filter_alpha"), 0.9);
    EXPECT_EQ(value_of(*c, "fit_window"), 30);
    EXPECT_EQ(value_of(*c, "centre_slope_threshold"), 0.0013);
}

TEST(Params, EveryParameterIsNamedRangedAndDescribed) {
    for (std::string_view n : classifier_names()) {
        auto c = make_classifier(n, calib());
        std::set<std::string> names;
        for (const ParamInfo& p : c->params()) {
            EXPECT_TRUE(names.insert(p.name).second) << "duplicate " << p.name;
            EXPECT_FALSE(p.description.empty()) << p.name;
            EXPECT_LE(p.min, p.value) << p.name;
            EXPECT_GE(p.max, p.value) << p.name;
        }
        EXPECT_TRUE(names.count("track.max_tracks"));
    }
}

TEST(Params, SetRejectsUnknownOutOfRangeAndNaN) {
    auto c = make_classifier("thesis", calib());
    EXPECT_EQ(c->set_param("slope_threshold", 4.25), ParamStatus::Ok);
    EXPECT_EQ(value_of(*c, "slope_threshold"), 4.25);
    EXPECT_EQ(c->set_param("no_such", 1), ParamStatus::UnknownName);
    EXPECT_EQ(c->set_param("filter_alpha", 1.5), ParamStatus::OutOfRange);
    EXPECT_EQ(c->set_param("filter_alpha", std::nan("")), ParamStatus::NotANumber);
    EXPECT_EQ(value_of(*c, "filter_alpha"), 0.9);
    EXPECT_EQ(c->set_param("track.track_scale", 0.5), ParamStatus::Ok);
    EXPECT_EQ(value_of(*c, "track.track_scale"), 0.5);
}

TEST(Params, MapRoundTripAndErrorsReported) {
    auto a = make_classifier("flow", calib());
    ASSERT_EQ(a->set_param("side_inv_ttc_threshold", 0.75), ParamStatus::Ok);
    ASSERT_EQ(a->set_param("confirm_frames", 3), ParamStatus::Ok);
    ASSERT_EQ(a->set_param("use_velocity_for_foe", 0), ParamStatus::Ok);
    const ParamMap m = a->params_to_map();
    EXPECT_EQ(m.at("side_inv_ttc_threshold"), "0.75");
    EXPECT_EQ(m.at("confirm_frames"), "3");
    EXPECT_EQ(m.at("use_velocity_for_foe"), "0");
    auto b = make_classifier("flow", calib());
    EXPECT_TRUE(b->params_from_map(m).ok());
    EXPECT_EQ(b->params_to_map(), m);

    ParamMap bad{{"confirm_frames", "x"}, {"zzz", "1"}, {"centre_window", "5"}};
    const ParamMapErrors e = b->params_from_map(bad);
    ASSERT_EQ(e.rejected.size(), 2u);
    EXPECT_EQ(value_of(*b, "centre_window"), 5);  // the valid key still applied
}
