#ifdef GS_HAVE_GUI

#include "app/gui_adapter.hpp"

#include "drone/sim/scenarios.hpp"

#include <algorithm>

namespace gs::app {

GuiAdapter::GuiAdapter(Session& session, Clock& clock)
    : session_(session), clock_(clock), scenarios_(sim::list_scenes()) {}

void GuiAdapter::note(std::string m, ui::LogLevel level) {
    messages_.push_back({std::move(m), level, static_cast<double>(clock_.now_ns()) * 1e-9});
    while (messages_.size() > kMaxMessages) messages_.pop_front();
    messages_changed_ = true;
}

void GuiAdapter::on_source_change() {
    nav_valid_ = false;
    replay_nav_valid_ = false;
    out_.reset();
    shown_out_ = nullptr;
    path_.reset();
    assist_out_gen_ = assist_nav_gen_ = assist_rnav_gen_ = 0;
    hold_forward_takeoff_sent_ = false;
    camera_channel_ = 0;
    shown_camera_ = CameraId::Front;
    start_camera_sent_ = false;
    at_rate_.reset();
    nav_bytes_rate_.reset();
    video_bytes_rate_.reset();
    at_bytes_rate_.reset();
    nav_rate_.reset();
    video_rate_.reset();
    replay_rate_.reset();
    last_video_frame_ns_ = 0;
    video_connected_ = false;
    link_connected_ = false;
    prev_emergency_bit_ = emergency_commanded_ = false;
    emergency_sent_ns_ = 0;
    config_read_ = false;
    config_values_.clear();
    config_requested_ = false;
    shown_source_id_ = source_.id;
}

// Drone -> Settings: the configuration as read back, and what became of each write.
void GuiAdapter::fill_config(ui::GuiSnapshot& s) {
    ui::DroneConfigView& cv = s.config;
    cv.available = source_.link && s.connection.state == ui::LinkState::Connected;
    if (source_.link) {
        protocol::ConfigMap cfg;
        if (source_.link->config().read_if_newer(config_gen_, cfg)) {
            config_values_ = cfg.entries();  // only when a new dump arrived
            config_read_ = true;
        }
    }
    cv.read = config_read_;
    if (cv.values.size() != config_values_.size() || cv.writes.size() != config_writes_.size() ||
        config_dirty_) {
        cv.values = config_values_;
        cv.writes = config_writes_;
        config_dirty_ = false;
    }
}

// The assist's inputs (the newest classifier output and navdata of this source) and what the
// window shows of it. Decisions are fed here, once per new output; commands go in consume().
void GuiAdapter::fill_assist(ui::GuiSnapshot& s) {
    if (out_ && out_gen_ != assist_out_gen_ && out_->source_id == source_.id) {
        path_.on_output(*out_);
        assist_out_gen_ = out_gen_;
    }
    if (source_.kind == SessionSource::Replay) {
        if (replay_nav_valid_ && rnav_gen_ != assist_rnav_gen_) {
            path_.on_navdata(replay_nav_);
            assist_rnav_gen_ = rnav_gen_;
        }
    } else if (nav_valid_ && nav_gen_ != assist_nav_gen_) {
        path_.on_navdata(nav_.state);
        assist_nav_gen_ = nav_gen_;
    }
    const AssistStatus st = path_.status();
    ui::AssistView& a = s.assist;
    a.available = source_.kind != SessionSource::None;
    a.enabled = st.enabled;
    a.override_held = st.override_held;
    a.dry_run = st.dry_run || source_.kind == SessionSource::Replay;
    a.acting = st.acting;
    a.unknown = st.unknown;
    a.confirming = st.confirming;
    a.action = st.action;
    a.line = st.line;
    a.brief = st.brief;
    a.interventions = st.interventions;
}

void GuiAdapter::fill(ui::GuiSnapshot& s) {
    const TimeNs now = clock_.now_ns();
    s.now_ns = now;
    if (session_.source().read_if_newer(source_gen_, source_)) {
        if (!source_.error.empty()) note(source_.error, ui::LogLevel::Error);
    }
    if (source_.id != shown_source_id_) on_source_change();
    while (auto m = session_.next_message()) {
        const bool bad =
            m->find("fail") != std::string::npos || m->find("cannot") != std::string::npos ||
            m->find("error") != std::string::npos || m->find("stale") != std::string::npos;
        note(std::move(*m), bad ? ui::LogLevel::Warn : ui::LogLevel::Info);
    }
    poll_results();
    const OpeningInfo opening = session_.opening().latest().value_or(OpeningInfo{});
    const bool opening_pending = opening.count > source_.opens_handled;

    link_connected_ = false;  // fill_link() says otherwise
    ui::ConnectionInfo& c = s.connection;
    c.scenarios = scenarios_;
    c.address = source_.address;
    c.scenario = source_.scenario;
    switch (source_.kind) {
        case SessionSource::None:
            c.state = ui::LinkState::Disconnected;
            c.source = last_kind_;
            c.reason = source_.error.empty() ? "not connected" : source_.error;
            s.link = ui::LinkHealth{};
            break;
        case SessionSource::Drone:
        case SessionSource::Sim:
            c.source =
                source_.kind == SessionSource::Sim ? ui::SourceKind::Sim : ui::SourceKind::Drone;
            last_kind_ = c.source;
            fill_link(s, now);
            break;
        case SessionSource::Replay:
            c.state = ui::LinkState::Replay;
            c.source = ui::SourceKind::Replay;
            c.reason.clear();
            c.address = source_.path;
            s.link = ui::LinkHealth{};
            break;
    }
    fill_telemetry(s);
    if (session_.calibration().read_if_newer(calib_gen_, calib_))
        undistorter_.set_calibration(calib_.camera);
    fill_output(s);
    fill_calibration(s);
    fill_activity(s, opening, opening_pending);
    fill_config(s);
    fill_assist(s);

    session_.replay().read_if_newer(replay_gen_, replay_);
    ui::ReplayStatus& r = s.replay;
    r.open = replay_.open;
    r.path = replay_.path;
    r.frame = std::max<std::int64_t>(replay_.frame, 0);
    r.frame_count = replay_.frame_count;
    r.fps = replay_.fps;
    r.playing = replay_.playing;
    r.speed = replay_.speed;
    r.loop = replay_.loop;
    r.error = replay_.error;
    r.missing_inputs = replay_.missing_inputs;

    if (auto rec = session_.recording().latest()) {
        ui::RecordingStatus& rs = s.recording;
        rs.active = rec->status.recording;
        rs.path = rec->status.path.empty() ? rec->last_path : rec->status.path;
        rs.duration_s = rec->status.duration_s;
        rs.frames = rec->status.frames;
        rs.navdata = rec->status.navdata;
        rs.drops = rec->status.drops;
        rs.disk_bytes = rec->status.bytes;
        rs.disk_free_bytes = rec->disk_free_bytes;
        rs.error = rec->status.error;
    } else {
        s.recording = ui::RecordingStatus{};
    }

    if (s.messages.size() != messages_.size() || messages_changed_) {
        s.messages.assign(messages_.begin(), messages_.end());
        messages_changed_ = false;
    }
}

}  // namespace gs::app

#endif  // GS_HAVE_GUI
