#pragma once
// Actions: what the user asked for during one window frame. The window never talks to the link,
// the recorder or the classifier; it fills one Actions per frame and the caller turns it into typed
// commands. Edge-type requests (takeoff, connect ...) are set only on the frame they happened.

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace gs::ui {

// Progressive command fractions in [-1, 1] (AT*PCMD convention, docs/protocol.md §2.6):
// roll < 0 = move left, pitch < 0 = move forward, gaz > 0 = climb, yaw > 0 = turn clockwise.
struct PilotInput {
    float roll = 0, pitch = 0, gaz = 0, yaw = 0;
    bool any() const { return roll != 0 || pitch != 0 || gaz != 0 || yaw != 0; }
    friend bool operator==(const PilotInput&, const PilotInput&) = default;
};

struct ConnectRequest {
    bool sim = false;      // true: the built-in virtual drone
    std::string address;   // real drone address (sim == false)
    std::string scenario;  // virtual-drone scenario (sim == true)
};

struct Actions {
    // Piloting. `pilot` is the manual command this frame (all zero = hover). `manual` is true
    // while the user is actively steering (a movement key held or a stick outside the dead zone):
    // the caller must then let this input override any automatic command (manual input wins).
    PilotInput pilot;
    bool manual = false;
    bool takeoff = false, land = false, emergency = false, flat_trim = false, switch_camera = false;
    bool calibrate_magnetometer = false;  // in flight: the drone turns a full circle
    // The collision-prevention assist: switch it on/off (an edge: the key, the gamepad button or
    // the status bar's toggle) and its override, held (level: true while the key or button is
    // down; commands pass unchanged).
    bool assist_toggle = false;
    bool assist_override = false;

    // Drone -> Settings: configuration writes (key, value as the drone prints it) and a request
    // to read the whole configuration back.
    std::vector<std::pair<std::string, std::string>> config_writes;
    bool config_read = false;

    std::optional<ConnectRequest> connect;
    bool disconnect = false;

    bool record_start = false, record_stop = false;

    std::optional<std::string> replay_open;  // dataset path
    bool replay_play = false, replay_pause = false;
    int replay_step = 0;                      // -1 / +1 frame
    std::optional<std::int64_t> replay_seek;  // frame index
    std::optional<double> replay_speed;       // 0.25 .. 8
    std::optional<bool> replay_loop;

    std::optional<std::string> classifier_select;
    std::vector<std::pair<std::string, double>> param_changes;  // (name, new value)

    // Calibration mode (the Calibration window). Start (with the board) when the window opens or
    // the board changes, stop when it closes; capture keeps the current frame only if the board is
    // found and the view adds coverage (the session's calibration worker decides).
    struct CalibrationBoard {
        int cols = 9, rows = 6;
        double square_m = 0.05;
    };
    std::optional<CalibrationBoard> calibration_start;
    bool calibration_stop = false;
    bool calibration_capture = false, calibration_undo = false, calibration_reset = false;
    std::optional<bool> calibration_auto;  // auto capture on / off
    bool calibration_save = false;         // calibrate, save as the drone's calibration, apply
    // Level, every frame: the video window shows the undistorted image.
    bool undistort_preview = false;

    bool quit = false;  // the window may close now (after the landing confirmation if flying)

    // Lines for the message log that the window itself produced ("take-off: not available in a
    // replay", a migrated keymap ...). Usually empty.
    std::vector<std::string> notes;
};

}  // namespace gs::ui
