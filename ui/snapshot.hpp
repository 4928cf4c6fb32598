#pragma once
// GuiSnapshot: everything the ground-station window draws in one frame, as plain data.
// The window never reaches into the link, the classifier or the dataset reader: an adapter copies
// the latest values out of their slots into one GuiSnapshot per frame (by value, so one frame never
// mixes two navdata packets) and the windows draw only that. The window's own state (toggles, plot
// history, text fields) lives in ViewState (ui/view_state.hpp).

#include "drone/core/clock.hpp"
#include "drone/core/sample.hpp"

#include <opencv2/core.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace gs::ui {

// ---- Connection -----------------------------------------------------------------------------

enum class LinkState {
    Disconnected,  // nothing selected / user disconnected
    Connecting,    // sockets open, waiting for the first navdata / bootstrap handshake
    Connected,     // navdata flowing
    Lost,          // was connected, navdata silent beyond the timeout
    Replay,        // showing a recorded dataset, no drone
};
const char* to_string(LinkState s);

enum class SourceKind { Drone, Sim, Replay, Demo };
const char* to_string(SourceKind k);

struct ConnectionInfo {
    LinkState state = LinkState::Disconnected;
    SourceKind source = SourceKind::Drone;
    std::string reason;  // human text: why Connecting / Lost / Disconnected ("no navdata for more
                         // than 500 ms")
    // What is happening now, as it happens: "Starting virtual drone 'warehouse'...",
    // "Connecting to 192.168.1.1...", "Waiting for video...", "" when nothing is pending.
    std::string activity;
    bool opening = false;  // a source is being opened (state and source say which one)
    std::string address;   // drone address in use ("192.168.1.1", "127.0.0.1:5554" for the sim)
    std::string scenario;  // virtual-drone scenario when source == Sim
    std::vector<std::string> scenarios;  // scenarios the virtual drone offers (for the picker)
};

// ---- Link health ----------------------------------------------------------------------------

// Counters for one stream (navdata UDP, video TCP, AT UDP). Unknown rates/ages are NaN.
struct StreamHealth {
    bool active = false;  // the stream is open
    // Packets (navdata), frames (video), datagrams (AT) per s, over a sliding window of the
    // items received: falls to 0 when they stop.
    double rate_hz = kUnknown;
    double age_ms = kUnknown;       // time since the last packet
    double bytes_per_s = kUnknown;  // the bytes the link counts, over the same sliding window
    std::uint64_t packets = 0;
    std::uint64_t gaps = 0;   // sequence gaps (missing sequence numbers)
    std::uint64_t drops = 0;  // dropped on our side (queue full, late, reordered)
    std::uint64_t checksum_failures = 0;
    std::uint64_t decode_errors = 0;
    std::uint64_t idr_waits = 0;  // frames skipped waiting for a key frame (video only)
};

struct LinkHealth {
    StreamHealth navdata, video, at;
    double expected_navdata_hz = kUnknown;  // 15 (demo) or 200 (full), from the state bits
};

// Past this age video and navdata are shown as stale ("VIDEO STALE 1.6 s", regions unknown).
inline constexpr double kStaleAfterMs = 500.0;

// ---- Telemetry ------------------------------------------------------------------------------

// drone_state bits by name (docs/protocol.md §3.2).
struct DroneStateBits {
    bool flying = false, video_enabled = false, vision_enabled = false,
         angular_speed_control = false, altitude_control = false, user_feedback_start = false,
         command_ack = false, camera_ready = false, travelling = false, usb_ready = false,
         navdata_demo = false, navdata_bootstrap = false, motors_problem = false, com_lost = false,
         software_fault = false, battery_low = false, user_emergency_landing = false,
         timer_elapsed = false, magneto_needs_calib = false, angles_out_of_range = false,
         too_much_wind = false, ultrasound_deaf = false, cutout = false, pic_version_ok = false,
         atcodec_thread_on = false, navdata_thread_on = false, video_thread_on = false,
         acq_thread_on = false, ctrl_watchdog = false, adc_watchdog = false, com_watchdog = false,
         emergency = false;

    static DroneStateBits from_raw(std::uint32_t bits);
    std::uint32_t to_raw() const;
};

// Bit index and SDK name of every drone_state bit, in bit order (for the telemetry table).
struct StateBitName {
    int bit;
    const char* sdk_name;
    const char* meaning;
};
const std::array<StateBitName, 32>& drone_state_bit_names();

// "LANDED", "HOVERING / LOST_COM" ... from the raw ctrl_state (major << 16 | minor).
std::string ctrl_state_name(std::uint32_t ctrl_state);

// One row of the generic "every navdata field" table.
struct TelemetryField {
    std::string group;  // navdata option name ("demo", "raw_measures", "pwm" ...)
    std::string name;   // field name with unit ("vbat_raw_mV")
    std::string value;  // already formatted
};

struct Telemetry {
    bool valid = false;                   // at least one navdata sample arrived
    NavState nav;                         // latest state, units in field names, NaN = unknown
    std::optional<DroneStateBits> state;  // decoded nav.drone_state
    std::string ctrl_state;               // ctrl_state_name(nav.ctrl_state), or "" if unknown
    double battery_low_pct = 20.0;        // below this the HUD warns
    std::vector<TelemetryField> fields;
    double age_ms = kUnknown;  // age of the newest navdata sample (live); unknown in a replay
    bool stale = false;        // live and older than kStaleAfterMs
    // The pilot commanded the emergency the drone reports (EMERGENCY key or button, within a
    // few seconds before the drone raised its emergency bit): the motors were cut on purpose.
    bool emergency_commanded = false;
};

// ---- Video ----------------------------------------------------------------------------------

struct VideoFrame {
    cv::Mat bgr;              // BGR8; empty = no video
    std::int64_t index = -1;  // frame index in its stream; changes when a new frame arrives
    TimeNs t_ns = 0;          // capture time
    std::string camera = "front";
    double fps = kUnknown;         // frames received per second (sliding window; 0 when they stop)
    double latency_ms = kUnknown;  // capture (or receive) to available for display
    // Age of the newest frame received (live: since the link got it); unknown in a replay,
    // whose frames are not live.
    double age_ms = kUnknown;
    bool stale = false;  // live and older than kStaleAfterMs: the picture is frozen
    // Undistortion preview: `bgr` is the undistorted image (same camera matrix) and every overlay
    // in image pixels (classifier, calibration corners) has been moved onto it. When the preview
    // was asked for but cannot be shown, `undistort_note` says why and the raw image is shown.
    bool undistorted = false;
    std::string undistort_note;
};

// ---- Classifier -----------------------------------------------------------------------------

// Colours are ImGui-style packed RGBA (same packing as IM_COL32: 0xAABBGGRR).
constexpr std::uint32_t rgba(unsigned r, unsigned g, unsigned b, unsigned a = 255) {
    return (a & 0xFFu) << 24 | (b & 0xFFu) << 16 | (g & 0xFFu) << 8 | (r & 0xFFu);
}

struct Point2f {
    float x = 0, y = 0;
};

// Layered overlay in image pixel coordinates (the window scales it with the image).
struct RegionBar {
    std::string name;      // "left", "center", "right"
    float x0 = 0, x1 = 0;  // horizontal extent in image pixels
    bool flagged = false;  // unsafe: drawn red, else green (when known)
    double score = kUnknown, threshold = kUnknown;
    // No measured decision this frame: drawn grey "no data", with the reason as a tooltip.
    bool known = true;
    std::string unknown_reason;
    // Known, but judged only for things moving toward the camera (it is still: hovering): drawn
    // steel blue "still", never green "clear", since an obstacle standing ahead is not seen.
    bool still = false;
};
struct OverlayPolyline {
    std::vector<Point2f> points;
    std::uint32_t rgba = 0xFFFFFFFFu;
    float thickness = 1.5f;
};
struct OverlayPoint {
    Point2f p;
    std::uint32_t rgba = 0xFFFFFFFFu;
    float radius = 2.5f;
};
struct OverlayLine {
    Point2f a, b;
    std::uint32_t rgba = 0xFFFFFFFFu;
    float thickness = 1.0f;
};
struct Overlay {
    std::vector<RegionBar> regions;             // layer "regions": the bar along the image top
    std::vector<OverlayPolyline> trajectories;  // layer "trajectories", coloured by slope
    std::vector<OverlayPoint> center_points;    // layer "centre band points"
    std::vector<OverlayLine> boundaries;        // layer "region boundaries"
};

struct RegionDecision {
    std::string name;
    bool flagged = false;
    double score = kUnknown, threshold = kUnknown;
    bool known = true;           // measured this frame
    std::string unknown_reason;  // why not ("too few tracked points", "video stale" ...)
    bool still = false;          // measured for approaching things only (RegionBar::still)
    // A flagged side's obstacle: how far beside the flight line its inner edge is (m; negative:
    // across it), when the classifier places it.
    double edge_m = kUnknown;
};

// Generic tunable parameter, so the window needs no knowledge of a classifier's internals.
struct ClassifierParam {
    std::string name;
    double value = 0, min = 0, max = 1, default_value = 0;
    bool integer = false;
    std::string description;
};

// A plot series as plain vectors; x empty = index 0..n-1.
struct SeriesData {
    std::string name;
    std::vector<double> x, y;
    std::uint32_t rgba = 0;  // 0 = automatic palette colour
};
struct ThresholdLine {
    std::string name;
    double y = 0;
    std::uint32_t rgba = 0;
};
struct PlotData {
    std::string name;  // key the plots window looks for ("scores" ...)
    std::string title, x_label, y_label;
    std::vector<SeriesData> series;
    std::vector<ThresholdLine> thresholds;
};

struct ClassifierOutput {
    std::vector<std::string> available;  // classifier names to pick from
    std::string active;
    // Why the classifier did not run on the frame shown ("" when it ran), e.g. the video is from
    // the bottom camera: the obstacle classifier is for the front camera.
    std::string not_running;
    std::vector<RegionDecision> decisions;  // usually 3: left, center, right
    std::vector<ClassifierParam> params;
    Overlay overlay;
    // Named plots: "trajectories_x" (x of each trajectory over frames), "center_scale"
    // (raw / filtered / fitted + threshold), "scores" (score per region + thresholds); any other
    // name is drawn too, in order.
    std::vector<PlotData> plots;
    double cycle_ms = kUnknown;  // classifier time per frame
};

// ---- Visual odometry (bottom camera) ------------------------------------------------------

// The session's visual odometry on the bottom camera (thesis §3.1, single-camera mode: the
// bottom camera with the navdata altitude as its distance to the floor). Per-sample values are
// the estimate after the thesis' filters, in the body frame at the sample (forward, right),
// yaw clockwise seen from above.
struct OdometryView {
    bool active = false;       // the video is from the bottom camera and the odometry runs on it
    std::uint64_t run = 0;     // changes when the odometry restarted (source, seek, camera switch)
    std::int64_t sample = -1;  // index of the newest sample in the run (0 only primes)
    bool valid = false;        // the camera gave a motion this sample
    std::string status;        // "ok", "too few inliers", "no distance" ...
    int corners = 0, tracked = 0, inliers = 0;
    double distance_m = kUnknown;  // to the floor (navdata altitude)
    double dx_m = kUnknown, dy_m = kUnknown, dyaw_deg = kUnknown;  // this sample, filtered
    double dyaw_navdata_deg = kUnknown;                            // navdata heading change
    bool spike_zeroed = false, rotation_gated = false;
    double ms = kUnknown, ms_mean = kUnknown;  // odometry time, this sample / mean
    std::int64_t samples = 0, invalid = 0, spike_samples = 0, gated_samples = 0;
    // Integrated (eq. 6.2) since the run started, in the navdata heading frame.
    double x_m = kUnknown, y_m = kUnknown, yaw_deg = kUnknown;
    double nav_x_m = kUnknown, nav_y_m = kUnknown;  // navdata velocities over the same samples
    double start_t_s = kUnknown;  // flight time of the run's first frame (where its path starts)
    // The path as drawn on the top view: x = right (eq. 6.2 y), y = forward (eq. 6.2 x), from
    // the run's start at (0, 0); decimated on long flights.
    std::vector<double> path_x, path_y;
};

// ---- Recording / replay ---------------------------------------------------------------------

struct RecordingStatus {
    bool active = false;
    std::string path;
    double duration_s = 0;
    std::uint64_t frames = 0, navdata = 0, drops = 0;
    std::uint64_t disk_bytes = 0;
    double disk_free_bytes = kUnknown;
    std::string error;  // last error, empty if none
};

struct ReplayStatus {
    bool open = false;
    std::string path;
    std::int64_t frame = 0, frame_count = 0;
    double fps = kUnknown;
    bool playing = false;
    double speed = 1.0;
    bool loop = false;
    std::string error;
    std::vector<std::string> missing_inputs;  // what the classifier lacks in this dataset
};

// ---- Camera calibration mode --------------------------------------------------------------

// What the calibration mode (app/session's calibration worker around vision::CalibrationSession)
// reports: the board seen in the latest checked frame, the views kept so far, their coverage of
// the image and the running calibration. All in pixels of the video frame shown (corners moved
// onto the undistorted image when the preview is on).
struct CalibrationView {
    bool active = false;  // the mode is running (detecting boards in the video)
    int board_cols = 9, board_rows = 6;
    double square_m = 0.05;
    bool auto_capture = false;

    // Latest checked frame.
    std::int64_t frame = -1;       // video frame index the detection is of
    bool board_found = false;      // found and sharp
    bool adds_coverage = false;    // found and a capture would be kept
    int new_cells = 0;             // coverage cells a capture would add
    std::string status;            // "board found: +12 cells", "board not found" ...
    std::vector<Point2f> corners;  // detected corners, row by row (empty when not found)
    double detect_ms = kUnknown;   // time the last detection took
    std::uint64_t detections = 0;

    // Coverage of the kept views: grid_cols * grid_rows counts, row by row.
    int image_w = 0, image_h = 0;
    int grid_cols = 0, grid_rows = 0;
    std::vector<int> coverage;
    double coverage_fraction = 0;
    int corner_regions = 0;  // of 4

    int views = 0, min_views = 3;
    double rms_px = kUnknown;  // running RMS reprojection error, unknown before min_views
    bool has_result = false;
    double fx = kUnknown, fy = kUnknown, cx = kUnknown, cy = kUnknown;
    std::array<double, 5> dist{};
    std::string result_error;  // why the running calibration failed, if it did

    std::uint64_t captures = 0;  // capture requests handled
    bool last_capture_kept = false;
    std::string last_capture;  // "view 4 kept (+9 cells)" / "not kept: adds no coverage"

    std::string save_path;  // where "Save and apply" writes
    std::uint64_t saves = 0;
    std::string saved_path;  // last file written, empty before
    std::string save_error;
    bool applied = false;  // the saved calibration is the one the pipeline uses now
    std::string in_use;    // the calibration the pipeline uses: "fx 568.1 ... (origin)"
};

// ---- Drone configuration (Drone -> Settings) -------------------------------------------

// One configuration write and what became of it.
enum class ConfigWriteState { Pending, Confirmed, Ignored, Refused, TimedOut, NotConnected };
const char* to_string(ConfigWriteState s);
struct ConfigWrite {
    std::string key, value;
    ConfigWriteState state = ConfigWriteState::Pending;
    std::string detail;    // what the read-back found, why it was refused
    std::uint64_t id = 0;  // increasing, one per write
};

struct DroneConfigView {
    bool available = false;  // a live link that can read and write the configuration
    bool read = false;       // a configuration dump has been read back
    std::vector<std::pair<std::string, std::string>> values;  // key -> value, as read back
    std::vector<ConfigWrite> writes;                          // newest last
    const std::string* get(std::string_view key) const {
        for (const auto& [k, v] : values)
            if (k == key) return &v;
        return nullptr;
    }
    const ConfigWrite* last_write(std::string_view key) const {
        for (auto it = writes.rbegin(); it != writes.rend(); ++it)
            if (it->key == key) return &*it;
        return nullptr;
    }
};

// ---- Messages -------------------------------------------------------------------------------

enum class LogLevel { Info, Ok, Warn, Error };
struct LogLine {
    std::string text;
    LogLevel level = LogLevel::Info;
    double t_s = kUnknown;  // seconds on the snapshot clock when it was logged
};

// ---- The snapshot ---------------------------------------------------------------------------

// The collision-prevention assist between the pilot and the drone (app/pilot_path.hpp).
struct AssistView {
    bool available = false;  // a source is open (live: it filters; replay: a dry run)
    bool enabled = true;     // ASSIST ON / OFF
    bool override_held = false;
    bool dry_run = false;     // a replay: what it would have done, nothing sent
    bool acting = false;      // braking, holding or blocking a side now
    bool unknown = false;     // flying forward into a centre with no evidence: not braking
    bool confirming = false;  // a centre alarm being confirmed: braking if it holds
    std::string action;       // "BRAKING", "HOLDING", "LEFT BLOCKED", "UNKNOWN", "WATCHING" ...
    std::string line;         // "BRAKING: obstacle ahead, contact in 1.8 s", "ASSIST ON" ...
    // The action words alone, drawn where `line` does not fit: "STEERING LEFT; BRAKE PENDING".
    std::string brief;
    std::uint64_t interventions = 0;
};

struct GuiSnapshot {
    TimeNs now_ns = 0;  // monotonic time the snapshot was taken (ages and plot history use it)
    ConnectionInfo connection;
    LinkHealth link;
    Telemetry telemetry;
    VideoFrame video;
    ClassifierOutput classifier;
    OdometryView odometry;
    RecordingStatus recording;
    ReplayStatus replay;
    CalibrationView calibration;
    DroneConfigView config;
    AssistView assist;
    std::vector<LogLine> messages;  // recent log lines, newest last
};

}  // namespace gs::ui
