#include "ui/demo_snapshot.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace gs::ui {

namespace {

constexpr double kPi = std::numbers::pi;

// Slope colour: small |dx/frame| green, large red (the overlay's "coloured by slope").
std::uint32_t slope_color(double slope) {
    const double t = std::clamp(std::fabs(slope) / 3.0, 0.0, 1.0);
    const auto r = static_cast<unsigned>(60 + 195 * t), g = static_cast<unsigned>(220 - 150 * t);
    return rgba(r, g, 60, 230);
}

void draw_scene(cv::Mat& img, int frame, int w, int h) {
    img.create(h, w, CV_8UC3);
    const int horizon = h * 45 / 100;
    // Sky/wall gradient and floor.
    for (int y = 0; y < h; ++y) {
        const cv::Vec3b c =
            y < horizon ? cv::Vec3b(static_cast<uchar>(150 + y * 60 / horizon),
                                    static_cast<uchar>(140 + y * 50 / horizon),
                                    static_cast<uchar>(120 + y * 40 / horizon))
                        : cv::Vec3b(static_cast<uchar>(70 + (y - horizon) * 40 / (h - horizon)),
                                    static_cast<uchar>(85 + (y - horizon) * 40 / (h - horizon)),
                                    static_cast<uchar>(95 + (y - horizon) * 45 / (h - horizon)));
        img.row(y).setTo(c);
    }
    // Floor tiles converging to the vanishing point, drifting with the frame (forward motion).
    const cv::Point vp(w / 2, horizon);
    for (int i = -8; i <= 8; ++i)
        cv::line(img, vp, cv::Point(w / 2 + i * w / 6, h), cv::Scalar(60, 70, 80), 1, cv::LINE_AA);
    for (int k = 0; k < 8; ++k) {
        const double z = std::fmod(k + frame * 0.05, 8.0) + 1.0;
        const int y = horizon + static_cast<int>((h - horizon) / z);
        cv::line(img, cv::Point(0, y), cv::Point(w, y), cv::Scalar(60, 70, 80), 1, cv::LINE_AA);
    }
    // Obstacle on the left growing as we approach: a box with a texture.
    const double grow = 1.0 + 0.015 * (frame % 120);
    const int bw = static_cast<int>(w * 0.16 * grow), bh = static_cast<int>(h * 0.42 * grow);
    const cv::Rect box(static_cast<int>(w * 0.17) - bw / 2, horizon - bh / 2, bw, bh);
    cv::rectangle(img, box, cv::Scalar(40, 60, 140), cv::FILLED);
    for (int i = 0; i < 6; ++i)
        cv::line(img, {box.x, box.y + i * bh / 6}, {box.x + bw, box.y + i * bh / 6},
                 cv::Scalar(30, 45, 110), 2);
    cv::rectangle(img, box, cv::Scalar(20, 30, 80), 2);
    // A far door in the centre and a pillar on the right.
    cv::rectangle(img, cv::Rect(w / 2 - 18, horizon - 40, 36, 60), cv::Scalar(90, 100, 110),
                  cv::FILLED);
    cv::rectangle(img, cv::Rect(w * 80 / 100, horizon - 70, 26, 120), cv::Scalar(120, 125, 128),
                  cv::FILLED);
    // Top left, under the region bar: the HUD's bottom strip would hide it at the bottom.
    cv::putText(img, "DEMO", {8, h * 16 / 100}, cv::FONT_HERSHEY_SIMPLEX, 0.5,
                cv::Scalar(230, 230, 230), 1, cv::LINE_AA);
}

}  // namespace

void make_demo_snapshot(GuiSnapshot& s, int frame, const DemoOptions& opt) {
    const double t = frame / opt.fps;
    const int w = opt.width, h = opt.height;
    s.now_ns = static_cast<TimeNs>(t * 1e9);

    s.connection.state = LinkState::Connected;
    s.connection.source = SourceKind::Demo;
    s.connection.address = "demo";
    s.connection.reason.clear();
    s.connection.scenarios = {"corridor", "obstacle_left", "obstacle_right", "open_space",
                              "lossy_link"};
    s.connection.scenario = "obstacle_left";

    auto stream = [&](StreamHealth& st, double rate, double age, double bps, std::uint64_t gaps) {
        st.active = true;
        st.rate_hz = rate;
        st.age_ms = age;
        st.bytes_per_s = bps;
        st.packets = static_cast<std::uint64_t>(rate * t);
        st.gaps = gaps;
    };
    stream(s.link.navdata, 200.0, 3.0 + 2.0 * std::sin(t), 200 * 2100, 2);
    stream(s.link.video, opt.fps, 12.0, 1.1e6 / 8, 0);
    stream(s.link.at, 33.3, 10.0, 33.3 * 60, 0);
    s.link.video.idr_waits = 1;

    Telemetry& tm = s.telemetry;
    tm.valid = true;
    NavState& n = tm.nav;
    n.t_ns = s.now_ns;
    n.roll_deg = 4.0 * std::sin(t * 0.9);
    n.pitch_deg = -5.0 + 2.0 * std::sin(t * 0.6);
    n.yaw_deg = std::fmod(30.0 + 12.0 * t + 180.0, 360.0) - 180.0;
    n.vx_mps = 0.6 + 0.1 * std::sin(t);
    n.vy_mps = 0.08 * std::sin(t * 0.9);
    n.vz_mps = 0.05 * std::cos(t * 0.7);
    n.altitude_m = 1.2 + 0.1 * std::sin(t * 0.7);
    n.battery_pct = opt.battery_pct;
    n.seq = static_cast<std::uint32_t>(1000 + frame * 7);
    const std::uint32_t bits = (1u << 0) | (1u << 2) | (1u << 4) | (1u << 5) | (1u << 7) |
                               (1u << 23) | (1u << 24) | (1u << 25) | (1u << 26) | (1u << 27) |
                               (opt.battery_pct < 20 ? (1u << 15) : 0u);
    n.drone_state = bits;
    n.ctrl_state = (3u << 16);
    tm.state = DroneStateBits::from_raw(bits);
    tm.ctrl_state = ctrl_state_name(*n.ctrl_state);
    tm.fields = {{"demo", "ctrl_state", "0x00030000"},
                 {"demo", "vbat_flying_percentage", "67"},
                 {"demo", "theta_mdeg", "-5000.0"},
                 {"demo", "altitude_mm", "1200"},
                 {"raw_measures", "vbat_raw_mV", "11686"},
                 {"raw_measures", "alt_temp_raw_mm", "1198"},
                 {"pwm", "motor1", "152"},
                 {"pwm", "motor2", "149"},
                 {"pwm", "motor3", "151"},
                 {"pwm", "motor4", "150"}};

    VideoFrame& v = s.video;
    draw_scene(v.bgr, frame, w, h);
    v.index = frame;
    v.t_ns = s.now_ns;
    v.fps = opt.fps;
    v.latency_ms = 84.0;
    v.camera = "front";

    // Classifier output: three regions, the flagged ones red.
    ClassifierOutput& c = s.classifier;
    c.available = {"thesis_scale", "thesis_flow_divergence"};
    c.active = "thesis_scale";
    c.cycle_ms = 9.5;
    const float third = static_cast<float>(w) / 3.0f;
    const bool flags[3] = {opt.flag_left, opt.flag_center, opt.flag_right};
    const char* names[3] = {"left", "center", "right"};
    const double scores[3] = {flags[0] ? 1.31 : 0.42, flags[1] ? 1.22 : 0.57,
                              flags[2] ? 1.4 : 0.35};
    c.decisions.clear();
    c.overlay = Overlay{};
    for (int i = 0; i < 3; ++i) {
        c.decisions.push_back({names[i],
                               flags[i],
                               scores[i],
                               1.0,
                               true,
                               {},
                               false,
                               i != 1 && flags[i] ? 0.31 : kUnknown});
        c.overlay.regions.push_back({names[i],
                                     third * static_cast<float>(i),
                                     third * static_cast<float>(i + 1),
                                     flags[i],
                                     scores[i],
                                     1.0,
                                     true,
                                     {}});
    }
    for (int i = 1; i < 3; ++i)
        c.overlay.boundaries.push_back({{third * static_cast<float>(i), 0.0f},
                                        {third * static_cast<float>(i), static_cast<float>(h)},
                                        rgba(255, 255, 255, 140),
                                        1.0f});
    // Trajectories: points flowing outward from the focus of expansion, longer near the obstacle.
    for (int k = 0; k < 36; ++k) {
        OverlayPolyline pl;
        const double ang = 2 * kPi * k / 36.0 + 0.3;
        const double r0 = 30 + 7 * (k % 5);
        const double speed = (std::cos(ang) < -0.3 ? 2.6 : 1.0) * (1.0 + 0.1 * (k % 3));
        for (int j = 0; j < 8; ++j) {
            const double r = r0 + speed * 8.0 * j;
            pl.points.push_back({static_cast<float>(w / 2 + r * std::cos(ang)),
                                 static_cast<float>(h * 0.45 + r * std::sin(ang) * 0.6)});
        }
        pl.rgba = slope_color(speed * std::cos(ang));
        c.overlay.trajectories.push_back(std::move(pl));
    }
    for (int k = 0; k < 24; ++k)
        c.overlay.center_points.push_back({{static_cast<float>(w * 0.2 + k * w * 0.6 / 23),
                                            static_cast<float>(h * 0.45 + 6 * std::sin(k + t))},
                                           rgba(80, 200, 255, 255),
                                           2.5f});
    c.params = {
        {"window_frames", 10, 3, 30, 10, true, "Frames in the trajectory window."},
        {"max_corners", 400, 50, 2000, 400, true, "Features tracked per frame (Shi-Tomasi)."},
        {"center_band_pct", 20, 5, 50, 20, false,
         "Height of the centre band, percent of the image."},
        {"scale_threshold", 1.08, 1.0, 1.5, 1.05, false,
         "Expansion ratio above which the centre is unsafe."},
        {"slope_threshold", 1.0, 0.1, 5.0, 1.0, false,
         "Mean trajectory slope flagging a side region."},
        {"filter_alpha", 0.3, 0.0, 1.0, 0.3, false, "Exponential smoothing of the scale estimate."},
    };

    // Plots over the last 60 frames.
    c.plots.clear();
    const int n_hist = 60;
    PlotData traj{"trajectories_x", "Trajectory x over frames", "frame", "px", {}, {}};
    for (int k = 0; k < 5; ++k) {
        SeriesData sd;
        sd.name = "track " + std::to_string(k + 1);
        for (int j = 0; j < n_hist; ++j) {
            sd.x.push_back(frame - n_hist + j);
            sd.y.push_back(w / 2 + (k - 2) * 60 + (k - 2) * 1.6 * j + 4 * std::sin(j * 0.3 + k));
        }
        traj.series.push_back(std::move(sd));
    }
    c.plots.push_back(std::move(traj));
    PlotData scale{"center_scale", "Centre scale", "frame", "ratio", {}, {{"threshold", 1.05, 0}}};
    SeriesData raw{"raw", {}, {}, 0}, filt{"filtered", {}, {}, 0}, fit{"fitted", {}, {}, 0};
    for (int j = 0; j < n_hist; ++j) {
        const double x = frame - n_hist + j;
        const double base = 1.0 + 0.0006 * j;
        raw.x.push_back(x);
        raw.y.push_back(base + 0.02 * std::sin(j * 1.7) + 0.01 * std::cos(j * 3.1));
        filt.x.push_back(x);
        filt.y.push_back(base + 0.006 * std::sin(j * 0.5));
        fit.x.push_back(x);
        fit.y.push_back(base);
    }
    scale.series = {raw, filt, fit};
    c.plots.push_back(std::move(scale));
    PlotData sc{"scores", "Region scores", "frame", "score", {}, {{"threshold", 1.0, 0}}};
    for (int i = 0; i < 3; ++i) {
        SeriesData sd;
        sd.name = names[i];
        for (int j = 0; j < n_hist; ++j) {
            sd.x.push_back(frame - n_hist + j);
            sd.y.push_back(scores[i] * (0.5 + 0.5 * j / (n_hist - 1)) +
                           0.03 * std::sin(j * 0.8 + i));
        }
        sc.series.push_back(std::move(sd));
    }
    c.plots.push_back(std::move(sc));

    s.recording.active = true;
    s.recording.path = "~/flights/2026-11-22_0640";
    s.recording.duration_s = t + 42.0;
    s.recording.frames = static_cast<std::uint64_t>((t + 42.0) * opt.fps);
    s.recording.navdata = static_cast<std::uint64_t>((t + 42.0) * 200);
    s.recording.disk_bytes = static_cast<std::uint64_t>((t + 42.0) * 160000);
    s.recording.disk_free_bytes = 48e9;
    s.replay = ReplayStatus{};
    s.messages = {{"navdata: configured (full mode)", LogLevel::Info, 1.0},
                  {"video: first IDR after 1 frame", LogLevel::Info, 1.2},
                  {"recording to ~/flights/2026-11-22_0640", LogLevel::Ok, 2.0}};
}

GuiSnapshot demo_no_link() {
    GuiSnapshot s;
    s.connection.state = LinkState::Disconnected;
    s.connection.reason = "not connected";
    s.connection.scenarios = {"corridor", "obstacle_left"};
    return s;
}

GuiSnapshot demo_no_video() {
    GuiSnapshot s;
    make_demo_snapshot(s, 45);
    s.video = VideoFrame{};
    s.link.video = StreamHealth{};
    s.link.video.active = true;
    s.link.video.idr_waits = 12;
    s.classifier.overlay = Overlay{};
    return s;
}

}  // namespace gs::ui
