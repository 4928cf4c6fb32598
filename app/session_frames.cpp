// Frame processing: each frame through the classifier (front camera) or the odometry (bottom
// camera) into a pooled PipelineOutput; live video that stopped republished as unknown.
#include "app/session_current.hpp"

namespace gs::app {

// Both vision stages forget their history (new source, seek, new calibration, camera switch).
void Session::reset_vision() {
    pipeline_.reset();
    odometry_.restart();
}

void Session::process(FrameSample& f, TimeNs recv_ns) {
    Current& c = *cur_;
    update_camera();
    if (c.kind == SessionSource::Replay && !f.image.empty()) {
        cv::Mat buf = c.pool->acquire();
        f.image.copyTo(buf);
        f.image = std::move(buf);
    }
    // Outputs come from a pool (drone/core/object_pool.hpp) and go back to it when the last holder
    // drops them (the slot keeps the latest, the window a copy of it while drawing): assigning into
    // one reuses its vectors, so a frame allocates nothing here once the pool is warm. All out (a
    // slow reader): a fresh one, counted in the pool's exhausted().
    std::shared_ptr<PipelineOutput> out = out_pool_.acquire();
    if (!out) out = std::make_shared<PipelineOutput>();
    out->source_id = c.id;
    out->classifier = pipeline_.classifier_name();
    out->camera = c.camera;
    out->stale = false;
    out->result = {};
    if (c.kind != SessionSource::Replay) {
        last_live_frame_ns_ = recv_ns > 0 ? recv_ns : clock_.now_ns();
        stale_published_ = false;
    }
    // A drone streaming another size than the calibration's (720p, set in Drone -> Settings):
    // the same lens, its intrinsics scaled to the frames.
    if (c.camera == CameraId::Front && !f.image.empty() && calib_in_use_.width > 0 &&
        (f.image.cols != calib_in_use_.width || f.image.rows != calib_in_use_.height)) {
        const CameraCalibration scaled = calib_in_use_.scaled_to(f.image.cols, f.image.rows);
        use_calibration(scaled, calib_origin_ + " (scaled to " + std::to_string(f.image.cols) +
                                    "x" + std::to_string(f.image.rows) + ")");
        reset_vision();
        message("video " + std::to_string(f.image.cols) + "x" + std::to_string(f.image.rows) +
                ": calibration scaled to it");
    }
    out->odometry.active = false;
    if (c.settle > 0) {
        --c.settle;  // may still be of the camera before the switch
    } else if (c.camera == CameraId::Bottom) {
        // The obstacle classifier is for the front camera: the floor seen from above is for
        // the odometry.
        odometry_.process(f, out->odometry);
    } else if (pipeline_.ok() && !f.image.empty()) {
        out->result = pipeline_.process(f);
    }
    const TimeNs now = clock_.now_ns();
    out->latency_ms = recv_ns > 0 ? ns_to_ms(now - recv_ns) : kUnknown;
    if (c.rate_n == 0) c.rate_t0 = now;
    ++c.rate_n;
    if (now - c.rate_t0 >= ms_to_ns(1000)) {
        c.fps = static_cast<double>(c.rate_n - 1) * 1e9 / static_cast<double>(now - c.rate_t0);
        c.rate_t0 = now;
        c.rate_n = 1;
    }
    out->fps = c.fps;
    out->frames_dropped = c.frames ? c.frames->dropped() : 0;
    out->frame = std::move(f);
    // The calibration mode gets the frame too (a header; its worker detects on its own thread).
    if (calibrator_ && calibrator_->active())
        calibrator_->offer(out->frame.image, out->frame.index, c.id);
    if (c.kind == SessionSource::Replay) {
        c.rinfo.frame = out->frame.index;
        publish_replay();
    }
    output_.publish(std::move(out));
    ++processed_;
}

// Live video that stopped: the decision on screen is of a frozen picture. Its regions are
// republished unknown (StaleVideo), so that nothing downstream (the window, an assist) takes the
// last "clear" for a current one.
void Session::check_stale(TimeNs now) {
    if (stale_published_ || last_live_frame_ns_ == 0 || now - last_live_frame_ns_ <= kGapNs) return;
    const auto latest = output_.latest();
    if (!latest || !*latest || (*latest)->source_id != cur_->id) return;
    auto stale = std::make_shared<PipelineOutput>(**latest);  // once per stall: not per frame
    mark_unknown(stale->result, vision::UnknownReason::StaleVideo);
    stale->stale = true;
    output_.publish(std::move(stale));
    stale_published_ = true;
    message("video stale: no frame for " + std::to_string((now - last_live_frame_ns_) / 1'000'000) +
            " ms; regions unknown until it is back");
}

}  // namespace gs::app
