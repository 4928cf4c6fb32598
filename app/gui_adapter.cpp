#ifdef GS_HAVE_GUI

#include "app/gui_adapter.hpp"

#include "drone/protocol/navdata_layout.hpp"
#include "drone/sim/scenarios.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <type_traits>

namespace gs::app {

namespace {

ui::LinkState to_ui(link::ConnectionState s) {
    switch (s) {
        case link::ConnectionState::Disconnected:
            return ui::LinkState::Disconnected;
        case link::ConnectionState::Bootstrapping:
        case link::ConnectionState::Configuring:
            return ui::LinkState::Connecting;
        case link::ConnectionState::Connected:
            return ui::LinkState::Connected;
        case link::ConnectionState::LinkLost:
            return ui::LinkState::Lost;
    }
    return ui::LinkState::Disconnected;
}

std::uint32_t to_rgba(vision::Rgb c, unsigned alpha = 255) {
    return ui::rgba(c.r, c.g, c.b, alpha);
}

double age_ms(TimeNs now, TimeNs last) {
    return last > 0 ? ns_to_ms(now - last) : kUnknown;
}

// One navdata field as text: numbers with %g, arrays as [a, b, ...].
template <class T>
void format_field(std::string& out, const T& v) {
    if constexpr (std::is_same_v<T, bool>) {
        out += v ? "1" : "0";
    } else if constexpr (std::is_floating_point_v<T>) {
        char b[32];
        std::snprintf(b, sizeof b, "%.6g", static_cast<double>(v));
        out += b;
    } else if constexpr (std::is_arithmetic_v<T>) {
        out += std::to_string(+v);
    } else if constexpr (std::is_same_v<T, protocol::navdata::GpsChannel>) {
        out += "{sat " + std::to_string(+v.sat) + ", cn0 " + std::to_string(+v.cn0) + "}";
    } else {
        out += '[';
        bool first = true;
        for (const auto& e : v) {
            if (!first) out += ", ";
            first = false;
            format_field(out, e);
        }
        out += ']';
    }
}

// Every field of every option present, grouped by option, in wire order, names with units.
void navdata_fields(const protocol::navdata::Navdata& nd, std::vector<ui::TelemetryField>& out) {
    out.clear();
    protocol::navdata::layout::for_each_option_type([&]<class T>(std::type_identity<T>) {
        using S = protocol::navdata::layout::Spec<T>;
        const auto& opt = nd.*S::member;
        if (!opt) return;
        S::fields(*opt, [&](std::size_t, std::string_view name, std::string_view unit,
                            const auto& field) {
            ui::TelemetryField f;
            f.group = std::string(S::name);
            f.name = std::string(name);
            if (!unit.empty()) f.name += " [" + std::string(unit) + "]";
            format_field(f.value, field);
            out.push_back(std::move(f));
        });
    });
}

const vision::PlotSeries* find(const vision::FrameResult& r, std::string_view name) {
    return r.find_series(name);
}

bool any_finite(const vision::PlotSeries& s) {
    for (std::size_t i = 0; i < s.points.size(); ++i)
        if (std::isfinite(s.points[i].y)) return true;
    return false;
}

ui::SeriesData series_data(const vision::PlotSeries& ps, std::string name) {
    ui::SeriesData sd;
    sd.name = std::move(name);
    const std::size_t n = ps.points.size();
    sd.x.resize(n);
    sd.y.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        sd.x[i] = ps.points[i].x;
        sd.y[i] = ps.points[i].y;
    }
    return sd;
}

// Last finite value of a series (a threshold drawn as a line).
double last_value(const vision::PlotSeries* ps) {
    if (!ps) return kUnknown;
    for (std::size_t i = ps->points.size(); i-- > 0;)
        if (std::isfinite(ps->points[i].y)) return ps->points[i].y;
    return kUnknown;
}

constexpr std::array<const char*, 3> kRegionNames = {"left", "center", "right"};
constexpr std::array<const char*, 3> kSeriesPrefix = {"left", "centre", "right"};

// Overlay primitives (raw, distorted pixels) moved onto the undistorted image (same camera
// matrix, the Undistorter's view); the region bar stays across the image top.
void undistort_overlay(ui::Overlay& ov, const CameraCalibration& cal) {
    std::vector<cv::Point2f> pts;
    for (const auto& p : ov.center_points) pts.emplace_back(p.p.x, p.p.y);
    for (const auto& t : ov.trajectories)
        for (const auto& p : t.points) pts.emplace_back(p.x, p.y);
    for (const auto& l : ov.boundaries) {
        pts.emplace_back(l.a.x, l.a.y);
        pts.emplace_back(l.b.x, l.b.y);
    }
    if (pts.empty()) return;
    cal.undistort_points(pts, pts);
    std::size_t k = 0;
    auto next = [&] {
        const cv::Point2f& q = pts[k++];
        return ui::Point2f{q.x, q.y};
    };
    for (auto& p : ov.center_points) p.p = next();
    for (auto& t : ov.trajectories)
        for (auto& p : t.points) p = next();
    for (auto& l : ov.boundaries) {
        l.a = next();
        l.b = next();
    }
}

// The odometry's sample and path as the window shows them (reusing the view's vectors).
void odometry_view(const OdometryOutput& o, ui::OdometryView& v) {
    v.active = o.active;
    if (!o.active) {
        v.path_x.clear();
        v.path_y.clear();
        return;
    }
    const vision::OdometrySample& s = o.sample;
    v.run = o.run;
    v.sample = s.index;
    v.valid = s.valid;
    v.status = vision::to_string(s.bottom.status);
    v.corners = s.bottom.corners;
    v.tracked = s.bottom.tracked;
    v.inliers = s.bottom.inliers;
    v.distance_m = o.distance_m;
    v.dx_m = s.out.forward_m;
    v.dy_m = s.out.right_m;
    v.dyaw_deg = s.out.yaw_deg;
    v.dyaw_navdata_deg = s.yaw_navdata_deg;
    v.spike_zeroed = s.out.spike_zeroed;
    v.rotation_gated = s.out.rotation_gated;
    v.ms = s.total_ms;
    v.ms_mean = o.ms_mean;
    v.samples = o.samples;
    v.invalid = o.invalid;
    v.spike_samples = o.spike_zeroed;
    v.gated_samples = o.rotation_gated;
    v.x_m = s.pose.x_m;
    v.y_m = s.pose.y_m;
    v.yaw_deg = s.pose.yaw_deg;
    v.nav_x_m = s.nav_path_valid ? s.nav_pose.x_m : kUnknown;
    v.nav_y_m = s.nav_path_valid ? s.nav_pose.y_m : kUnknown;
    v.start_t_s = static_cast<double>(o.start_t_ns) * 1e-9;
    v.path_x.resize(o.path.size());
    v.path_y.resize(o.path.size());
    for (std::size_t i = 0; i < o.path.size(); ++i) {
        v.path_x[i] = o.path[i].y_m;  // right
        v.path_y[i] = o.path[i].x_m;  // forward
    }
}

void classifier_output(const PipelineOutput& o, ui::ClassifierOutput& c, double fit_window) {
    const vision::FrameResult& r = o.result;
    c.decisions.clear();
    for (std::size_t i = 0; i < 3; ++i) {
        const vision::RegionDecision& d = r.regions[i];
        c.decisions.push_back({kRegionNames[i], d.valid && d.unsafe, d.score, d.threshold, d.valid,
                               d.valid ? std::string() : vision::to_string(d.unknown)});
    }
    c.cycle_ms = r.timings.total_ms;

    ui::Overlay& ov = c.overlay;
    ov = ui::Overlay{};
    for (std::size_t i = 0; i < r.overlay.bars.size() && i < 3; ++i) {
        const auto& b = r.overlay.bars[i];
        const vision::RegionDecision& d = r.regions[i];
        ov.regions.push_back({kRegionNames[i], b.rect.x, b.rect.x + b.rect.width,
                              d.valid && d.unsafe, d.score, d.threshold, d.valid,
                              d.valid ? std::string() : vision::to_string(d.unknown)});
    }
    for (const auto& l : r.overlay.lines)
        ov.boundaries.push_back(
            {{l.a.x, l.a.y}, {l.b.x, l.b.y}, to_rgba(l.colour, 150), l.thickness_px});
    for (const auto& p : r.overlay.points) {
        if (p.filled) {
            ov.center_points.push_back({{p.p.x, p.p.y}, to_rgba(p.colour), p.radius_px * 0.8f});
            continue;
        }
        // A tracked point coloured by its score: a small ring in the "trajectories" layer.
        ui::OverlayPolyline ring;
        constexpr int kSides = 8;
        for (int k = 0; k <= kSides; ++k) {
            const double a = 2.0 * std::numbers::pi * k / kSides;
            ring.points.push_back({p.p.x + p.radius_px * static_cast<float>(std::cos(a)),
                                   p.p.y + p.radius_px * static_cast<float>(std::sin(a))});
        }
        ring.rgba = to_rgba(p.colour, 230);
        ring.thickness = 1.5f;
        ov.trajectories.push_back(std::move(ring));
    }

    // Plots: the named ones the plots window knows, then any other series.
    c.plots.clear();
    std::vector<const vision::PlotSeries*> used;
    auto take = [&](std::string_view name) {
        const vision::PlotSeries* ps = find(r, name);
        if (ps) used.push_back(ps);
        return ps;
    };
    ui::PlotData scores{"scores", "Region scores", "frame", "score", {}, {}};
    for (std::size_t i = 0; i < 3; ++i) {
        const std::string p = kSeriesPrefix[i];
        if (const auto* s = take(p + ".score"))
            scores.series.push_back(series_data(*s, kRegionNames[i]));
        const double thr = last_value(take(p + ".threshold"));
        if (!std::isfinite(thr)) continue;
        // Left and right usually share one threshold: one "side" line instead of two labels.
        bool merged = false;
        for (auto& t : scores.thresholds)
            if (std::fabs(t.y - thr) < 1e-9) {
                t.name = i == 2 && t.name == "left threshold" ? "side threshold" : t.name;
                merged = true;
            }
        if (!merged)
            scores.thresholds.push_back({std::string(kRegionNames[i]) + " threshold", thr, 0});
    }
    if (!scores.series.empty()) c.plots.push_back(std::move(scores));

    ui::PlotData scale{"center_scale", "Centre scale", "frame", "ratio", {}, {}};
    // flow: the corridor points' expansion rate, and the homography's when that channel is on.
    const bool rates = find(r, "centre.points_rate") != nullptr;
    if (rates) {
        scale.title = "Centre expansion rate";
        scale.y_label = "1/s";
    }
    for (const char* n : {"centre.scale_raw", "centre.scale_filtered", "centre.scale_fitted",
                          "centre.points_rate", "centre.homography_rate", "centre.rate_raw"})
        if (const auto* s = take(n); s && any_finite(*s))  // a channel switched off stays out
            scale.series.push_back(series_data(*s, std::string(n).substr(7)));
    // The centre threshold, where it shares the plot's units. The thesis classifier flags the
    // centre when the fitted curve's tangent slope exceeds the threshold (per sample): drawn as a
    // line of that slope ending at the newest fitted point, over the fit window (a fitted curve
    // climbing more steeply than it is unsafe). The flow classifier compares the expansion rate
    // (1/s) with it: a horizontal line against its rates.
    const double cthr = last_value(find(r, "centre.threshold"));
    if (std::isfinite(cthr)) {
        const auto* fitted = find(r, "centre.scale_fitted");
        if (rates || find(r, "centre.rate_raw"))
            scale.thresholds.push_back({"centre threshold [1/s]", cthr, 0});
        if (fitted) {
            std::optional<vision::PlotPoint> last;
            for (std::size_t i = fitted->points.size(); i-- > 0;)
                if (std::isfinite(fitted->points[i].y)) {
                    last = fitted->points[i];
                    break;
                }
            if (last) {
                ui::SeriesData th;
                th.name = "threshold slope";
                th.rgba = ui::rgba(235, 65, 55, 230);
                const double w = std::max(2.0, fit_window);
                th.x = {last->x - w, last->x};
                th.y = {last->y - cthr * w, last->y};
                scale.series.push_back(std::move(th));
                char t[96];
                std::snprintf(t, sizeof t, "Centre scale (slope %.4f, thr %.4f)",
                              r.regions[1].score, cthr);
                if (std::isfinite(r.regions[1].score)) scale.title = t;
            }
        }
    }
    if (!scale.series.empty()) c.plots.push_back(std::move(scale));

    ui::PlotData traj{"trajectories_x", "Trajectory x over frames", "frame", "px", {}, {}};
    const std::size_t n_traces = std::min<std::size_t>(r.traces.size(), 16);
    for (std::size_t k = 0; k < n_traces; ++k) {
        const vision::TrajectoryTrace& t = r.traces[k];
        ui::SeriesData sd;
        sd.name = "track " + std::to_string(t.id);
        for (int i = 0; i < t.count; ++i) {
            sd.x.push_back(static_cast<double>(t.last_frame - t.count + 1 + i));
            sd.y.push_back(static_cast<double>(t.x[static_cast<std::size_t>(i)]));
        }
        traj.series.push_back(std::move(sd));
    }
    if (!traj.series.empty()) c.plots.push_back(std::move(traj));

    ui::PlotData more{"classifier_other", "Other classifier series", "frame", "", {}, {}};
    for (const auto& ps : r.series)
        if (std::find(used.begin(), used.end(), &ps) == used.end() && ps.points.size() > 0)
            more.series.push_back(series_data(ps, ps.name));
    if (!more.series.empty()) c.plots.push_back(std::move(more));
}

}  // namespace

double GuiAdapter::SlidingRate::update(std::uint64_t count, TimeNs now) {
    constexpr TimeNs kWindow = ms_to_ns(1000);
    if (size > 0) {
        const auto& newest = ring[(head + kSamples - 1) % kSamples];
        if (count < newest.second || now < newest.first) reset();  // a new stream or source
    }
    ring[head] = {now, count};
    head = (head + 1) % kSamples;
    size = std::min(size + 1, kSamples);
    // The oldest sample inside the window (or the oldest kept, if the window is not full yet).
    std::size_t oldest = (head + kSamples - size) % kSamples;
    for (std::size_t k = 0; k + 1 < size; ++k) {
        const std::size_t i = (head + kSamples - size + k) % kSamples;
        const std::size_t next = (i + 1) % kSamples;
        if (now - ring[next].first >= kWindow)
            oldest = next;
        else
            break;
    }
    const TimeNs span = now - ring[oldest].first;
    if (span < ms_to_ns(250)) return hz;  // too short to say yet: keep the last value
    hz = static_cast<double>(count - ring[oldest].second) * 1e9 / static_cast<double>(span);
    return hz;
}

GuiAdapter::GuiAdapter(Session& session, Clock& clock)
    : session_(session), clock_(clock), scenarios_(sim::list_scenes()) {}

void GuiAdapter::note(std::string m, ui::LogLevel level) {
    messages_.push_back({std::move(m), level, static_cast<double>(clock_.now_ns()) * 1e-9});
    while (messages_.size() > kMaxMessages) messages_.pop_front();
    messages_changed_ = true;
}

void GuiAdapter::on_source_change() {
    nav_valid_ = false;
    replay_nav_valid_ = false;
    out_.reset();
    shown_out_ = nullptr;
    manual_ = false;
    last_pilot_ = {};
    camera_channel_ = 0;
    shown_camera_ = CameraId::Front;
    start_camera_sent_ = false;
    at_rate_.reset();
    nav_bytes_rate_.reset();
    video_bytes_rate_.reset();
    at_bytes_rate_.reset();
    nav_rate_.reset();
    video_rate_.reset();
    replay_rate_.reset();
    last_video_frame_ns_ = 0;
    video_connected_ = false;
    prev_emergency_bit_ = emergency_commanded_ = false;
    emergency_sent_ns_ = 0;
    config_read_ = false;
    config_values_.clear();
    config_requested_ = false;
    shown_source_id_ = source_.id;
}

void GuiAdapter::fill_link(ui::GuiSnapshot& s, TimeNs now) {
    const link::LinkStatus st = source_.link->status();
    s.connection.state = to_ui(st.state);
    s.connection.reason = st.reason;
    if (start_channel_ >= 0 && !start_camera_sent_ &&
        st.state == link::ConnectionState::Connected) {
        start_camera_sent_ = true;
        camera_channel_ = start_channel_;
        command(link::SwitchCamera{start_channel_});
    }

    ui::StreamHealth& n = s.link.navdata;
    n = ui::StreamHealth{};
    n.active = source_.link->running();
    n.rate_hz = nav_rate_.update(st.navdata.accepted, now);
    n.age_ms = age_ms(st.now_ns, st.navdata.last_ns);
    s.link.expected_navdata_hz = kUnknown;
    if (nav_valid_ && nav_.state.drone_state)
        s.link.expected_navdata_hz = (*nav_.state.drone_state & (1u << 10)) ? 15.0 : 200.0;
    n.packets = st.navdata.accepted;
    n.gaps = st.machine.sequence_gaps;
    n.drops = st.machine.out_of_order + st.navdata.foreign_dropped + st.navdata.oversize;
    n.checksum_failures = st.navdata.checksum_failures;
    n.decode_errors = st.navdata.parse_errors;
    // Bytes counted by the link, as a rate over the same sliding window as the packets (the
    // link's own per-second figure reads 0 until its first full second).
    n.bytes_per_s = nav_bytes_rate_.update(st.navdata.bytes, now);

    ui::StreamHealth& v = s.link.video;
    v = ui::StreamHealth{};
    v.active = st.video.connected;
    v.rate_hz = video_rate_.update(st.video.decoded, now);
    v.age_ms = age_ms(st.now_ns, st.video.last_frame_ns);
    last_video_frame_ns_ = st.video.last_frame_ns;
    video_connected_ = st.video.connected;
    v.bytes_per_s = video_bytes_rate_.update(st.video.bytes, now);
    v.packets = st.video.decoded;
    v.gaps = st.video.frame_gaps;
    v.drops = out_ ? out_->frames_dropped : 0;  // frames the classifier could not keep up with
    // Frames in a codec other than H.264 cannot be decoded either (the reason is in last_error).
    v.decode_errors = st.video.decode_errors + st.video.unsupported_codec_frames;
    v.idr_waits = st.video.idr_waits;

    ui::StreamHealth& a = s.link.at;
    a = ui::StreamHealth{};
    a.active = source_.link->running();
    a.rate_hz = at_rate_.update(st.at.counters.datagrams, now);
    a.age_ms = st.at.period_ms_last;
    a.packets = st.at.counters.datagrams;
    a.bytes_per_s = at_bytes_rate_.update(st.at.bytes_sent, now);
    a.drops = st.at.counters.stale_moves_dropped;
    a.decode_errors = st.at.send_errors + st.at.counters.encode_errors;
}

void GuiAdapter::fill_telemetry(ui::GuiSnapshot& s) {
    ui::Telemetry& t = s.telemetry;
    if (source_.link) {
        if (source_.link->navdata().read_if_newer(nav_gen_, nav_)) {
            nav_valid_ = true;
            nav_dirty_ = true;
        }
        t.valid = nav_valid_;
        t.battery_low_pct = source_.link->config_used().min_takeoff_battery_pct;
        if (!nav_valid_) {
            t.fields.clear();
            t.state.reset();
            t.ctrl_state.clear();
            return;
        }
        t.nav = nav_.state;
        if (nav_dirty_) {
            navdata_fields(nav_.data, t.fields);
            nav_dirty_ = false;
        }
        t.age_ms = age_ms(clock_.now_ns(), nav_.recv_ns);
        t.stale = known(t.age_ms) && t.age_ms > ui::kStaleAfterMs;
    } else if (source_.kind == SessionSource::Replay) {
        if (session_.replay_nav().read_if_newer(rnav_gen_, replay_nav_)) replay_nav_valid_ = true;
        t.valid = replay_nav_valid_;
        t.nav = replay_nav_;
        t.fields.clear();
        if (!replay_nav_valid_) return;
        auto num = [&](const char* name, double v, const char* unit) {
            char b[48];
            std::snprintf(b, sizeof b, "%.3f", v);
            t.fields.push_back({"dataset", std::string(name) + " [" + unit + "]",
                                std::isfinite(v) ? b : "unknown"});
        };
        num("roll", replay_nav_.roll_deg, "deg");
        num("pitch", replay_nav_.pitch_deg, "deg");
        num("yaw", replay_nav_.yaw_deg, "deg");
        num("vx", replay_nav_.vx_mps, "m/s");
        num("vy", replay_nav_.vy_mps, "m/s");
        num("vz", replay_nav_.vz_mps, "m/s");
        num("altitude", replay_nav_.altitude_m, "m");
        num("battery", replay_nav_.battery_pct, "%");
        t.age_ms = kUnknown;  // a recording is not live: nothing goes stale
        t.stale = false;
    } else {
        t = ui::Telemetry{};
        return;
    }
    if (t.nav.drone_state)
        t.state = ui::DroneStateBits::from_raw(*t.nav.drone_state);
    else
        t.state.reset();
    t.ctrl_state = t.nav.ctrl_state ? ui::ctrl_state_name(*t.nav.ctrl_state) : std::string{};
    // Was the emergency the drone reports commanded from here? Yes when its bit rose within a
    // few seconds of our Emergency; a cut-out nobody asked for is a fault (Why not flying).
    const bool bit = source_.link && t.state && t.state->emergency;
    if (bit && !prev_emergency_bit_)
        emergency_commanded_ =
            emergency_sent_ns_ > 0 && clock_.now_ns() - emergency_sent_ns_ < ms_to_ns(3000);
    if (!bit) emergency_commanded_ = false;
    prev_emergency_bit_ = bit;
    t.emergency_commanded = emergency_commanded_;
}

void GuiAdapter::fill_output(ui::GuiSnapshot& s) {
    std::shared_ptr<const PipelineOutput> o;
    if (session_.output().read_if_newer(out_gen_, o) && o && o->source_id == source_.id)
        out_ = std::move(o);
    if (session_.classifier().read_if_newer(cls_gen_, cls_)) {
        if (!cls_.error.empty()) note("classifier: " + cls_.error);
    }
    ui::ClassifierOutput& c = s.classifier;
    c.available = cls_.available;
    c.active = cls_.active;
    c.params.clear();
    for (const auto& p : cls_.params)
        c.params.push_back({p.info.name, p.info.value, p.info.min, p.info.max, p.default_value,
                            p.info.type != vision::ParamType::Real, p.info.description});

    ui::VideoFrame& v = s.video;
    // Rate and age of the newest frame: measured every window frame, so a stalled stream shows
    // 0 fps and its age growing (the frame itself is only rebuilt when a new one comes).
    const bool live = source_.kind == SessionSource::Drone || source_.kind == SessionSource::Sim;
    const TimeNs now = clock_.now_ns();
    double fps = kUnknown, vage = kUnknown;
    if (live) {
        fps = s.link.video.rate_hz;
        vage = age_ms(now, last_video_frame_ns_);
    } else if (source_.kind == SessionSource::Replay) {
        fps = replay_rate_.update(session_.frames_processed(), now);
    }
    const bool stale = live && out_ && known(vage) && vage > ui::kStaleAfterMs;
    if (!out_) {
        shown_out_ = nullptr;
        v = ui::VideoFrame{};
        c.decisions.clear();
        c.overlay = ui::Overlay{};
        c.plots.clear();
        c.cycle_ms = kUnknown;
        c.not_running.clear();
        s.odometry.active = false;
        s.odometry.path_x.clear();
        s.odometry.path_y.clear();
        return;
    }
    v.fps = fps;
    v.age_ms = vage;
    v.stale = stale;
    // Redone when a new frame arrives, the preview is switched, or the calibration changes.
    if (out_.get() == shown_out_ && undistort_ == shown_undistort_ &&
        calib_gen_ == shown_calib_gen_ && v.index == out_->frame.index)
        return;
    shown_out_ = out_.get();
    shown_undistort_ = undistort_;
    shown_calib_gen_ = calib_gen_;
    v.bgr = out_->frame.image;  // shared, never rewritten by the pipeline
    v.index = out_->frame.index;
    v.t_ns = out_->frame.t_ns;
    v.latency_ms = out_->latency_ms;
    v.camera = to_string(out_->camera);
    // The C key asks for the other camera than the one the video comes from.
    if (out_->camera != shown_camera_) {
        shown_camera_ = out_->camera;
        camera_channel_ = out_->camera == CameraId::Bottom ? 1 : 0;
    }
    v.undistorted = false;
    v.undistort_note.clear();
    double fit_window = 30;
    for (const auto& p : cls_.params)
        if (p.info.name == "fit_window") fit_window = p.info.value;
    classifier_output(*out_, c, fit_window);
    c.not_running.clear();
    if (out_->camera == CameraId::Bottom) {
        // No region is "clear" when none was looked at.
        c.not_running =
            "not run: the video is from the bottom camera (the obstacle classifier is for the "
            "front camera)";
        c.decisions.clear();
    }
    odometry_view(out_->odometry, s.odometry);
    if (!undistort_ || v.bgr.empty()) return;
    if (!calib_.camera.valid()) {
        v.undistort_note = "no calibration to undistort with";
        return;
    }
    const cv::Mat& u = undistorter_.apply(v.bgr);
    if (u.empty()) {
        v.undistort_note = "undistortion failed";
        return;
    }
    cv::Mat& buf = undistorted_[static_cast<std::size_t>(undistorted_next_)];
    undistorted_next_ = 1 - undistorted_next_;
    u.copyTo(buf);
    v.bgr = buf;
    v.undistorted = true;
    shown_cal_ = calib_.camera;
    if (shown_cal_.width != buf.cols || shown_cal_.height != buf.rows)
        shown_cal_ = shown_cal_.scaled_to(buf.cols, buf.rows);
    undistort_overlay(c.overlay, shown_cal_);
}

void GuiAdapter::fill_calibration(ui::GuiSnapshot& s) {
    session_.calibration_mode().read_if_newer(mode_gen_, mode_);
    const vision::CalibrationModeState& m = mode_;
    ui::CalibrationView& cv = s.calibration;
    cv.active = m.active;
    cv.board_cols = m.board.cols;
    cv.board_rows = m.board.rows;
    cv.square_m = m.board.square_m;
    cv.auto_capture = m.auto_capture;
    cv.save_path = m.save_path;

    using vision::ViewCheck;
    const bool current = m.active && m.frame >= 0 && m.source_id == source_.id && out_;
    cv.frame = current ? m.frame : -1;
    cv.detections = m.detections;
    cv.detect_ms = m.detect_ms;
    cv.board_found =
        current && (m.check == ViewCheck::AddsCoverage || m.check == ViewCheck::NoNewCoverage);
    cv.adds_coverage = current && m.check == ViewCheck::AddsCoverage;
    cv.new_cells = current ? m.new_cells : 0;
    char buf[192];
    if (!m.active) {
        cv.status = m.result_error.empty() ? "calibration mode off" : m.result_error;
    } else if (!current) {
        cv.status = "waiting for video";
    } else {
        switch (m.check) {
            case ViewCheck::None:
                cv.status = "waiting for video";
                break;
            case ViewCheck::AddsCoverage:
                std::snprintf(buf, sizeof buf, "board found: +%d cells, capture it", m.new_cells);
                cv.status = buf;
                break;
            case ViewCheck::NoNewCoverage:
                cv.status = "board found, adds no coverage: move it to an uncovered area";
                break;
            case ViewCheck::NotFound:
                std::snprintf(buf, sizeof buf,
                              "no %dx%d board found (inner corners; the whole board in view)",
                              m.board.cols, m.board.rows);
                cv.status = buf;
                break;
            case ViewCheck::Blurry:
                cv.status = "board blurry: hold it still";
                break;
            case ViewCheck::SizeMismatch:
                cv.status = "frame size differs from the kept views";
                break;
            case ViewCheck::EmptyImage:
                cv.status = "empty frame";
                break;
        }
    }
    // Corners in pixels of the frame shown (moved onto the undistorted image under the preview).
    cv.corners.clear();
    if (current && (cv.board_found || m.check == ViewCheck::Blurry) &&
        m.image_size.width == out_->frame.image.cols &&
        m.image_size.height == out_->frame.image.rows) {
        std::vector<cv::Point2f> pts = m.corners;
        if (s.video.undistorted && !pts.empty()) shown_cal_.undistort_points(pts, pts);
        for (const auto& p : pts) cv.corners.push_back({p.x, p.y});
    }

    cv.image_w = m.views > 0 ? m.coverage_size.width : m.image_size.width;
    cv.image_h = m.views > 0 ? m.coverage_size.height : m.image_size.height;
    cv.grid_cols = m.grid_cols;
    cv.grid_rows = m.grid_rows;
    cv.coverage = m.coverage;
    cv.coverage_fraction = m.coverage_fraction;
    cv.corner_regions = m.corner_regions;

    cv.views = m.views;
    cv.min_views = m.min_views;
    cv.has_result = m.has_result;
    cv.rms_px = m.has_result ? m.rms_px : kUnknown;
    cv.fx = m.has_result ? m.camera.fx : kUnknown;
    cv.fy = m.has_result ? m.camera.fy : kUnknown;
    cv.cx = m.has_result ? m.camera.cx : kUnknown;
    cv.cy = m.has_result ? m.camera.cy : kUnknown;
    cv.dist = m.has_result ? m.camera.dist : std::array<double, 5>{};
    cv.result_error = m.active ? m.result_error : std::string{};
    cv.captures = m.captures;
    cv.last_capture_kept = m.last_capture_kept;
    cv.last_capture = m.last_capture;
    cv.saves = m.saves;
    cv.saved_path = m.saved_path;
    cv.save_error = m.save_error;
    cv.applied = !m.saved_path.empty() && calib_.origin == m.saved_path;
    const CameraCalibration& u = calib_.camera;
    std::snprintf(buf, sizeof buf, "fx %.1f fy %.1f cx %.1f cy %.1f k1 %.3f, %dx%d", u.fx, u.fy,
                  u.cx, u.cy, u.dist[0], u.width, u.height);
    cv.in_use = std::string(buf) + " (" + calib_.origin + ")";
}

void GuiAdapter::poll_results() {
    for (auto it = pending_.begin(); it != pending_.end();) {
        if (it->result.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
            ++it;
            continue;
        }
        const link::CommandResult r = it->result.get();
        ui::ConfigWrite* found = nullptr;
        for (auto& w : config_writes_)
            if (it->config_write != 0 && w.id == it->config_write) found = &w;
        if (found) {
            ui::ConfigWrite& w = *found;
            config_dirty_ = true;
            w.detail = r.reason;
            switch (r.code) {
                case link::ResultCode::Sent:
                    w.state = ui::ConfigWriteState::Confirmed;
                    break;
                case link::ResultCode::Rejected:
                    // Refused before it was sent, or acknowledged and then read back otherwise.
                    w.state = r.reason.find("reports") != std::string::npos ||
                                      r.reason.find("has no key") != std::string::npos
                                  ? ui::ConfigWriteState::Ignored
                                  : ui::ConfigWriteState::Refused;
                    break;
                case link::ResultCode::Timeout:
                    w.state = ui::ConfigWriteState::TimedOut;
                    break;
                case link::ResultCode::NotConnected:
                    w.state = ui::ConfigWriteState::NotConnected;
                    break;
            }
            note(
                w.key + " = " + w.value + ": " + ui::to_string(w.state) +
                    (r.reason.empty() ? "" : " (" + r.reason + ")"),
                w.state == ui::ConfigWriteState::Confirmed ? ui::LogLevel::Ok : ui::LogLevel::Warn);
        } else if (!r.ok()) {
            // "take-off rejected: battery 12 % is below the 20 % take-off minimum"
            note(it->what + " " + link::to_string(r.code) +
                     (r.reason.empty() ? "" : ": " + r.reason),
                 r.code == link::ResultCode::Rejected ? ui::LogLevel::Warn : ui::LogLevel::Error);
        } else if (!it->ok_text.empty()) {
            note(it->ok_text, ui::LogLevel::Ok);
        } else if (!r.reason.empty()) {
            note(it->what + ": " + r.reason);
        }
        it = pending_.erase(it);
    }
}

// What the session is doing now, in words, as it happens: starting the virtual drone, connecting,
// configuring, waiting for video.
void GuiAdapter::fill_activity(ui::GuiSnapshot& s, const OpeningInfo& op, bool pending) {
    ui::ConnectionInfo& c = s.connection;
    c.opening = pending;
    c.activity.clear();
    if (pending) {
        switch (op.kind) {
            case SessionSource::Sim:
                c.source = ui::SourceKind::Sim;
                c.scenario = op.what;
                c.activity = "Starting virtual drone '" + op.what + "'...";
                break;
            case SessionSource::Drone:
                c.source = ui::SourceKind::Drone;
                c.address = op.what;
                c.activity = "Connecting to " + op.what + "...";
                break;
            case SessionSource::Replay:
                c.source = ui::SourceKind::Replay;
                c.activity = "Opening replay " + op.what + "...";
                break;
            case SessionSource::None:
                break;
        }
        // Whatever was shown before is going: say what comes, not what was.
        if (op.kind == SessionSource::Sim || op.kind == SessionSource::Drone)
            c.state = ui::LinkState::Connecting;
        c.reason = c.activity;
        return;
    }
    if (source_.kind != SessionSource::Drone && source_.kind != SessionSource::Sim) return;
    const std::string who = source_.kind == SessionSource::Sim
                                ? "the virtual drone"
                                : (source_.address.empty() ? "the drone" : source_.address);
    switch (c.state) {
        case ui::LinkState::Connecting:
            c.activity = c.reason.rfind("writing", 0) == 0 || c.reason.rfind("configured", 0) == 0
                             ? "Configuring " + who + "..."
                             : "Connecting to " + who + "...";
            break;
        case ui::LinkState::Lost:
            c.activity = "Link lost: waiting for " + who + "...";
            break;
        case ui::LinkState::Connected:
            if (source_.link && source_.link->config_used().video && !out_)
                c.activity = "Waiting for video...";
            break;
        default:
            break;
    }
}

// Drone -> Settings: the configuration as read back, and what became of each write.
void GuiAdapter::fill_config(ui::GuiSnapshot& s) {
    ui::DroneConfigView& cv = s.config;
    cv.available = source_.link && s.connection.state == ui::LinkState::Connected;
    if (source_.link) {
        protocol::ConfigMap cfg;
        if (source_.link->config().read_if_newer(config_gen_, cfg)) {
            config_values_ = cfg.entries();  // only when a new dump arrived
            config_read_ = true;
        }
        // One read-back when connected, so the window shows the drone's values.
        if (cv.available && !config_requested_ && !config_read_) {
            config_requested_ = true;
            command(link::ReadConfig{});
        }
    }
    cv.read = config_read_;
    if (cv.values.size() != config_values_.size() || cv.writes.size() != config_writes_.size() ||
        config_dirty_) {
        cv.values = config_values_;
        cv.writes = config_writes_;
        config_dirty_ = false;
    }
}

void GuiAdapter::fill(ui::GuiSnapshot& s) {
    const TimeNs now = clock_.now_ns();
    s.now_ns = now;
    if (session_.source().read_if_newer(source_gen_, source_)) {
        if (!source_.error.empty()) note(source_.error, ui::LogLevel::Error);
    }
    if (source_.id != shown_source_id_) on_source_change();
    while (auto m = session_.next_message()) {
        const bool bad =
            m->find("fail") != std::string::npos || m->find("cannot") != std::string::npos ||
            m->find("error") != std::string::npos || m->find("stale") != std::string::npos;
        note(std::move(*m), bad ? ui::LogLevel::Warn : ui::LogLevel::Info);
    }
    poll_results();
    const OpeningInfo opening = session_.opening().latest().value_or(OpeningInfo{});
    const bool opening_pending = opening.count > source_.opens_handled;

    ui::ConnectionInfo& c = s.connection;
    c.scenarios = scenarios_;
    c.address = source_.address;
    c.scenario = source_.scenario;
    switch (source_.kind) {
        case SessionSource::None:
            c.state = ui::LinkState::Disconnected;
            c.source = last_kind_;
            c.reason = source_.error.empty() ? "not connected" : source_.error;
            s.link = ui::LinkHealth{};
            break;
        case SessionSource::Drone:
        case SessionSource::Sim:
            c.source =
                source_.kind == SessionSource::Sim ? ui::SourceKind::Sim : ui::SourceKind::Drone;
            last_kind_ = c.source;
            fill_link(s, now);
            break;
        case SessionSource::Replay:
            c.state = ui::LinkState::Replay;
            c.source = ui::SourceKind::Replay;
            c.reason.clear();
            c.address = source_.path;
            s.link = ui::LinkHealth{};
            break;
    }
    fill_telemetry(s);
    if (session_.calibration().read_if_newer(calib_gen_, calib_))
        undistorter_.set_calibration(calib_.camera);
    fill_output(s);
    fill_calibration(s);
    fill_activity(s, opening, opening_pending);
    fill_config(s);

    session_.replay().read_if_newer(replay_gen_, replay_);
    ui::ReplayStatus& r = s.replay;
    r.open = replay_.open;
    r.path = replay_.path;
    r.frame = std::max<std::int64_t>(replay_.frame, 0);
    r.frame_count = replay_.frame_count;
    r.fps = replay_.fps;
    r.playing = replay_.playing;
    r.speed = replay_.speed;
    r.loop = replay_.loop;
    r.error = replay_.error;
    r.missing_inputs = replay_.missing_inputs;

    if (auto rec = session_.recording().latest()) {
        ui::RecordingStatus& rs = s.recording;
        rs.active = rec->status.recording;
        rs.path = rec->status.path.empty() ? rec->last_path : rec->status.path;
        rs.duration_s = rec->status.duration_s;
        rs.frames = rec->status.frames;
        rs.navdata = rec->status.navdata;
        rs.drops = rec->status.drops;
        rs.disk_bytes = rec->status.bytes;
        rs.disk_free_bytes = rec->disk_free_bytes;
        rs.error = rec->status.error;
    } else {
        s.recording = ui::RecordingStatus{};
    }

    if (s.messages.size() != messages_.size() || messages_changed_) {
        s.messages.assign(messages_.begin(), messages_.end());
        messages_changed_ = false;
    }
}

void GuiAdapter::command(link::Command c, bool report_success, std::string ok_text) {
    const std::string what = link::command_name(c);
    if (!source_.link) {
        note(what + ": not connected to a drone", ui::LogLevel::Warn);
        return;
    }
    Pending p;
    p.what = what;
    p.ok_text = std::move(ok_text);
    p.result = source_.link->submit(std::move(c));
    pending_.push_back(std::move(p));
    if (report_success) note(what + " sent");
}

void GuiAdapter::consume(const ui::Actions& a) {
    for (const auto& n : a.notes) note(n);
    // Flight: emergency first, whatever else happened in the frame.
    if (a.emergency) {
        emergency_sent_ns_ = clock_.now_ns();
        command(link::Emergency{}, true);
    }
    if (a.takeoff) command(link::Takeoff{}, false, "take-off sent");
    if (a.land) command(link::Land{}, false, "land sent");
    if (a.flat_trim) command(link::FlatTrim{}, false, "flat trim sent");
    if (a.calibrate_magnetometer)
        command(link::Calibrate{}, false, "magnetometer calibration started: the drone turns");
    if (a.switch_camera) {
        camera_channel_ = 1 - camera_channel_;
        command(link::SwitchCamera{camera_channel_}, false,
                std::string("camera switched to ") + (camera_channel_ ? "bottom" : "front"));
    }
    // Drone -> Settings: each write with the multiconfiguration ids, read back to confirm.
    for (const auto& [key, value] : a.config_writes) {
        if (!source_.link) {
            note("config " + key + ": not connected to a drone", ui::LogLevel::Warn);
            continue;
        }
        config_writes_.push_back(
            {key, value, ui::ConfigWriteState::Pending, {}, ++config_write_id_});
        if (config_writes_.size() > kMaxConfigWrites) config_writes_.erase(config_writes_.begin());
        Pending p;
        p.what = "config " + key;
        p.config_write = config_write_id_;
        p.result = source_.link->submit(link::SetConfig{key, value, true});
        pending_.push_back(std::move(p));
        config_dirty_ = true;
    }
    if (a.config_read) command(link::ReadConfig{});
    // Manual input wins: while the user steers, every change goes out as Move (the link repeats
    // the current command every 30 ms); letting go sends one Hover.
    if (source_.link) {
        if (a.manual) {
            if (!manual_ || !(a.pilot == last_pilot_)) {
                (void)source_.link->submit(
                    link::Move{a.pilot.roll, a.pilot.pitch, a.pilot.gaz, a.pilot.yaw});
                ++moves_sent_;
            }
            manual_ = true;
            last_pilot_ = a.pilot;
        } else if (manual_) {
            (void)source_.link->submit(link::Hover{});
            ++hovers_sent_;
            manual_ = false;
            last_pilot_ = {};
        }
    }

    if (a.disconnect) session_.request(CloseSource{});
    if (a.connect) {
        if (a.connect->sim)
            session_.request(StartSim{a.connect->scenario, sim_autopilot_});
        else
            session_.request(ConnectDrone{a.connect->address});
    }
    if (a.record_start) session_.request(RecordStart{});
    if (a.record_stop) session_.request(RecordStop{});

    if (a.replay_open) session_.request(OpenReplay{*a.replay_open});
    if (a.replay_play) session_.request(ReplayPlay{true});
    if (a.replay_pause) session_.request(ReplayPlay{false});
    if (a.replay_step != 0) session_.request(ReplayStep{a.replay_step});
    if (a.replay_seek) session_.request(ReplaySeek{*a.replay_seek});
    if (a.replay_speed) session_.request(ReplaySpeed{*a.replay_speed});
    if (a.replay_loop) session_.request(ReplayLoop{*a.replay_loop});

    undistort_ = a.undistort_preview;
    // Auto capture first: the mode keeps it across a (re)start, so the frame on screen when the
    // mode starts is already checked with it.
    if (a.calibration_auto) session_.request(CalibrationAutoCapture{*a.calibration_auto});
    if (a.calibration_start)
        session_.request(CalibrationStart{vision::CalibrationBoard{
            a.calibration_start->cols, a.calibration_start->rows, a.calibration_start->square_m}});
    if (a.calibration_capture) session_.request(CalibrationCapture{});
    if (a.calibration_undo) session_.request(CalibrationUndo{});
    if (a.calibration_reset) session_.request(CalibrationReset{});
    if (a.calibration_save) session_.request(CalibrationSave{});
    if (a.calibration_stop) session_.request(CalibrationStop{});

    if (a.classifier_select) session_.request(SelectClassifier{*a.classifier_select});
    for (const auto& [name, value] : a.param_changes)
        session_.request(SetClassifierParam{name, value});
}

}  // namespace gs::app

#endif  // GS_HAVE_GUI
