#include "vision/fit.hpp"

#include "vision/common.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace gs::vision {

LineFit fit_line(std::span<const double> x, std::span<const double> y) {
    LineFit f;
    const std::size_t n = std::min(x.size(), y.size());
    if (n < 2) return f;
    double mx = 0, my = 0;
    for (std::size_t i = 0; i < n; ++i) {
        mx += x[i];
        my += y[i];
    }
    mx /= static_cast<double>(n);
    my /= static_cast<double>(n);
    double sxy = 0, sxx = 0;
    for (std::size_t i = 0; i < n; ++i) {
        sxy += (x[i] - mx) * (y[i] - my);
        sxx += (x[i] - mx) * (x[i] - mx);
    }
    if (sxx <= 0) return f;
    f.slope = sxy / sxx;
    f.intercept = my - f.slope * mx;
    f.ok = true;
    return f;
}

double slope_standard_error(std::span<const double> x, std::span<const double> y,
                            const LineFit& f) {
    const std::size_t n = std::min(x.size(), y.size());
    if (!f.ok || n < 3) return std::numeric_limits<double>::quiet_NaN();
    double mx = 0;
    for (std::size_t i = 0; i < n; ++i) mx += x[i];
    mx /= static_cast<double>(n);
    double sxx = 0, sr = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const double dx = x[i] - mx;
        const double res = y[i] - (f.intercept + f.slope * x[i]);
        sxx += dx * dx;
        sr += res * res;
    }
    return sxx > 0 ? std::sqrt(sr / static_cast<double>(n - 2) / sxx)
                   : std::numeric_limits<double>::quiet_NaN();
}

LineFit fit_line_indexed(std::span<const double> y) {
    LineFit f;
    const std::size_t n = y.size();
    if (n < 2) return f;
    const double dn = static_cast<double>(n);
    const double mx = (dn - 1) / 2;
    double my = 0;
    for (double v : y) my += v;
    my /= dn;
    double sxy = 0;
    for (std::size_t i = 0; i < n; ++i) sxy += (static_cast<double>(i) - mx) * (y[i] - my);
    const double sxx = dn * (dn * dn - 1) / 12;  // sum of (i - mean)^2 for i = 0..n-1
    f.slope = sxy / sxx;
    f.intercept = my - f.slope * mx;
    f.ok = true;
    return f;
}

QuadFit fit_quadratic(std::span<const double> x, std::span<const double> y) {
    QuadFit f;
    const std::size_t n = std::min(x.size(), y.size());
    if (n < 3) return f;
    // Shift x by its mean for conditioning; the coefficients are shifted back at the end.
    double mx = 0;
    for (std::size_t i = 0; i < n; ++i) mx += x[i];
    mx /= static_cast<double>(n);
    double s1 = 0, s2 = 0, s3 = 0, s4 = 0, sy = 0, sxy = 0, sx2y = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const double u = x[i] - mx;
        const double u2 = u * u;
        s1 += u;
        s2 += u2;
        s3 += u2 * u;
        s4 += u2 * u2;
        sy += y[i];
        sxy += u * y[i];
        sx2y += u2 * y[i];
    }
    const double dn = static_cast<double>(n);
    // Thesis eq. 3.25 in its centred-sum form.
    const double Sxx = s2 - s1 * s1 / dn;
    const double Sxy = sxy - s1 * sy / dn;
    const double Sxx2 = s3 - s2 * s1 / dn;
    const double Sx2y = sx2y - s2 * sy / dn;
    const double Sx2x2 = s4 - s2 * s2 / dn;
    const double den = Sxx * Sx2x2 - Sxx2 * Sxx2;
    if (!(std::abs(den) > 1e-12 * std::max(1.0, Sxx * Sx2x2))) return f;
    const double a = (Sx2y * Sxx - Sxy * Sxx2) / den;
    const double b = (Sxy * Sx2x2 - Sx2y * Sxx2) / den;
    const double c = sy / dn - b * s1 / dn - a * s2 / dn;
    // y = a u^2 + b u + c with u = x - mx.
    f.a = a;
    f.b = b - 2 * a * mx;
    f.c = a * mx * mx - b * mx + c;
    f.ok = true;
    return f;
}

QuadFit fit_quadratic_indexed(std::span<const double> y) {
    constexpr std::size_t kMax = 256;
    double xs[kMax];
    const std::size_t n = std::min(y.size(), kMax);
    for (std::size_t i = 0; i < n; ++i) xs[i] = static_cast<double>(i + 1);
    return fit_quadratic(std::span<const double>(xs, n), y.first(n));
}

double homography_scale(const cv::Matx33d& h) {
    const double h33 = h(2, 2);
    if (!(std::abs(h33) > 1e-12)) return kUnknown;
    const double a = h(0, 0) / h33;
    const double b = h(0, 1) / h33;
    return std::sqrt(a * a + b * b);
}

double homography_local_scale(const cv::Matx33d& h) {
    const double h33 = h(2, 2);
    if (!(std::abs(h33) > 1e-12)) return kUnknown;
    // x' = (A x + t) / (p.x + 1) after normalising: J(0) = A - t p^T.
    const double a = h(0, 0) / h33, b = h(0, 1) / h33, c = h(1, 0) / h33, d = h(1, 1) / h33;
    const double tx = h(0, 2) / h33, ty = h(1, 2) / h33;
    const double px = h(2, 0) / h33, py = h(2, 1) / h33;
    const double j11 = a - tx * px, j12 = b - tx * py, j21 = c - ty * px, j22 = d - ty * py;
    return std::sqrt(std::abs(j11 * j22 - j12 * j21));
}

double median_inplace(std::span<double> v) {
    if (v.empty()) return kUnknown;
    const std::size_t mid = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid), v.end());
    const double hi = v[mid];
    if (v.size() % 2 == 1) return hi;
    const double lo = *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(mid));
    return (lo + hi) / 2;
}

double kth_largest_inplace(std::span<double> v, int k) {
    if (k < 1 || static_cast<std::size_t>(k) > v.size()) return kUnknown;
    auto it = v.begin() + (k - 1);
    std::nth_element(v.begin(), it, v.end(), std::greater<>());
    return *it;
}

double position_scale(double x, double width, double edge, double centre) {
    const double half = width / 2;
    const double t = std::clamp(std::abs(x - half) / half, 0.0, 1.0);
    return centre + (edge - centre) * t;
}

cv::Vec3f structure_tensor(const cv::Mat& g, cv::Point2f p, int half) {
    if (g.type() != CV_8UC1) return {0, 0, 0};
    const int x0 = cvRound(p.x), y0 = cvRound(p.y);
    float a = 0, b = 0, c = 0;
    for (int y = std::max(1, y0 - half); y <= std::min(g.rows - 2, y0 + half); ++y) {
        const std::uint8_t* r = g.ptr<std::uint8_t>(y);
        const std::uint8_t* up = g.ptr<std::uint8_t>(y - 1);
        const std::uint8_t* dn = g.ptr<std::uint8_t>(y + 1);
        for (int x = std::max(1, x0 - half); x <= std::min(g.cols - 2, x0 + half); ++x) {
            const float ix = 0.5f * static_cast<float>(r[x + 1] - r[x - 1]);
            const float iy = 0.5f * static_cast<float>(dn[x] - up[x]);
            a += ix * ix;
            b += ix * iy;
            c += iy * iy;
        }
    }
    return {a, b, c};
}

EdgeNormal edge_normal(const cv::Matx22d& g, double edge_ratio) {
    const double tr = g(0, 0) + g(1, 1);
    const double det = g(0, 0) * g(1, 1) - g(0, 1) * g(1, 0);
    const double disc = std::sqrt(std::max(0.0, 0.25 * tr * tr - det));
    const double l1 = 0.5 * tr + disc, l2 = 0.5 * tr - disc;
    EdgeNormal e;
    if (!(l1 > 0) || l2 >= edge_ratio * l1) return e;  // a corner, or no texture at all
    // (g - l1 I) v = 0: v = (g01, l1 - g00), or (l1 - g11, g10) when that one vanishes.
    double nx = g(0, 1), ny = l1 - g(0, 0);
    if (std::abs(nx) + std::abs(ny) < 1e-9 * l1) {
        nx = l1 - g(1, 1);
        ny = g(1, 0);
    }
    const double n = std::hypot(nx, ny);
    if (!(n > 0)) return e;
    e.edge = true;
    e.nx = nx / n;
    e.ny = ny / n;
    return e;
}

}  // namespace gs::vision
