#pragma once
// ViewState: everything the window owns itself (docs/style.md rule 21): which windows are open,
// overlay toggles, text fields, the telemetry history behind the scrolling plots, the persisted
// settings, and the laid-out rectangles of the last frame (LayoutReport) for tests and offscreen
// checks.

#include "ui/actions.hpp"
#include "ui/history.hpp"
#include "ui/pilot_input.hpp"
#include "ui/settings.hpp"

#include <imgui.h>

#include <array>
#include <bitset>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace gs::ui {

struct OpenWindows {
    bool video = true, plots = true, telemetry = true, link = true, why_not_flying = true,
         classifier = true, recording = true, replay = true, connection = true, keys = false,
         calibration = false, drone_settings = false, messages = false;
};

// Something the user asked for that would stop commanding a flying drone: it waits behind the
// "The drone is flying" question ("Land, then ..." / "Cancel").
enum class LeaveKind { None, Quit, Disconnect, OpenReplay, Connect };
struct LeaveRequest {
    LeaveKind kind = LeaveKind::None;
    std::string replay_path;  // OpenReplay
    ConnectRequest connect;   // Connect
    bool pending() const { return kind != LeaveKind::None; }
};
const char* leave_verb(LeaveKind k);  // "quit", "disconnect", "open the replay", "connect"

struct Rect {
    float x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    float w() const { return x1 - x0; }
    float h() const { return y1 - y0; }
};

// Where things were drawn in the last frame, in window pixels (top-left origin).
struct LayoutReport {
    struct Bar {
        std::string name;
        Rect rect;
        bool flagged = false;
        bool known = true;        // false: grey "no data"
        bool confirming = false;  // amber: over the threshold, not yet confirmed unsafe
        bool still = false;       // steel blue: nothing approaching, what stands ahead not judged
        std::string reason;       // why unknown (its tooltip)
        std::string label;        // the text drawn in the bar ("" if none fitted)
    };
    Rect video_image;              // the image (aspect-correct) inside the video window
    std::vector<Bar> region_bars;  // classifier region bar, one per region
    Rect battery_outline;          // HUD battery gauge
    Rect battery_fill;             // its filled part (width = battery fraction of the outline)
    std::uint32_t battery_color = 0;
    std::string battery_text;
    bool battery_warning = false;
    std::vector<std::pair<std::string, Rect>> windows;  // name -> rect
    int popups_open = 0;            // menus, combos and dialogs open at the end of the frame
    double clock_s = 0;             // the snapshot's time (a lock-stepped run: the simulated clock)
    std::int64_t video_index = -1;  // the video frame shown
    std::string layout_mode;        // "engineering" / "flight"
    std::vector<std::pair<std::string, Rect>> labels;  // text items checked for overlap
    std::string tooltip;           // a tooltip shown this frame by the overlay (region bars)
    std::string video_stale_text;  // "VIDEO STALE 1.6 s" when drawn
    // The Telemetry window's note above its values ("No navdata received.", "STALE 3.4 s: ...").
    std::string telemetry_note;
    std::string hud_stale_text;  // "NAVDATA STALE 3.4 s" over the HUD's horizon when drawn
    // Drone settings as drawn: key -> "confirmed", "ignored by the drone", "sending" ...
    std::vector<std::pair<std::string, std::string>> setting_status;
    // Controls drawn disabled this frame, with the reason shown as their tooltip.
    std::vector<std::pair<std::string, std::string>> disabled;
    // The status bar as drawn (empty fields were not shown: no room or nothing to say).
    struct Status {
        std::string source, state, activity, battery, link, video, rec, message, assist;
        std::uint32_t source_color = 0;
        std::vector<std::string> banners;
    } status;
    // The assist as drawn: the status bar's toggle ("ASSIST ON (B)"), its row-2 banner when it
    // acts or says something ("BRAKING: obstacle ahead, contact in 1.8 s"), the HUD's line.
    struct Assist {
        std::string toggle, banner, hud;
    } assist;
    bool messages_at_end = false;  // the Messages window shows the newest line
    float replay_scroll_max = 0;   // > 0: the Replay window's content is taller than the window
    std::string replay_position;   // "frame N / LAST", written beside the seek slider
    std::vector<std::string> replay_notes;  // the Replay window's missing-input warnings as drawn
    bool keys_clipped = false;              // the key help does not fit its window
    int messages_shown = -1;                // lines in the Messages window (-1: not drawn)
    // Buttons a test may click: "quit.land", "calibration.capture", "calibration.save" ...
    std::vector<std::pair<std::string, Rect>> buttons;
    // The calibration mode as drawn.
    struct Calibration {
        bool drawn = false;     // the Calibration window was drawn this frame
        int corners_drawn = 0;  // board corners drawn over the video
        Rect coverage_map;      // the coverage map image in the Calibration window
        int views = 0;
        double rms_px = kUnknown;
        std::string status;
    } calibration;
    bool undistorted = false;  // the video window showed the undistorted image
    // The flight-path top view as drawn.
    struct FlightPath {
        bool drawn = false;
        std::vector<std::string> series;  // in legend order: "navdata", "visual odometry"
        bool legend = false;
        double x_per_px = 0, y_per_px = 0;  // metres per pixel of the two axes
        Rect area;                          // the map's data area
        // Where the odometry path starts on the map (the navdata path at the odometry's start).
        double odometry_x0 = kUnknown, odometry_y0 = kUnknown;
        std::size_t odometry_points = 0;
    } flight_path;

    const Rect* button(std::string_view name) const {
        for (const auto& [n, r] : buttons)
            if (n == name) return &r;
        return nullptr;
    }
};

// The calibration window's own fields (board being typed, what was asked of the session).
struct CalibrationUiState {
    int cols = 9, rows = 6;
    float square_mm = 50.0f;
    bool auto_capture = false;
    bool start_sent = false;  // a start is on its way (do not repeat it every frame)
    bool stop_sent = false;
};

struct ViewState {
    Settings settings;
    bool settings_dirty = false;
    OpenWindows open;
    TelemetryHistory history;
    PilotMapper pilot;
    PilotFrame last_pilot;  // shown in the connection window (what the sticks/keys command)

    std::array<char, 512> replay_path{};
    std::array<char, 128> drone_address{};
    std::array<char, 64> preset_name{};
    int scenario_index = 0;
    int plot_tab = 0;

    CalibrationUiState calib;

    // Leaving a flying drone (quit, disconnect, open a replay, connect elsewhere) asks first.
    LeaveRequest leave_asked;            // the question is (to be) shown about this
    bool leave_popup_requested = false;  // open the popup this frame
    LeaveRequest leave_after_landing;    // "Land, then ..." chosen: carried out once landed
    bool quit_after_landing = false;     // leave_after_landing is a quit (kept for readers)
    bool quit_dialog_open = false;       // the question was drawn this frame (any kind)

    bool messages_scroll_to_end = false;  // the Messages window scrolls to the newest line
    // Drone settings: slider values while edited (display units), by configuration key.
    std::map<std::string, float> settings_edits;
    std::set<std::string> settings_editing;

    // Notices the user must read once (a migrated keymap ...), shown until acknowledged.
    std::vector<std::string> notices;
    std::bitset<512> ui_prev_keys;  // keys held in the last frame (edges of the UI's own keys)

    // Layout bookkeeping (ui/layout.cpp).
    // The viewport each window was last placed in: a window not drawn while the viewport changed
    // (the other layout's, a closed one) scales with it when it comes back.
    std::map<std::string, ImVec2, std::less<>> window_display;
    int reset_layout_frames = 0;  // > 0: windows go to their defaults (View -> Reset layout)
    LayoutMode drawn_layout = LayoutMode::Engineering;  // the layout of the last frame

    double ui_frame_ms = kUnknown;  // measured by the run loop, shown in the link window
    double ui_fps = kUnknown;

    LayoutReport layout;
};

}  // namespace gs::ui
