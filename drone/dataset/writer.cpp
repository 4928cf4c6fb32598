#include "drone/dataset/writer.hpp"

#include "drone/dataset/align.hpp"
#include "drone/dataset/annexb.hpp"
#include "drone/dataset/csv.hpp"
#include "drone/dataset/raw.hpp"
#include "drone/dataset/value_rules.hpp"

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <deque>
#include <utility>

namespace gs::dataset {
namespace fs = std::filesystem;

namespace {

FileError io_error(const std::string& name, const std::string& what) {
    return FileError{FileErrorCode::Io, name, 0, 0, what};
}

std::string frame_file_name(std::int64_t index, const char* ext) {
    char b[40];
    std::snprintf(b, sizeof b, "%06lld%s", static_cast<long long>(index), ext);
    return b;
}

std::string hex32(std::uint32_t v) {
    char b[16];
    std::snprintf(b, sizeof b, "0x%08X", v);
    return b;
}

}  // namespace

std::string flight_json_text(const DatasetInfo& info) {
    nlohmann::ordered_json j;
    j["format"] = "ardrone-dataset";
    j["version"] = 1;
    j["camera"] = to_string(info.camera);
    j["width"] = info.width;
    j["height"] = info.height;
    j["fps"] = info.fps;
    if (info.frames) j["frames"] = *info.frames;
    j["video"] = info.video;
    j["images"] = info.images;
    if (info.calibration) {
        // The intrinsics only: the size is the flight's own width and height.
        j["calibration"] = calibration_to_json(*info.calibration, false);
    }
    if (!info.source.empty()) j["source"] = info.source;
    return j.dump(2) + "\n";
}

namespace {

// The navdata columns frames.csv and navdata.csv share, in their order (docs/dataset.md): one
// list for both files' headers and rows.
constexpr std::pair<const char*, double NavState::*> kNavColumns[] = {
    {"roll_deg", &NavState::roll_deg},    {"pitch_deg", &NavState::pitch_deg},
    {"yaw_deg", &NavState::yaw_deg},      {"vx_mps", &NavState::vx_mps},
    {"vy_mps", &NavState::vy_mps},        {"vz_mps", &NavState::vz_mps},
    {"altitude_m", &NavState::altitude_m}};

// ",roll_deg,pitch_deg,...": the shared columns' names, each after a comma.
std::string nav_column_names() {
    std::string out;
    for (const auto& [column, member] : kNavColumns) {
        out += ',';
        out += column;
    }
    return out;
}

// The shared columns' values of `s`, each after a comma.
void append_nav_columns(std::string& out, const NavState& s) {
    for (const auto& [column, member] : kNavColumns) {
        out += ',';
        out += csv::format_number(writable_value(column, s.*member));
    }
}

}  // namespace

std::string frames_csv_header() {
    return "frame,t_ms" + nav_column_names() + ",gt_x_m,gt_y_m,gt_z_m,gt_yaw_deg\n";
}

std::string frames_csv_row(const FrameRow& r) {
    std::string out = std::to_string(r.frame);
    out += ',' + csv::format_ms(r.nav.t_ns);
    append_nav_columns(out, r.nav);
    for (auto [column, v] : {std::pair{"gt_x_m", r.gt.x_m},
                             {"gt_y_m", r.gt.y_m},
                             {"gt_z_m", r.gt.z_m},
                             {"gt_yaw_deg", r.gt.yaw_deg}}) {
        out += ',';
        out += csv::format_number(writable_value(column, v));
    }
    out += '\n';
    return out;
}

std::string navdata_csv_header() {
    return "t_ms" + nav_column_names() + ",seq,state,ctrl_state,battery_pct\n";
}

std::string navdata_csv_row(const NavState& s) {
    std::string out = csv::format_ms(s.t_ns);
    append_nav_columns(out, s);
    out += ',';
    if (s.seq) out += std::to_string(*s.seq);
    out += ',';
    if (s.drone_state) out += hex32(*s.drone_state);
    out += ',';
    if (s.ctrl_state) out += std::to_string(*s.ctrl_state);
    out += ',';
    out += csv::format_number(writable_value("battery_pct", s.battery_pct));
    out += '\n';
    return out;
}

// ---------------------------------------------------------------------------------------------
// Worker-side state: only the worker thread touches it (after create()).

namespace {

struct OutFile {
    fs::path path;
    std::string name;
    int fd = -1;
    std::string buf;
    bool failed = false;
    std::uint64_t good_size = 0;  // bytes on disk, ending with a whole line or record
    // Test hook (DatasetWriterOptions::inject_failure_*): fail once this many bytes are on disk.
    std::optional<std::uint64_t> fail_at;

    std::optional<FileError> open_new(const fs::path& p, std::string n) {
        path = p;
        name = std::move(n);
        fd = ::open(p.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
        if (fd < 0) {
            failed = true;
            return io_error(name, std::string("cannot create: ") + std::strerror(errno));
        }
        return std::nullopt;
    }
    bool is_open() const { return fd >= 0; }
    // One write loop per flush: whole lines/records reach the file together. When a write fails
    // part-way, the file is cut back to its last whole line or record (readers then see a file
    // that ends cleanly) and the failure is recorded; the file takes nothing more.
    bool flush(DatasetWriterStats& st) {
        if (buf.empty()) return !failed;
        if (failed || fd < 0) {
            buf.clear();
            return false;
        }
        std::size_t done = 0;
        while (done < buf.size()) {
            std::size_t want = buf.size() - done;
            bool injected = false;
            if (fail_at) {
                const std::uint64_t on_disk = good_size + done;
                const std::uint64_t room = *fail_at > on_disk ? *fail_at - on_disk : 0;
                if (room < want) {
                    want = static_cast<std::size_t>(room);
                    injected = true;
                }
            }
            int e = ENOSPC;  // an injected failure, or a write that wrote nothing
            if (want > 0) {
                const ssize_t n = ::write(fd, buf.data() + done, want);
                if (n < 0 && errno == EINTR) continue;
                if (n > 0) {
                    done += static_cast<std::size_t>(n);
                    continue;
                }
                if (n < 0) e = errno;
            } else if (!injected) {
                continue;
            }
            failed = true;
            ++st.write_errors;
            // Whole lines and records only: what part of this flush reached the disk goes.
            const bool cut = ::ftruncate(fd, static_cast<off_t>(good_size)) == 0;
            if (st.first_error.empty()) {
                st.first_error = name + ": write failed: " + std::strerror(e);
                if (!cut) st.first_error += " (could not cut it back to its last whole line)";
                st.first_errno = e;
            }
            buf.clear();
            return false;
        }
        good_size += buf.size();
        st.bytes_written += buf.size();
        buf.clear();
        return true;
    }
    void close_file() {
        if (fd >= 0) ::close(fd);
        fd = -1;
    }
};

}  // namespace

struct DatasetWriter::Files {
    DatasetInfo info;
    OutFile frames_csv, navdata_csv, labels_csv, video, raw_nav, raw_pave, raw_chunks, raw_at,
        raw_connections, raw_captures;
    NavAligner aligner;
    DatasetWriterStats st;

    // frames
    std::optional<bool> video_mode;  // decided by the first accepted frame
    bool seen_idr = false;
    std::int64_t next_index = 0;
    std::int64_t durable = 0;  // frames [0, durable) have their pixels on disk
    TimeNs last_frame_t = 0;
    TimeNs last_nav_t = 0;                                 // navdata.csv
    TimeNs last_raw_nav_t = 0;                             // raw/navdata.bin
    TimeNs latest_t = 0;                                   // newest stream time seen in any record
    std::deque<std::optional<FrameLabel>> pending_labels;  // same order as aligner frames
    struct ReadyRow {
        std::int64_t index;
        std::string row;
        std::string label_row;
    };
    std::deque<ReadyRow> ready;

    explicit Files(TimeNs max_wait) : aligner(max_wait) {}

    std::array<OutFile*, 10> files() {
        return {&frames_csv, &navdata_csv, &labels_csv,      &video,        &raw_nav,
                &raw_pave,   &raw_chunks,  &raw_connections, &raw_captures, &raw_at};
    }
    std::size_t buffered() {
        std::size_t n = 0;
        for (OutFile* o : files()) n += o->buf.size();
        return n;
    }
    // The first write failure stops the writer: nothing more goes to any file.
    bool stopped() {
        for (OutFile* o : files())
            if (o->failed) return true;
        return st.write_errors > 0;
    }
    void note_error(const FileError& e) {
        ++st.write_errors;
        if (st.first_error.empty()) st.first_error = to_string(e);
    }
};

DatasetWriter::DatasetWriter(fs::path dir, DatasetWriterOptions opts, const Clock& clock)
    : dir_(std::move(dir)),
      opts_(std::move(opts)),
      clock_(clock),
      t0_(clock.now_ns()),
      queue_(opts_.queue_capacity, QueueFull::RejectNew) {}

Expected<std::unique_ptr<DatasetWriter>, FileError> DatasetWriter::create(
    const fs::path& dir, const DatasetWriterOptions& opts, const Clock& clock) {
    std::error_code ec;
    if (fs::exists(dir, ec)) {
        if (!fs::is_directory(dir, ec) || !fs::is_empty(dir, ec))
            return Unexpected(FileError{FileErrorCode::Io, dir.string(), 0, 0,
                                        "exists and is not an empty directory"});
    }
    fs::create_directories(dir, ec);
    if (ec) return Unexpected(io_error(dir.string(), "cannot create directory: " + ec.message()));
    if (opts.width < 1 || opts.height < 1 || !(opts.fps > 0))
        return Unexpected(FileError{FileErrorCode::OutOfRange, "flight.json", 0, 0,
                                    "width, height and fps must be positive"});
    auto opts2 = opts;
    if (opts2.flush_interval > std::chrono::seconds(1))
        opts2.flush_interval = std::chrono::seconds(1);
    if (opts2.flush_interval <= std::chrono::milliseconds(0))
        opts2.flush_interval = std::chrono::milliseconds(1);
    std::unique_ptr<DatasetWriter> w(new DatasetWriter(dir, opts2, clock));
    auto f = std::make_unique<Files>(opts2.max_nav_wait_ns);
    f->info.camera = opts2.camera;
    f->info.width = opts2.width;
    f->info.height = opts2.height;
    f->info.fps = opts2.fps;
    f->info.calibration = opts2.calibration;
    f->info.source = opts2.source;
    if (auto e = write_file_atomic(dir / "flight.json", flight_json_text(f->info), "flight.json"))
        return Unexpected(*e);
    if (auto e = f->frames_csv.open_new(dir / "frames.csv", "frames.csv")) return Unexpected(*e);
    if (auto e = f->navdata_csv.open_new(dir / "navdata.csv", "navdata.csv")) return Unexpected(*e);
    f->frames_csv.buf = frames_csv_header();
    f->navdata_csv.buf = navdata_csv_header();
    f->frames_csv.flush(f->st);
    f->navdata_csv.flush(f->st);
    if (opts2.write_raw) {
        fs::create_directories(dir / "raw", ec);
        if (ec) return Unexpected(io_error("raw/", "cannot create directory: " + ec.message()));
        if (auto e = f->raw_nav.open_new(dir / "raw/navdata.bin", "raw/navdata.bin"))
            return Unexpected(*e);
        if (auto e = f->raw_pave.open_new(dir / "raw/video.pave", "raw/video.pave"))
            return Unexpected(*e);
        if (auto e = f->raw_chunks.open_new(dir / "raw/video_chunks.bin", "raw/video_chunks.bin"))
            return Unexpected(*e);
        if (auto e = f->raw_at.open_new(dir / "raw/at.log", "raw/at.log")) return Unexpected(*e);
    }
    if (opts2.write_raw) {
        if (auto e = f->raw_connections.open_new(dir / "raw/video_connections.csv",
                                                 "raw/video_connections.csv"))
            return Unexpected(*e);
        // The connection open when the recording began starts at offset 0 (docs/dataset.md 1.1).
        f->raw_connections.buf = "offset,t_us\n0,0\n";
        f->raw_connections.flush(f->st);
        f->st.video_connections = 1;
        if (auto e =
                f->raw_captures.open_new(dir / "raw/capture_times.csv", "raw/capture_times.csv"))
            return Unexpected(*e);
        f->raw_captures.buf = "frame_number,timestamp_ms,t_us\n";
        f->raw_captures.flush(f->st);
    }
    if (!opts2.inject_failure_file.empty()) {
        for (OutFile* o : f->files())
            if (o->name == opts2.inject_failure_file) o->fail_at = opts2.inject_failure_after_bytes;
    }
    if (opts2.write_images) {
        fs::create_directories(dir / "frames", ec);
        if (ec) return Unexpected(io_error("frames/", "cannot create directory: " + ec.message()));
    }
    w->files_ = std::move(f);
    w->stats_.publish(w->files_->st);
    w->worker_ = std::thread([p = w.get()] { p->run(); });
    return w;
}

DatasetWriter::~DatasetWriter() {
    close();
}

bool DatasetWriter::push(Record r) {
    if (stopped_.load(std::memory_order_relaxed)) return false;  // counted by the worker's stats
    if (queue_.push(std::move(r))) {
        enqueued_.fetch_add(1, std::memory_order_relaxed);
        return true;
    }
    return false;
}

bool DatasetWriter::add_navdata(TimeNs recv_ns, std::span<const std::uint8_t> datagram,
                                const std::optional<NavState>& decoded) {
    if (datagram.size() > kMaxRawDatagram) return push(NavIn{recv_ns, {}, decoded});
    return push(NavIn{recv_ns, {datagram.begin(), datagram.end()}, decoded});
}

bool DatasetWriter::take_navdata(TimeNs recv_ns, std::vector<std::uint8_t>&& datagram,
                                 const std::optional<NavState>& decoded) {
    if (datagram.size() > kMaxRawDatagram) return push(NavIn{recv_ns, {}, decoded});
    return push(NavIn{recv_ns, std::move(datagram), decoded});
}

bool DatasetWriter::add_video_bytes(TimeNs recv_ns, std::span<const std::uint8_t> bytes) {
    return push(VideoIn{recv_ns, {bytes.begin(), bytes.end()}});
}

bool DatasetWriter::take_video_bytes(TimeNs recv_ns, std::vector<std::uint8_t>&& bytes) {
    return push(VideoIn{recv_ns, std::move(bytes)});
}

bool DatasetWriter::take_frame(TimeNs capture_ns, std::vector<std::uint8_t>&& access_unit,
                               const cv::Mat& image, std::optional<FrameLabel> label) {
    return push(
        FrameIn{capture_ns, std::move(access_unit), opts_.write_images ? image : cv::Mat(), label});
}

bool DatasetWriter::add_frame(TimeNs capture_ns, std::span<const std::uint8_t> access_unit,
                              const cv::Mat& image, std::optional<FrameLabel> label) {
    return push(FrameIn{capture_ns,
                        {access_unit.begin(), access_unit.end()},
                        opts_.write_images ? image : cv::Mat(),
                        label});
}

bool DatasetWriter::add_video_connection(TimeNs opened_ns) {
    return push(ConnectIn{opened_ns});
}

bool DatasetWriter::add_capture_time(std::uint32_t frame_number, std::uint32_t pave_timestamp_ms,
                                     TimeNs capture_ns) {
    return push(CaptureIn{frame_number, pave_timestamp_ms, capture_ns});
}

bool DatasetWriter::add_at(TimeNs send_ns, std::string_view datagram) {
    return push(AtIn{send_ns, std::string(datagram)});
}

bool DatasetWriter::set_labels(const FlightLabels& labels) {
    return push(LabelsIn{labels});
}

DatasetWriterStats DatasetWriter::stats() const {
    DatasetWriterStats s = stats_.latest().value_or(DatasetWriterStats{});
    s.enqueued = enqueued_.load(std::memory_order_relaxed);
    s.dropped_queue_full = queue_.dropped();
    return s;
}

void DatasetWriter::close() {
    if (closed_.exchange(true)) {
        if (worker_.joinable()) worker_.join();
        return;
    }
    queue_.close();
    if (worker_.joinable()) worker_.join();
}

void DatasetWriter::run() {
    Files& f = *files_;
    // Stream times are whole microseconds, the resolution of raw/, so replaying raw/ gives the
    // very same times (and interpolation weights) as the recording.
    const auto to_stream = [this](TimeNs abs) {
        const TimeNs d = abs - t0_;
        return d >= 0 ? d / 1000 * 1000 : -((-d + 999) / 1000 * 1000);
    };
    const auto us = [](TimeNs t) { return t < 0 ? std::int64_t{0} : t / 1000; };

    auto settle_rows = [&](TimeNs now_stream) {
        std::int64_t index = 0;
        NavState nav;
        while (f.aligner.pop_ready(now_stream, index, nav)) {
            std::optional<FrameLabel> label = std::move(f.pending_labels.front());
            f.pending_labels.pop_front();
            FrameRow row;
            row.frame = index;
            row.nav = nav;
            if (label) row.gt = label->gt;
            if (opts_.row_tap) opts_.row_tap->push(row);  // a full tap counts its own drops
            Files::ReadyRow rr{index, frames_csv_row(row), {}};
            if (label) {
                rr.label_row = std::to_string(index) + ',' + csv::format_number(label->distance_m) +
                               ',' + csv::format_number(label->lateral_m) + '\n';
            }
            f.ready.push_back(std::move(rr));
        }
    };

    // Files opened late (video.h264 at the first frame, labels.csv at the first label) get the
    // test hook's failure point too.
    auto arm = [&](OutFile& o) {
        if (!opts_.inject_failure_file.empty() && o.name == opts_.inject_failure_file)
            o.fail_at = opts_.inject_failure_after_bytes;
    };
    std::uint64_t rows_buffered = 0;  // frames.csv rows appended since the last flush

    // At the first failure: nothing more is written; what was waiting is counted as lost.
    auto stop_writing = [&] {
        if (!f.st.stopped) {
            f.st.stopped = true;
            stopped_ = true;
        }
        for (OutFile* o : f.files()) o->buf.clear();
        f.st.frames_lost_io += f.ready.size();  // frames still in the aligner come here later
        f.ready.clear();
    };

    auto flush_all = [&] {
        if (f.stopped()) {
            stop_writing();
            stats_.publish(f.st);
            return;
        }
        // Whole records everywhere; the first failure stops the rest (stop_writing).
        auto flushed = [&](OutFile& o) {
            if (f.stopped()) return false;
            o.flush(f.st);
            return !f.stopped();
        };
        if (!flushed(f.raw_nav) || !flushed(f.raw_pave) || !flushed(f.raw_chunks) ||
            !flushed(f.raw_connections) || !flushed(f.raw_captures) || !flushed(f.raw_at)) {
            stop_writing();
            stats_.publish(f.st);
            return;
        }
        if (f.video_mode.value_or(false)) {
            if (f.video.flush(f.st) && !f.video.failed) f.durable = f.next_index;
        }
        if (!flushed(f.navdata_csv)) {
            stop_writing();
            stats_.publish(f.st);
            return;
        }
        // Rows go out only for frames whose pixels are on disk.
        while (!f.ready.empty() && f.ready.front().index < f.durable) {
            f.frames_csv.buf += f.ready.front().row;
            if (!f.ready.front().label_row.empty()) {
                if (!f.labels_csv.is_open() && !f.labels_csv.failed) {
                    if (auto e = f.labels_csv.open_new(dir_ / "labels.csv", "labels.csv"))
                        f.note_error(*e);
                    arm(f.labels_csv);
                    f.labels_csv.buf = "frame,distance_m,lateral_m\n";
                }
                f.labels_csv.buf += f.ready.front().label_row;
            }
            f.ready.pop_front();
            ++rows_buffered;  // counted as written once the flush below succeeds
        }
        // Frames whose pixels can never reach the disk any more.
        const bool pixels_dead = f.video_mode.value_or(false) && f.video.failed;
        while (pixels_dead && !f.ready.empty()) {
            f.ready.pop_front();
            ++f.st.frames_lost_io;
        }
        if (flushed(f.frames_csv)) {
            f.st.frames_written += rows_buffered;
            flushed(f.labels_csv);
        } else {
            f.st.frames_lost_io += rows_buffered;  // their rows did not reach frames.csv
        }
        rows_buffered = 0;
        if (f.stopped()) stop_writing();
        ++f.st.flushes;
        stats_.publish(f.st);
    };

    auto on_frame = [&](FrameIn& in) {
        TimeNs t = to_stream(in.capture_ns);
        // frames.csv t_ms strictly increases (docs/dataset.md 1.1): a capture time equal to or
        // before the previous frame's moves 1 us past it (counted; the capture clock should not do
        // it).
        if (f.next_index > 0 && t <= f.last_frame_t) {
            t = f.last_frame_t + 1000;
            ++f.st.frame_time_adjusted;
        }
        const bool have_au = !in.au.empty();
        const bool have_img = opts_.write_images && !in.image.empty();
        if (!f.video_mode) {
            if (!have_au && !have_img) {
                ++f.st.frames_skipped;
                return;
            }
            f.video_mode = have_au;
        }
        if (*f.video_mode) {
            if (!have_au) {
                ++f.st.frames_skipped;
                return;
            }
            if (!f.seen_idr) {
                if (!annexb_has_idr(in.au)) {
                    ++f.st.frames_skipped;
                    return;
                }
                f.seen_idr = true;
            }
            if (!f.video.is_open() && !f.video.failed) {
                if (auto e = f.video.open_new(dir_ / "video.h264", "video.h264")) f.note_error(*e);
                arm(f.video);
            }
            if (f.video.failed) {
                ++f.st.frames_lost_io;
                return;
            }
        } else if (!have_img) {
            ++f.st.frames_skipped;
            return;
        }
        const std::int64_t index = f.next_index;
        if (have_img) {
            std::vector<std::uint8_t> png;
            bool ok = false;
            try {
                ok = cv::imencode(".png", in.image, png);
            } catch (const cv::Exception&) {
                ok = false;
            }
            const std::string name = "frames/" + frame_file_name(index, ".png");
            std::optional<FileError> e;
            if (!ok) {
                e = io_error(name, "PNG encoding failed");
            } else {
                e = write_file_atomic(
                    dir_ / name,
                    std::string_view(reinterpret_cast<const char*>(png.data()), png.size()), name);
            }
            if (e) {
                f.note_error(*e);
                if (!*f.video_mode) {
                    ++f.st.frames_lost_io;
                    return;
                }
            }
        }
        if (*f.video_mode) {
            f.video.buf.append(reinterpret_cast<const char*>(in.au.data()), in.au.size());
        }
        ++f.next_index;
        if (!*f.video_mode) f.durable = f.next_index;  // the image file is complete already
        f.last_frame_t = t;
        f.latest_t = std::max(f.latest_t, t);
        f.aligner.push_frame(index, t);
        f.pending_labels.push_back(in.label);
    };

    auto process = [&](Record& r) {
        if (f.st.stopped) {
            ++f.st.records_lost_stopped;
            if (std::holds_alternative<FrameIn>(r)) ++f.st.frames_lost_io;
            return;
        }
        if (auto* c = std::get_if<ConnectIn>(&r)) {
            if (f.raw_connections.is_open() && f.raw_pave.is_open()) {
                const std::uint64_t offset = f.raw_pave.good_size + f.raw_pave.buf.size();
                const TimeNs t = std::max<TimeNs>(to_stream(c->opened_ns), 0);
                f.raw_connections.buf +=
                    std::to_string(offset) + ',' + std::to_string(us(t)) + '\n';
                ++f.st.video_connections;
            }
            return;
        }
        if (auto* ci = std::get_if<CaptureIn>(&r)) {
            if (f.raw_captures.is_open()) {
                // The same rounding as frames.csv's t_ms (whole microseconds of stream time).
                f.raw_captures.buf += std::to_string(ci->frame_number) + ',' +
                                      std::to_string(ci->pave_timestamp_ms) + ',' +
                                      std::to_string(to_stream(ci->capture_ns) / 1000) + '\n';
            }
            return;
        }
        if (auto* n = std::get_if<NavIn>(&r)) {
            // raw/navdata.bin (every datagram) and navdata.csv (the accepted samples) arrive as
            // two streams, each in its own time order: each keeps its own.
            const TimeNs t_in = to_stream(n->recv_ns);
            f.latest_t = std::max(f.latest_t, t_in);
            if (f.raw_nav.is_open() && !n->bytes.empty()) {
                const TimeNs t = std::max(t_in, f.last_raw_nav_t);
                f.last_raw_nav_t = t;
                append_raw_record(f.raw_nav.buf, us(t), n->bytes);
                ++f.st.raw_navdata_records;
            }
            if (n->nav) {
                const TimeNs t = std::max(t_in, f.last_nav_t);
                f.last_nav_t = t;
                NavState s = *n->nav;
                s.t_ns = t;
                f.navdata_csv.buf += navdata_csv_row(s);
                ++f.st.navdata_written;
                f.aligner.push_nav(s);
            }
        } else if (auto* v = std::get_if<VideoIn>(&r)) {
            const TimeNs t = to_stream(v->recv_ns);
            f.latest_t = std::max(f.latest_t, t);
            if (f.raw_pave.is_open()) {
                f.raw_pave.buf.append(reinterpret_cast<const char*>(v->bytes.data()),
                                      v->bytes.size());
                append_chunk_record(f.raw_chunks.buf, us(t),
                                    static_cast<std::uint32_t>(v->bytes.size()));
                ++f.st.video_chunks;
            }
        } else if (auto* fr = std::get_if<FrameIn>(&r)) {
            on_frame(*fr);
        } else if (auto* a = std::get_if<AtIn>(&r)) {
            if (f.raw_at.is_open()) {
                append_at_line(f.raw_at.buf, us(to_stream(a->send_ns)), a->datagram);
                ++f.st.at_records;
            }
        } else if (auto* l = std::get_if<LabelsIn>(&r)) {
            nlohmann::json j = nlohmann::json::object();
            if (!l->labels.json.empty()) {
                j = nlohmann::json::parse(l->labels.json, nullptr, false);
                if (!j.is_object()) j = nlohmann::json::object();
            }
            j["scenario"] = to_string(l->labels.scenario);
            auto e = opts_.inject_failure_file == "labels.json"
                         ? std::optional(io_error("labels.json", "write failed: injected ENOSPC"))
                         : write_file_atomic(dir_ / "labels.json", j.dump(2) + "\n", "labels.json");
            if (e) {
                f.note_error(*e);
                f.st.first_errno = ENOSPC;
                stop_writing();
            }
        }
    };

    TimeNs next_flush = clock_.now_ns() + std::chrono::nanoseconds(opts_.flush_interval).count();
    while (true) {
        const TimeNs now = clock_.now_ns();
        const TimeNs wait_ns = std::clamp<TimeNs>(next_flush - now, 1'000'000, 50'000'000);
        auto r = queue_.pop_for(std::chrono::nanoseconds(wait_ns));
        if (r) {
            process(*r);
        } else if (queue_.closed()) {
            break;
        }
        // While idle, wall time moves the stream on (navdata may have stopped); while busy only
        // the records do, so a backlog does not time frames out before their navdata is read.
        TimeNs stream_now = f.latest_t;
        if (queue_.size() == 0) stream_now = std::max(stream_now, to_stream(clock_.now_ns()));
        settle_rows(stream_now);
        if (clock_.now_ns() >= next_flush || f.buffered() > opts_.max_buffer_bytes) {
            flush_all();
            next_flush = clock_.now_ns() + std::chrono::nanoseconds(opts_.flush_interval).count();
        }
    }
    // Closing: every frame gets its row (nearest navdata when nothing came after it).
    f.aligner.finish();
    settle_rows(f.latest_t);
    flush_all();
    // flight.json with the frame count; after a failure the one written at the start stays (it
    // has no count, and frames.csv says how many frames there are).
    if (!f.st.stopped) {
        f.info.frames = f.st.frames_written;
        auto e =
            opts_.inject_failure_file == "flight.json"
                ? std::optional(io_error("flight.json", "write failed: injected ENOSPC"))
                : write_file_atomic(dir_ / "flight.json", flight_json_text(f.info), "flight.json");
        if (e) {
            f.note_error(*e);
            f.st.first_errno = ENOSPC;
            f.st.stopped = true;
        }
    }
    for (OutFile* o : f.files()) {
        if (o->fd >= 0 && ::fsync(o->fd) != 0) f.note_error(io_error(o->name, "fsync failed"));
        o->close_file();
    }
    f.st.closed = true;
    stats_.publish(f.st);
}

}  // namespace gs::dataset
