#pragma once
// Between the Session and the window, on the UI thread. Snapshot in, actions out:
//   fill()    copies the session's latest values into one ui::GuiSnapshot per frame and only
//             reads: each view has its file (app/gui_link.cpp link status and byte rates,
//             gui_telemetry.cpp navdata, gui_video.cpp the classified frame and overlay,
//             gui_plots.cpp plot series, gui_calibration.cpp calibration status; the settings
//             view, replay and recording status here in gui_adapter.cpp).
//   consume() turns the window's Actions into typed drone commands (DroneLink::submit, never
//             blocking) and session requests (app/gui_actions.cpp): the only path that sends.
//             The pilot's stick input goes through the pilot path (app/pilot_path.hpp): the
//             collision-prevention assist, then PilotCommands; on a replay the assist runs dry.
// Results of commands arrive later through their futures and are shown as messages, so a refused
// take-off says why. Built only with the window (GS_HAVE_GUI).
#ifdef GS_HAVE_GUI

#include "app/gui_rate.hpp"
#include "app/pilot_path.hpp"
#include "app/session.hpp"
#include "ui/actions.hpp"
#include "ui/snapshot.hpp"
#include "vision/undistort.hpp"

#include <array>
#include <chrono>
#include <deque>
#include <future>
#include <memory>
#include <string>
#include <vector>

namespace gs::app {

class GuiAdapter {
public:
    explicit GuiAdapter(Session& session, Clock& clock = SteadyClock::instance());

    // The snapshot for the frame about to be drawn. Reuses `s`'s buffers; never blocks.
    void fill(ui::GuiSnapshot& s);
    // What the user asked for in that frame. Never blocks.
    void consume(const ui::Actions& a);

    // A virtual drone started from the window's Connect button flies its scripted flight.
    void set_sim_autopilot(bool on) { sim_autopilot_ = on; }
    // Switches a drone or virtual drone to this camera channel (0 front, 1 bottom) once it is
    // connected, for every source opened from now on; -1: leave it as it is.
    void set_start_camera(int channel) { start_channel_ = channel; }
    // Adds a line to the window's message log.
    void note(std::string m, ui::LogLevel level = ui::LogLevel::Info);

    std::uint64_t moves_sent() const { return path_.moves(); }
    std::uint64_t hovers_sent() const { return path_.hovers(); }

    // The collision-prevention assist (on unless switched off: `--assist off`, the toggle).
    void set_assist(bool on) { path_.set_enabled(on); }
    const PilotPath& pilot_path() const { return path_; }
    // Offscreen runs and tests: a scripted pilot that takes off once the drone is connected and
    // landed, then holds "forward" at this fraction through the same path as the keys (the
    // window's own stick input is ignored meanwhile). 0: off.
    void set_hold_forward(float pitch_fraction) { hold_forward_ = pitch_fraction; }

private:
    struct Pending {
        std::string what;
        std::future<link::CommandResult> result;
        std::string ok_text;             // said when it succeeded ("" : nothing)
        std::uint64_t config_write = 0;  // ConfigWrite::id when a configuration write
    };

    void on_source_change();
    // Views (read only; each in its file, see above).
    void fill_link(ui::GuiSnapshot& s, TimeNs now);
    void fill_telemetry(ui::GuiSnapshot& s);
    void fill_output(ui::GuiSnapshot& s);
    void fill_calibration(ui::GuiSnapshot& s);
    void fill_config(ui::GuiSnapshot& s);
    void fill_assist(ui::GuiSnapshot& s);
    void fill_activity(ui::GuiSnapshot& s, const OpeningInfo& opening, bool opening_pending);
    // Actions (app/gui_actions.cpp).
    void poll_results();
    void send_due();  // what the adapter sends by itself once connected (start camera, read-back)
    void send_pilot(const ui::Actions& a);
    void command(link::Command c, bool report_success = false, std::string ok_text = {});

    Session& session_;
    Clock& clock_;
    std::vector<std::string> scenarios_;

    std::uint64_t source_gen_ = 0, nav_gen_ = 0, out_gen_ = 0, cls_gen_ = 0, replay_gen_ = 0,
                  rnav_gen_ = 0;
    SourceInfo source_;
    std::uint64_t shown_source_id_ = ~0ull;
    ui::SourceKind last_kind_ = ui::SourceKind::Sim;
    link::NavSample nav_;
    bool nav_valid_ = false;
    bool nav_dirty_ = false;
    std::shared_ptr<const PipelineOutput> out_;
    ClassifierInfo cls_;
    ReplayInfo replay_;
    NavState replay_nav_;
    bool replay_nav_valid_ = false;
    SlidingRate nav_bytes_rate_, video_bytes_rate_, at_bytes_rate_;
    SlidingRate at_rate_, nav_rate_, video_rate_, replay_rate_;
    TimeNs last_video_frame_ns_ = 0;  // the link's newest frame (live)
    bool video_connected_ = false;
    bool link_connected_ = false;  // the link's state at the last fill()
    // The emergency the drone reports was commanded from here (key, button) just before.
    TimeNs emergency_sent_ns_ = 0;
    bool prev_emergency_bit_ = false, emergency_commanded_ = false;
    // Configuration: what the drone reported last and the writes sent from Drone -> Settings.
    std::uint64_t config_gen_ = 0;
    bool config_read_ = false;
    std::vector<std::pair<std::string, std::string>> config_values_;
    std::vector<ui::ConfigWrite> config_writes_;
    bool config_requested_ = false;  // a read-back asked for this source

    // Piloting: manual input through the assist, sent as Move while it lasts, then one Hover.
    PilotPath path_;
    std::uint64_t assist_out_gen_ = 0, assist_nav_gen_ = 0, assist_rnav_gen_ = 0;
    float hold_forward_ = 0;
    bool hold_forward_takeoff_sent_ = false;
    int camera_channel_ = 0;                   // the channel the C key asked for last
    CameraId shown_camera_ = CameraId::Front;  // the camera of the frames shown
    bool sim_autopilot_ = false;
    int start_channel_ = -1;
    bool start_camera_sent_ = false;

    // Calibration in use and the undistortion preview (remapped here, on the UI thread, only
    // when a new frame arrives while the preview is on: one cv::remap, ~1 ms at 640x360).
    std::uint64_t calib_gen_ = 0, mode_gen_ = 0;
    CalibrationInUse calib_;
    vision::CalibrationModeState mode_;
    bool undistort_ = false;
    vision::Undistorter undistorter_;
    std::array<cv::Mat, 2> undistorted_;  // alternated: a new buffer means a new texture upload
    int undistorted_next_ = 0;
    CameraCalibration shown_cal_;  // the model the shown frame was undistorted with
    const PipelineOutput* shown_out_ = nullptr;
    bool shown_undistort_ = false;
    std::uint64_t shown_calib_gen_ = 0;

    std::vector<Pending> pending_;
    std::deque<ui::LogLine> messages_;
    bool messages_changed_ = false;
    static constexpr std::size_t kMaxMessages = 200;
    static constexpr std::size_t kMaxConfigWrites = 32;
    bool config_dirty_ = false;
    std::uint64_t config_write_id_ = 0;
};

}  // namespace gs::app

#endif  // GS_HAVE_GUI
