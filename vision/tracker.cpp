#include "vision/tracker.hpp"
#include "drone/core/geometry.hpp"
#include "vision/common.hpp"
#include "vision/fit.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace gs::vision {

namespace {
bool inside(cv::Point2f p, float w, float h, float m) {
    return p.x >= m && p.y >= m && p.x <= w - 1 - m && p.y <= h - 1 - m;
}
}  // namespace

void TrajectoryTracker::configure(const CameraCalibration& calib, const TrackerParams& p) {
    calib_ = calib;
    p_ = p;
    centre_ = p_.rotate_about_principal_point
                  ? cv::Point2f(static_cast<float>(calib.cx), static_cast<float>(calib.cy))
                  : cv::Point2f(static_cast<float>(calib.width - 1) / 2.f,
                                static_cast<float>(calib.height - 1) / 2.f);
    const auto n = static_cast<std::size_t>(std::max(1, p_.max_tracks));
    tracks_.reserve(n);
    prev_pts_.reserve(n);
    cur_pts_.reserve(n);
    raw_.reserve(n);
    und_.reserve(n);
    status_.reserve(n);
    err_.reserve(n);
    corners_.reserve(n);
    reset();
}

void TrajectoryTracker::compensate_gain() {
    cv::Mat& g = grey_track_;
    const int H = g.rows, W = g.cols;
    const int B = std::clamp(p_.gain_bands, 1, std::max(1, H / 2));
    row_mean_.resize(std::size_t(H));
    for (int y = 0; y < H; ++y) {
        const std::uint8_t* r = g.ptr<std::uint8_t>(y);
        int sum = 0;
        for (int x = 0; x < W; ++x) sum += r[x];
        row_mean_[std::size_t(y)] = double(sum) / std::max(1, W);
    }
    band_mean_.assign(std::size_t(B), 0.0);
    for (int b = 0; b < B; ++b) {
        const int y0 = b * H / B, y1 = (b + 1) * H / B;
        for (int y = y0; y < y1; ++y) band_mean_[std::size_t(b)] += row_mean_[std::size_t(y)];
        band_mean_[std::size_t(b)] /= std::max(1, y1 - y0);
    }
    if (band_ref_.size() != band_mean_.size() || !have_prev_) {
        band_ref_ = band_mean_;
        return;
    }
    // Each band's gain toward its reference, linear between band centres.
    row_gain_.resize(std::size_t(H));
    auto gain = [&](int b) {
        return std::clamp(band_ref_[std::size_t(b)] / std::max(1.0, band_mean_[std::size_t(b)]),
                          0.5, 2.0);
    };
    for (int y = 0; y < H; ++y) {
        const double pos = (y + 0.5) * B / H - 0.5;  // in band units, centres at integers
        const int b0 = std::clamp(int(std::floor(pos)), 0, B - 1), b1 = std::min(B - 1, b0 + 1);
        const double f = std::clamp(pos - b0, 0.0, 1.0);
        row_gain_[std::size_t(y)] = gain(b0) + f * (gain(b1) - gain(b0));
    }
    for (int y = 0; y < H; ++y) {
        const double k = row_gain_[std::size_t(y)];
        if (std::abs(k - 1) < 1e-3) continue;
        std::uint8_t* r = g.ptr<std::uint8_t>(y);
        for (int x = 0; x < W; ++x) r[x] = cv::saturate_cast<std::uint8_t>(r[x] * k);
    }
    // The reference follows the raw image slowly.
    const double a = 1 / std::max(1.0, p_.gain_tau_frames);
    for (int b = 0; b < B; ++b)
        band_ref_[std::size_t(b)] += a * (band_mean_[std::size_t(b)] - band_ref_[std::size_t(b)]);
}

void TrajectoryTracker::find_step() {
    // The mean of each block of an 8 x 6 grid (at 640 x 360, 80 x 60 px): texture and the
    // camera's motion average out in a block, and change its mean only by what enters and leaves
    // it; a gain changes every block's by itself.
    const int tw = std::max(4, grey_track_.cols / 40), th = std::max(3, grey_track_.rows / 30);
    cv::resize(grey_track_, thumb_, cv::Size(tw, th), 0, 0, cv::INTER_AREA);
    step_log_ = 0;
    if (have_prev_ && thumb_prev_.size() == thumb_.size()) {
        step_ratio_.clear();
        for (int y = 0; y < th; ++y) {
            const std::uint8_t* a = thumb_prev_.ptr<std::uint8_t>(y);
            const std::uint8_t* b = thumb_.ptr<std::uint8_t>(y);
            for (int x = 0; x < tw; ++x) {
                // Clipped blocks say nothing of a gain.
                if (a[x] < 8 || b[x] < 8 || a[x] > 247 || b[x] > 247) continue;
                step_ratio_.push_back(
                    std::log(static_cast<float>(b[x]) / static_cast<float>(a[x])));
            }
        }
        if (step_ratio_.size() >= static_cast<std::size_t>(tw * th / 2)) {
            const auto mid =
                step_ratio_.begin() + static_cast<std::ptrdiff_t>(step_ratio_.size() / 2);
            std::nth_element(step_ratio_.begin(), mid, step_ratio_.end());
            const double m = *mid;
            if (std::abs(m) > p_.step_gain_min) {
                std::size_t same = 0;
                for (float r : step_ratio_)
                    same += static_cast<double>(r) * m > 0.25 * m * m ? 1 : 0;
                if (static_cast<double>(same) >=
                    p_.step_gain_share * static_cast<double>(step_ratio_.size())) {
                    step_log_ = m;
                    ++steps_found_;
                }
            }
        }
    }
    std::swap(thumb_prev_, thumb_);
}

void TrajectoryTracker::scale_previous_pyramid(double k) {
    // Each level whole, with the border the pyramid was built with (LK reads into it near the
    // image's edges).
    for (cv::Mat& level : pyr_prev_) {
        cv::Size whole;
        cv::Point ofs;
        level.locateROI(whole, ofs);
        cv::Mat all = level;
        all.adjustROI(ofs.y, whole.height - level.rows - ofs.y, ofs.x,
                      whole.width - level.cols - ofs.x);
        all.convertTo(all, -1, k, 0);
    }
}

void TrajectoryTracker::own_grey_track(const cv::Mat& image) {
    if (grey_track_.data == image.data) {
        grey_track_.copyTo(grey_own_);  // never change the caller's image
        grey_track_ = grey_own_;
    }
}

void TrajectoryTracker::reset() {
    tracks_.clear();
    prev_pts_.clear();
    have_prev_ = false;
    band_ref_.clear();
    step_log_ = 0;
    steps_found_ = 0;
    frame_ = 0;
    next_id_ = 1;
    ended_ = added_ = 0;
    mask_roll_deg_ = kUnknown;
    last_rotation_rad_ = {0, 0, 0};
    have_rotation_ = false;
    nav_error_.reset(rate_error_params());
    image_roll_deg_ = 0;
    roll_used_deg_ = 0;
    correction_deg_ = {0, 0, 0};
}

void TrajectoryTracker::set_roll(double roll_deg) {
    roll_used_deg_ = !std::isnan(roll_deg) ? roll_deg : p_.image_roll ? image_roll_deg_ : 0.0;
    stab_.set(centre_, p_.roll_sign * roll_used_deg_);
}

cv::Point2f TrajectoryTracker::to_full(cv::Point2f p) const {
    if (p_.track_scale == 1.0) return p;
    const auto s = static_cast<float>(p_.track_scale);
    return {(p.x + 0.5f) / s - 0.5f, (p.y + 0.5f) / s - 0.5f};
}
cv::Point2f TrajectoryTracker::to_track(cv::Point2f p) const {
    if (p_.track_scale == 1.0) return p;
    const auto s = static_cast<float>(p_.track_scale);
    return {(p.x + 0.5f) * s - 0.5f, (p.y + 0.5f) * s - 0.5f};
}

void TrajectoryTracker::set_params(const TrackerParams& p) {
    p_ = p;
    nav_error_.set_params(rate_error_params());
}

double TrajectoryTracker::readout_s() const {
    // The parameter's, or (negative) the camera's, else the AR.Drone 2 front camera's.
    return 1e-3 * (p_.readout_ms >= 0                 ? p_.readout_ms
                   : std::isfinite(calib_.readout_ms) ? calib_.readout_ms
                                                      : TrackerParams::kArDroneReadoutMs);
}

RateErrorParams TrajectoryTracker::rate_error_params() const {
    return {p_.ego_bias_sigma_dps, p_.ego_bias_tau_s, p_.ego_scale_sigma, p_.ego_scale_walk,
            p_.ego_latency_sigma_s};
}

EgoMotionParams TrajectoryTracker::ego_params() const {
    EgoMotionParams e;
    e.noise_px = p_.ego_noise_px;
    e.huber_k = p_.ego_huber_k;
    e.outlier_k = p_.ego_outlier_k;
    e.min_points = p_.ego_min_points;
    e.translation_k = p_.ego_translation_k;
    e.still_k = p_.ego_still_k;
    e.prior_gate = p_.ego_prior_gate;
    e.image_floor_deg = p_.ego_image_floor_deg;
    e.max_rotation_deg = p_.ego_max_rotation_deg;
    e.reliable_foe_sigma_px = p_.ego_reliable_foe_sigma_px;
    return e;
}

void TrajectoryTracker::update(const cv::Mat& image, std::int64_t t_ns, double roll_deg,
                               const cv::Matx33d& base_h_in, const EgoPrior& prior_in) {
    timings_ = {};
    ended_ = added_ = 0;
    const double t_s = static_cast<double>(t_ns) * 1e-9;
    const double dt = have_prev_ ? std::max(0.0, t_s - now_s_) : 0.0;
    now_s_ = t_s;
    const auto w = static_cast<float>(calib_.width);
    const auto h = static_cast<float>(calib_.height);
    correction_deg_ = {0, 0, 0};
    // Without a navdata rotation, the last frame's rotation predicts this one's (a turning
    // camera keeps turning): a better start for the search and for the estimate.
    EgoPrior prior = prior_in;
    prior.rotation_sigma_deg = p_.ego_prior_sigma_deg;
    cv::Matx33d base_h = base_h_in;
    cv::Vec3d base_rot(0, 0, 0);
    if (prior.rotation) {
        const geom::Mat3 k = geom::from_cv(calib_.camera_matrix());
        base_rot = geom::to_cv(geom::vector_from_rotation(k.inverse() * geom::from_cv(base_h) * k));
    } else if (p_.ego_motion && p_.predict_rotation && have_rotation_) {
        // The camera's inertia: its rotation changes little from one frame to the next, so the
        // last one predicts this one, a prior as the navdata's would be (looser).
        base_rot = last_rotation_rad_;
        base_h = small_rotation_homography(calib_, base_rot);
        prior.rotation = true;
        prior.rotation_sigma_deg = p_.ego_prediction_sigma_deg;
    }
    const bool navdata_rotation = prior_in.rotation;
    shutter_rate_ = prior.rotation && dt > 0 ? base_rot * (1.0 / dt) : cv::Vec3d(0, 0, 0);
    {
        // Less the deadband on each axis (readout_deadband_dps): the navdata's noise between
        // frames is not unrolled, a manoeuvre nearly whole, with no step where a rate crosses it.
        const double band = p_.readout_deadband_dps * CV_PI / 180.0;
        for (int k = 0; k < 3; ++k) {
            const double rate = shutter_rate_[k];
            shutter_rate_[k] = std::copysign(std::max(0.0, std::abs(rate) - band), rate);
        }
    }
    set_roll(roll_deg);
    auto t0 = StageClock::now();
    const cv::Mat* grey = &image;
    if (image.channels() != 1) {
        cv::cvtColor(image, grey_full_, cv::COLOR_BGR2GRAY);
        grey = &grey_full_;
    }
    grey_ = *grey;
    if (p_.track_scale != 1.0) {
        const cv::Size ts(static_cast<int>(std::lround(calib_.width * p_.track_scale)),
                          static_cast<int>(std::lround(calib_.height * p_.track_scale)));
        cv::resize(*grey, grey_track_, ts, 0, 0, cv::INTER_AREA);
    } else {
        grey_track_ = *grey;  // header only
    }
    // Exposure steps: on the raw brightness (the other compensations change it themselves).
    if (p_.step_gain_min > 0 && p_.gain_bands == 0 && p_.highpass_px == 0)
        find_step();
    else
        step_log_ = 0;
    if (p_.gain_bands > 0) {
        own_grey_track(image);
        compensate_gain();
    }
    if (p_.highpass_px > 0) {
        own_grey_track(image);
        const int k = p_.highpass_px | 1;
        cv::blur(grey_track_, local_mean_, cv::Size(k, k), cv::Point(-1, -1), cv::BORDER_REPLICATE);
        for (int y = 0; y < grey_track_.rows; ++y) {
            std::uint8_t* g = grey_track_.ptr<std::uint8_t>(y);
            const std::uint8_t* m = local_mean_.ptr<std::uint8_t>(y);
            for (int x = 0; x < grey_track_.cols; ++x)
                g[x] = cv::saturate_cast<std::uint8_t>(int{g[x]} - int{m[x]} + 128);
        }
    }
    timings_.grey_ms = ms_since(t0);

    t0 = StageClock::now();
    const cv::Size win(p_.lk_window_px, p_.lk_window_px);
    cv::buildOpticalFlowPyramid(grey_track_, pyr_cur_, win, p_.lk_levels, false);
    timings_.pyramid_ms = ms_since(t0);

    // Track: survivors are compacted in place, in the order of tracks_.
    std::size_t n = 0;
    if (have_prev_ && !tracks_.empty()) {
        t0 = StageClock::now();
        // Start each search where the attitude change alone moves the point: a fast pitch or yaw
        // (tens of pixels a frame) is then no harder to track than hover.
        int flags = 0;
        if (base_h != cv::Matx33d::eye()) {
            cur_pts_.resize(tracks_.size());
            for (std::size_t i = 0; i < tracks_.size(); ++i)
                cur_pts_[i] =
                    to_track(calib_.distort_point(apply_homography(base_h, tracks_[i].undist)));
            flags = cv::OPTFLOW_USE_INITIAL_FLOW;
        }
        // An exposure step between the two frames: the last one brought to this one's
        // brightness for this search only (this frame stays as filmed for the next).
        if (step_log_ != 0) scale_previous_pyramid(std::exp(step_log_));
        // err_ gets each point's smaller gradient-matrix eigenvalue: how well it is determined.
        cv::calcOpticalFlowPyrLK(pyr_prev_, pyr_cur_, prev_pts_, cur_pts_, status_, err_, win,
                                 p_.lk_levels,
                                 cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS,
                                                  p_.lk_iterations, p_.lk_epsilon),
                                 flags | cv::OPTFLOW_LK_GET_MIN_EIGENVALS, p_.lk_min_eig);
        fb_px_.assign(tracks_.size(), 0.0f);
        if (p_.fb_max_px > 0) {
            // Back from where LK put each point, starting at where it came from: a point tracked
            // consistently is found there at once, so the base level alone is searched.
            back_pts_ = prev_pts_;
            cv::calcOpticalFlowPyrLK(
                pyr_cur_, pyr_prev_, cur_pts_, back_pts_, back_status_, back_err_, win, 0,
                cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, p_.lk_iterations,
                                 p_.lk_epsilon),
                cv::OPTFLOW_USE_INITIAL_FLOW, p_.lk_min_eig);
            for (std::size_t i = 0; i < status_.size(); ++i) {
                const cv::Point2f d = back_pts_[i] - prev_pts_[i];
                fb_px_[i] = back_status_[i]
                                ? static_cast<float>(std::sqrt(static_cast<double>(d.dot(d))) /
                                                     p_.track_scale)
                                : std::numeric_limits<float>::infinity();
            }
        }
        timings_.lk_ms = ms_since(t0);

        t0 = StageClock::now();
        raw_.resize(tracks_.size());
        for (std::size_t i = 0; i < tracks_.size(); ++i) {
            if (!status_[i]) continue;
            const cv::Point2f full = to_full(cur_pts_[i]);
            if (!inside(full, w, h, 0)) continue;
            if (n != i) tracks_[n] = tracks_[i];
            raw_[n] = full;
            err_[n] = err_[i];
            fb_px_[n] = fb_px_[i];
            ++n;
        }
        raw_.resize(n);
        und_.resize(n);
        calib_.undistort_points(raw_, und_);
        unroll_shutter(raw_, und_);
        // Where the known rotation alone would have moved each point; then what the images say.
        pred_.resize(n);
        for (std::size_t i = 0; i < n; ++i) pred_[i] = apply_homography(base_h, tracks_[i].undist);
        cv::Vec3d total = base_rot;
        have_rotation_ = prior.rotation;
        if (p_.ego_motion) {
            const EgoMotion& em = ego_.estimate(calib_, pred_, und_, prior, ego_params(),
                                                std::span<const float>(err_.data(), n));
            if (em.valid) {
                // On top of the navdata, what the images find is an error of the attitude
                // samples. An IMU's errors are a small bias and a scale, so the error is followed
                // over frames as such (follow_navdata_error): one frame where the images trade a
                // rotation for a shift of the FOE barely moves it, and neither does a steady pull
                // while flying straight (a near obstacle on one side), which no real gyro bias
                // could be. A sample the images reject outright (stale, from the wrong instant)
                // is replaced by the images' own rotation. Without navdata the images' rotation
                // is the rotation itself.
                cv::Vec3d corr = em.correction_rad;
                if (navdata_rotation && em.prior_rotation_used)
                    corr = nav_error_.update(em.image_rad, em.image_var, base_rot, dt);
                else if (navdata_rotation)
                    corr = em.image_rad;
                if (corr != em.correction_rad) ego_.refine(calib_, corr);
                const cv::Matx33d hr = small_rotation_homography(calib_, corr);
                for (cv::Point2f& q : pred_) q = apply_homography(hr, q);
                correction_deg_ = corr * (180.0 / CV_PI);
                total += corr;
                have_rotation_ = true;
            }
        }
        last_rotation_rad_ = total;
        // Roll about the optical axis: the drone's roll (camera z = body x; a right-side-down
        // roll turns the camera by -roll about its z axis).
        if (std::isnan(roll_deg) && p_.image_roll && have_rotation_) {
            const double leak = p_.image_roll_tau_s > 0 ? std::exp(-dt / p_.image_roll_tau_s) : 0.0;
            image_roll_deg_ = leak * (image_roll_deg_ - total[2] * 180.0 / CV_PI);
        }
        set_roll(roll_deg);
        std::size_t m = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const cv::Point2f s = stab_.apply(und_[i]);
            // Thesis: a trajectory ends when it leaves the (stabilised, cropped) image.
            if (!inside(s, w, h, 0)) continue;
            Trajectory& tr = tracks_[m];
            if (m != i) tr = tracks_[i];
            const cv::Point2f derot = tr.at_back(0).derot + (und_[i] - pred_[i]);
            tr.raw = raw_[i];
            tr.structure = structure_tensor(grey_track_, to_track(raw_[i]), p_.lk_window_px / 2);
            tr.moving_streak = p_.ego_motion && ego_.outlier(i) ? tr.moving_streak + 1 : 0;
            tr.undist_prev = tr.undist;
            tr.undist = und_[i];
            tr.push({s, derot, t_s, fb_px_[i]});
            ++m;
        }
        ended_ = static_cast<int>(tracks_.size() - m);
        tracks_.resize(m);
        timings_.geometry_ms = ms_since(t0);
    } else {
        ended_ = static_cast<int>(tracks_.size());
        tracks_.clear();
        last_rotation_rad_ = {0, 0, 0};
        have_rotation_ = false;
    }

    if (frame_ % std::max(1, p_.detect_interval) == 0) {
        t0 = StageClock::now();
        mark_centre_reserve();
        if (grid_on()) balance_grid();
        if (static_cast<int>(tracks_.size()) - reserved_ < p_.max_tracks ||
            p_.centre_min_tracks > 0)
            detect(roll_used_deg_);
        timings_.detect_ms = ms_since(t0);
    }

    prev_pts_.resize(tracks_.size());
    for (std::size_t i = 0; i < tracks_.size(); ++i) prev_pts_[i] = to_track(tracks_[i].raw);
    std::swap(pyr_prev_, pyr_cur_);
    have_prev_ = true;
    ++frame_;
}

void TrajectoryTracker::unroll_shutter(const std::vector<cv::Point2f>& raw,
                                       std::vector<cv::Point2f>& und) const {
    const double readout_s = this->readout_s();
    if (!(readout_s > 0) || shutter_rate_ == cv::Vec3d(0, 0, 0) || calib_.height <= 0) return;
    for (std::size_t i = 0; i < und.size(); ++i) {
        // The row's delay after mid-frame; the camera turned by rate x delay since then.
        const double delay_s =
            (static_cast<double>(raw[i].y) / static_cast<double>(calib_.height) - 0.5) * readout_s;
        und[i] =
            apply_homography(small_rotation_homography(calib_, shutter_rate_ * -delay_s), und[i]);
    }
}

int TrajectoryTracker::cell_of(cv::Point2f raw) const {
    const int cx =
        std::clamp(static_cast<int>(static_cast<double>(raw.x) * p_.grid_cols / calib_.width), 0,
                   p_.grid_cols - 1);
    const int cy =
        std::clamp(static_cast<int>(static_cast<double>(raw.y) * p_.grid_rows / calib_.height), 0,
                   p_.grid_rows - 1);
    return cy * p_.grid_cols + cx;
}

int TrajectoryTracker::cell_quota() const {
    const int cells = p_.grid_cols * p_.grid_rows;
    return std::max(1, (p_.max_tracks + cells - 1) / cells);
}

void TrajectoryTracker::mask_live_tracks(cv::Mat& mask) const {
    // No new corner this close to a live trajectory (new_point_min_distance_px).
    const int r = static_cast<int>(std::lround(p_.new_point_min_distance_px * p_.track_scale));
    if (r <= 0) return;
    for (const Trajectory& t : tracks_) {
        const cv::Point2f q = to_track(t.raw);
        cv::circle(
            mask, cv::Point(static_cast<int>(std::lround(q.x)), static_cast<int>(std::lround(q.y))),
            r, cv::Scalar(0), cv::FILLED);
    }
}

void TrajectoryTracker::order_by_length() {
    // order_: indices of tracks_, longest first (ties: older id first).
    order_.resize(tracks_.size());
    for (std::size_t i = 0; i < tracks_.size(); ++i) order_[i] = i;
    std::sort(order_.begin(), order_.end(), [&](std::size_t a, std::size_t b) {
        if (tracks_[a].length != tracks_[b].length) return tracks_[a].length > tracks_[b].length;
        return tracks_[a].id < tracks_[b].id;
    });
}

TrajectoryTracker::BandGrid TrajectoryTracker::band_grid() const {
    // Cells of about kBandCellPx x 1.5 kBandCellPx (full-size px) over the band's raw columns
    // (roll and distortion move the band little near the centre).
    constexpr double kBandCellPx = 40;
    BandGrid g;
    g.x0 = calib_.width / 2.0 - p_.centre_band_px;
    g.cols = std::max(1, static_cast<int>(std::lround(2 * p_.centre_band_px / kBandCellPx)));
    g.rows = std::max(1, static_cast<int>(std::lround(calib_.height / (1.5 * kBandCellPx))));
    g.cw = 2 * p_.centre_band_px / g.cols;
    g.ch = static_cast<double>(calib_.height) / g.rows;
    g.quota = std::max(1, (p_.centre_min_tracks + g.cols * g.rows - 1) / (g.cols * g.rows));
    return g;
}

int TrajectoryTracker::BandGrid::cell(cv::Point2f raw) const {
    const int cx = std::clamp(static_cast<int>(std::floor((static_cast<double>(raw.x) - x0) / cw)),
                              0, cols - 1);
    const int cy =
        std::clamp(static_cast<int>(std::floor(static_cast<double>(raw.y) / ch)), 0, rows - 1);
    return cy * cols + cx;
}

void TrajectoryTracker::mark_centre_reserve() {
    // In each cell of the centre band the longest trajectories (ties: older id first), up to the
    // cell's share of centre_min_tracks, are the band's reserve: kept whatever their grid cell
    // holds, and counted neither toward a grid cell's share nor toward max_tracks.
    reserve_.assign(tracks_.size(), 0);
    reserved_ = 0;
    if (p_.centre_min_tracks <= 0) return;
    const BandGrid g = band_grid();
    order_by_length();
    band_count_.assign(static_cast<std::size_t>(g.cols * g.rows), 0);
    for (std::size_t i : order_) {
        if (!in_centre_band(tracks_[i])) continue;
        int& n = band_count_[static_cast<std::size_t>(g.cell(tracks_[i].raw))];
        if (n >= g.quota) continue;
        ++n;
        reserve_[i] = 1;
        ++reserved_;
    }
}

void TrajectoryTracker::balance_grid() {
    const auto cells = static_cast<std::size_t>(p_.grid_cols * p_.grid_rows);
    const int quota = cell_quota();
    cell_count_.assign(cells, 0);
    for (std::size_t i = 0; i < tracks_.size(); ++i)
        if (!reserve_[i]) ++cell_count_[static_cast<std::size_t>(cell_of(tracks_[i].raw))];
    bool crowded = false;
    for (int n : cell_count_) crowded = crowded || n > quota;
    if (!crowded) return;
    // In each crowded cell the longest trajectories keep their place (ties: older id first).
    order_by_length();
    drop_.assign(tracks_.size(), 0);
    cell_count_.assign(cells, 0);
    for (std::size_t i : order_) {
        if (reserve_[i]) continue;
        int& n = cell_count_[static_cast<std::size_t>(cell_of(tracks_[i].raw))];
        if (n >= quota)
            drop_[i] = 1;
        else
            ++n;
    }
    std::size_t m = 0;
    for (std::size_t i = 0; i < tracks_.size(); ++i) {
        if (drop_[i]) continue;
        if (m != i) {
            tracks_[m] = tracks_[i];
            reserve_[m] = reserve_[i];
        }
        ++m;
    }
    reserve_.resize(m);
    ended_ += static_cast<int>(tracks_.size() - m);
    tracks_.resize(m);
}

void TrajectoryTracker::detect(double roll) {
    if (std::isnan(mask_roll_deg_) || std::abs(roll - mask_roll_deg_) >= p_.mask_roll_step_deg) {
        detection_mask(calib_, stab_, p_.border_margin_px, p_.track_scale, mask_base_);
        mask_roll_deg_ = roll;
    }
    mask_base_.copyTo(mask_);
    if (grid_on()) {
        // Full cells take no new corners (counts as balance_grid() left them).
        const int quota = cell_quota();
        const double cw = calib_.width * p_.track_scale / p_.grid_cols;
        const double ch = calib_.height * p_.track_scale / p_.grid_rows;
        for (int c = 0; c < p_.grid_cols * p_.grid_rows; ++c) {
            if (cell_count_[static_cast<std::size_t>(c)] < quota) continue;
            const int cx = c % p_.grid_cols, cy = c / p_.grid_cols;
            const cv::Point a(static_cast<int>(std::floor(cx * cw)),
                              static_cast<int>(std::floor(cy * ch)));
            const cv::Point b(static_cast<int>(std::ceil((cx + 1) * cw)),
                              static_cast<int>(std::ceil((cy + 1) * ch)));
            cv::rectangle(mask_, a, b, cv::Scalar(0), cv::FILLED);
        }
    }
    mask_live_tracks(mask_);
    const int want = p_.max_tracks - (static_cast<int>(tracks_.size()) - reserved_);
    if (want > 0) {
        cv::goodFeaturesToTrack(grey_track_, corners_, want, p_.quality_level,
                                std::max(1.0, p_.min_corner_distance_px * p_.track_scale), mask_,
                                p_.block_size);
        add_corners(false);
    }
    if (p_.centre_min_tracks > 0) top_up_centre_band();
}

void TrajectoryTracker::top_up_centre_band() {
    // Each cell of the band is topped up to its share with the strongest corners in it: the
    // band's strongest are mostly the background beside a near obstacle, the cells spread them
    // over the obstacle. A corner must be as strong, relative to the image's strongest, as the
    // main detection asks (quality_level): a plain surface's noise is not a corner.
    const BandGrid g = band_grid();
    const int x0 =
        std::clamp(static_cast<int>(std::floor(g.x0 * p_.track_scale)), 0, mask_base_.cols);
    const int x1 =
        std::clamp(static_cast<int>(std::ceil((g.x0 + 2 * p_.centre_band_px) * p_.track_scale)), x0,
                   mask_base_.cols);
    if (x1 <= x0 || mask_base_.rows <= 0) return;
    band_count_.assign(static_cast<std::size_t>(g.cols * g.rows), 0);
    for (const Trajectory& t : tracks_)
        if (in_centre_band(t)) ++band_count_[static_cast<std::size_t>(g.cell(t.raw))];

    // No new corner where a trajectory is, nor off the valid image.
    band_mask_.create(mask_base_.size(), mask_base_.type());
    band_mask_.setTo(cv::Scalar(0));
    const cv::Rect band(x0, 0, x1 - x0, mask_base_.rows);
    mask_base_(band).copyTo(band_mask_(band));
    mask_live_tracks(band_mask_);
    cv::cornerMinEigenVal(grey_track_, eig_, p_.block_size, 3);
    double strongest = 0;
    cv::minMaxLoc(eig_, nullptr, &strongest, nullptr, nullptr, mask_base_);
    const auto floor_eig = static_cast<float>(p_.quality_level * strongest);
    if (!(floor_eig > 0)) return;

    // Candidates: local maxima (3 x 3) over the floor in cells below their share, strongest first.
    band_candidates_.clear();
    for (int y = 1; y + 1 < eig_.rows; ++y) {
        const float* up = eig_.ptr<float>(y - 1);
        const float* e = eig_.ptr<float>(y);
        const float* dn = eig_.ptr<float>(y + 1);
        const std::uint8_t* m = band_mask_.ptr<std::uint8_t>(y);
        for (int x = std::max(1, x0); x < std::min(x1, eig_.cols - 1); ++x) {
            const float v = e[x];
            if (!m[x] || v < floor_eig) continue;
            if (v < e[x - 1] || v < e[x + 1] || v < up[x - 1] || v < up[x] || v < up[x + 1] ||
                v < dn[x - 1] || v < dn[x] || v < dn[x + 1])
                continue;
            band_candidates_.push_back(
                {v, cv::Point2f(static_cast<float>(x), static_cast<float>(y))});
        }
    }
    std::sort(band_candidates_.begin(), band_candidates_.end(),
              [](const BandCandidate& a, const BandCandidate& b) {
                  if (a.eig != b.eig) return a.eig > b.eig;
                  return a.at.y != b.at.y ? a.at.y < b.at.y : a.at.x < b.at.x;
              });
    const float min_d =
        static_cast<float>(std::max(1.0, p_.min_corner_distance_px * p_.track_scale));
    corners_.clear();
    for (const BandCandidate& c : band_candidates_) {
        int& n = band_count_[static_cast<std::size_t>(g.cell(to_full(c.at)))];
        if (n >= g.quota) continue;
        bool near = false;
        for (const cv::Point2f& q : corners_) {
            const cv::Point2f d = q - c.at;
            near = near || d.dot(d) < min_d * min_d;
        }
        if (near) continue;
        corners_.push_back(c.at);
        ++n;
    }
    add_corners(true);
}

bool TrajectoryTracker::in_centre_band(cv::Point2f stab) const {
    return std::abs(static_cast<double>(stab.x) - calib_.width / 2.0) <= p_.centre_band_px;
}

bool TrajectoryTracker::in_centre_band(const Trajectory& t) const {
    return t.length > 0 && in_centre_band(t.at_back(0).stab);
}

void TrajectoryTracker::add_corners(bool centre_band_only) {
    if (corners_.empty()) return;
    raw_.resize(corners_.size());
    for (std::size_t i = 0; i < corners_.size(); ++i) raw_[i] = to_full(corners_[i]);
    und_.resize(raw_.size());
    calib_.undistort_points(raw_, und_);
    unroll_shutter(raw_, und_);
    const auto w = static_cast<float>(calib_.width);
    const auto h = static_cast<float>(calib_.height);
    for (std::size_t i = 0; i < raw_.size(); ++i) {
        const cv::Point2f s = stab_.apply(und_[i]);
        if (!inside(s, w, h, 0)) continue;  // the mask is conservative, this is exact
        if (centre_band_only && !in_centre_band(s)) continue;
        Trajectory& t = tracks_.emplace_back();
        t.id = next_id_++;
        t.first_frame = frame_;
        t.raw = raw_[i];
        t.undist = und_[i];
        t.undist_prev = und_[i];
        t.push({s, und_[i], now_s_});
        ++added_;
    }
}

}  // namespace gs::vision
