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
// The standard error of `f`'s slope (fitted to these points) from the scatter of its residuals:
// sqrt(sum r^2 / (n - 2) / sum (x - mean x)^2). NaN with fewer than 3 points, all x equal or no
// fit.
double slope_standard_error(std::span<const double> x, std::span<const double> y, const LineFit& f);

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

// The image's structure tensor at p: sums of Ix^2, Ix Iy, Iy^2 (central differences) over the
// (2 half + 1)^2 window around p's pixel, inside the image. 8-bit grey only (else zeros).
cv::Vec3f structure_tensor(const cv::Mat& grey, cv::Point2f p, int half);

// The aperture problem at a point: when the smaller eigenvalue of its structure tensor g is
// below edge_ratio of the larger, the point lies on an edge and only its flow along the edge's
// normal (unit, the larger eigenvalue's eigenvector) is measured: the component along the edge
// is the tracker's guess.
struct EdgeNormal {
    bool edge = false;
    double nx = 0, ny = 0;
};
EdgeNormal edge_normal(const cv::Matx22d& g, double edge_ratio);

// Scale factor for a point at horizontal position x in an image of width w: linear from `edge` at
// x = 0 to `centre` at x = w/2 and back to `edge` at x = w (thesis fig. 3.26, 3 -> 1 -> 3).
double position_scale(double x, double width, double edge, double centre);

}  // namespace gs::vision
