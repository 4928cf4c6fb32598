// Camera tracking (which camera the video comes from) and the calibration in use.
#include "app/session_current.hpp"

#include <cstdio>
#include <filesystem>

namespace gs::app {

CameraCalibration front_calibration() {
    auto c = default_calibration(CameraId::Front, assets_dir());
    // The same numbers compiled in if the asset is missing (docs/protocol.md §6.2).
    return c ? *c : builtin_calibration(CameraId::Front);
}

CameraCalibration bottom_calibration() {
    auto c = default_calibration(CameraId::Bottom, assets_dir());
    return c ? *c : builtin_calibration(CameraId::Bottom);
}

void Session::use_calibration(const CameraCalibration& c, std::string origin) {
    calib_in_use_ = c;
    calib_origin_ = std::move(origin);
    pipeline_.set_calibration(c);
    publish_calibration();
}

void Session::publish_calibration() {
    CalibrationInUse u;
    u.which = cur_->camera;
    if (cur_->camera == CameraId::Bottom) {
        u.camera = odometry_.calibration();
        u.origin =
            cur_->kind == SessionSource::Replay ? calib_origin_ : "assets default (bottom camera)";
    } else {
        u.camera = calib_in_use_;
        u.origin = calib_origin_;
    }
    u.source_id = cur_->id;
    calibration_.publish(std::move(u));
}

void Session::set_camera(CameraId camera, const char* why) {
    Current& c = *cur_;
    if (camera == c.camera) return;
    c.camera = camera;
    c.settle = kCameraSettleFrames;
    reset_vision();
    publish_calibration();
    message(std::string("video: ") + to_string(camera) + " camera (" + why + ")" +
            (camera == CameraId::Bottom
                 ? ": visual odometry runs; the obstacle classifier waits for the front camera"
                 : ": the obstacle classifier runs"));
    if (recorder_ && recorder_->recording())
        message(
            "the recording in progress keeps the camera it started with in flight.json: "
            "stop and record again for a dataset of one camera");
}

// Live: the camera the drone's configuration reports (read back after every switch).
void Session::update_camera() {
    Current& c = *cur_;
    if (!c.link || c.link->config().generation() == c.config_gen) return;
    protocol::ConfigMap cfg;
    if (!c.link->config().read_if_newer(c.config_gen, cfg)) return;
    const auto v = cfg.get("video:video_channel");
    const auto ch = v ? protocol::config_int(*v) : std::nullopt;
    if (!ch) return;
    set_camera(*ch == 1 ? CameraId::Bottom : CameraId::Front, "drone configuration");
}

// A real drone: the calibration the calibration mode saved, when there is one.
CameraCalibration Session::drone_calibration(std::string& origin) const {
    std::error_code ec;
    if (!opts_.calibration_file.empty() && std::filesystem::exists(opts_.calibration_file, ec)) {
        auto c = load_calibration_file(opts_.calibration_file);
        if (c && c->valid()) {
            origin = opts_.calibration_file.string();
            return *c;
        }
    }
    origin = "assets default (front)";
    return front_calibration();
}

vision::CalibrationMode& Session::calibration_worker() {
    if (!calibrator_) {
        vision::CalibrationModeOptions mo;
        mo.save_path = opts_.calibration_file.string();
        mo.interval_ms = opts_.calibration_interval_ms;
        mo.auto_interval_ms = opts_.calibration_auto_interval_ms;
        calibrator_ = std::make_unique<vision::CalibrationMode>(
            std::move(mo),
            [this](const vision::CalibrationModeState& st) { calibration_mode_.publish(st); },
            // Saved on the worker thread: applied by the session thread, in request order.
            [this](const CameraCalibration& cam, const std::string& source,
                   const std::string& path) {
                CameraCalibration applied = cam;
                applied.source = source;
                (void)requests_.push(ApplyCalibration{std::move(applied), path});
            });
    }
    return *calibrator_;
}

// A calibration saved by the mode (or handed in): used from now on until the source changes.
void Session::apply_calibration(const ApplyCalibration& q) {
    if (!q.camera.valid()) {
        message("calibration from " + q.origin + " is not valid; not applied");
        return;
    }
    use_calibration(q.camera, q.origin);
    reset_vision();  // the tracks were undistorted with the old model
    char b[160];
    std::snprintf(b, sizeof b, "calibration applied: fx %.1f fy %.1f cx %.1f cy %.1f", q.camera.fx,
                  q.camera.fy, q.camera.cx, q.camera.cy);
    message(std::string(b) + " (" + q.origin + ")");
}

}  // namespace gs::app
