#pragma once
// ViewState: everything the window owns itself (lesson 6): which windows are open, overlay
// toggles, text fields, the telemetry history behind the scrolling plots, the persisted settings,
// and the laid-out rectangles of the last frame (LayoutReport) for tests and offscreen checks.

#include "ui/history.hpp"
#include "ui/pilot_input.hpp"
#include "ui/settings.hpp"

#include <imgui.h>

#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace gs::ui {

struct OpenWindows {
    bool video = true, plots = true, telemetry = true, link = true, why_not_flying = true,
         classifier = true, recording = true, replay = true, connection = true, keys = false,
         calibration = false;
};

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
    };
    Rect video_image;              // the image (aspect-correct) inside the video window
    std::vector<Bar> region_bars;  // classifier region bar, one per region
    Rect battery_outline;          // HUD battery gauge
    Rect battery_fill;             // its filled part (width = battery fraction of the outline)
    std::uint32_t battery_color = 0;
    std::string battery_text;
    bool battery_warning = false;
    std::vector<std::pair<std::string, Rect>> windows;  // name -> rect
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

    bool confirm_quit = false;        // the "drone is flying" dialog is up
    bool quit_after_landing = false;  // user chose "land, then quit"
    bool quit_dialog_open = false;    // the dialog was drawn this frame

    double ui_frame_ms = kUnknown;  // measured by the run loop, shown in the link window
    double ui_fps = kUnknown;

    LayoutReport layout;
};

}  // namespace gs::ui
