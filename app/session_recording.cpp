// Recording control: a live source (drone or virtual drone) recorded as a dataset, its status and
// the free space where it writes (polled every 2 s).
#include "app/session_current.hpp"
#include "drone/core/file_io.hpp"
#include "drone/dataset/raw_replay.hpp"

#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <map>

namespace gs::app {

std::filesystem::path default_record_root() {
    const char* home = std::getenv("HOME");
    if (home && *home) return std::filesystem::path(home) / "ardrone-gs" / "flights";
    return "flights";
}

namespace {

// PaVE frame number -> the dataset's frame index (raw/capture_times.csv and frames.csv). A
// recording without capture times or a readable frames.csv maps nothing: the rows keep their
// PaVE frame number and leave `frame` empty.
std::map<std::uint32_t, std::int64_t> recorded_frames(const std::filesystem::path& dir) {
    auto captures = dataset::read_capture_times(dir / "raw");
    if (!captures || !*captures) return {};
    auto text = read_text_file(dir / "frames.csv", "frames.csv", 256u << 20);
    if (!text) return {};
    auto frames = dataset::parse_frames_csv(std::move(*text));
    if (!frames) return {};
    return dataset::frames_of_pave_numbers(*frames, **captures);
}

std::string assist_cmd_cells(const FlightCommand& c) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%d,%.3f,%.3f,%.3f,%.3f", c.progressive ? 1 : 0,
                  static_cast<double>(c.roll), static_cast<double>(c.pitch),
                  static_cast<double>(c.gaz), static_cast<double>(c.yaw));
    return buf;
}

}  // namespace

// assist.csv (docs/dataset.md "assist.csv"): one row per intervention of the assist during the
// recording, always written (header only when it never acted).
std::optional<FileError> write_assist_csv(const std::filesystem::path& dir, TimeNs start_ns,
                                          const std::vector<Intervention>& rows) {
    const auto frames = recorded_frames(dir);
    std::string text =
        "t_ms,frame,pave_frame,decision_ms,action,region,reason,"
        "before_progressive,before_roll,before_pitch,before_gaz,before_yaw,"
        "after_progressive,after_roll,after_pitch,after_gaz,after_yaw\n";
    for (const Intervention& i : rows) {
        std::string frame, pave, decision;
        if (i.pave_frame) {
            pave = std::to_string(*i.pave_frame);
            if (const auto it = frames.find(*i.pave_frame); it != frames.end())
                frame = std::to_string(it->second);
        }
        if (i.decision_ns > 0) {
            char b[32];
            std::snprintf(b, sizeof b, "%.3f",
                          static_cast<double>(i.decision_ns - start_ns) * 1e-6);
            decision = b;
        }
        std::string reason = i.reason;
        for (char& ch : reason)
            if (ch == ',' || ch == '"' || ch == '\n') ch = ';';
        char t[32];
        std::snprintf(t, sizeof t, "%.3f", static_cast<double>(i.t_ns - start_ns) * 1e-6);
        text += std::string(t) + ',' + frame + ',' + pave + ',' + decision + ',' +
                to_string(i.action) + ',' + vision::to_string(i.region) + ',' + reason + ',' +
                assist_cmd_cells(i.before) + ',' + assist_cmd_cells(i.after) + '\n';
    }
    return write_file_atomic(dir / "assist.csv", text, "assist.csv");
}

void Session::record_assist(const Intervention& i) {
    if (!recorder_ || !recorder_->recording()) return;
    if (assist_rows_.size() >= kMaxAssistRows) {
        ++assist_rows_dropped_;
        return;
    }
    assist_rows_.push_back(i);
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
    ro.writer.inject_failure_file = opts_.record_inject_failure_file;
    ro.writer.inject_failure_after_bytes = opts_.record_inject_failure_after_bytes;
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
    assist_rows_.clear();
    assist_rows_dropped_ = 0;
    last_space_check_ = 0;
    message("recording to " + last_record_path_ + " (" + to_string(c.camera) + " camera)");
    publish_recording(clock_.now_ns());
}

void Session::record_stop() {
    if (!recorder_) return;
    const record::RecorderStatus st = recorder_->stop();
    recorder_.reset();
    if (!st.path.empty())
        if (auto e = write_assist_csv(st.path, st.start_ns, assist_rows_))
            message("assist.csv could not be written in " + st.path + ": " + to_string(*e));
    if (assist_rows_dropped_ > 0)
        message("assist.csv: " + std::to_string(assist_rows_dropped_) +
                " interventions beyond the first " + std::to_string(kMaxAssistRows) + " dropped");
    assist_rows_.clear();
    RecordingInfo ri;
    ri.status = st;
    ri.status.recording = false;
    ri.disk_free_bytes = disk_free_bytes_;
    ri.last_path = last_record_path_;
    // Published before it is said: whoever reads the message finds the recording stopped.
    recording_.publish(std::move(ri));
    // A recorder that stopped itself at a write failure (a full disk): its sentence names the
    // dataset, the disk and what is kept, as the terminal's `record` prints it. Said once (the
    // recorder is gone now). The link was never touched: flying goes on.
    if (st.disk_full)
        message(st.error);
    else
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
    last_record_publish_ = now;
    // A write failed (a full disk): the recorder stopped itself. Finish it as a stop does, with
    // one message naming the dataset and the disk (issue 14 point 4: terminal and window).
    if (!ri.status.recording && ri.status.disk_full) {
        record_stop();
        return;
    }
    recording_.publish(std::move(ri));
}

}  // namespace gs::app
