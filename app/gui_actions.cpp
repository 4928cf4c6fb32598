#ifdef GS_HAVE_GUI

// The action path: the window's Actions become typed drone commands (DroneLink::submit, never
// blocking) and session requests; the commands' results come back as messages. The only place
// the adapter sends anything: fill() and its views only read.

#include "app/gui_adapter.hpp"

#include <optional>

namespace gs::app {

void GuiAdapter::poll_results() {
    for (auto it = pending_.begin(); it != pending_.end();) {
        if (it->result.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
            ++it;
            continue;
        }
        const link::CommandResult r = it->result.get();
        ui::ConfigWrite* found = nullptr;
        for (auto& w : config_writes_)
            if (it->config_write != 0 && w.id == it->config_write) found = &w;
        if (found) {
            ui::ConfigWrite& w = *found;
            config_dirty_ = true;
            w.detail = r.reason;
            switch (r.code) {
                case link::ResultCode::Sent:
                    w.state = ui::ConfigWriteState::Confirmed;
                    break;
                case link::ResultCode::Rejected:
                    // Refused before it was sent, or acknowledged and then read back otherwise.
                    w.state = r.reason.find("reports") != std::string::npos ||
                                      r.reason.find("has no key") != std::string::npos
                                  ? ui::ConfigWriteState::Ignored
                                  : ui::ConfigWriteState::Refused;
                    break;
                case link::ResultCode::Timeout:
                    w.state = ui::ConfigWriteState::TimedOut;
                    break;
                case link::ResultCode::NotConnected:
                    w.state = ui::ConfigWriteState::NotConnected;
                    break;
            }
            note(
                w.key + " = " + w.value + ": " + ui::to_string(w.state) +
                    (r.reason.empty() ? "" : " (" + r.reason + ")"),
                w.state == ui::ConfigWriteState::Confirmed ? ui::LogLevel::Ok : ui::LogLevel::Warn);
        } else if (!r.ok()) {
            // "take-off rejected: battery 12 % is below the 20 % take-off minimum"
            note(it->what + " " + link::to_string(r.code) +
                     (r.reason.empty() ? "" : ": " + r.reason),
                 r.code == link::ResultCode::Rejected ? ui::LogLevel::Warn : ui::LogLevel::Error);
        } else if (!it->ok_text.empty()) {
            note(it->ok_text, ui::LogLevel::Ok);
        } else if (!r.reason.empty()) {
            note(it->what + ": " + r.reason);
        }
        it = pending_.erase(it);
    }
}

void GuiAdapter::command(link::Command c, bool report_success, std::string ok_text) {
    const std::string what = link::command_name(c);
    if (!source_.link) {
        note(what + ": not connected to a drone", ui::LogLevel::Warn);
        return;
    }
    Pending p;
    p.what = what;
    p.ok_text = std::move(ok_text);
    p.result = source_.link->submit(std::move(c));
    pending_.push_back(std::move(p));
    if (report_success) note(what + " sent");
}

// Once the link is up: the camera asked for at start, and one configuration read-back so the
// Settings window shows the drone's values. Sent from here, never from fill().
void GuiAdapter::send_due() {
    if (!source_.link || !link_connected_) return;
    if (start_channel_ >= 0 && !start_camera_sent_) {
        start_camera_sent_ = true;
        camera_channel_ = start_channel_;
        command(link::SwitchCamera{start_channel_});
    }
    if (!config_requested_ && !config_read_) {
        config_requested_ = true;
        command(link::ReadConfig{});
    }
}

// The pilot's stick input to the AT sender through the assist (app/pilot_path.hpp), every frame
// (also when the input did not change: a new obstacle brakes a held "forward"). A replay runs
// the assist dry: shown, nothing sent. Every intervention goes to the log and, while recording,
// to the dataset's assist.csv.
void GuiAdapter::send_pilot(const ui::Actions& a) {
    if (a.assist_toggle) {
        path_.set_enabled(!path_.enabled());
        note(path_.enabled() ? "assist ON: moves toward obstacles are limited"
                             : "assist OFF: commands pass unchanged",
             path_.enabled() ? ui::LogLevel::Ok : ui::LogLevel::Warn);
    }
    path_.set_override(a.assist_override);
    std::optional<link::Move> input;
    if (a.manual) input = link::Move{a.pilot.roll, a.pilot.pitch, a.pilot.gaz, a.pilot.yaw};
    if (hold_forward_ != 0 && source_.link && link_connected_) {
        // The scripted pilot: take off once, then hold forward once flying.
        // Forward once the take-off is over (ctrl_state major flying 3 or hovering 4).
        const bool flying = nav_valid_ && nav_.state.drone_state && (*nav_.state.drone_state & 1u);
        const std::uint32_t major = nav_.state.ctrl_state ? *nav_.state.ctrl_state >> 16 : 0;
        if (!hold_forward_takeoff_sent_ && !flying) {
            hold_forward_takeoff_sent_ = true;
            command(link::Takeoff{}, false, "take-off sent (scripted pilot)");
        }
        input.reset();
        if (flying && (major == 3 || major == 4)) input = link::Move{0, -hold_forward_, 0, 0};
    }
    if (source_.kind == SessionSource::Replay) {
        path_.dry_run(input);
    } else if (source_.link) {
        if (auto c = path_.step(input, clock_.now_ns())) (void)source_.link->submit(std::move(*c));
    }
    for (Intervention& i : path_.take_new()) {
        note((source_.kind == SessionSource::Replay ? "dry run: " : "") + describe(i),
             ui::LogLevel::Warn);
        if (source_.kind != SessionSource::Replay)
            (void)session_.request(AssistRecord{std::move(i)});
    }
}

void GuiAdapter::consume(const ui::Actions& a) {
    send_due();
    for (const auto& n : a.notes) note(n);
    // Flight: emergency first, whatever else happened in the frame.
    if (a.emergency) {
        emergency_sent_ns_ = clock_.now_ns();
        command(link::Emergency{}, true);
    }
    if (a.takeoff) command(link::Takeoff{}, false, "take-off sent");
    if (a.land) command(link::Land{}, false, "land sent");
    if (a.flat_trim) command(link::FlatTrim{}, false, "flat trim sent");
    if (a.calibrate_magnetometer)
        command(link::Calibrate{}, false, "magnetometer calibration started: the drone turns");
    if (a.switch_camera) {
        camera_channel_ = 1 - camera_channel_;
        command(link::SwitchCamera{camera_channel_}, false,
                std::string("camera switched to ") + (camera_channel_ ? "bottom" : "front"));
    }
    // Drone -> Settings: each write with the multiconfiguration ids, read back to confirm.
    for (const auto& [key, value] : a.config_writes) {
        if (!source_.link) {
            note("config " + key + ": not connected to a drone", ui::LogLevel::Warn);
            continue;
        }
        config_writes_.push_back(
            {key, value, ui::ConfigWriteState::Pending, {}, ++config_write_id_});
        if (config_writes_.size() > kMaxConfigWrites) config_writes_.erase(config_writes_.begin());
        Pending p;
        p.what = "config " + key;
        p.config_write = config_write_id_;
        p.result = source_.link->submit(link::SetConfig{key, value, true});
        pending_.push_back(std::move(p));
        config_dirty_ = true;
    }
    if (a.config_read) command(link::ReadConfig{});
    send_pilot(a);

    if (a.disconnect) session_.request(CloseSource{});
    if (a.connect) {
        if (a.connect->sim)
            session_.request(StartSim{a.connect->scenario, sim_autopilot_});
        else
            session_.request(ConnectDrone{a.connect->address});
    }
    if (a.record_start) session_.request(RecordStart{});
    if (a.record_stop) session_.request(RecordStop{});

    if (a.replay_open) session_.request(OpenReplay{*a.replay_open});
    if (a.replay_play) session_.request(ReplayPlay{true});
    if (a.replay_pause) session_.request(ReplayPlay{false});
    if (a.replay_step != 0) session_.request(ReplayStep{a.replay_step});
    if (a.replay_seek) session_.request(ReplaySeek{*a.replay_seek});
    if (a.replay_speed) session_.request(ReplaySpeed{*a.replay_speed});
    if (a.replay_loop) session_.request(ReplayLoop{*a.replay_loop});

    undistort_ = a.undistort_preview;
    // Auto capture first: the mode keeps it across a (re)start, so the frame on screen when the
    // mode starts is already checked with it.
    if (a.calibration_auto) session_.request(CalibrationAutoCapture{*a.calibration_auto});
    if (a.calibration_start)
        session_.request(CalibrationStart{vision::CalibrationBoard{
            a.calibration_start->cols, a.calibration_start->rows, a.calibration_start->square_m}});
    if (a.calibration_capture) session_.request(CalibrationCapture{});
    if (a.calibration_undo) session_.request(CalibrationUndo{});
    if (a.calibration_reset) session_.request(CalibrationReset{});
    if (a.calibration_save) session_.request(CalibrationSave{});
    if (a.calibration_stop) session_.request(CalibrationStop{});

    if (a.classifier_select) session_.request(SelectClassifier{*a.classifier_select});
    for (const auto& [name, value] : a.param_changes)
        session_.request(SetClassifierParam{name, value});
}

}  // namespace gs::app

#endif  // GS_HAVE_GUI
