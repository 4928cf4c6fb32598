#include "drone/sim/realism.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

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
    o.low_texture_walls_pct = 50;
    o.glossy_floor_pct = 20;
    o.glossy_floor_blur_deg = 1.5;
    o.people_crossing = 1;
    o.person_speed_mps = 1.3;
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
    {"low_texture_walls_pct", &RealismOptions::low_texture_walls_pct, 0, 100,
     "Low-texture walls: share of the room's four walls repainted plain (%, whole walls)"},
    {"glossy_floor_pct", &RealismOptions::glossy_floor_pct, 0, 100,
     "Glossy floor: share of the floor's light that mirrors the scene above it (%)"},
    {"glossy_floor_blur_deg", &RealismOptions::glossy_floor_blur_deg, 0, 20,
     "Glossy floor: blur of the reflection, angular Gaussian sigma (deg)"},
    {"people_crossing", &RealismOptions::people_crossing, 0, 10,
     "People crossing the flight path, >= 6 m ahead of the drone (count)"},
    {"person_speed_mps", &RealismOptions::person_speed_mps, 0.3, 3,
     "Walking speed of the people crossing (m/s)"},
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
    if (people_crossing != std::floor(people_crossing))
        return "realism.people_crossing = " + std::to_string(people_crossing) +
               " is not a whole number";
    return std::nullopt;
}

// ---- Scene ----

RenderOptions render_options(const RealismOptions& o) {
    RenderOptions r;
    if (o.glossy_floor_pct > 0) {
        r.floor_reflection = o.glossy_floor_pct / 100;
        r.floor_blur_deg = o.glossy_floor_blur_deg;
    }
    return r;
}

CameraCalibration rendered_front_camera(const RealismOptions& o) {
    CameraCalibration c = builtin_calibration(CameraId::Front);
    c.readout_ms = o.rolling_shutter_ms;
    return c;
}

SceneEffects apply_scene_effects(Scene& scene, const RealismOptions& o, std::uint64_t seed) {
    SceneEffects out;
    Room& r = scene.room;
    std::array<std::pair<const char*, TextureSpec*>, 4> walls{{{"front", &r.wall_front},
                                                               {"back", &r.wall_back},
                                                               {"left", &r.wall_left},
                                                               {"right", &r.wall_right}}};
    const int n = int(std::lround(4 * o.low_texture_walls_pct / 100));
    if (n > 0) {
        Rng rng(mix_seed(seed, 0x91a1));
        // The first n of a seeded shuffle.
        for (int i = 3; i > 0; --i)
            std::swap(walls[std::size_t(i)], walls[std::size_t(rng.range(0, i))]);
        for (int i = 0; i < n; ++i) {
            TextureSpec& t = *walls[std::size_t(i)].second;
            // The wall's own colour, plain: faint mottling only (TextureKind::Plain).
            t.kind = TextureKind::Plain;
            t.seed = mix_seed(seed, 0x91a1 + std::uint64_t(i));
            t.has_color2 = false;
            out.plain_walls.push_back(walls[std::size_t(i)].first);
        }
        std::sort(out.plain_walls.begin(), out.plain_walls.end());
    }
    return out;
}

// ---- People ----

Obstacle PersonTrack::at(double t_s) const {
    Obstacle o;
    o.id = "person";
    o.shape = ObstacleShape::Box;
    const double along = speed_mps * (t_s - cross_s);
    o.x_m = cross_x_m + dir_x * along;
    o.y_m = cross_y_m + dir_y * along;
    o.size_x_m = 0.3;  // along the walk (local x = walking direction)
    o.size_y_m = 0.5;  // shoulders
    o.height_m = 1.75;
    o.yaw_deg = std::atan2(dir_y, dir_x) * 180 / std::numbers::pi;
    o.texture = clothes;
    o.clutter = true;
    return o;
}

nlohmann::json PersonTrack::to_json() const {
    nlohmann::ordered_json j;
    j["cross_s"] = cross_s;
    j["cross_xy_m"] = {cross_x_m, cross_y_m};
    j["direction"] = {dir_x, dir_y};
    j["from_s"] = from_s;
    j["to_s"] = to_s;
    j["speed_mps"] = speed_mps;
    return nlohmann::json(j);
}

std::vector<PersonTrack> plan_people(const RealismOptions& o, const Room& room, double x0,
                                     double y0, double heading_deg, double max_speed_mps,
                                     std::uint64_t seed) {
    std::vector<PersonTrack> out;
    const int n = int(std::lround(o.people_crossing));
    if (n <= 0) return out;
    Rng rng(mix_seed(seed, 0x9e0b1e));
    const double h = heading_deg * std::numbers::pi / 180;
    const double hx = std::cos(h), hy = std::sin(h);  // along the flight
    const double ex = -hy, ey = hx;                   // to its right
    const double margin = 0.5;  // the person's centre stays this far from the walls
    const double xl = room.x_min_m + margin, xh = room.x_max_m - margin;
    const double yl = room.y_min_m + margin, yh = room.y_max_m - margin;
    // How far the line from (x, y) along (dx, dy) runs inside the room's inner box, both ways.
    auto extent = [&](double x, double y, double dx, double dy, double& lo, double& hi) {
        lo = -1e9;
        hi = 1e9;
        auto slab = [&](double p, double d, double a, double b) {
            if (std::abs(d) < 1e-12) {
                if (p < a || p > b) hi = lo - 1;
                return;
            }
            double t1 = (a - p) / d, t2 = (b - p) / d;
            if (t1 > t2) std::swap(t1, t2);
            lo = std::max(lo, t1);
            hi = std::min(hi, t2);
        };
        slab(x, dx, xl, xh);
        slab(y, dy, yl, yh);
    };
    double a_lo = 0, a_hi = 0;
    extent(x0, y0, hx, hy, a_lo, a_hi);
    const double clear_m = 7.0;  // 6 m and a margin
    for (int k = 0; k < n; ++k) {
        PersonTrack p;
        p.speed_mps = o.person_speed_mps;
        double t_c = 3.0 * (k + 1) + rng.uniform(-0.5, 0.5);
        // The drone is at most max_speed * t_c along the line by then; the person crosses 7 m
        // beyond. Too far for the room: cross earlier, nearer (down to 1 s into the recording).
        double a_c = max_speed_mps * t_c + clear_m;
        if (a_c > a_hi - 0.3) {
            t_c = (a_hi - 0.3 - clear_m) / std::max(max_speed_mps, 1e-3);
            a_c = a_hi - 0.3;
        }
        const bool left_to_right = rng.chance(0.5);
        TextureSpec t;
        t.kind = TextureKind::Noise;
        t.seed = rng.next();
        t.scale_m = 0.6;
        const cv::Vec3b palette[] = {{40, 50, 90}, {120, 30, 30},   {30, 30, 30},
                                     {60, 90, 60}, {150, 140, 120}, {90, 60, 110}};
        t.color_rgb = palette[rng.range(0, 5)];
        p.clothes = t;
        if (t_c < 1.0) continue;  // no room ahead for this one
        p.cross_s = t_c;
        p.cross_x_m = x0 + hx * a_c;
        p.cross_y_m = y0 + hy * a_c;
        p.dir_x = left_to_right ? ex : -ex;
        p.dir_y = left_to_right ? ey : -ey;
        double w_lo = 0, w_hi = 0;
        extent(p.cross_x_m, p.cross_y_m, p.dir_x, p.dir_y, w_lo, w_hi);
        if (!(w_lo < 0 && w_hi > 0)) continue;
        p.from_s = t_c + w_lo / p.speed_mps;  // w_lo < 0: before the crossing
        p.to_s = t_c + w_hi / p.speed_mps;
        out.push_back(p);
    }
    return out;
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

// The lens model of distort_to_pixel in float, its coefficients hoisted out of the pixel loop.
struct FloatLens {
    float fx, fy, cx, cy, k1, k2, k3, p1, p2;
    explicit FloatLens(const CameraCalibration& c)
        : fx(float(c.fx)),
          fy(float(c.fy)),
          cx(float(c.cx)),
          cy(float(c.cy)),
          k1(float(c.dist[0])),
          k2(float(c.dist[1])),
          k3(float(c.dist[4])),
          p1(float(c.dist[2])),
          p2(float(c.dist[3])) {}
    // The pixel where the ray (nx, ny, nz) appears (nz clamped to 1e-3 as before).
    inline void project(float nx, float ny, float nz, float& px, float& py) const {
        const float inv = 1.0f / std::max(nz, 1e-3f);
        const float x = nx * inv, y = ny * inv;
        const float xx = x * x, yy = y * y, xy = x * y, r2 = xx + yy;
        const float radial = 1 + r2 * (k1 + r2 * (k2 + r2 * k3));
        px = fx * (x * radial + 2 * p1 * xy + p2 * (r2 + 2 * xx)) + cx;
        py = fy * (y * radial + p1 * (r2 + 2 * yy) + 2 * p2 * xy) + cy;
    }
};

// One pixel as four floats (B, G, R, unused): the bilinear taps below work on whole pixels with
// the compiler's 4-lane vectors (GCC and Clang vector extensions; SSE on x86, NEON on ARM).
using Px = float __attribute__((vector_size(16)));

// Adds the bilinear interpolation of the 2x2 pixels at (x0, y0) of `src` (Px pixels, rows `step`
// pixels apart) with weights (fx, fy) to acc. The caller keeps (x0 + 1, y0 + 1) inside the image.
inline void bilinear_tap(const Px* src, std::size_t step, int x0, int y0, float fx, float fy,
                         Px& acc) {
    const Px* a = src + std::size_t(y0) * step + std::size_t(x0);
    const Px* b = a + step;
    const Px top = a[0] + fx * (a[1] - a[0]);
    const Px bot = b[0] + fx * (b[1] - b[0]);
    acc += top + fy * (bot - top);
}

// Adds the bilinear sample of `src` at (x, y), clamped to the image, to acc.
inline void sample_bilinear(const Px* src, std::size_t step, int W, int H, float x, float y,
                            Px& acc) {
    x = std::clamp(x, 0.0f, float(W - 1));
    y = std::clamp(y, 0.0f, float(H - 1));
    const int x0 = std::min(int(x), W - 2), y0 = std::min(int(y), H - 2);
    bilinear_tap(src, step, x0, y0, x - float(x0), y - float(y0), acc);
}

// The warp's first pass over one row: each pixel's ray r = (rx, ry, 1) moves as
// d n / d tau = omega x r + v w (w = 1 / Z); its pixel at tau = ta is (pax, pay), and at tb that
// plus (dx, dy). Branch-free on unaliased arrays, so the compiler vectorises it.
void project_row(const FloatLens& lens, const float* __restrict rx_p, const float* __restrict ry_p,
                 const float* __restrict w_p, int W, float wx, float wy, float wz, float vx,
                 float vy, float vz, float ta, float tb, float* __restrict pax,
                 float* __restrict pay, float* __restrict dxs, float* __restrict dys) {
    for (int x = 0; x < W; ++x) {
        const float rx = rx_p[x], ry = ry_p[x], w = w_p[x];
        const float gx = wy - wz * ry + vx * w;
        const float gy = wz * rx - wx + vy * w;
        const float gz = wx * ry - wy * rx + vz * w;
        float ax, ay, bx, by;
        lens.project(rx + ta * gx, ry + ta * gy, 1 + ta * gz, ax, ay);
        lens.project(rx + tb * gx, ry + tb * gy, 1 + tb * gz, bx, by);
        pax[x] = ax;
        pay[x] = ay;
        dxs[x] = bx - ax;
        dys[x] = by - ay;
    }
}

// Rounds a non-negative sum to a byte (std::lround's result for values >= 0).
inline std::uint8_t to_byte(float v) {
    return std::uint8_t(std::min(int(v + 0.5f), 255));
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
    const bool moving = vx != 0 || vy != 0 || vz != 0;
    const FloatLens lens(calib_);
    // The source as float pixels once per frame: the taps below then read, not convert, values.
    cv::cvtColor(src, src4_, cv::COLOR_BGR2BGRA);
    src4_.convertTo(srcf_, CV_32FC4);
    const Px* const s = reinterpret_cast<const Px*>(srcf_.ptr<float>(0));
    const std::size_t step = srcf_.step[0] / sizeof(Px);
    const float* const rx_p = rx_.data();
    const float* const ry_p = ry_.data();
    const float* const w_p = depth && moving ? inv_depth.data() : nullptr;
    row_.resize(std::size_t(W) * 4);
    zeros_.assign(std::size_t(W), 0.0f);
    float* const pax = row_.data();
    float* const pay = pax + W;
    float* const dxs = pay + W;
    float* const dys = dxs + W;
    const float xmax = float(W - 1), ymax = float(H - 1);
    for (int y = 0; y < H; ++y) {
        const float tau = float(H > 1 ? (double(y) / (H - 1) - 0.5) * readout : 0.0);
        const float ta = tau - float(expo / 2), tb = tau + float(expo / 2);
        const std::size_t row = std::size_t(y) * std::size_t(W);
        // Pass 1 (vectorised): where the ray of each pixel is at the start and the end of its
        // row's exposure.
        project_row(lens, rx_p + row, ry_p + row, w_p ? w_p + row : zeros_.data(), W, wx, wy, wz,
                    vx, vy, vz, ta, tb, pax, pay, dxs, dys);
        // Pass 2: the box exposure as taps less than a pixel apart along that path.
        std::uint8_t* o = dst.ptr<std::uint8_t>(y);
        for (int x = 0; x < W; ++x) {
            Px acc = {0, 0, 0, 0};
            const float ax = pax[x], ay = pay[x];
            if (expo <= 0) {
                sample_bilinear(s, step, W, H, ax, ay, acc);
            } else {
                const float dx = dxs[x], dy = dys[x];
                const float len = std::sqrt(dx * dx + dy * dy);
                const int taps = std::clamp(int(std::ceil(len)) + 1, 1, 24);
                const float inv_taps = 1.0f / float(taps);
                const float bx = ax + dx, by = ay + dy;
                if (std::min(ax, bx) >= 0 && std::max(ax, bx) < xmax - 1 && std::min(ay, by) >= 0 &&
                    std::max(ay, by) < ymax - 1) {
                    // Inside the image all along: no clamping.
                    for (int k = 0; k < taps; ++k) {
                        const float f = (float(k) + 0.5f) * inv_taps;
                        const float px = ax + f * dx, py = ay + f * dy;
                        const int x0 = int(px), y0 = int(py);
                        bilinear_tap(s, step, x0, y0, px - float(x0), py - float(y0), acc);
                    }
                } else {
                    for (int k = 0; k < taps; ++k) {
                        const float f = (float(k) + 0.5f) * inv_taps;
                        sample_bilinear(s, step, W, H, ax + f * dx, ay + f * dy, acc);
                    }
                }
                acc *= inv_taps;
            }
            o[3 * x] = to_byte(acc[0]);
            o[3 * x + 1] = to_byte(acc[1]);
            o[3 * x + 2] = to_byte(acc[2]);
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
                p[3 * x + c] = v > 0 ? to_byte(v) : std::uint8_t(0);
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

NavState true_navdata(const FlightState& s, TimeNs t_ns) {
    NavState n;
    n.t_ns = t_ns;
    n.roll_deg = s.roll_deg;
    n.pitch_deg = s.pitch_deg;
    n.yaw_deg = s.yaw_deg;
    n.vx_mps = s.vx_body_mps();
    n.vy_mps = s.vy_body_mps();
    n.vz_mps = s.vz_mps;
    n.altitude_m = s.z_m;
    return n;
}

}  // namespace gs::sim
