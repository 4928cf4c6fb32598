#include "vision/fit.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace gs::vision;

TEST(Fit, LineSlopeOfExactLine) {
    const std::vector<double> y{1, 3, 5, 7};
    const LineFit f = fit_line_indexed(y);
    ASSERT_TRUE(f.ok);
    EXPECT_DOUBLE_EQ(f.slope, 2.0);
    EXPECT_DOUBLE_EQ(f.intercept, 1.0);
}

TEST(Fit, LineSlopeLeastSquaresByHand) {
    // mean x 1.5, mean y 1, Sxy = 3, Sxx = 5: slope 0.6, intercept 1 - 0.6 * 1.5 = 0.1.
    const std::vector<double> x{0, 1, 2, 3}, y{0, 1, 1, 2};
    const LineFit f = fit_line(x, y);
    ASSERT_TRUE(f.ok);
    EXPECT_NEAR(f.slope, 0.6, 1e-12);
    EXPECT_NEAR(f.intercept, 0.1, 1e-12);
    const LineFit g = fit_line_indexed(y);
    EXPECT_NEAR(g.slope, 0.6, 1e-12);
}

TEST(Fit, SlopeStandardErrorByHand) {
    // The fit above: residuals 0 - 0.1, 1 - 0.7, 1 - 1.3, 2 - 1.9 = -0.1, 0.3, -0.3, 0.1; their
    // squares sum to 0.2, over n - 2 = 2 and Sxx = 5: sqrt(0.02).
    const std::vector<double> x{0, 1, 2, 3}, y{0, 1, 1, 2};
    const LineFit f = fit_line(x, y);
    EXPECT_NEAR(slope_standard_error(x, y, f), std::sqrt(0.02), 1e-12);
    // An exact line has none; two points cannot say; no fit, no error.
    const std::vector<double> exact{1, 3, 5, 7};
    EXPECT_NEAR(slope_standard_error(x, exact, fit_line(x, exact)), 0.0, 1e-12);
    const std::vector<double> x2{0, 1}, y2{0, 1};
    EXPECT_TRUE(std::isnan(slope_standard_error(x2, y2, fit_line(x2, y2))));
    const std::vector<double> same{2, 2, 2}, y3{1, 2, 3};
    EXPECT_TRUE(std::isnan(slope_standard_error(same, y3, fit_line(same, y3))));
}

TEST(Fit, LineRejectsDegenerateInput) {
    const std::vector<double> one{4};
    EXPECT_FALSE(fit_line_indexed(one).ok);
    const std::vector<double> x{2, 2, 2}, y{1, 2, 3};
    EXPECT_FALSE(fit_line(x, y).ok);
}

TEST(Fit, QuadraticRecoversExactParabola) {
    const std::vector<double> y{0, 3, 10, 21, 36};  // 2x^2 - 3x + 1 at x = 1..5
    const QuadFit f = fit_quadratic_indexed(y);
    ASSERT_TRUE(f.ok);
    EXPECT_NEAR(f.a, 2, 1e-9);
    EXPECT_NEAR(f.b, -3, 1e-9);
    EXPECT_NEAR(f.c, 1, 1e-9);
    EXPECT_NEAR(f.slope_at(5), 17, 1e-9);  // thesis eq. 3.26 with n = 5
}

TEST(Fit, QuadraticLeastSquaresByHand) {
    // Normal equations solved exactly in fractions: a = 3/14, b = -11/14, c = 7/5.
    const std::vector<double> y{1, 0, 2, 1, 3};
    const QuadFit f = fit_quadratic_indexed(y);
    ASSERT_TRUE(f.ok);
    EXPECT_NEAR(f.a, 3.0 / 14, 1e-12);
    EXPECT_NEAR(f.b, -11.0 / 14, 1e-12);
    EXPECT_NEAR(f.c, 7.0 / 5, 1e-12);
}

TEST(Fit, QuadraticTangentAtSampleThirty) {
    // Scales 1 + 1e-4 * x^2 over 30 samples: tangent 2 * 1e-4 * 30 = 0.006 at the newest.
    std::vector<double> y(30);
    for (int i = 0; i < 30; ++i) y[static_cast<std::size_t>(i)] = 1 + 1e-4 * (i + 1) * (i + 1);
    const QuadFit f = fit_quadratic_indexed(y);
    ASSERT_TRUE(f.ok);
    EXPECT_NEAR(f.slope_at(30), 0.006, 1e-10);
}

TEST(Fit, HomographyScaleOfThesisExample) {
    // Thesis eq. 3.11: sqrt(0.9598^2 + 0.0337^2).
    const cv::Matx33d h(0.9598, -0.0337, 52.8250, 0.0182, 0.9659, 12.0100, 0, 0, 1);
    EXPECT_NEAR(homography_scale(h), 0.9603914462, 1e-9);
    EXPECT_NEAR(homography_scale(h * 2.0), 0.9603914462, 1e-9);  // scale-invariant
}

TEST(Fit, HomographyScaleOfRotatedExpansion) {
    const double s = 1.1, a = 30 * CV_PI / 180;
    const cv::Matx33d h(s * std::cos(a), -s * std::sin(a), 5, s * std::sin(a), s * std::cos(a), -7,
                        0, 0, 1);
    EXPECT_NEAR(homography_scale(h), 1.1, 1e-12);
    EXPECT_NEAR(homography_local_scale(h), 1.1, 1e-12);
    EXPECT_TRUE(std::isnan(homography_scale(cv::Matx33d(1, 0, 0, 0, 1, 0, 0, 0, 0))));
}

TEST(Fit, LocalScaleIgnoresProjectiveTermsAtOrigin) {
    // A wall parallel to the flight seen in centred coordinates: x' = x / (1 - a x), no scale at 0.
    const cv::Matx33d h(1, 0, 0, 0, 1, 0, -0.001, 0, 1);
    EXPECT_NEAR(homography_local_scale(h), 1.0, 1e-12);
    // The same map in pixel coordinates (origin at the corner, centre at 320, 180) biases eq. 3.23.
    const cv::Matx33d t(1, 0, 320, 0, 1, 180, 0, 0, 1);
    const cv::Matx33d hp = t * h * t.inv();
    // H11 = 1 - 0.32, H33 = 1 + 0.32 (row 3 = (-0.001, 0, 1.32)), H12 = 0.
    EXPECT_NEAR(homography_scale(hp), 0.68 / 1.32, 1e-9);
}

TEST(Fit, PositionScaleIsThreeOneThree) {
    EXPECT_DOUBLE_EQ(position_scale(0, 640, 3, 1), 3);
    EXPECT_DOUBLE_EQ(position_scale(160, 640, 3, 1), 2);
    EXPECT_DOUBLE_EQ(position_scale(320, 640, 3, 1), 1);
    EXPECT_DOUBLE_EQ(position_scale(480, 640, 3, 1), 2);
    EXPECT_DOUBLE_EQ(position_scale(640, 640, 3, 1), 3);
}

TEST(Fit, RobustStatistics) {
    std::vector<double> v{5, 1, 4, 2, 3};
    EXPECT_DOUBLE_EQ(median_inplace(v), 3);
    std::vector<double> e{4, 1, 3, 2};
    EXPECT_DOUBLE_EQ(median_inplace(e), 2.5);
    std::vector<double> k{0.1, 0.9, 0.5, 0.7, 100};
    EXPECT_DOUBLE_EQ(kth_largest_inplace(k, 1), 100);
    EXPECT_DOUBLE_EQ(kth_largest_inplace(k, 3), 0.7);
    EXPECT_TRUE(std::isnan(kth_largest_inplace(k, 6)));
    std::vector<double> none;
    EXPECT_TRUE(std::isnan(median_inplace(none)));
}

TEST(Fit, AnEdgeConstrainsOnlyTheFlowAcrossIt) {
    // A vertical step edge: the gradient is horizontal, so the tensor says "edge" with its
    // normal along x; a chequer corner constrains every direction.
    cv::Mat edge(40, 40, CV_8UC1, cv::Scalar(40));
    edge(cv::Rect(20, 0, 20, 40)).setTo(200);
    const cv::Vec3f ge = structure_tensor(edge, {20, 20}, 5);
    EXPECT_GT(ge[0], 0.f);
    EXPECT_EQ(ge[1], 0.f);
    EXPECT_EQ(ge[2], 0.f);
    const auto as_matx = [](cv::Vec3f s) {
        return cv::Matx22d(static_cast<double>(s[0]), static_cast<double>(s[1]),
                           static_cast<double>(s[1]), static_cast<double>(s[2]));
    };
    const EdgeNormal n = edge_normal(as_matx(ge), 0.2);
    ASSERT_TRUE(n.edge);
    EXPECT_NEAR(std::abs(n.nx), 1.0, 1e-9);
    EXPECT_NEAR(n.ny, 0.0, 1e-9);
    // A point on it whose true flow is (3, 0) px/frame but which LK lets slide 5 px/frame along
    // the edge: only the normal component is real, and it gives the true flow along a ray.
    const cv::Vec2d tracked(3, 5), ray(1, 0);
    const double normal_flow = tracked[0] * n.nx + tracked[1] * n.ny;
    const double along_ray = normal_flow / (n.nx * ray[0] + n.ny * ray[1]);
    EXPECT_NEAR(along_ray, 3.0, 1e-9);

    cv::Mat corner(40, 40, CV_8UC1, cv::Scalar(40));
    corner(cv::Rect(20, 0, 20, 20)).setTo(200);
    corner(cv::Rect(0, 20, 20, 20)).setTo(200);
    EXPECT_FALSE(edge_normal(as_matx(structure_tensor(corner, {20, 20}, 5)), 0.2).edge);
    // No texture: no edge either (nothing measured at all).
    const cv::Mat flat(40, 40, CV_8UC1, cv::Scalar(90));
    EXPECT_FALSE(edge_normal(as_matx(structure_tensor(flat, {20, 20}, 5)), 0.2).edge);
    // Only 8-bit grey; the window is clipped at the border.
    EXPECT_EQ(structure_tensor(cv::Mat(10, 10, CV_32FC1), {5, 5}, 3), cv::Vec3f(0, 0, 0));
    EXPECT_GT(structure_tensor(edge, {20, 0}, 5)[0], 0.f);
    // A diagonal edge: the normal is at 45 degrees.
    cv::Mat diag(40, 40, CV_8UC1);
    for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 40; ++x) diag.at<std::uint8_t>(y, x) = x + y < 40 ? 40 : 200;
    const EdgeNormal d = edge_normal(as_matx(structure_tensor(diag, {20, 20}, 5)), 0.2);
    ASSERT_TRUE(d.edge);
    EXPECT_NEAR(std::abs(d.nx), std::sqrt(0.5), 0.02);
    EXPECT_NEAR(d.nx, d.ny, 0.02);
}
