// Recording control: a live source (drone or virtual drone) recorded as a dataset, its status and
// the free space where it writes (polled every 2 s).
#include "app/session_current.hpp"

#include <ctime>
#include <filesystem>

namespace gs::app {

std::filesystem::path default_record_root() {
    const char* home = std::getenv("HOME");
    if (home && *home) return std::filesystem::path(home) / "ardrone-gs" / "flights";
    return "flights";
}

void Session::record_start(const std::string& dir) {
    Current& c = *cur_;
    if (!c.link) {
        message("recording needs a drone or the virtual drone (a replay is already recorded)");
        return;
    }
    if (recorder_ && recorder_->recording()) {
        message("already recording to " + last_record_path_);
        return;
    }
    std::filesystem::path path = dir;
    if (path.empty()) {
        const std::time_t t = std::time(nullptr);
        std::tm tm{};
        localtime_r(&t, &tm);
        char name[64];
        std::strftime(name, sizeof name, "%Y-%m-%d_%H%M%S", &tm);
        path = (opts_.record_root.empty() ? default_record_root() : opts_.record_root) / name;
    }
    std::error_code ec;
    std::filesystem::create_directories(path.parent_path(), ec);
    recorder_ = std::make_unique<record::Recorder>(*c.link, c.drone.get());
    record::RecorderOptions ro;
    // The camera the video comes from now, with its calibration: a bottom-camera flight replays
    // through the odometry (`ardrone-gs odometry`, the window).
    update_camera();
    ro.camera = c.camera;
    ro.writer.calibration = c.camera == CameraId::Bottom ? odometry_.calibration() : calib_in_use_;
    ro.writer.source = c.kind == SessionSource::Sim ? "simulated (virtual drone)" : "recorded";
    if (auto st = recorder_->start(path, ro); !st) {
        message("recording failed: " + st.error().message);
        recorder_.reset();
        RecordingInfo ri;
        ri.status.error = st.error().message;
        ri.last_path = last_record_path_;
        recording_.publish(std::move(ri));
        return;
    }
    last_record_path_ = path.string();
    last_space_check_ = 0;
    message("recording to " + last_record_path_ + " (" + to_string(c.camera) + " camera)");
    publish_recording(clock_.now_ns());
}

void Session::record_stop() {
    if (!recorder_) return;
    const record::RecorderStatus st = recorder_->stop();
    recorder_.reset();
    RecordingInfo ri;
    ri.status = st;
    ri.status.recording = false;
    ri.disk_free_bytes = disk_free_bytes_;
    ri.last_path = last_record_path_;
    recording_.publish(std::move(ri));
    message("recording stopped: " + std::to_string(st.frames) + " frames, " +
            std::to_string(st.navdata) + " navdata in " + last_record_path_ +
            (st.drops ? ", " + std::to_string(st.drops) + " dropped" : ""));
}

void Session::publish_recording(TimeNs now) {
    if (!recorder_) return;
    if (now - last_space_check_ > ms_to_ns(2000)) {  // statvfs is a syscall: every 2 s is enough
        std::error_code ec;
        const auto sp = std::filesystem::space(last_record_path_, ec);
        disk_free_bytes_ = ec ? kUnknown : static_cast<double>(sp.available);
        last_space_check_ = now;
    }
    RecordingInfo ri;
    ri.status = recorder_->status();
    ri.disk_free_bytes = disk_free_bytes_;
    ri.last_path = last_record_path_;
    recording_.publish(std::move(ri));
    last_record_publish_ = now;
}

}  // namespace gs::app
