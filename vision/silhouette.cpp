#include "vision/silhouette.hpp"

#include "vision/fit.hpp"
#include "vision/stabilisation.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace gs::vision {

void SilhouetteCue::set_params(const SilhouetteParams& p) {
    p_ = p;
}

void SilhouetteCue::reset() {
    lose();
}

void SilhouetteCue::lose() {
    hist_.clear();
    r_ = {};
}

bool SilhouetteCue::read_profile(const cv::Mat& grey, int row, int centre_col) {
    const int half = std::max(0, p_.strip_rows / 2);
    const int y0 = std::max(0, row - half), y1 = std::min(grey.rows - 1, row + half);
    if (y1 - y0 < half) return false;  // fewer than half the strip's rows in the image
    const int reach = p_.search_px + p_.outside_gap_px + p_.outside_px + p_.step_px + 2;
    const int x0 = std::max(0, centre_col - reach);
    const int x1 = std::min(grey.cols - 1, centre_col + reach);
    if (x1 - x0 < 4 * p_.step_px) return false;
    const auto n = static_cast<std::size_t>(x1 - x0 + 1);
    const auto rows = static_cast<std::size_t>(y1 - y0 + 1);
    column_.resize(rows);
    median_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t k = 0; k < rows; ++k)
            column_[k] = grey.ptr<std::uint8_t>(y0 + static_cast<int>(k))[x0 + static_cast<int>(i)];
        auto mid = column_.begin() + static_cast<std::ptrdiff_t>(rows / 2);
        std::nth_element(column_.begin(), mid, column_.end());
        median_[i] = static_cast<float>(*mid);
    }
    // Smoothed [1 2 1] / 4 across the columns.
    profile_.resize(n);
    profile_[0] = median_[0];
    profile_[n - 1] = median_[n - 1];
    for (std::size_t i = 1; i + 1 < n; ++i)
        profile_[i] = 0.25f * (median_[i - 1] + 2 * median_[i] + median_[i + 1]);
    // prefix_[i]: the sum of profile_[0, i).
    prefix_.resize(n + 1);
    prefix_[0] = 0;
    for (std::size_t i = 0; i < n; ++i) prefix_[i + 1] = prefix_[i] + profile_[i];
    x0_ = x0;
    return true;
}

double SilhouetteCue::step_at(int i) const {
    const int k = p_.step_px;
    const auto ui = static_cast<std::size_t>(i);
    const auto uk = static_cast<std::size_t>(k);
    const double after = prefix_[ui + 1 + uk] - prefix_[ui + 1];
    const double before = prefix_[ui] - prefix_[ui - uk];
    return (after - before) / k;
}

double SilhouetteCue::locate_end(int found, int dir) const {
    // The run is plain up to its end: the end is where the profile, walking out of the run,
    // first leaves the run's level by half a step (interpolated). Unlike the strongest gradient,
    // that place does not move with the texture beyond the end, only with the end's blur.
    const int n = static_cast<int>(profile_.size());
    const int k = p_.step_px;
    double inside = 0;
    for (int i = 1; i <= k; ++i)
        inside += static_cast<double>(profile_[static_cast<std::size_t>(found - dir * i)]);
    inside /= k;
    const double tau = 0.5 * p_.step_grey;
    int prev = found - dir;
    for (int x = found; x >= 0 && x < n && std::abs(x - found) <= k + 2; x += dir) {
        const double dev =
            std::abs(static_cast<double>(profile_[static_cast<std::size_t>(x)]) - inside);
        if (dev >= tau) {
            const double dev_prev =
                std::abs(static_cast<double>(profile_[static_cast<std::size_t>(prev)]) - inside);
            const double f = dev > dev_prev ? (tau - dev_prev) / (dev - dev_prev) : 0.0;
            return prev + dir * std::clamp(f, 0.0, 1.0);
        }
        prev = x;
    }
    return found;
}

bool SilhouetteCue::find_run(int c0, double& left, double& right) const {
    const int n = static_cast<int>(profile_.size());
    const int k = p_.step_px;
    if (c0 < k || c0 + k >= n) return false;
    if (std::abs(step_at(c0)) >= p_.step_grey) return false;  // the FOE sits on an edge
    const int lo = std::max(k, c0 - p_.search_px), hi = std::min(n - 1 - k, c0 + p_.search_px);
    int l = -1, r = -1;
    for (int i = c0 - 1; i >= lo; --i)
        if (std::abs(step_at(i)) >= p_.step_grey) {
            l = i;
            break;
        }
    for (int i = c0 + 1; i <= hi; ++i)
        if (std::abs(step_at(i)) >= p_.step_grey) {
            r = i;
            break;
        }
    if (l < 0 || r < 0) return false;
    left = locate_end(l, -1);
    right = locate_end(r, +1);
    return right > left;
}

std::size_t SilhouetteCue::capacity() const {
    return static_cast<std::size_t>(std::max({2, p_.window, p_.own_frames + 1})) + 1;
}

double SilhouetteCue::outside_cover(double end, int dir, const Sample& base, double growth) {
    // The texture beside the end now, against the same texture then as it would be had it moved
    // with the end: the profile around the end then, stretched by the end's own growth since
    // (texture at the end's depth spreads from the FOE as the end does). The shift that matches
    // them best is how far the end moved outward over that texture.
    const int n = static_cast<int>(profile_.size());
    const int len = p_.outside_px;
    const double here = end - x0_;  // profile index
    const int a = dir < 0 ? static_cast<int>(std::floor(here)) - p_.outside_gap_px - len + 1
                          : static_cast<int>(std::ceil(here)) + p_.outside_gap_px;
    if (a < 0 || a + len > n || len < 4 || !(growth > -0.5)) return kUnknown;
    double m = 0, s2 = 0;
    for (int i = 0; i < len; ++i) {
        const double x = profile_[static_cast<std::size_t>(a + i)];
        m += x;
        s2 += x * x;
    }
    m /= len;
    const double sd = std::sqrt(std::max(0.0, s2 / len - m * m));
    if (sd < p_.outside_min_std) return kUnknown;
    const std::vector<float>& old = pool_[base.slot];
    const int pn = static_cast<int>(old.size());
    const double base_end = static_cast<double>(dir < 0 ? base.left : base.right);
    // From the end having slid inward over the texture by half its path to its having covered
    // its whole path (the texture stayed put while the end moved), and a margin either way.
    const double path = std::abs(end - base_end);
    const int lo = -p_.own_search_px - static_cast<int>(std::ceil(0.5 * path));
    const int hi = p_.own_search_px + static_cast<int>(std::ceil(path));
    const auto count = static_cast<std::size_t>(hi - lo + 1);
    if (count > 512) return kUnknown;
    scores_.assign(count, -2.0);
    stretched_.resize(static_cast<std::size_t>(len));
    int best = -1;
    for (int k = 0; k < static_cast<int>(count); ++k) {
        // Outward motion `shift` of the end over the texture: content now at x was at
        // base_end + (x - end + dir * shift) / (1 + growth).
        const double shift = lo + k;
        bool inside = true;
        double om = 0, os2 = 0;
        for (int i = 0; i < len && inside; ++i) {
            const double x = x0_ + a + i;
            const double then = base_end + (x - end + dir * shift) / (1 + growth) - base.x0;
            const auto j0 = static_cast<int>(std::floor(then));
            if (j0 < 0 || j0 + 1 >= pn) {
                inside = false;
                break;
            }
            const double f = then - j0;
            const double v = (1 - f) * static_cast<double>(old[static_cast<std::size_t>(j0)]) +
                             f * static_cast<double>(old[static_cast<std::size_t>(j0 + 1)]);
            stretched_[static_cast<std::size_t>(i)] = v;
            om += v;
            os2 += v * v;
        }
        if (!inside) continue;
        om /= len;
        const double osd = std::sqrt(std::max(0.0, os2 / len - om * om));
        if (osd <= 0) continue;
        double c = 0;
        for (int i = 0; i < len; ++i)
            c += (static_cast<double>(profile_[static_cast<std::size_t>(a + i)]) - m) *
                 (stretched_[static_cast<std::size_t>(i)] - om);
        const double sc = c / (len * sd * osd);
        scores_[static_cast<std::size_t>(k)] = sc;
        if (best < 0 || sc > scores_[static_cast<std::size_t>(best)]) best = k;
    }
    if (best < 0 || scores_[static_cast<std::size_t>(best)] < p_.outside_min_ncc) return kUnknown;
    // A texture that matches nearly as well elsewhere (repeats, or too little of it) is not read.
    for (int k = 0; k < static_cast<int>(count); ++k)
        if (std::abs(k - best) > 3 &&
            scores_[static_cast<std::size_t>(k)] > scores_[static_cast<std::size_t>(best)] - 0.1)
            return kUnknown;
    double off = 0;
    if (best > 0 && best + 1 < static_cast<int>(count)) {
        const double sm = scores_[static_cast<std::size_t>(best - 1)];
        const double s0 = scores_[static_cast<std::size_t>(best)];
        const double sp = scores_[static_cast<std::size_t>(best + 1)];
        const double den = sm - 2 * s0 + sp;
        if (sm > -2 && sp > -2 && den < 0) off = std::clamp(0.5 * (sm - sp) / den, -0.5, 0.5);
    }
    return lo + best + off;
}

const SilhouetteResult& SilhouetteCue::update(const cv::Mat& grey, const CameraCalibration& calib,
                                              cv::Point2f foe, const cv::Matx33d& rotation,
                                              double t_s) {
    if (grey.empty() || grey.type() != CV_8UC1 || !std::isfinite(foe.x) || !std::isfinite(foe.y)) {
        lose();
        return r_;
    }
    const cv::Point2f foe_raw = calib.distort_point(foe);
    if (!std::isfinite(foe_raw.x) || !std::isfinite(foe_raw.y)) {
        lose();
        return r_;
    }
    // The run followed so far ends at the last sample (none: no run).
    const bool had = !hist_.empty();
    const Sample last = had ? hist_.back() : Sample{};
    // The strip follows the FOE's row slowly while a run is followed: the FOE's estimate jitters
    // by more than an outline's ends may move between frames.
    const int foe_row = static_cast<int>(std::lround(foe_raw.y));
    const int row =
        had ? last.row + std::clamp(foe_row - last.row, -p_.row_step_px, p_.row_step_px) : foe_row;
    const int col = static_cast<int>(std::lround(foe_raw.x));
    if (row < 0 || row >= grey.rows || col < 0 || col >= grey.cols ||
        !read_profile(grey, row, col)) {
        lose();
        return r_;
    }
    double l = 0, r = 0;
    if (!find_run(col - x0_, l, r)) {
        lose();
        return r_;
    }
    const auto left = static_cast<float>(l + x0_), right = static_cast<float>(r + x0_);
    std::array<cv::Point2f, 2> ends{cv::Point2f(left, static_cast<float>(row)),
                                    cv::Point2f(right, static_cast<float>(row))};
    calib.undistort_points(ends, ends);
    const double width = static_cast<double>(ends[1].x - ends[0].x);
    if (width < p_.min_width_px) {  // too narrow to measure (texture's gaps)
        lose();
        return r_;
    }
    // The same run: both ends near where they were, and its width not changed by more than an
    // approach can change it in a frame (an end that jumped to another step is a new run).
    const bool follows = had && std::abs(left - last.left) <= p_.max_jump_px &&
                         std::abs(right - last.right) <= p_.max_jump_px &&
                         std::abs(width - last.width) <= 1.5 + p_.max_width_step * last.width;
    if (!follows) hist_.clear();
    Sample s{t_s,
             std::log(width),
             kUnknown,
             kUnknown,
             static_cast<double>(ends[0].x - foe.x),
             static_cast<double>(ends[1].x - foe.x),
             width,
             left,
             right,
             ends[0],
             ends[1],
             row,
             x0_,
             0};
    if (follows) {
        // Where the last frame's ends are now for the rotation alone.
        s.d_left = static_cast<double>(ends[0].x - apply_homography(rotation, last.left_u).x);
        s.d_right = static_cast<double>(ends[1].x - apply_homography(rotation, last.right_u).x);
    }
    // An end that moved, rotation aside, further than any approach moves it (an end at distance
    // a from the FOE moves a * rate * dt, give or take the FOE's error) jumped to another step:
    // a new run.
    const double dt = had ? t_s - last.t_s : 0.0;
    const auto plausible = [&](double d, double a) {
        return std::abs(d) <=
               p_.end_noise_px + p_.max_end_rate * (std::abs(a) + p_.foe_error_px) * dt;
    };
    if (follows && !(plausible(s.d_left, s.a_left) && plausible(s.d_right, s.a_right))) {
        hist_.clear();
        s.d_left = s.d_right = kUnknown;
    }
    const std::size_t cap = capacity();
    if (pool_.size() != cap) {
        pool_.assign(cap, {});
        hist_.clear();
        s.d_left = s.d_right = kUnknown;
    }
    while (hist_.size() + 1 >= cap) hist_.erase(hist_.begin());
    s.slot = next_slot_;
    next_slot_ = (next_slot_ + 1) % cap;
    pool_[s.slot].assign(profile_.begin(), profile_.end());
    hist_.push_back(s);
    r_ = {};
    r_.run = true;
    r_.row = static_cast<float>(row);
    r_.left = left;
    r_.right = right;
    r_.width_px = width;
    finish();
    return r_;
}

void SilhouetteCue::finish() {
    const std::size_t n = hist_.size();
    const Sample& now = hist_.back();
    // Each end's motion over the texture beside it, since it last moved own_path_px (a longer
    // path lets a texture match elsewhere), or own_frames ago when it moved less.
    const std::size_t oldest =
        n - 1 - std::min(n - 1, static_cast<std::size_t>(std::max(1, p_.own_frames)));
    // The path is the end's own, rotation aside: a turn moves the texture beside it alike.
    for (int e = 0; e < 2; ++e) {
        const float end_now = e == 0 ? now.left : now.right;
        std::size_t j = n - 1;
        double path = 0;
        while (j > oldest) {
            path += std::abs(e == 0 ? hist_[j].d_left : hist_[j].d_right);
            --j;
            if (path >= static_cast<double>(p_.own_path_px)) break;
        }
        if (j == n - 1) continue;
        // The end's own growth about the FOE since then, rotation aside: its distance from the
        // FOE then and now (an end near the FOE, whose growth the FOE's error swamps, is capped).
        double moved = 0;
        for (std::size_t k = j + 1; k < n; ++k)
            moved += e == 0 ? hist_[k].d_left : hist_[k].d_right;
        const double a_now = e == 0 ? now.a_left : now.a_right;
        const double a_then = a_now - moved;
        const double growth = std::abs(a_then) > 1 && a_now * a_then > 0
                                  ? std::clamp(a_now / a_then - 1, -0.3, 0.5)
                                  : 0.0;
        (e == 0 ? r_.own_left : r_.own_right) =
            outside_cover(static_cast<double>(end_now), e == 0 ? -1 : +1, hist_[j], growth);
    }
    const std::size_t w = std::min(n, static_cast<std::size_t>(std::max(2, p_.window)));
    r_.frames = static_cast<int>(w);
    if (r_.frames < std::max(2, p_.min_frames)) return;
    ts_.clear();
    ys_.clear();
    for (std::size_t k = n - w; k < n; ++k) {
        ts_.push_back(hist_[k].t_s - now.t_s);
        ys_.push_back(hist_[k].log_w);
    }
    const LineFit f = fit_line(ts_, ys_);
    if (!f.ok) return;
    r_.width_rate = f.slope;
    // The slope's standard error from the fit's scatter: an end that wavers between two steps
    // scatters the width, and the cue reads the rate it is sure of, slope - k * error.
    r_.width_rate_se = slope_standard_error(ts_, ys_, f);
    // The run's motion less the rotation over the fit's window: each step's expansion about the
    // FOE is the width's growth over the width; what both ends still share is the unexplained
    // shift.
    double shift = 0;
    for (std::size_t k = n - w + 1; k < n; ++k) {
        const Sample& q = hist_[k];
        const double e = (q.d_right - q.d_left) / q.width;
        shift += 0.5 * ((q.d_left - e * q.a_left) + (q.d_right - e * q.a_right));
    }
    r_.shift_px = shift;
    // Every end whose outside can be read covers it, and at least one can be read.
    const double th = p_.own_min_px;
    const bool read_l = !std::isnan(r_.own_left), read_r = !std::isnan(r_.own_right);
    const bool outline =
        (read_l || read_r) && (!read_l || r_.own_left >= th) && (!read_r || r_.own_right >= th);
    r_.one_surface = outline && std::abs(shift) <= p_.shift_max_px;
    const double rate = r_.one_surface ? f.slope - p_.rate_k_se * r_.width_rate_se : kUnknown;
    r_.rate = rate;
}

}  // namespace gs::vision
