#include "drone/sim/odometry_flights.hpp"
#include "drone/core/geometry.hpp"
#include "drone/sim/units.hpp"

#include "drone/dataset/csv.hpp"
#include "drone/dataset/writer.hpp"
#include "drone/sim/renderer.hpp"
#include "drone/sim/rng.hpp"

#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <numbers>
#include <sstream>

namespace gs::sim {
namespace fs = std::filesystem;
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTopAboveBottom_m = 0.05;  // the cameras sit back to back on the plate

// Smooth random motion: three sines per channel, RMS = amplitude, zero at t = 0.
struct Wobble {
    std::array<double, 3> f{}, ph{}, a{};
    Wobble() = default;
    Wobble(Rng& rng, double rms) {
        for (int k = 0; k < 3; ++k) {
            f[std::size_t(k)] = rng.uniform(0.1, 1.0);
            ph[std::size_t(k)] = rng.uniform(0, 2 * kPi);
            a[std::size_t(k)] = rms / std::sqrt(1.5);
        }
    }
    double raw(double t) const {
        double v = 0;
        for (std::size_t k = 0; k < 3; ++k) v += a[k] * std::sin(2 * kPi * f[k] * t + ph[k]);
        return v;
    }
    double operator()(double t) const { return raw(t) - raw(0); }
};

// Cosine-eased 0 -> 1 over [0, 1] (zero velocity at both ends).
double ease(double u) {
    u = std::clamp(u, 0.0, 1.0);
    return (1 - std::cos(kPi * u)) / 2;
}

// A segment of the nominal path: move (world dx, dy) or turn (dyaw), eased, then hold.
struct Segment {
    double duration_s = 0;
    double dx = 0, dy = 0, dyaw = 0;
};

struct NominalPath {
    std::vector<Segment> segs;
    double total_s = 0;
    std::function<double(double)> yaw_fn;  // rotation test: yaw as a function of time

    Pose at(double t) const {
        Pose p;
        if (yaw_fn) {
            p.yaw_deg = yaw_fn(t);
            return p;
        }
        double t0 = 0;
        for (const Segment& s : segs) {
            const double u = s.duration_s > 0 ? (t - t0) / s.duration_s : 1.0;
            const double e = ease(u);
            p.x_m += s.dx * e;
            p.y_m += s.dy * e;
            p.yaw_deg += s.dyaw * e;
            t0 += s.duration_s;
        }
        return p;
    }
};

NominalPath make_path(const OdometryFlightParams& p) {
    NominalPath path;
    const double v = std::max(p.speed_mps, 1e-3);
    auto move = [&](double dx, double dy) {
        // Eased: peak speed = pi/2 x mean speed, so the duration makes the peak `v`.
        path.segs.push_back({kPi * std::hypot(dx, dy) / (2 * v), dx, dy, 0});
    };
    auto hold = [&](double s) { path.segs.push_back({s, 0, 0, 0}); };
    auto turn = [&](double deg) {
        path.segs.push_back({kPi * std::abs(deg) / (2 * std::max(p.yaw_rate_dps, 1.0)), 0, 0, deg});
    };
    switch (p.test) {
        case OdometryTest::Hover:
            hold(60);
            break;
        case OdometryTest::Rotation:
            // -90° .. +90° continuously (period 20 s), starting at 0.
            path.yaw_fn = [](double t) { return 90.0 * std::sin(2 * kPi * t / 20.0); };
            hold(60);
            break;
        case OdometryTest::Translation:
        case OdometryTest::TranslationRotation: {
            // A loop inside the 3 x 2 m tracked area: forward, right, back, left (fig. 5.7/5.8).
            const bool rot = p.test == OdometryTest::TranslationRotation;
            hold(1);
            move(1.6, 0);
            hold(1);
            if (rot) {
                turn(90);
                hold(1);
            }
            move(0, 1.0);
            hold(1);
            if (rot) {
                turn(-90);
                hold(1);
            }
            move(-1.6, 0);
            hold(1);
            if (rot) {
                turn(-90);
                hold(1);
            }
            move(0, -1.0);
            hold(1);
            if (rot) {
                turn(90);
                hold(1);
            }
            break;
        }
    }
    for (const Segment& s : path.segs) path.total_s += s.duration_s;
    return path;
}

double gaussian(Rng& rng) {
    const double u1 = std::max(rng.uniform(), 1e-300), u2 = rng.uniform();
    return std::sqrt(-2 * std::log(u1)) * std::cos(2 * kPi * u2);
}

double quantise(double v, double step) {
    return step > 0 ? std::round(v / step) * step : v;
}

std::string frame_name(int i, const char* ext) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%06d.%s", i, ext);
    return buf;
}

std::string fixed3(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3f", v);
    return buf;
}

}  // namespace

std::string to_string(OdometryTest t) {
    switch (t) {
        case OdometryTest::Hover:
            return "hover";
        case OdometryTest::Translation:
            return "translation";
        case OdometryTest::TranslationRotation:
            return "translation_rotation";
        case OdometryTest::Rotation:
            return "rotation";
    }
    return "?";
}

std::optional<OdometryTest> odometry_test_from_string(const std::string& s) {
    for (OdometryTest t : {OdometryTest::Hover, OdometryTest::Translation,
                           OdometryTest::TranslationRotation, OdometryTest::Rotation})
        if (to_string(t) == s) return t;
    return std::nullopt;
}

std::vector<OdometryFlightSample> odometry_flight_samples(const OdometryFlightParams& p,
                                                          std::uint64_t seed) {
    const NominalPath path = make_path(p);
    Rng rng(mix_seed(seed, 0x0D0));
    const Wobble wx(rng, p.wobble_xy_m), wy(rng, p.wobble_xy_m), wz(rng, p.wobble_z_m),
        wroll(rng, p.wobble_tilt_deg), wpitch(rng, p.wobble_tilt_deg), wyaw(rng, p.wobble_yaw_deg);
    auto pose_at = [&](double t) {
        Pose q = path.at(t);
        q.x_m += wx(t);
        q.y_m += wy(t);
        q.z_m = p.height_m + wz(t);
        q.roll_deg = wroll(t);
        q.pitch_deg = wpitch(t);
        q.yaw_deg += wyaw(t);
        return q;
    };
    // The distance sensors update at their own rate; each reading has its own noise draw.
    auto reading = [&](std::uint64_t sensor, double t) {
        const double rate = std::max(p.distance_rate_hz, 0.1);
        const auto k = static_cast<std::uint64_t>(std::floor(t * rate));
        const double tk = static_cast<double>(k) / rate;
        const Pose q = pose_at(tk);
        const double cam_z = q.z_m + (sensor == 1 ? kTopAboveBottom_m : 0.0);
        // Along the sensor axis (tilted with the plate) to the horizontal plane.
        const double tilt =
            (geom::level_from_body_matrix(q.roll_deg, q.pitch_deg) * geom::Vec3::UnitZ())
                .z();  // the body's down axis, vertical part
        const double d = (sensor == 1 ? p.ceiling_m - cam_z : cam_z) / std::max(tilt, 0.5);
        Rng r(mix_seed(seed, sensor * 1'000'003ULL + k));
        return quantise(d + p.distance_noise_m * gaussian(r), p.distance_resolution_m);
    };

    const double duration = p.duration_s > 0 ? p.duration_s : path.total_s;
    const int n = std::max(2, static_cast<int>(std::floor(duration * p.fps)) + 1);
    std::vector<OdometryFlightSample> out;
    out.reserve(std::size_t(n));
    Rng nav_rng(mix_seed(seed, 0xA5));
    // The attitude bias: its own generator, so the noise above is the same with or without it.
    Rng bias_rng(mix_seed(seed, 0xB1A5));
    double bias_roll = p.nav_attitude_bias_deg * (bias_rng.uniform() < 0.5 ? -1 : 1);
    double bias_pitch = p.nav_attitude_bias_deg * (bias_rng.uniform() < 0.5 ? -1 : 1);
    const double walk = p.nav_attitude_bias_walk_dps * std::sqrt(1.0 / p.fps);
    for (int i = 0; i < n; ++i) {
        OdometryFlightSample s;
        s.t_s = i / p.fps;
        s.bottom = pose_at(s.t_s);
        s.top = pose_at(s.t_s + p.top_delay_s);
        s.top.z_m += kTopAboveBottom_m;
        s.bottom_distance_m = reading(0, s.t_s);
        s.top_distance_m = reading(1, s.t_s + p.top_delay_s);
        // Velocity by a central difference of the true path, into the body frame.
        const double h = 1e-3;
        const Pose a = pose_at(s.t_s - h), b = pose_at(s.t_s + h);
        const geom::Vec2 v_world((b.x_m - a.x_m) / (2 * h), (b.y_m - a.y_m) / (2 * h));
        const geom::Vec2 v_level = geom::world_from_heading(s.bottom.yaw_deg).inverse() * v_world;
        NavState& nav = s.nav;
        nav.t_ns = static_cast<TimeNs>(std::llround(s.t_s * 1e9));
        if (i > 0) {
            bias_roll += walk * gaussian(bias_rng);
            bias_pitch += walk * gaussian(bias_rng);
        }
        nav.roll_deg = s.bottom.roll_deg + bias_roll + p.nav_attitude_noise_deg * gaussian(nav_rng);
        nav.pitch_deg =
            s.bottom.pitch_deg + bias_pitch + p.nav_attitude_noise_deg * gaussian(nav_rng);
        nav.yaw_deg = s.bottom.yaw_deg + p.nav_yaw_drift_dps * s.t_s +
                      p.nav_attitude_noise_deg * gaussian(nav_rng);
        nav.vx_mps = v_level.x() + p.nav_velocity_noise_mps * gaussian(nav_rng);
        nav.vy_mps = v_level.y() + p.nav_velocity_noise_mps * gaussian(nav_rng);
        nav.vz_mps = (b.z_m - a.z_m) / (2 * h);
        nav.altitude_m = s.bottom_distance_m;
        out.push_back(s);
    }
    return out;
}

Scene odometry_scene(const OdometryFlightParams& p, std::uint64_t seed) {
    Scene s;
    s.name = "odometry_" + to_string(p.test);
    s.description = "Motion-capture room with taped floor and ceiling (thesis fig. 5.6)";
    s.room.x_min_m = -6;
    s.room.x_max_m = 8;
    s.room.y_min_m = -6;
    s.room.y_max_m = 7;
    s.room.height_m = p.ceiling_m;
    // Black floor with white tape; black cloth with white tape on the ceiling.
    s.room.floor = TextureSpec{TextureKind::Tape, mix_seed(seed, 1), 1.0, {25, 25, 28}};
    s.room.ceiling = TextureSpec{TextureKind::Tape, mix_seed(seed, 2), 2.0, {30, 30, 32}};
    const TextureSpec wall{TextureKind::Concrete, mix_seed(seed, 3), 2.0, {150, 150, 150}};
    s.room.wall_front = s.room.wall_back = s.room.wall_left = s.room.wall_right = wall;
    s.lighting.gain = 1.0;
    s.lighting.vignette = 0.25;
    return s;
}

Expected<OdometryFlightSummary, std::string> write_odometry_flight(const fs::path& dir,
                                                                   const OdometryFlightParams& p,
                                                                   std::uint64_t seed) {
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_empty(dir, ec))
        return Unexpected(dir.string() + " exists and is not empty");
    fs::create_directories(dir / "frames", ec);
    if (!ec && p.top_camera) fs::create_directories(dir / "top", ec);
    if (ec) return Unexpected("cannot create " + dir.string() + ": " + ec.message());

    const Scene scene = odometry_scene(p, seed);
    const gs::CameraCalibration calib = builtin_calibration(CameraId::Bottom);
    auto rb = Renderer::create(scene, calib, CameraKind::Bottom);
    if (!rb) return Unexpected("bottom renderer: " + to_string(rb.error()));
    std::optional<Renderer> rt;
    if (p.top_camera) {
        auto r = Renderer::create(scene, calib, CameraKind::Top);
        if (!r) return Unexpected("top renderer: " + to_string(r.error()));
        rt.emplace(std::move(r).value());
    }

    const std::vector<OdometryFlightSample> samples = odometry_flight_samples(p, seed);
    OdometryFlightSummary sum;
    sum.frames = static_cast<int>(samples.size());
    sum.duration_s = samples.back().t_s;
    std::string frames_csv = dataset::frames_csv_header();
    std::string distances = "frame,bottom_m,top_m\n";
    const std::vector<int> jpeg{cv::IMWRITE_JPEG_QUALITY, p.jpeg_quality};
    cv::Mat img;
    for (std::size_t i = 0; i < samples.size(); ++i) {
        const OdometryFlightSample& s = samples[i];
        if (i > 0)
            sum.path_length_m += std::hypot(s.bottom.x_m - samples[i - 1].bottom.x_m,
                                            s.bottom.y_m - samples[i - 1].bottom.y_m);
        const int fi = static_cast<int>(i);
        auto t0 = std::chrono::steady_clock::now();
        rb->render(s.bottom, img);
        auto t1 = std::chrono::steady_clock::now();
        sum.render_ms += std::chrono::duration<double, std::milli>(t1 - t0).count();
        if (!cv::imwrite((dir / "frames" / frame_name(fi, "jpg")).string(), img, jpeg))
            return Unexpected("cannot write frames/" + frame_name(fi, "jpg"));
        auto t2 = std::chrono::steady_clock::now();
        sum.write_ms += std::chrono::duration<double, std::milli>(t2 - t1).count();
        if (rt) {
            rt->render(s.top, img);
            auto t3 = std::chrono::steady_clock::now();
            sum.render_ms += std::chrono::duration<double, std::milli>(t3 - t2).count();
            if (!cv::imwrite((dir / "top" / frame_name(fi, "jpg")).string(), img, jpeg))
                return Unexpected("cannot write top/" + frame_name(fi, "jpg"));
            sum.write_ms +=
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t3)
                    .count();
        }
        dataset::FrameRow row;
        row.frame = fi;
        row.nav = s.nav;
        row.gt = {s.bottom.x_m, s.bottom.y_m, s.bottom.z_m, s.bottom.yaw_deg};
        frames_csv += dataset::frames_csv_row(row);
        distances += std::to_string(fi) + ',' + fixed3(s.bottom_distance_m) + ',' +
                     (p.top_camera ? fixed3(s.top_distance_m) : std::string()) + '\n';
    }

    dataset::DatasetInfo info;
    info.camera = CameraId::Bottom;
    info.width = calib.width;
    info.height = calib.height;
    info.fps = p.fps;
    info.frames = sum.frames;
    info.images = "frames";
    info.calibration = calib;
    std::ostringstream imu;
    imu << ", navdata attitude noise " << p.nav_attitude_noise_deg << " deg";
    if (p.nav_attitude_bias_deg > 0 || p.nav_attitude_bias_walk_dps > 0)
        imu << ", bias " << p.nav_attitude_bias_deg << " deg walking "
            << p.nav_attitude_bias_walk_dps << " deg/sqrt(s)";
    info.source = "simulated: odometry test " + to_string(p.test) + ", seed " +
                  std::to_string(seed) + (p.top_camera ? ", two cameras" : "") + imu.str();
    std::ostringstream top_json;
    top_json.precision(10);
    top_json << "{\n  \"camera\": \"top\",\n  \"width\": " << calib.width
             << ",\n  \"height\": " << calib.height << ",\n  \"fx\": " << calib.fx
             << ",\n  \"fy\": " << calib.fy << ",\n  \"cx\": " << calib.cx
             << ",\n  \"cy\": " << calib.cy << ",\n  \"dist\": [" << calib.dist[0] << ", "
             << calib.dist[1] << ", " << calib.dist[2] << ", " << calib.dist[3] << ", "
             << calib.dist[4]
             << "],\n  \"source\": \"simulated upward camera (bottom model)\"\n}\n";
    for (auto [name, text] : std::array<std::pair<const char*, std::string>, 4>{
             {{"flight.json", dataset::flight_json_text(info)},
              {"frames.csv", frames_csv},
              {"distances.csv", distances},
              {"top.json", top_json.str()}}}) {
        if (!p.top_camera && std::string(name) == "top.json") continue;
        if (auto e = write_file_atomic(dir / name, text, name)) return Unexpected(to_string(*e));
    }
    return sum;
}

Expected<TwoCameraExtras, std::string> read_two_camera_extras(const fs::path& dir,
                                                              std::int64_t frames) {
    TwoCameraExtras x;
    std::error_code ec;
    const fs::path top = dir / "top";
    if (fs::is_directory(top, ec)) {
        for (std::int64_t i = 0; i < frames; ++i) {
            const std::string base = frame_name(static_cast<int>(i), "");
            fs::path f;
            for (const char* ext : {"png", "jpg", "jpeg"})
                if (fs::exists(top / (base + ext), ec)) {
                    f = top / (base + ext);
                    break;
                }
            if (f.empty())
                return Unexpected("top/: no image for frame " + std::to_string(i) + " (expected " +
                                  base + "png or .jpg)");
            x.top_images.push_back(f);
        }
    }
    if (fs::exists(dir / "top.json", ec)) {
        auto c = load_calibration_file(dir / "top.json");
        if (!c) return Unexpected(to_string(c.error()));
        x.top_calibration = *c;
    }
    const fs::path dist = dir / "distances.csv";
    if (fs::exists(dist, ec)) {
        auto text = read_text_file(dist, "distances.csv", 256u << 20);
        if (!text) return Unexpected(to_string(text.error()));
        x.bottom_m.assign(std::size_t(frames), kUnknown);
        x.top_m.assign(std::size_t(frames), kUnknown);
        auto t = dataset::csv::Table::parse(std::move(*text), "distances.csv");
        if (!t) return Unexpected(to_string(t.error()));
        const auto cf = t->column("frame"), cb = t->column("bottom_m"), ct = t->column("top_m");
        if (!cf) return Unexpected(std::string("distances.csv line 1: no 'frame' column"));
        // A distance: empty = unknown; else finite and >= 0 (docs/dataset.md 1.1).
        auto distance = [&](std::size_t r,
                            std::optional<std::size_t> c) -> Expected<double, std::string> {
            if (!c) return kUnknown;
            auto v = t->number(r, *c);
            if (!v) return Unexpected(to_string(v.error()));
            if (*v < 0) return Unexpected(to_string(t->error_at(r, *c, "a distance is >= 0")));
            return *v;
        };
        for (std::size_t r = 0; r < t->rows(); ++r) {
            auto fi = t->integer(r, *cf);
            if (!fi) return Unexpected(to_string(fi.error()));
            if (*fi < 0 || *fi >= frames)
                return Unexpected(to_string(
                    t->error_at(r, *cf, "frame " + std::to_string(*fi) + " out of range")));
            auto b = distance(r, cb), tm = distance(r, ct);
            if (!b) return Unexpected(b.error());
            if (!tm) return Unexpected(tm.error());
            x.bottom_m[std::size_t(*fi)] = *b;
            x.top_m[std::size_t(*fi)] = *tm;
        }
    }
    return x;
}

}  // namespace gs::sim
