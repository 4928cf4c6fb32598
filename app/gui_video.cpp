#ifdef GS_HAVE_GUI

// Video view: the classified frame, its decisions and overlay (moved onto the undistorted image
// under the preview), the odometry's view of a bottom-camera frame.

#include "app/gui_adapter.hpp"
#include "app/gui_views.hpp"

#include <cmath>
#include <numbers>

namespace gs::app {

namespace {

std::uint32_t to_rgba(vision::Rgb c, unsigned alpha = 255) {
    return ui::rgba(c.r, c.g, c.b, alpha);
}

}  // namespace

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
                               d.valid ? std::string() : vision::to_string(d.unknown),
                               d.valid && d.approach_only, d.valid ? d.edge_m : kUnknown});
    }
    c.cycle_ms = r.timings.total_ms;

    ui::Overlay& ov = c.overlay;
    ov = ui::Overlay{};
    for (std::size_t i = 0; i < r.overlay.bars.size() && i < 3; ++i) {
        const auto& b = r.overlay.bars[i];
        const vision::RegionDecision& d = r.regions[i];
        ov.regions.push_back({kRegionNames[i], b.rect.x, b.rect.x + b.rect.width,
                              d.valid && d.unsafe, d.score, d.threshold, d.valid,
                              d.valid ? std::string() : vision::to_string(d.unknown),
                              d.valid && d.approach_only});
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

    plot_series(r, fit_window, c.plots);
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

}  // namespace gs::app

#endif  // GS_HAVE_GUI
