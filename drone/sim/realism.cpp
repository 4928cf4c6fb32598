#include "drone/sim/realism.hpp"

#include <opencv2/calib3d.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace gs::sim {

double gaussian(Rng& r, double sigma) {
    if (sigma <= 0) return 0;
    const double u1 = std::max(r.uniform(), 1e-300), u2 = r.uniform();
    return sigma * std::sqrt(-2 * std::log(u1)) * std::cos(2 * std::numbers::pi * u2);
}

// ---- Options ----

RealismOptions RealismOptions::real_camera() {
    RealismOptions o;
    o.rolling_shutter_ms = 25;
    o.exposure_ms = 12;
    o.exposure_step_pct = 15;
    o.exposure_step_interval_s = 2;
    o.flicker_pct = 3;
    o.flicker_hz = 100;
    o.vignetting_pct = 30;
    o.noise_pct = 1.5;
    o.slice_loss_pct = 2;
    o.nav_latency_ms = 30;
    o.nav_jitter_ms = 10;
    o.attitude_bias_deg = 0.3;
    o.velocity_bias_mps = 0.03;
    o.bias_tau_s = 30;
    return o;
}

namespace {

constexpr RealismField kFields[] = {
    {"rolling_shutter_ms", &RealismOptions::rolling_shutter_ms, 0, 100,
     "Rolling shutter: sensor readout time, first row to last (ms)"},
    {"exposure_ms", &RealismOptions::exposure_ms, 0, 100,
     "Motion blur: exposure time of each row (ms)"},
    {"exposure_step_pct", &RealismOptions::exposure_step_pct, 0, 50,
     "Auto-exposure: gain step (%)"},
    {"exposure_step_interval_s", &RealismOptions::exposure_step_interval_s, 0.1, 1000,
     "Auto-exposure: mean time between steps (s)"},
    {"flicker_pct", &RealismOptions::flicker_pct, 0, 50, "Light flicker amplitude (%)"},
    {"flicker_hz", &RealismOptions::flicker_hz, 1, 1000,
     "Light flicker frequency (Hz; 100 under 50 Hz mains)"},
    {"vignetting_pct", &RealismOptions::vignetting_pct, 0, 90,
     "Vignetting: darkening at the image corners (%)"},
    {"noise_pct", &RealismOptions::noise_pct, 0, 20,
     "Sensor shot noise: sigma at mid grey (% of full scale)"},
    {"slice_loss_pct", &RealismOptions::slice_loss_pct, 0, 50,
     "Wi-Fi damage: P frames losing the tail of their slice (%)"},
    {"nav_latency_ms", &RealismOptions::nav_latency_ms, 0, 500,
     "Navdata sample older than the frame by (ms)"},
    {"nav_jitter_ms", &RealismOptions::nav_jitter_ms, 0, 200,
     "Navdata latency jitter, Gaussian sigma (ms)"},
    {"attitude_bias_deg", &RealismOptions::attitude_bias_deg, 0, 10,
     "Drifting attitude bias, stationary sigma (deg)"},
    {"velocity_bias_mps", &RealismOptions::velocity_bias_mps, 0, 2,
     "Drifting velocity bias, stationary sigma (m/s)"},
    {"bias_tau_s", &RealismOptions::bias_tau_s, 0.1, 10000,
     "Correlation time of the drifting biases (s)"},
};

}  // namespace

std::span<const RealismField> realism_fields() {
    return kFields;
}

nlohmann::json RealismOptions::to_json() const {
    nlohmann::ordered_json j;
    for (const RealismField& f : kFields) j[f.name] = this->*f.member;
    return nlohmann::json(j);
}

std::optional<std::string> RealismOptions::from_json(const nlohmann::json& j, RealismOptions& out) {
    if (!j.is_object()) return std::string("realism: expected an object");
    RealismOptions o;
    for (const RealismField& f : kFields) {
        if (!j.contains(f.name)) continue;
        if (!j[f.name].is_number()) return std::string("realism.") + f.name + ": expected a number";
        o.*f.member = j[f.name].get<double>();
    }
    if (auto e = o.check()) return e;
    out = o;
    return std::nullopt;
}

std::optional<std::string> RealismOptions::check() const {
    for (const RealismField& f : kFields) {
        const double v = this->*f.member;
        if (!(v >= f.lo && v <= f.hi))
            return std::string("realism.") + f.name + " = " + std::to_string(v) + " is outside [" +
                   std::to_string(f.lo) + ", " + std::to_string(f.hi) + "]";
    }
    return std::nullopt;
}

// ---- Camera ----

CameraMotion camera_motion(const Pose& from, const Pose& to, double dt_s, CameraKind camera) {
    CameraMotion m;
    if (!(dt_s > 0)) return m;
    const cv::Matx33d ra = world_from_camera(from, camera), rb = world_from_camera(to, camera);
    cv::Vec3d rvec;
    cv::Rodrigues(cv::Mat(ra.t() * rb), rvec);
    m.omega_rad_s = rvec / dt_s;
    // World positions in the renderer's frame (x forward, y right, z down).
    const cv::Vec3d d(to.x_m - from.x_m, to.y_m - from.y_m, -(to.z_m - from.z_m));
    m.v_mps = rb.t() * d / dt_s;
    return m;
}

CameraEffects::CameraEffects(const CameraCalibration& calib, const RealismOptions& o,
                             std::uint64_t seed)
    : calib_(calib), o_(o), rng_(mix_seed(seed, 0x5ea1)), noise_seed_(mix_seed(seed, 0x4015e)) {
    const int W = calib.width, H = calib.height;
    const std::size_t n = std::size_t(W) * std::size_t(H);
    if (o.geometric()) {
        rx_.resize(n);
        ry_.resize(n);
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
                const auto r = undistort_pixel(calib, {double(x), double(y)});
                // Outside the model's invertible range (the far corners of a strong barrel
                // lens): the pinhole ray, which the pixel keeps unmoved-ish.
                const cv::Point2d q =
                    r ? *r : cv::Point2d((x - calib.cx) / calib.fx, (y - calib.cy) / calib.fy);
                rx_[i] = float(q.x);
                ry_[i] = float(q.y);
            }
    }
    if (o.vignetting_pct > 0) {
        vig_.resize(n);
        const double rmax2 = std::max(
            {calib.cx * calib.cx + calib.cy * calib.cy,
             (W - 1 - calib.cx) * (W - 1 - calib.cx) + (H - 1 - calib.cy) * (H - 1 - calib.cy),
             (W - 1 - calib.cx) * (W - 1 - calib.cx) + calib.cy * calib.cy,
             calib.cx * calib.cx + (H - 1 - calib.cy) * (H - 1 - calib.cy)});
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const double d2 =
                    ((x - calib.cx) * (x - calib.cx) + (y - calib.cy) * (y - calib.cy)) / rmax2;
                vig_[std::size_t(y) * std::size_t(W) + std::size_t(x)] =
                    float(1 - o.vignetting_pct / 100 * d2);
            }
    }
    flicker_phase_ = 2 * std::numbers::pi * rng_.uniform();
    next_step_s_ = o.exposure_step_interval_s * -std::log(std::max(rng_.uniform(), 1e-12));
}

namespace {

inline void sample_bilinear(const cv::Mat& src, float x, float y, float acc[3]) {
    const int W = src.cols, H = src.rows;
    x = std::clamp(x, 0.0f, float(W - 1));
    y = std::clamp(y, 0.0f, float(H - 1));
    const int x0 = std::min(int(x), W - 2), y0 = std::min(int(y), H - 2);
    const float fx = x - float(x0), fy = y - float(y0);
    const std::uint8_t* a = src.ptr<std::uint8_t>(y0) + 3 * x0;
    const std::uint8_t* b = src.ptr<std::uint8_t>(y0 + 1) + 3 * x0;
    for (int c = 0; c < 3; ++c) {
        const float top = float(a[c]) + fx * (float(a[3 + c]) - float(a[c]));
        const float bot = float(b[c]) + fx * (float(b[3 + c]) - float(b[c]));
        acc[c] += top + fy * (bot - top);
    }
}

}  // namespace

void CameraEffects::warp(const cv::Mat& src, cv::Mat& dst, const CameraMotion& m,
                         std::span<const float> inv_depth) {
    const int W = src.cols, H = src.rows;
    dst.create(H, W, CV_8UC3);
    const double readout = o_.rolling_shutter_ms * 1e-3, expo = o_.exposure_ms * 1e-3;
    const float wx = float(m.omega_rad_s[0]), wy = float(m.omega_rad_s[1]),
                wz = float(m.omega_rad_s[2]);
    const float vx = float(m.v_mps[0]), vy = float(m.v_mps[1]), vz = float(m.v_mps[2]);
    const bool depth = inv_depth.size() == std::size_t(W) * std::size_t(H);
    auto project = [&](float nx, float ny, float nz) {
        if (nz < 1e-3f) nz = 1e-3f;
        return distort_to_pixel(calib_, {double(nx / nz), double(ny / nz)});
    };
    for (int y = 0; y < H; ++y) {
        const float tau = float(H > 1 ? (double(y) / (H - 1) - 0.5) * readout : 0.0);
        const float ta = tau - float(expo / 2), tb = tau + float(expo / 2);
        std::uint8_t* o = dst.ptr<std::uint8_t>(y);
        for (int x = 0; x < W; ++x) {
            const std::size_t i = std::size_t(y) * std::size_t(W) + std::size_t(x);
            const float rx = rx_[i], ry = ry_[i];
            const float w = depth ? inv_depth[i] : 0.0f;
            // d n / d tau = omega x r + v / Z, r = (rx, ry, 1).
            const float gx = wy * 1 - wz * ry + vx * w;
            const float gy = wz * rx - wx * 1 + vy * w;
            const float gz = wx * ry - wy * rx + vz * w;
            const cv::Point2d pa = project(rx + ta * gx, ry + ta * gy, 1 + ta * gz);
            float acc[3] = {0, 0, 0};
            if (expo <= 0) {
                sample_bilinear(src, float(pa.x), float(pa.y), acc);
            } else {
                const cv::Point2d pb = project(rx + tb * gx, ry + tb * gy, 1 + tb * gz);
                const double len = std::hypot(pb.x - pa.x, pb.y - pa.y);
                const int taps = std::clamp(int(std::ceil(len)) + 1, 1, 24);
                for (int k = 0; k < taps; ++k) {
                    const double s = (k + 0.5) / taps;
                    sample_bilinear(src, float(pa.x + s * (pb.x - pa.x)),
                                    float(pa.y + s * (pb.y - pa.y)), acc);
                }
                for (float& a : acc) a /= float(taps);
            }
            for (int c = 0; c < 3; ++c)
                o[3 * x + c] = std::uint8_t(std::clamp(std::lround(acc[c]), 0L, 255L));
        }
    }
}

void CameraEffects::photometry(cv::Mat& img, double t_s) {
    const int W = img.cols, H = img.rows;
    if (o_.exposure_step_pct > 0) {
        // Auto-exposure: a bounded walk of gain steps at Poisson times.
        while (t_s >= next_step_s_) {
            int dir = rng_.chance(0.5) ? 1 : -1;
            if (std::abs(steps_ + dir) > 3) dir = -dir;
            steps_ += dir;
            next_step_s_ +=
                o_.exposure_step_interval_s * -std::log(std::max(rng_.uniform(), 1e-12));
        }
        gain_ = std::pow(1 + o_.exposure_step_pct / 100, steps_);
    }
    const double readout = o_.rolling_shutter_ms * 1e-3;
    const float sigma_mid = float(o_.noise_pct / 100 * 255);
    if (sigma_mid > 0) {
        noise_.create(H, W * 3, CV_32F);
        cv::RNG r(mix_seed(noise_seed_, std::uint64_t(frame_)));
        r.fill(noise_, cv::RNG::NORMAL, 0.0, 1.0);
    }
    for (int y = 0; y < H; ++y) {
        const double t_row = t_s + (H > 1 ? (double(y) / (H - 1) - 0.5) * readout : 0.0);
        double g = gain_;
        if (o_.flicker_pct > 0)
            g *= 1 + o_.flicker_pct / 100 *
                         std::sin(2 * std::numbers::pi * o_.flicker_hz * t_row + flicker_phase_);
        std::uint8_t* p = img.ptr<std::uint8_t>(y);
        const float* nz = sigma_mid > 0 ? noise_.ptr<float>(y) : nullptr;
        const float* vg = vig_.empty() ? nullptr : vig_.data() + std::size_t(y) * std::size_t(W);
        for (int x = 0; x < W; ++x) {
            const float gx = float(g) * (vg ? vg[x] : 1.0f);
            for (int c = 0; c < 3; ++c) {
                float v = float(p[3 * x + c]) * gx;
                if (nz) v += nz[3 * x + c] * sigma_mid * std::sqrt(std::max(v, 0.0f) / 128.0f);
                p[3 * x + c] = std::uint8_t(std::clamp(std::lround(v), 0L, 255L));
            }
        }
    }
}

void CameraEffects::apply(cv::Mat& bgr, double t_s, const CameraMotion& motion,
                          std::span<const float> inverse_depth) {
    if (o_.geometric()) {
        warp(bgr, tmp_, motion, inverse_depth);
        std::swap(bgr, tmp_);
    }
    if (o_.photometric()) photometry(bgr, t_s);
    ++frame_;
}

// ---- Stream ----

bool StreamDamage::apply(std::vector<std::uint8_t>& au, bool idr) {
    if (idr || p_ <= 0 || au.size() < 64 || !rng_.chance(p_)) return false;
    // The slice NAL starts after the last start code; keep its header and a random share of
    // its macroblocks (10-90 %), as when one of the frame's packets is lost.
    std::size_t start = 0;
    for (std::size_t i = 0; i + 3 < au.size(); ++i)
        if (au[i] == 0 && au[i + 1] == 0 && au[i + 2] == 1) start = i + 3;
    const std::size_t body = au.size() - start;
    if (body < 32) return false;
    const std::size_t keep = start + 8 + std::size_t(double(body - 8) * rng_.uniform(0.1, 0.9));
    au.resize(std::min(au.size(), keep));
    ++damaged_;
    return true;
}

// ---- Navdata ----

NavdataEffects::NavdataEffects(const RealismOptions& o, std::uint64_t seed)
    : o_(o), rng_(mix_seed(seed, 0x9a7d)) {
    // The biases start in their stationary distribution.
    for (int k = 0; k < 5; ++k)
        bias_[std::size_t(k)] = gaussian(rng_, k < 3 ? o.attitude_bias_deg : o.velocity_bias_mps);
}

void NavdataEffects::push_truth(const NavState& truth) {
    history_.push_back(truth);
    // Keep a second (plenty for latencies of tens of ms plus jitter).
    while (history_.size() > 2 && truth.t_ns - history_[1].t_ns > 1'000'000'000)
        history_.pop_front();
}

NavState NavdataEffects::sample(TimeNs t_ns) {
    NavState s;
    if (history_.empty()) return s;
    const double lag_ms = std::max(0.0, o_.nav_latency_ms + gaussian(rng_, o_.nav_jitter_ms));
    const TimeNs at = t_ns - TimeNs(std::llround(lag_ms * 1e6));
    if (at <= history_.front().t_ns) {
        s = history_.front();
    } else if (at >= history_.back().t_ns) {
        s = history_.back();
    } else {
        std::size_t k = 1;
        while (history_[k].t_ns < at) ++k;
        s = interpolate(history_[k - 1], history_[k], at);
    }
    s.t_ns = t_ns;
    // Gauss-Markov biases, advanced to this frame: b += -b dt / tau + sigma sqrt(2 dt / tau) n.
    const double dt = last_bias_t_ ? double(t_ns - *last_bias_t_) * 1e-9 : 0.0;
    last_bias_t_ = t_ns;
    if (dt > 0) {
        const double a = std::exp(-dt / o_.bias_tau_s), q = std::sqrt(1 - a * a);
        for (int k = 0; k < 5; ++k) {
            double& b = bias_[std::size_t(k)];
            b = a * b + gaussian(rng_, q * (k < 3 ? o_.attitude_bias_deg : o_.velocity_bias_mps));
        }
    }
    s.roll_deg += bias_[0];
    s.pitch_deg += bias_[1];
    s.yaw_deg += bias_[2];
    s.vx_mps += bias_[3];
    s.vy_mps += bias_[4];
    return s;
}

}  // namespace gs::sim
