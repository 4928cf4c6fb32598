#pragma once
// Small least-squares fits and robust statistics used by the classifiers: the thesis' slope
// (eq. 3.22), second-order fit (eq. 3.25) and homography scale (eq. 3.23). Pure functions, no
// allocation.

#include <opencv2/core.hpp>

#include <span>

namespace gs::vision {

// y = slope * x + intercept. ok = false when fewer than 2 points or all x equal.
struct LineFit {
    double slope = 0;
    double intercept = 0;
    bool ok = false;
};
LineFit fit_line(std::span<const double> x, std::span<const double> y);
// x = 0, 1, ..., n-1 (the frame index inside a window).
LineFit fit_line_indexed(std::span<const double> y);

// y = a x^2 + b x + c, with the thesis' closed form (centred sums). ok = false when singular.
struct QuadFit {
    double a = 0, b = 0, c = 0;
    bool ok = false;
    double at(double x) const { return (a * x + b) * x + c; }
    double slope_at(double x) const { return 2 * a * x + b; }
};
QuadFit fit_quadratic(std::span<const double> x, std::span<const double> y);
// x = 1, 2, ..., n, so slope_at(n) is the thesis' tangent "at sample 30" (eq. 3.26).
QuadFit fit_quadratic_indexed(std::span<const double> y);

// S = sqrt(H11^2 + H12^2) of H normalised to H33 = 1 (thesis eq. 3.23, 1-based indices).
// NaN when H is empty or H33 is zero.
double homography_scale(const cv::Matx33d& h);

// Area scale of H at the coordinate origin, sqrt(|det J|) with J the Jacobian of the mapping
// there: unlike eq. 3.23 it does not depend on rotation and is not biased by the projective terms
// a plane at an angle adds (those only vanish at the origin, so centre the points first).
double homography_local_scale(const cv::Matx33d& h);

// Median of values (reorders them). NaN when empty.
double median_inplace(std::span<double> values);
// k-th largest (k = 1 is the maximum), reorders. NaN when k > size or k < 1.
double kth_largest_inplace(std::span<double> values, int k);

// Scale factor for a point at horizontal position x in an image of width w: linear from `edge` at
// x = 0 to `centre` at x = w/2 and back to `edge` at x = w (thesis fig. 3.26, 3 -> 1 -> 3).
double position_scale(double x, double width, double edge, double centre);

}  // namespace gs::vision
