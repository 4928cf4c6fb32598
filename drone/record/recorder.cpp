#include "drone/record/recorder.hpp"

#include <nlohmann/json.hpp>

#include <sys/statvfs.h>

#include <cerrno>
#include <cstdio>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <deque>

namespace gs::record {
namespace {

constexpr std::size_t kTruthHistory = 1024;  // 20 s at the virtual drone's 50 Hz
constexpr std::size_t kTapPending = 256;
constexpr TimeNs kStatusPeriod = 100'000'000;

double thread_cpu_ms() {
    timespec ts{};
    ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

double wrap180(double deg) {
    deg = std::fmod(deg + 180.0, 360.0);
    if (deg < 0) deg += 360.0;
    return deg - 180.0;
}

// The pose at `t` from samples in time order: interpolated inside, nearest outside.
TruthPose pose_at(const std::deque<TruthSample>& h, TimeNs t) {
    auto after = std::lower_bound(h.begin(), h.end(), t,
                                  [](const TruthSample& g, TimeNs v) { return g.t_ns < v; });
    if (after == h.end()) return h.back().pose;
    if (after == h.begin() || after->t_ns == t) return after->pose;
    const TruthSample& a = *(after - 1);
    const TruthSample& b = *after;
    const double w = static_cast<double>(t - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns);
    auto lerp = [w](double x, double y) { return x + (y - x) * w; };
    TruthPose p;
    p.x_m = lerp(a.pose.x_m, b.pose.x_m);
    p.y_m = lerp(a.pose.y_m, b.pose.y_m);
    p.z_m = lerp(a.pose.z_m, b.pose.z_m);
    p.roll_deg = lerp(a.pose.roll_deg, b.pose.roll_deg);
    p.pitch_deg = lerp(a.pose.pitch_deg, b.pose.pitch_deg);
    p.yaw_deg = wrap180(a.pose.yaw_deg + wrap180(b.pose.yaw_deg - a.pose.yaw_deg) * w);
    return p;
}

// "the disk holding /media/x is full: 0 B free" for a recording's failure message.
std::string disk_text(const std::filesystem::path& dir, int err) {
    // The mount point: the longest mount path that is a prefix of the dataset's real path.
    std::error_code ec;
    const std::string real = std::filesystem::weakly_canonical(dir, ec).string();
    std::string mount = "/";
    if (std::FILE* m = std::fopen("/proc/self/mounts", "r")) {
        char dev[512], at[512];
        while (std::fscanf(m, "%511s %511s %*[^\n]", dev, at) == 2) {
            const std::string a = at;
            const bool prefix = real.rfind(a, 0) == 0 &&
                                (a == "/" || real.size() == a.size() || real[a.size()] == '/');
            if (prefix && a.size() > mount.size()) mount = a;
        }
        std::fclose(m);
    }
    struct statvfs v {};
    std::string free_text;
    if (::statvfs(mount.c_str(), &v) == 0) {
        char b[64];
        std::snprintf(b, sizeof b, "%.1f MB free",
                      static_cast<double>(v.f_bavail) * static_cast<double>(v.f_frsize) / 1e6);
        free_text = b;
    }
    return (err == ENOSPC ? "the disk holding it is full: " : "the disk holding it failed: ") +
           mount + (free_text.empty() ? "" : ", " + free_text);
}

// The camera the link's last configuration dump names (front when there is none).
CameraId reported_camera(const link::DroneLink& link) {
    const auto cfg = link.config().latest();
    const auto v = cfg ? cfg->get("video:video_channel") : std::nullopt;
    const auto ch = v ? protocol::config_int(*v) : std::nullopt;
    return ch && *ch == 1 ? CameraId::Bottom : CameraId::Front;
}

}  // namespace

dataset::Scenario scenario_of(const std::string& name) {
    if (name == "left") return dataset::Scenario::Left;
    if (name == "right") return dataset::Scenario::Right;
    if (name == "center" || name == "centre") return dataset::Scenario::Center;
    return dataset::Scenario::None;
}

struct Recorder::State {
    RecorderOptions opts;
    std::filesystem::path dir;
    std::unique_ptr<dataset::DatasetWriter> writer;
    std::shared_ptr<BoundedQueue<link::RawEvent>> raw;
    std::shared_ptr<BoundedQueue<link::AccessUnitEvent>> units;
    std::shared_ptr<BoundedQueue<dataset::FrameRow>> rows;  // the writer's row tap (frame_tap only)
    link::VideoStats video_at_start;  // the link's counters when recording began

    // A unit is recorded only when raw/video.pave holds it whole: the link may have been in the
    // middle of a frame when the recording began. Offsets are the video receiver's (RawEvent and
    // AccessUnitEvent count the same bytes), so nothing is framed twice.
    std::optional<std::uint64_t> raw_video_from;  // stream offset of the first recorded byte
    std::uint64_t raw_video_end = 0;              // one past the last recorded byte
    std::uint64_t not_in_raw = 0;
    std::uint64_t dropped_reference_lost = 0, dropped_no_picture = 0, dropped_not_h264 = 0;
    std::uint64_t concealed = 0;
    std::uint64_t navdata_accepted = 0;
    std::uint64_t first_ordinal = 0, last_ordinal = 0;  // of the accepted samples recorded

    // Frames waiting for a ground-truth sample after their capture.
    std::deque<link::AccessUnitEvent> pending;
    std::deque<TruthSample> truth;

    // The writer's frame index, predicted by its own rule (the first IDR starts the video).
    bool seen_idr = false;
    std::int64_t next_index = 0;
    std::vector<TimeNs> frame_capture_ns;  // per written frame (ground truth only): collisions.csv
    struct TapFrame {
        std::int64_t index;
        TimeNs recv_ns;
        TimeNs capture_ns;
        std::uint32_t frame_number;
        cv::Mat image;
    };
    std::deque<TapFrame> tap_pending;
    std::uint64_t tap_lost = 0;

    double cpu_ms = 0;
};

Recorder::Recorder(link::DroneLink& link, const GroundTruthSource* truth)
    : link_(link), truth_(truth) {}

Recorder::~Recorder() {
    stop();
}

Expected<void, StartError> Recorder::start(const std::filesystem::path& dir, RecorderOptions opts) {
    if (running_) {
        auto st = status();
        return Unexpected(
            StartError{StartError::Code::AlreadyRecording, "already recording to " + st.path});
    }
    auto s = std::make_unique<State>();
    opts.writer.write_raw = true;
    const CameraId camera = opts.camera ? *opts.camera : reported_camera(link_);
    if (camera != opts.writer.camera) {
        // A calibration given with writer.camera is that camera's: when the drone reports the
        // other one, its default is written instead.
        if (!opts.camera) opts.writer.calibration.reset();
        opts.writer.camera = camera;
    }
    if (!opts.writer.calibration) {
        auto c = default_calibration(opts.writer.camera, assets_dir());
        if (c) opts.writer.calibration = c->scaled_to(opts.writer.width, opts.writer.height);
    }
    if (opts.frame_tap > 0) {
        s->rows = std::make_shared<BoundedQueue<dataset::FrameRow>>(
            std::max<std::size_t>(opts.frame_tap, 64));
        opts.writer.row_tap = s->rows;
    }
    auto w = dataset::DatasetWriter::create(dir, opts.writer, link_.clock());
    if (!w) return Unexpected(StartError{StartError::Code::Dataset, to_string(w.error())});
    s->writer = std::move(*w);
    s->dir = dir;
    s->opts = opts;
    if (truth_ != nullptr) {
        const TruthScene scene = truth_->truth_scene();
        nlohmann::ordered_json j;
        j["scenario"] = to_string(scenario_of(scene.scenario));
        j["scene"] = scene.name;
        if (!scene.target_id.empty()) j["target"] = scene.target_id;
        j["source"] = "virtual drone ground truth";
        if (!scene.description.empty()) j["description"] = scene.description;
        (void)s->writer->set_labels(dataset::FlightLabels{scenario_of(scene.scenario), j.dump()});
    }
    tap_ =
        opts.frame_tap > 0 ? std::make_shared<BoundedQueue<FrameSample>>(opts.frame_tap) : nullptr;
    s->video_at_start = link_.status().video;
    // Units before raw bytes (and the reverse when stopping): a frame wholly in raw/ is then a
    // unit the recorder saw, and a unit is kept only when its bytes are all in raw/ (offsets).
    s->units = link_.subscribe_access_units(opts.access_unit_queue);
    s->raw = link_.subscribe_raw(opts.raw_queue);
    state_ = std::move(s);

    RecorderStatus st;
    st.recording = true;
    st.path = dir.string();
    st.labels = truth_ != nullptr;
    status_.publish(st);
    stop_ = false;
    running_ = true;
    thread_ = std::thread([this] { run(); });
    return {};
}

RecorderStatus Recorder::stop() {
    if (!running_.load()) return status();
    stop_ = true;
    if (thread_.joinable()) thread_.join();
    running_ = false;
    return status();
}

RecorderStatus Recorder::status() const {
    return status_.latest().value_or(RecorderStatus{});
}

// collisions.csv (docs/dataset.md "collisions.csv"): the contacts the ground truth reports during
// the recording, each with the last frame captured at or before it.
void Recorder::write_collisions(const std::filesystem::path& dir, TimeNs start, TimeNs end,
                                const std::vector<TimeNs>& frame_capture_ns) const {
    std::FILE* f = std::fopen((dir / "collisions.csv").c_str(), "w");
    if (f == nullptr) return;  // the dataset stays valid without it
    std::fprintf(f, "t_ms,frame,crash,kind,what,x_m,y_m,z_m,speed_mps,approach_mps\n");
    for (const TruthCollision& c : truth_->truth_collisions()) {
        if (c.t_ns < start || c.t_ns > end) continue;
        const auto it = std::upper_bound(frame_capture_ns.begin(), frame_capture_ns.end(), c.t_ns);
        const std::string frame = it == frame_capture_ns.begin()
                                      ? std::string()
                                      : std::to_string(it - frame_capture_ns.begin() - 1);
        std::string what = c.what;
        std::replace(what.begin(), what.end(), ',', ' ');
        std::replace(what.begin(), what.end(), '"', ' ');
        std::fprintf(f, "%.3f,%s,%d,%s,%s,%.4f,%.4f,%.4f,%.4f,%.4f\n",
                     static_cast<double>(c.t_ns - start) * 1e-6, frame.c_str(), c.crash ? 1 : 0,
                     c.kind.c_str(), what.c_str(), c.pose.x_m, c.pose.y_m, c.pose.z_m, c.speed_mps,
                     c.approach_mps);
    }
    std::fclose(f);
}

void Recorder::run() {
    State& s = *state_;
    dataset::DatasetWriter& w = *s.writer;
    const Clock& clock = link_.clock();
    const double cpu0 = thread_cpu_ms();
    std::vector<link::RawEvent> raws;
    std::vector<link::AccessUnitEvent> units;
    TimeNs last_status = 0;

    auto on_raw = [&](link::RawEvent& e) {
        switch (e.kind) {
            case link::RawEvent::Kind::Navdata:
                // raw/navdata.bin keeps every datagram received, navdata.csv the samples the
                // link accepted from them, in the order it accepted them.
                if (e.accepted) {
                    ++s.navdata_accepted;
                    if (s.first_ordinal == 0) s.first_ordinal = e.accepted_ordinal;
                    s.last_ordinal = e.accepted_ordinal;
                }
                (void)w.take_navdata(e.t_ns, std::move(e.bytes), e.accepted);
                break;
            case link::RawEvent::Kind::Video:
                if (!s.raw_video_from) s.raw_video_from = e.stream_offset;
                s.raw_video_end = e.stream_offset + e.bytes.size();
                (void)w.take_video_bytes(e.t_ns, std::move(e.bytes));
                break;
            case link::RawEvent::Kind::VideoConnect:
                // A connection that opens before any video byte was recorded is the first one:
                // raw/video.pave starts with it (offset 0).
                if (s.raw_video_from) (void)w.add_video_connection(e.t_ns);
                break;
            case link::RawEvent::Kind::At:
                (void)w.add_at(e.t_ns,
                               std::string_view(reinterpret_cast<const char*>(e.bytes.data()),
                                                e.bytes.size()));
                break;
        }
    };

    auto truth_ready = [&](TimeNs capture, TimeNs now, bool flushing) {
        if (truth_ == nullptr || flushing) return true;
        if (!s.truth.empty() && s.truth.back().t_ns >= capture) return true;
        return now - capture > s.opts.truth_wait_ns;
    };

    auto write_frame = [&](link::AccessUnitEvent& e) {
        std::optional<dataset::FrameLabel> label;
        if (truth_ != nullptr) {
            dataset::FrameLabel l;
            if (!s.truth.empty()) {
                const TruthPose p = pose_at(s.truth, e.capture_ns);
                l.gt = dataset::GroundTruthPose{p.x_m, p.y_m, p.z_m, p.yaw_deg};
                if (const auto hit = truth_->target_offset(p)) {
                    l.distance_m = hit->distance_m;
                    l.lateral_m = hit->lateral_m;
                }
            }
            label = l;
        }
        const bool idr = e.is_idr;
        cv::Mat image = std::move(e.image);  // released at the end of this call unless tapped
        // Stamped with the capture clock the live path uses (PaVE timestamp mapped onto ours),
        // not the time of the TCP read that completed the frame.
        if (!w.take_frame(e.capture_ns, std::move(e.bytes), {}, label)) return;  // counted there
        if (!s.seen_idr && !idr) return;  // the writer skips it too (and counts it)
        s.seen_idr = true;
        const std::int64_t index = s.next_index++;
        if (truth_ != nullptr) s.frame_capture_ns.push_back(e.capture_ns);
        if (tap_) {
            s.tap_pending.push_back(
                {index, e.recv_ns, e.capture_ns, e.frame_number, std::move(image)});
            if (s.tap_pending.size() > kTapPending) {
                s.tap_pending.pop_front();
                ++s.tap_lost;
            }
        }
    };

    auto on_unit = [&](link::AccessUnitEvent& e) {
        // Begun before the recording, or ended after it (its bytes are not all in raw/): not
        // part of it.
        if (!s.raw_video_from || e.stream_offset < *s.raw_video_from ||
            e.stream_end > s.raw_video_end) {
            ++s.not_in_raw;
            return;
        }
        if (e.pave_timestamp_ms)
            (void)w.add_capture_time(e.frame_number, *e.pave_timestamp_ms, e.capture_ns);
        switch (e.fate) {
            case video::UnitFate::Decoded:
                break;
            case video::UnitFate::Concealed:
                ++s.concealed;
                break;
            case video::UnitFate::WaitingIdr:
                // Before the recording's first kept frame this is the stream's start, not a loss.
                if (s.seen_idr)
                    ++s.dropped_reference_lost;
                else
                    ++s.not_in_raw;
                return;
            case video::UnitFate::NotH264:
                ++s.dropped_not_h264;
                return;
            case video::UnitFate::NoPicture:
            case video::UnitFate::NotDecoded:
                ++s.dropped_no_picture;
                return;
        }
        s.pending.push_back(std::move(e));
    };

    auto drain_pending = [&](TimeNs now, bool flushing) {
        while (!s.pending.empty() && truth_ready(s.pending.front().capture_ns, now, flushing)) {
            write_frame(s.pending.front());
            s.pending.pop_front();
        }
    };

    auto drain_rows = [&] {
        if (!s.rows) return;
        while (auto row = s.rows->try_pop()) {
            while (!s.tap_pending.empty() && s.tap_pending.front().index < row->frame) {
                s.tap_pending.pop_front();
                ++s.tap_lost;
            }
            if (s.tap_pending.empty() || s.tap_pending.front().index != row->frame) continue;
            State::TapFrame& t = s.tap_pending.front();
            FrameSample fs;
            fs.index = row->frame;
            fs.t_ns = row->nav.t_ns;
            fs.recv_ns = t.recv_ns;
            fs.capture_ns = t.capture_ns;
            fs.frame_number = t.frame_number;
            fs.image = std::move(t.image);
            fs.nav = row->nav;
            s.tap_pending.pop_front();
            (void)tap_->push(std::move(fs));  // a full tap counts the drop
        }
    };

    auto publish = [&](TimeNs now, bool recording) {
        const auto ws = w.stats();
        const auto video = link_.status().video;
        RecorderStatus st;
        st.recording = recording;
        st.path = s.dir.string();
        st.duration_s = static_cast<double>(now - w.start_ns()) * 1e-9;
        st.start_ns = w.start_ns();
        st.frames = ws.frames_written;
        st.navdata = ws.navdata_written;
        st.at = ws.at_records;
        st.bytes = ws.bytes_written;
        st.dropped_link = s.raw->dropped() + s.units->dropped();
        st.dropped_writer = ws.dropped_queue_full + ws.frames_lost_io;
        st.dropped_tap =
            s.tap_lost + (tap_ ? tap_->dropped() : 0) + (s.rows ? s.rows->dropped() : 0);
        st.dropped_reference_lost = s.dropped_reference_lost;
        st.dropped_no_picture = s.dropped_no_picture;
        st.dropped_not_h264 = s.dropped_not_h264;
        st.dropped_cut_by_reset = video.cut_by_reset - s.video_at_start.cut_by_reset;
        st.drops = st.dropped_link + st.dropped_writer + st.dropped_tap +
                   st.dropped_reference_lost + st.dropped_no_picture + st.dropped_not_h264 +
                   st.dropped_cut_by_reset;
        st.concealed = s.concealed;
        st.frames_skipped = ws.frames_skipped + s.not_in_raw;
        st.video_connections = ws.video_connections;
        st.navdata_accepted = s.navdata_accepted;
        st.navdata_link_span = s.first_ordinal == 0 ? 0 : s.last_ordinal - s.first_ordinal + 1;
        st.write_errors = ws.write_errors;
        st.disk_full = ws.stopped;
        if (ws.stopped) {
            st.error = "recording stopped: " + s.dir.string() + ": " + ws.first_error + " (" +
                       disk_text(s.dir, ws.first_errno) + "); the " +
                       std::to_string(ws.frames_written) +
                       " frames on disk are kept and the dataset opens";
        } else {
            st.error = ws.first_error;
        }
        st.labels = truth_ != nullptr;
        st.cpu_ms = thread_cpu_ms() - cpu0;
        status_.publish(std::move(st));
    };

    auto cycle = [&](bool flushing) {
        // Access units first, then raw: the chunk completing a frame was queued before the
        // frame's access unit, so the first recorded offset is known when the unit is looked at.
        while (auto u = s.units->try_pop()) units.push_back(std::move(*u));
        while (auto r = s.raw->try_pop()) raws.push_back(std::move(*r));
        for (auto& r : raws) on_raw(r);
        raws.clear();
        if (truth_ != nullptr) {
            const TruthSample g = truth_->truth_sample();
            if (g.t_ns != 0 && (s.truth.empty() || g.t_ns > s.truth.back().t_ns)) {
                s.truth.push_back(g);
                if (s.truth.size() > kTruthHistory) s.truth.pop_front();
            }
        }
        for (auto& u : units) on_unit(u);
        units.clear();
        drain_pending(clock.now_ns(), flushing);
        drain_rows();
    };

    bool failed = false;
    while (!stop_.load()) {
        // Wake on the busiest stream (AT alone is ~33 Hz), never sleep long.
        if (auto first = s.raw->pop_for(std::chrono::milliseconds(10)))
            raws.push_back(std::move(*first));
        cycle(false);
        const TimeNs now = clock.now_ns();
        // The disk failed: stop at once (the writer has already stopped writing).
        if (w.stats().stopped) {
            failed = true;
            break;
        }
        if (now - last_status >= kStatusPeriod) {
            publish(now, true);
            last_status = now;
        }
    }
    // The reverse of start()'s order (unsubscribe() returns once the link threads moved on).
    link_.unsubscribe(s.raw.get());
    link_.unsubscribe(s.units.get());
    if (!failed) cycle(true);
    const TimeNs end = clock.now_ns();
    w.close();  // settles every row
    drain_rows();
    if (truth_ != nullptr) write_collisions(s.dir, w.start_ns(), end, s.frame_capture_ns);
    if (tap_) tap_->close();
    publish(end, false);
}

}  // namespace gs::record
