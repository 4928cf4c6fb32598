#pragma once
// Recording a flight as a dataset (docs/dataset.md) while flying. The link threads hand over what
// they receive and send through add_*(), which never block: records go through a bounded queue to a
// worker thread that does all file I/O. A full queue drops records and counts them; it never
// stalls flight control. Files are flushed at least every flush_interval (<= 1 s) in an order
// that keeps the dataset readable if the process is killed: video bytes before the frames.csv
// rows that describe them, whole lines and whole records only.
//
// A failing disk (full, or any write error) stops the writer at the first failure: the file that
// failed is cut back to its last whole line or record, nothing more is written to any file, the
// records still queued or buffered are counted as lost, and what is on disk stays a dataset that
// opens and replays (frames.csv describes only frames whose bytes are in video.h264). stats()
// says so (stopped, first_error naming the file and the reason) for the recorder to report.

#include "drone/core/clock.hpp"
#include "drone/core/sample.hpp"
#include "drone/core/sync.hpp"
#include "drone/dataset/dataset.hpp"

#include <opencv2/core.hpp>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <thread>
#include <variant>
#include <vector>

namespace gs::dataset {

struct DatasetWriterOptions {
    CameraId camera = CameraId::Front;
    int width = 640, height = 360;
    double fps = 30;
    std::optional<CameraCalibration> calibration;  // written to flight.json when set
    std::string source = "recorded";
    bool write_raw = true;      // raw/ captures
    bool write_images = false;  // frames/NNNNNN.png from the decoded images given to add_frame
    std::size_t queue_capacity = 2048;
    std::chrono::milliseconds flush_interval{250};  // at most 1 s
    TimeNs max_nav_wait_ns = 500'000'000;     // how long a frame waits for the navdata after it
    std::size_t max_buffer_bytes = 4u << 20;  // flush early when buffered data exceeds this
    // When set, every frames.csv row is also pushed here as soon as its attitude is settled
    // (before it reaches the disk): a live consumer sees exactly what replay will read.
    std::shared_ptr<BoundedQueue<FrameRow>> row_tap;
    // Tests: the write that would take `inject_failure_file` (a dataset-relative name such as
    // "frames.csv" or "raw/video.pave") past `inject_failure_after_bytes` writes only up to that
    // size and then fails with ENOSPC, as a full disk does.
    std::string inject_failure_file;
    std::uint64_t inject_failure_after_bytes = 0;
};

struct DatasetWriterStats {
    std::uint64_t enqueued = 0;
    std::uint64_t dropped_queue_full = 0;  // add_*() returned false
    std::uint64_t frames_written = 0;      // frames.csv rows
    std::uint64_t frames_skipped = 0;      // before the first IDR, or no bytes/image to write
    std::uint64_t frames_lost_io = 0;      // dropped because a file could not be written
    std::uint64_t navdata_written = 0;     // navdata.csv rows
    std::uint64_t raw_navdata_records = 0;
    std::uint64_t at_records = 0;
    std::uint64_t video_chunks = 0;
    std::uint64_t bytes_written = 0;
    std::uint64_t write_errors = 0;
    std::uint64_t flushes = 0;
    std::uint64_t video_connections = 0;     // raw/video_connections.csv rows
    std::uint64_t frame_time_adjusted = 0;   // capture times moved 1 us past an equal predecessor
    std::uint64_t records_lost_stopped = 0;  // records dropped because the writer had stopped
    std::string first_error;                 // first I/O error, empty when none
    int first_errno = 0;                     // its errno (ENOSPC: the disk is full), 0 when none
    bool stopped = false;                    // a write failed: nothing more is written (see above)
    bool closed = false;
};

// Per-frame ground truth from the virtual drone (labels.csv).
struct FrameLabel {
    double distance_m = kUnknown;
    double lateral_m = kUnknown;
    GroundTruthPose gt;  // frames.csv gt_* columns (NaN: not written)
};

class DatasetWriter {
public:
    // Creates `dir` (it must not exist or be empty), writes flight.json and the CSV headers, starts
    // the worker. Stream time 0 is clock.now_ns() at this call (times are kept in whole
    // microseconds, the resolution of raw/): every *_ns argument below is on
    // the same monotonic clock.
    static Expected<std::unique_ptr<DatasetWriter>, FileError> create(
        const std::filesystem::path& dir, const DatasetWriterOptions& opts, const Clock& clock);
    ~DatasetWriter();
    DatasetWriter(const DatasetWriter&) = delete;
    DatasetWriter& operator=(const DatasetWriter&) = delete;

    // All return false (and count a drop) when the queue is full or the writer closed.
    // One received navdata datagram and, when it parsed, its state (t_ns is replaced by recv time).
    bool add_navdata(TimeNs recv_ns, std::span<const std::uint8_t> datagram,
                     const std::optional<NavState>& decoded);
    // take_*: the same as add_*, taking over the bytes (no copy).
    bool take_navdata(TimeNs recv_ns, std::vector<std::uint8_t>&& datagram,
                      const std::optional<NavState>& decoded);
    // A chunk of the video TCP stream as received (raw/video.pave).
    bool add_video_bytes(TimeNs recv_ns, std::span<const std::uint8_t> bytes);
    bool take_video_bytes(TimeNs recv_ns, std::vector<std::uint8_t>&& bytes);
    // A new video TCP connection begins with the next video bytes (docs/dataset.md 1.1
    // raw/video_connections.csv). The bytes before the first call are the connection that was
    // open when the recording began (offset 0).
    bool add_video_connection(TimeNs opened_ns);
    // The capture time the live video receiver gave a PaVE frame whose bytes are in raw/ (raw/
    // capture_times.csv, an extension: the receiver's clock model has history from before the
    // recording, so replay takes the times it used instead of re-deriving them).
    bool add_capture_time(std::uint32_t frame_number, std::uint32_t pave_timestamp_ms,
                          TimeNs capture_ns);
    // One frame: its Annex-B access unit (video.h264) and/or decoded image (frames/ when
    // write_images), captured at `capture_ns`. Frames before the first IDR are skipped.
    bool add_frame(TimeNs capture_ns, std::span<const std::uint8_t> access_unit,
                   const cv::Mat& image = {}, std::optional<FrameLabel> label = std::nullopt);
    bool take_frame(TimeNs capture_ns, std::vector<std::uint8_t>&& access_unit,
                    const cv::Mat& image = {}, std::optional<FrameLabel> label = std::nullopt);
    // One AT datagram as sent.
    bool add_at(TimeNs send_ns, std::string_view datagram);
    // labels.json (rewritten on each call).
    bool set_labels(const FlightLabels& labels);

    // Drains the queue, settles pending frames, rewrites flight.json with the frame count,
    // flushes and joins the worker. Idempotent; the destructor calls it.
    void close();

    DatasetWriterStats stats() const;
    TimeNs start_ns() const { return t0_; }
    const std::filesystem::path& dir() const { return dir_; }

private:
    struct NavIn {
        TimeNs recv_ns;
        std::vector<std::uint8_t> bytes;
        std::optional<NavState> nav;
    };
    struct VideoIn {
        TimeNs recv_ns;
        std::vector<std::uint8_t> bytes;
    };
    struct FrameIn {
        TimeNs capture_ns;
        std::vector<std::uint8_t> au;
        cv::Mat image;
        std::optional<FrameLabel> label;
    };
    struct AtIn {
        TimeNs send_ns;
        std::string datagram;
    };
    struct LabelsIn {
        FlightLabels labels;
    };
    struct ConnectIn {
        TimeNs opened_ns;
    };
    struct CaptureIn {
        std::uint32_t frame_number, pave_timestamp_ms;
        TimeNs capture_ns;
    };
    using Record = std::variant<NavIn, VideoIn, FrameIn, AtIn, LabelsIn, ConnectIn, CaptureIn>;
    struct Files;

    DatasetWriter(std::filesystem::path dir, DatasetWriterOptions opts, const Clock& clock);
    bool push(Record r);
    void run();

    std::filesystem::path dir_;
    DatasetWriterOptions opts_;
    const Clock& clock_;
    TimeNs t0_;
    BoundedQueue<Record> queue_;
    LatestValue<DatasetWriterStats> stats_;
    std::atomic<std::uint64_t> enqueued_{0};
    std::unique_ptr<Files> files_;
    std::thread worker_;
    std::atomic<bool> closed_{false};
    std::atomic<bool> stopped_{false};  // set by the worker at the first write failure
};

// flight.json text for `info` (what the writer and the thesis import write).
std::string flight_json_text(const DatasetInfo& info);
// frames.csv header and one row, as the writer writes them.
std::string frames_csv_header();
std::string frames_csv_row(const FrameRow& row);
std::string navdata_csv_header();
std::string navdata_csv_row(const NavState& s);

}  // namespace gs::dataset
