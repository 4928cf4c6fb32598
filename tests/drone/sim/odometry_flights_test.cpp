// The odometry flights' navdata model (drone/sim/odometry_flights.hpp): roll and pitch as an
// onboard estimator reports them, white noise plus a bias that starts at a given size and walks.
#include "drone/sim/odometry_flights.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace gs::sim;

namespace {

OdometryFlightParams hover(double seconds) {
    OdometryFlightParams p;
    p.test = OdometryTest::Hover;
    p.duration_s = seconds;
    p.top_camera = false;
    return p;
}

TEST(OdometryFlights, AttitudeBiasIsAConstantOffsetOnTheSameNoise) {
    OdometryFlightParams p = hover(4);
    const std::vector<OdometryFlightSample> plain = odometry_flight_samples(p, 3);
    p.nav_attitude_bias_deg = 0.3;
    const std::vector<OdometryFlightSample> biased = odometry_flight_samples(p, 3);
    ASSERT_EQ(plain.size(), biased.size());
    ASSERT_GT(plain.size(), 50u);
    const double roll0 = biased[0].nav.roll_deg - plain[0].nav.roll_deg;
    const double pitch0 = biased[0].nav.pitch_deg - plain[0].nav.pitch_deg;
    EXPECT_NEAR(std::abs(roll0), 0.3, 1e-9);
    EXPECT_NEAR(std::abs(pitch0), 0.3, 1e-9);
    for (std::size_t i = 0; i < plain.size(); ++i) {
        // The same truth and the same noise: the bias generator is separate.
        EXPECT_EQ(plain[i].bottom.roll_deg, biased[i].bottom.roll_deg) << i;
        EXPECT_NEAR(biased[i].nav.roll_deg - plain[i].nav.roll_deg, roll0, 1e-9) << i;
        EXPECT_NEAR(biased[i].nav.pitch_deg - plain[i].nav.pitch_deg, pitch0, 1e-9) << i;
        EXPECT_EQ(plain[i].nav.yaw_deg, biased[i].nav.yaw_deg) << i;
    }
    // Its sign comes from the seed: some seed gives each sign on roll.
    bool pos = false, neg = false;
    for (std::uint64_t seed = 1; seed <= 16; ++seed) {
        p.nav_attitude_bias_deg = 0;
        const double a = odometry_flight_samples(p, seed)[0].nav.roll_deg;
        p.nav_attitude_bias_deg = 0.3;
        const double b = odometry_flight_samples(p, seed)[0].nav.roll_deg;
        (b > a ? pos : neg) = true;
    }
    EXPECT_TRUE(pos && neg);
}

TEST(OdometryFlights, AttitudeBiasWalksAtTheGivenRate) {
    OdometryFlightParams p = hover(60);
    const std::vector<OdometryFlightSample> plain = odometry_flight_samples(p, 5);
    p.nav_attitude_bias_walk_dps = 0.05;  // degrees per square-root second
    const std::vector<OdometryFlightSample> walked = odometry_flight_samples(p, 5);
    ASSERT_EQ(plain.size(), walked.size());
    // The bias's steps: white, with a standard deviation of 0.05 deg x sqrt(1 / 15 s).
    double sum2 = 0;
    std::size_t n = 0;
    for (std::size_t i = 1; i < plain.size(); ++i) {
        const double b1 = walked[i].nav.roll_deg - plain[i].nav.roll_deg;
        const double b0 = walked[i - 1].nav.roll_deg - plain[i - 1].nav.roll_deg;
        sum2 += (b1 - b0) * (b1 - b0);
        ++n;
    }
    const double step_sd = std::sqrt(sum2 / static_cast<double>(n));
    EXPECT_NEAR(step_sd, 0.05 * std::sqrt(1.0 / p.fps), 0.1 * 0.05 * std::sqrt(1.0 / p.fps));
    EXPECT_EQ(walked[0].nav.roll_deg, plain[0].nav.roll_deg);  // starts at 0 here
}

}  // namespace
