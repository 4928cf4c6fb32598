// Recording control: a live source (drone or virtual drone) recorded as a dataset, its status and
// the free space where it writes (polled every 2 s).
#include "app/session_current.hpp"

#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace gs::app {

std::filesystem::path default_record_root() {
    const char* home = std::getenv("HOME");
    if (home && *home) return std::filesystem::path(home) / "ardrone-gs" / "flights";
    return "flights";
}

namespace {

// The columns of a CSV header line, by name.
std::map<std::string, std::size_t> csv_columns(const std::string& header) {
    std::map<std::string, std::size_t> cols;
    std::stringstream ss(header);
    std::string name;
    for (std::size_t i = 0; std::getline(ss, name, ','); ++i) {
        if (!name.empty() && name.back() == '\r') name.pop_back();
        cols[name] = i;
    }
    return cols;
}

std::vector<std::string> csv_cells(const std::string& line) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, ',')) cells.push_back(c);
    return cells;
}

// PaVE frame number -> the dataset's frame index, through raw/capture_times.csv (frame number ->
// capture time) and frames.csv (capture time -> frame). Frames the recording did not keep map
// to nothing.
std::map<std::uint32_t, std::int64_t> dataset_frames(const std::filesystem::path& dir) {
    std::map<std::int64_t, std::int64_t> frame_of_us;
    std::map<std::uint32_t, std::int64_t> out;
    std::ifstream frames(dir / "frames.csv");
    std::string line;
    if (!std::getline(frames, line)) return out;
    auto cols = csv_columns(line);
    if (!cols.count("frame") || !cols.count("t_ms")) return out;
    const std::size_t cf = cols["frame"], ct = cols["t_ms"];
    while (std::getline(frames, line)) {
        const auto c = csv_cells(line);
        if (c.size() <= std::max(cf, ct)) continue;
        try {
            frame_of_us[std::llround(std::stod(c[ct]) * 1000.0)] = std::stoll(c[cf]);
        } catch (...) {
        }
    }
    std::ifstream captures(dir / "raw" / "capture_times.csv");
    if (!std::getline(captures, line)) return out;
    cols = csv_columns(line);
    if (!cols.count("frame_number") || !cols.count("t_us")) return out;
    const std::size_t cn = cols["frame_number"], cu = cols["t_us"];
    while (std::getline(captures, line)) {
        const auto c = csv_cells(line);
        if (c.size() <= std::max(cn, cu)) continue;
        try {
            const auto it = frame_of_us.find(std::stoll(c[cu]));
            if (it != frame_of_us.end())
                out[static_cast<std::uint32_t>(std::stoul(c[cn]))] = it->second;
        } catch (...) {
        }
    }
    return out;
}

std::string assist_cmd_cells(const FlightCommand& c) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%d,%.3f,%.3f,%.3f,%.3f", c.progressive ? 1 : 0, double{c.roll},
                  double{c.pitch}, double{c.gaz}, double{c.yaw});
    return buf;
}

}  // namespace

// assist.csv (docs/dataset.md "assist.csv"): one row per intervention of the assist during the
// recording, always written (header only when it never acted).
bool write_assist_csv(const std::filesystem::path& dir, TimeNs start_ns,
                      const std::vector<Intervention>& rows) {
    const auto frames = dataset_frames(dir);
    std::FILE* f = std::fopen((dir / "assist.csv").c_str(), "w");
    if (f == nullptr) return false;
    std::fprintf(f,
                 "t_ms,frame,pave_frame,decision_ms,action,region,reason,"
                 "before_progressive,before_roll,before_pitch,before_gaz,before_yaw,"
                 "after_progressive,after_roll,after_pitch,after_gaz,after_yaw\n");
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
        std::fprintf(f, "%.3f,%s,%s,%s,%s,%s,%s,%s,%s\n",
                     static_cast<double>(i.t_ns - start_ns) * 1e-6, frame.c_str(), pave.c_str(),
                     decision.c_str(), to_string(i.action), vision::to_string(i.region),
                     reason.c_str(), assist_cmd_cells(i.before).c_str(),
                     assist_cmd_cells(i.after).c_str());
    }
    return std::fclose(f) == 0;
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
    if (!st.path.empty() && !write_assist_csv(st.path, st.start_ns, assist_rows_))
        message("assist.csv could not be written in " + st.path);
    if (assist_rows_dropped_ > 0)
        message("assist.csv: " + std::to_string(assist_rows_dropped_) +
                " interventions beyond the first " + std::to_string(kMaxAssistRows) + " dropped");
    assist_rows_.clear();
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
