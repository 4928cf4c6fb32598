#pragma once
// Recording a flight as a dataset (DATASET.md) while flying. The link threads hand over what they
// receive and send through add_*(), which never block: records go through a bounded queue to a
// worker thread that does all file I/O. A full queue or a failing disk drops records and counts
// them; it never stalls flight control. Files are flushed at least every flush_interval (<= 1 s)
// in an order that keeps the dataset readable if the process is killed: video bytes before the
// frames.csv rows that describe them, whole lines and whole records only.

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
    std::string first_error;  // first I/O error, empty when none
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
    using Record = std::variant<NavIn, VideoIn, FrameIn, AtIn, LabelsIn>;
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
};

// flight.json text for `info` (what the writer and the thesis import write).
std::string flight_json_text(const DatasetInfo& info);
// frames.csv header and one row, as the writer writes them.
std::string frames_csv_header();
std::string frames_csv_row(const FrameRow& row);
std::string navdata_csv_header();
std::string navdata_csv_row(const NavState& s);

}  // namespace gs::dataset
