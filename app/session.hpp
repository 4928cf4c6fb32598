#pragma once
// The window's session: owns the current source (a real drone through a DroneLink, the built-in
// virtual drone on loopback with a DroneLink to it, or a recorded dataset replayed through a
// DatasetSource) and the pipeline thread that runs frames through the ObstaclePipeline.
//
// The video's camera decides what runs on a frame: the obstacle classifier on the front camera,
// visual odometry (app/live_odometry.hpp) on the bottom camera. Live, the camera is the one the
// drone's configuration reports (video:video_channel in its last configuration dump, read back
// after every camera switch); a replayed dataset names it in flight.json.
//
// Threads: the caller (the UI thread) only posts requests to a bounded queue and reads
// latest-value slots; the session thread opens and closes sources (binding sockets, loading a
// scene and its textures, opening a dataset: all slow or failing), pulls frames (live: a bounded
// subscription of 2 frames, oldest dropped; replay: the source's pacing) through the classifier
// and publishes the results. Flight commands go straight to the link (DroneLink::submit never
// blocks), so the UI never waits on the network, the disk or the classifier.
//
// The implementation is one file per concern (app/session_current.hpp lists them): source
// lifecycle, replay control, recording control, camera tracking, frame processing, and the
// requests, handled by one visitor with a handler per request type (a new type left unhandled
// does not compile).

#include "app/assist_gate.hpp"
#include "app/live_odometry.hpp"
#include "app/pipeline.hpp"
#include "drone/core/clock.hpp"
#include "drone/core/file_error.hpp"
#include "drone/core/object_pool.hpp"
#include "drone/core/sample.hpp"
#include "drone/core/sync.hpp"
#include "drone/dataset/dataset_source.hpp"
#include "drone/link/drone_link.hpp"
#include "drone/record/recorder.hpp"
#include "drone/sim/virtual_drone.hpp"
#include "vision/calibration_mode.hpp"
#include "vision/classifier.hpp"

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <variant>
#include <vector>

namespace gs::app {

enum class SessionSource { None, Drone, Sim, Replay };
const char* to_string(SessionSource s);

// ---- Requests (UI thread -> session thread) -------------------------------------------------

struct ConnectDrone {
    std::string address;  // "192.168.1.1"
};
struct StartSim {
    std::string scenario;    // shipped scene name or scene JSON path; empty = "warehouse"
    bool autopilot = false;  // fly the scene's scripted flight after boot
};
struct OpenReplay {
    std::string path;  // dataset directory
};
struct CloseSource {};
struct ReplayPlay {
    bool play = true;
};
struct ReplayStep {
    int delta = 1;  // +1 next frame, -1 previous frame
};
struct ReplaySeek {
    std::int64_t frame = 0;
};
struct ReplaySpeed {
    double speed = 1.0;  // clamped to [0.25, 8]
};
struct ReplayLoop {
    bool loop = false;
};
struct SelectClassifier {
    std::string name;
};
struct SetClassifierParam {
    std::string name;
    double value = 0;
};
struct RecordStart {
    std::string dir;  // empty: a new timestamped folder under SessionOptions::record_root
};
struct RecordStop {};
// Calibration mode (the window's Calibration window): vision::CalibrationMode's worker thread
// detects the board in the video and keeps views (vision/calibration_mode.hpp).
struct CalibrationStart {
    vision::CalibrationBoard board;  // (re)starts the mode: earlier views are forgotten
};
struct CalibrationStop {};
// Keeps the current frame as a view when the board is found and the view adds coverage.
struct CalibrationCapture {};
struct CalibrationUndo {};   // forgets the last kept view
struct CalibrationReset {};  // forgets every view
struct CalibrationAutoCapture {
    // Capture every checked frame that adds coverage (at most one view per
    // SessionOptions::calibration_auto_interval_ms).
    bool on = false;
};
// Calibrates from the kept views, saves the result as the drone's calibration
// (SessionOptions::calibration_file) and applies it to the pipeline at once.
struct CalibrationSave {};
// Uses this calibration in the pipeline from now on (until the source changes).
struct ApplyCalibration {
    CameraCalibration camera;
    std::string origin;  // file or description, shown in the window
};
// An intervention of the assist on the pilot's path (app/pilot_path.hpp), for the recording in
// progress: written to its assist.csv when it stops (docs/dataset.md). Ignored when not recording.
struct AssistRecord {
    Intervention what;
};
using SessionRequest =
    std::variant<ConnectDrone, StartSim, OpenReplay, CloseSource, ReplayPlay, ReplayStep,
                 ReplaySeek, ReplaySpeed, ReplayLoop, SelectClassifier, SetClassifierParam,
                 RecordStart, RecordStop, CalibrationStart, CalibrationStop, CalibrationCapture,
                 CalibrationUndo, CalibrationReset, CalibrationAutoCapture, CalibrationSave,
                 ApplyCalibration, AssistRecord>;

// ---- Published state (session thread -> readers) --------------------------------------------

// The current source. Changes only when a source opens or closes (`id` increments each time).
struct SourceInfo {
    SessionSource kind = SessionSource::None;
    std::uint64_t id = 0;
    std::string address;   // drone address ("127.0.0.1:<port>" for the virtual drone)
    std::string scenario;  // virtual drone scene name
    std::string path;      // replayed dataset
    std::string error;     // why the last open failed (kind is then None), else empty
    std::shared_ptr<link::DroneLink> link;             // Drone and Sim
    std::shared_ptr<sim::VirtualDrone> virtual_drone;  // Sim
    // Open requests (ConnectDrone, StartSim, OpenReplay) handled so far, failed ones included:
    // while Session::opening() counts more, a source is being opened.
    std::uint64_t opens_handled = 0;
};

// The open request posted last (published by request(), before the session thread sees it), so
// the window can say "Starting virtual drone..." from the first frame.
struct OpeningInfo {
    std::uint64_t count = 0;  // open requests posted so far
    SessionSource kind = SessionSource::None;
    std::string what;  // scenario, drone address or dataset path
};

struct ReplayInfo {
    bool open = false;
    std::string path;
    std::int64_t frame = -1;  // index of the frame shown last (-1 before the first)
    std::int64_t frame_count = 0;
    double fps = kUnknown;
    bool playing = false;
    double speed = 1.0;
    bool loop = false;
    bool ended = false;
    std::string error;
    std::vector<std::string> missing_inputs;  // inputs the classifier lacks, with the cost
};

// The recorder's status plus the free space where it writes.
struct RecordingInfo {
    record::RecorderStatus status;
    double disk_free_bytes = kUnknown;
    std::string last_path;  // the last dataset written (kept after stop)
};

struct ParamState {
    vision::ParamInfo info;
    double default_value = 0;
};

struct ClassifierInfo {
    std::string active;
    std::vector<std::string> available;
    std::vector<ParamState> params;
    std::string error;  // last rejected selection / parameter, empty if none
};

// One processed frame: the frame itself (image shared, never rewritten afterwards) and a copy
// of what ran on it: the classifier's result (front camera; empty on bottom-camera frames) or
// the visual odometry's sample and paths (bottom camera; `odometry.active` false otherwise).
struct PipelineOutput {
    std::uint64_t source_id = 0;
    FrameSample frame;
    CameraId camera = CameraId::Front;  // the camera the frame came from
    vision::FrameResult result;
    std::string classifier;  // the classifier selected (it ran only when camera is Front)
    OdometryOutput odometry;
    double fps = kUnknown;             // frames classified per second
    double latency_ms = kUnknown;      // receive (live) to classified
    std::uint64_t frames_dropped = 0;  // frames the pipeline did not keep up with (live)
    // Republished because no live frame came for kGapNs: the regions are unknown (StaleVideo).
    bool stale = false;
};

// The camera model in use for the video shown now (changes with the source, the camera and on
// ApplyCalibration): the classifier's on the front camera, the odometry's on the bottom one.
struct CalibrationInUse {
    CameraCalibration camera;
    CameraId which = CameraId::Front;
    std::string origin;  // "dataset", "assets default", a file path ...
    std::uint64_t source_id = 0;
};

struct SessionOptions {
    std::string classifier = std::string(vision::kDefaultClassifier);
    double sim_battery_pct = 100.0;  // the virtual drone's battery at boot
    bool sim_video = true;
    bool replay_autoplay = true;  // a replay starts playing when opened
    // Replay frames advance only on ReplayStep (nothing paced): the offscreen window uses it so
    // that window frame k shows dataset frame k, whatever the machine's speed.
    bool replay_lockstep = false;
    std::size_t frame_queue = 2;  // live frames waiting for the classifier
    // Where recordings go when RecordStart names no folder: <root>/<YYYY-MM-DD_HHMMSS>.
    // Empty: $HOME/ardrone-gs/flights (./flights without HOME).
    std::filesystem::path record_root;
    // The drone's own calibration: the calibration mode saves here, and a real drone connected
    // from the window uses it when the file exists (else assets/' default). Empty: the mode
    // calibrates and applies but cannot save.
    std::filesystem::path calibration_file;
    // The calibration worker checks at most one frame per this many ms (0: every frame it gets),
    // and auto capture keeps at most one view per calibration_auto_interval_ms.
    int calibration_interval_ms = 150;
    int calibration_auto_interval_ms = 1000;
    // Tests: a recording's writer fails as a full disk does once this dataset-relative file
    // ("frames.csv", "raw/video.pave" ...) would pass record_inject_failure_after_bytes
    // (dataset::DatasetWriterOptions::inject_failure_file). Empty: no injected failure.
    std::string record_inject_failure_file;
    std::uint64_t record_inject_failure_after_bytes = 0;
};

// Writes <dir>/assist.csv (docs/dataset.md) from a recording's interventions; `start_ns`: the
// recording's t = 0 on the link's clock. The problem when the file cannot be written.
[[nodiscard]] std::optional<FileError> write_assist_csv(const std::filesystem::path& dir,
                                                        TimeNs start_ns,
                                                        const std::vector<Intervention>& rows);

// $HOME/ardrone-gs/flights, or ./flights.
std::filesystem::path default_record_root();

class Session {
public:
    explicit Session(SessionOptions options = {}, Clock& clock = SteadyClock::instance());
    ~Session();
    Session(const Session&) = delete;
    Session& operator=(const Session&) = delete;

    // Posts a request to the session thread. False when the queue is full (counted, reported).
    bool request(SessionRequest r);

    // Latest values (any thread).
    const LatestValue<SourceInfo>& source() const { return source_; }
    const LatestValue<OpeningInfo>& opening() const { return opening_; }
    const LatestValue<ReplayInfo>& replay() const { return replay_; }
    const LatestValue<ClassifierInfo>& classifier() const { return classifier_; }
    const LatestValue<std::shared_ptr<const PipelineOutput>>& output() const { return output_; }
    // Replay telemetry (the dataset's navdata stream at the replay position).
    const LatestValue<NavState>& replay_nav() const { return replay_nav_; }
    const LatestValue<RecordingInfo>& recording() const { return recording_; }
    const LatestValue<CalibrationInUse>& calibration() const { return calibration_; }
    // The calibration mode (inactive until a CalibrationStart).
    const LatestValue<vision::CalibrationModeState>& calibration_mode() const {
        return calibration_mode_;
    }
    // Human-readable events from the session thread ("virtual drone 'warehouse' on 127.0.0.1").
    // Bounded; the oldest is dropped when nobody reads.
    std::optional<std::string> next_message() { return messages_.try_pop(); }

    std::uint64_t requests_dropped() const { return requests_.dropped(); }
    // Frames classified since construction (any source).
    std::uint64_t frames_processed() const { return processed_.load(); }

private:
    struct Current;  // the open source (app/session_current.hpp)

    // The thread, requests (the visitor) and publishing: app/session.cpp.
    void run();
    void handle(SessionRequest& r);
    void message(std::string m);
    void publish_source(std::string error = {});
    void publish_replay();
    void publish_classifier(std::string error = {});
    // Source lifecycle: app/session_sources.cpp.
    void open_drone(const std::string& address);
    void open_sim(const StartSim& s);
    void open_replay(const std::string& path);
    void close_current();
    CameraCalibration drone_calibration(std::string& origin) const;
    // Replay control: app/session_replay.cpp.
    bool replay_open();  // false (and said so) without a replay
    void replay_control(const ReplayPlay& q);
    void replay_control(const ReplayStep& q);
    void replay_control(const ReplaySeek& q);
    void replay_control(const ReplaySpeed& q);
    void replay_control(const ReplayLoop& q);
    bool replay_tick(TimeNs& wait_ns);
    bool replay_step(int delta);
    // Recording control: app/session_recording.cpp. A recorder that stopped itself (a write
    // failed: a full disk) is stopped by the next publish_recording(), which says so once.
    void record_start(const std::string& dir);
    void record_stop();
    void record_assist(const Intervention& i);
    void publish_recording(TimeNs now);
    // Camera tracking and the calibration in use: app/session_camera.cpp.
    void update_camera();
    void set_camera(CameraId camera, const char* why);
    void use_calibration(const CameraCalibration& c, std::string origin);
    void apply_calibration(const ApplyCalibration& q);
    void publish_calibration();
    vision::CalibrationMode& calibration_worker();
    // Frame processing: app/session_frames.cpp.
    void process(FrameSample& f, TimeNs recv_ns);
    void reset_vision();

    SessionOptions opts_;
    Clock& clock_;
    std::unique_ptr<Current> cur_;  // session thread only
    // Outputs: the slot's, the window's copy, one being filled. Acquired on the session thread,
    // released on whichever thread drops the last copy.
    ObjectPool<PipelineOutput> out_pool_{3};
    ObstaclePipeline pipeline_;  // session thread only
    std::uint64_t next_id_ = 1;

    BoundedQueue<SessionRequest> requests_{256};
    std::mutex opening_mutex_;  // request() may be called from more than one thread
    OpeningInfo opening_last_;  // guarded by opening_mutex_
    LatestValue<OpeningInfo> opening_;
    std::uint64_t opens_handled_ = 0;  // session thread only
    // Stale video: when the newest live frame is older than kGapNs its regions are republished
    // unknown (StaleVideo), once per stall.
    TimeNs last_live_frame_ns_ = 0;
    bool stale_published_ = false;
    void check_stale(TimeNs now);
    BoundedQueue<std::string> messages_{64, QueueFull::DropOldest};
    LatestValue<SourceInfo> source_;
    LatestValue<ReplayInfo> replay_;
    LatestValue<ClassifierInfo> classifier_;
    LatestValue<std::shared_ptr<const PipelineOutput>> output_;
    LatestValue<NavState> replay_nav_;
    LatestValue<RecordingInfo> recording_;
    LatestValue<CalibrationInUse> calibration_;
    LatestValue<vision::CalibrationModeState> calibration_mode_;
    // The front camera's model (the classifier's) and where it came from; session thread only.
    CameraCalibration calib_in_use_;
    std::string calib_origin_;
    LiveOdometry odometry_;  // session thread only
    // Created on the first CalibrationStart; session thread only (its worker publishes above).
    std::unique_ptr<vision::CalibrationMode> calibrator_;
    std::unique_ptr<record::Recorder> recorder_;  // session thread only; before the link dies
    std::string last_record_path_;
    // The assist's interventions during the recording in progress (assist.csv at its stop).
    std::vector<Intervention> assist_rows_;
    std::uint64_t assist_rows_dropped_ = 0;
    static constexpr std::size_t kMaxAssistRows = 100000;
    TimeNs last_record_publish_ = 0, last_space_check_ = 0;
    double disk_free_bytes_ = kUnknown;
    std::atomic<std::uint64_t> processed_{0};
    std::atomic<bool> running_{true};
    std::thread thread_;
};

}  // namespace gs::app
