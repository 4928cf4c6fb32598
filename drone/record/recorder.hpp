#pragma once
// Recording a live flight as a dataset (docs/dataset.md 1.1): attaches to a running DroneLink
// through its recording subscriptions and drains them on its own thread into a DatasetWriter:
//   raw/           every byte received and sent (raw events), with the video connections;
//   navdata.csv    the navdata samples the link accepted, in the order it accepted them;
//   video.h264     the access units the link's video receiver turned into a picture (the
//                  receiver's own units, never re-framed here), from the recording's first IDR;
//   frames.csv     one row per kept unit, at its capture time, attitude interpolated by the writer.
// A unit that gave no picture (its reference lost to a reset or a gap, damaged beyond repair, not
// H.264) is not kept and is counted as a drop with its reason, so a recording whose counters say 0
// drops replays every frame. A failing disk stops the recording at once with a message naming the
// dataset and the disk (status().error); what is on disk opens; the link is not affected. Attached
// to the virtual drone as well, it writes the ground truth: labels.json (the scene's scenario) and
// labels.csv + gt_* columns (the pose at each frame's capture time against the scene's target
// obstacle).
//
// Nothing here can block the link: the subscriptions reject what does not fit and the writer's
// queue does the same; every loss is counted in status().drops. status() is a latest-value read,
// cheap enough for a GUI frame.

#include "drone/core/sample.hpp"
#include "drone/core/sync.hpp"
#include "drone/dataset/writer.hpp"
#include "drone/link/drone_link.hpp"
#include "drone/record/ground_truth.hpp"

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace gs::record {

struct RecorderOptions {
    // size, fps, calibration, source of flight.json; queue sizes. write_raw stays on; the
    // camera comes from `camera` below.
    dataset::DatasetWriterOptions writer;
    // flight.json's camera, writer.calibration being its calibration. Unset: the camera the
    // drone's configuration reports (video:video_channel in the link's last configuration dump;
    // front when the link has none); writer.calibration is then taken as writer.camera's and
    // replaced by the reported camera's default when they differ. Without a writer.calibration,
    // the camera's default calibration is written.
    std::optional<CameraId> camera;
    std::size_t raw_queue = 8192;  // link raw events (navdata, video chunks, AT): ~10 s at 200 Hz
    std::size_t access_unit_queue = 256;  // ~8 s of frames
    // > 0: every recorded frame (dataset index, frames.csv time and attitude, decoded image) is
    // also handed to frames() for a live consumer (the obstacle pipeline), as replay will see it.
    std::size_t frame_tap = 0;
    // How long a frame waits for a ground-truth sample after its capture (virtual drone only).
    TimeNs truth_wait_ns = 100'000'000;
};

struct RecorderStatus {
    bool recording = false;
    std::string path;
    double duration_s = 0;             // stream time since start()
    std::uint64_t frames = 0;          // frames.csv rows written
    std::uint64_t navdata = 0;         // navdata.csv rows written
    std::uint64_t at = 0;              // AT datagrams in raw/at.log
    std::uint64_t bytes = 0;           // written to disk
    std::uint64_t drops = 0;           // everything lost, the sum of the three below
    std::uint64_t dropped_link = 0;    // link subscription queues full (recorder too slow)
    std::uint64_t dropped_writer = 0;  // writer queue full or frames lost to I/O (disk too slow)
    std::uint64_t dropped_tap = 0;     // frames the live consumer did not take in time
    std::uint64_t frames_skipped = 0;  // before the first IDR, or begun before the recording
    // Frames not kept, by reason (each also in drops):
    std::uint64_t dropped_reference_lost = 0;  // P-frames after a video reset or a frame gap
    std::uint64_t dropped_no_picture = 0;      // damaged beyond what the decoder conceals
    std::uint64_t dropped_not_h264 = 0;        // another codec on the video port
    std::uint64_t dropped_cut_by_reset = 0;    // a frame a connection ended inside
    std::uint64_t concealed = 0;               // kept, with damage the decoder concealed
    std::uint64_t video_connections = 0;       // raw/video_connections.csv rows
    std::uint64_t navdata_accepted = 0;        // samples the link accepted while recording
    // How many samples the link accepted from the first recorded one to the last, both included
    // (RawEvent::accepted_ordinal): equal to navdata_accepted when none was lost in between.
    std::uint64_t navdata_link_span = 0;
    std::uint64_t write_errors = 0;
    bool disk_full = false;  // stopped because the disk is full (or another write failed)
    std::string error;       // the first I/O error, as the pilot reads it
    bool labels = false;     // ground truth is being written
    double cpu_ms = 0;       // CPU time of the recorder's own thread (not the writer's)
    TimeNs start_ns = 0;     // the link's clock at the dataset's t = 0 (frames.csv t_ms origin)
};

// Why Recorder::start() failed; `message` is the sentence shown to the user.
struct StartError {
    enum class Code { AlreadyRecording, Dataset };
    Code code;
    std::string message;
};

class Recorder {
public:
    // `link` (and `truth`, when given) must outlive the recorder.
    explicit Recorder(link::DroneLink& link, const GroundTruthSource* truth = nullptr);
    ~Recorder();
    Recorder(const Recorder&) = delete;
    Recorder& operator=(const Recorder&) = delete;

    // Creates the dataset in `dir` (new or empty) and starts recording. Fails when already
    // recording or the directory cannot be written.
    [[nodiscard]] Expected<void, StartError> start(const std::filesystem::path& dir,
                                                   RecorderOptions opts = {});
    // Stops, writes everything still queued, closes the dataset; returns the final status.
    // Idempotent.
    RecorderStatus stop();
    RecorderStatus status() const;
    bool recording() const { return running_.load(); }

    // The recorded-frame tap (RecorderOptions::frame_tap), null otherwise. Closed by stop()
    // once the last frame went in.
    std::shared_ptr<BoundedQueue<FrameSample>> frames() const { return tap_; }

private:
    struct State;
    void run();
    void write_collisions(const std::filesystem::path& dir, TimeNs start, TimeNs end,
                          const std::vector<TimeNs>& frame_capture_ns) const;

    link::DroneLink& link_;
    const GroundTruthSource* truth_;
    std::atomic<bool> running_{false};
    std::atomic<bool> stop_{false};
    std::unique_ptr<State> state_;  // the recorder thread's own (set before it starts)
    std::shared_ptr<BoundedQueue<FrameSample>> tap_;
    std::thread thread_;
    LatestValue<RecorderStatus> status_;
};

// labels.json's scenario from a scene's ("left", "right", "center", "none"; else none).
dataset::Scenario scenario_of(const std::string& name);

}  // namespace gs::record
