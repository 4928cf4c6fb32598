#include "app/session_current.hpp"

#include "drone/core/overloaded.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>

namespace gs::app {

const char* to_string(SessionSource s) {
    switch (s) {
        case SessionSource::None:
            return "none";
        case SessionSource::Drone:
            return "drone";
        case SessionSource::Sim:
            return "virtual drone";
        case SessionSource::Replay:
            return "replay";
    }
    return "?";
}

Session::Session(SessionOptions options, Clock& clock)
    : opts_(std::move(options)),
      clock_(clock),
      cur_(std::make_unique<Current>()),
      pipeline_(opts_.classifier, front_calibration()),
      odometry_(bottom_calibration()) {
    if (!pipeline_.ok()) (void)pipeline_.select(std::string(vision::kDefaultClassifier));
    use_calibration(front_calibration(), "assets default (front)");
    publish_source();
    publish_replay();
    publish_classifier();
    thread_ = std::thread([this] { run(); });
}

Session::~Session() {
    running_ = false;
    requests_.close();
    if (thread_.joinable()) thread_.join();
    close_current();
    calibrator_.reset();  // joins the worker (its apply() only posts to the closed queue)
}

bool Session::request(SessionRequest r) {
    // An open request is announced before it is queued, so no reader sees the old source as the
    // current one after asking for another (the session thread's answer comes later).
    const bool opens = std::holds_alternative<ConnectDrone>(r) ||
                       std::holds_alternative<StartSim>(r) || std::holds_alternative<OpenReplay>(r);
    if (!opens) return requests_.push(std::move(r));
    std::lock_guard lock(opening_mutex_);
    OpeningInfo o;
    o.count = opening_last_.count + 1;
    if (const auto* d = std::get_if<ConnectDrone>(&r)) {
        o.kind = SessionSource::Drone;
        o.what = d->address.empty() ? "192.168.1.1" : d->address;
    } else if (const auto* sim = std::get_if<StartSim>(&r)) {
        o.kind = SessionSource::Sim;
        o.what = sim->scenario.empty() ? "warehouse" : sim->scenario;
    } else if (const auto* rp = std::get_if<OpenReplay>(&r)) {
        o.kind = SessionSource::Replay;
        o.what = rp->path;
    }
    const OpeningInfo before = opening_last_;
    opening_last_ = o;
    opening_.publish(o);
    if (requests_.push(std::move(r))) return true;
    opening_last_ = before;  // never queued: nothing is being opened
    opening_.publish(before);
    return false;
}

void Session::message(std::string m) {
    messages_.push(std::move(m));
}

void Session::publish_source(std::string error) {
    SourceInfo s;
    s.kind = cur_->kind;
    s.id = cur_->id;
    s.address = cur_->address;
    s.scenario = cur_->scenario;
    s.path = cur_->path;
    s.error = std::move(error);
    s.link = cur_->link;
    s.virtual_drone = cur_->drone;
    s.opens_handled = opens_handled_;
    source_.publish(std::move(s));
}

void Session::publish_replay() {
    replay_.publish(cur_->rinfo);
}

void Session::publish_classifier(std::string error) {
    ClassifierInfo c;
    c.active = pipeline_.classifier_name();
    for (auto n : vision::classifier_names()) c.available.emplace_back(n);
    if (pipeline_.ok()) {
        // Defaults from a fresh instance: what "reset to default" goes back to.
        const auto fresh = vision::make_classifier(c.active, CameraCalibration{});
        std::vector<vision::ParamInfo> defaults;
        if (fresh) defaults = fresh->params();
        for (auto& p : pipeline_.classifier().params()) {
            ParamState ps;
            ps.default_value = p.value;
            for (const auto& d : defaults)
                if (d.name == p.name) ps.default_value = d.value;
            ps.info = std::move(p);
            c.params.push_back(std::move(ps));
        }
    }
    c.error = std::move(error);
    classifier_.publish(std::move(c));
}

// One handler per request type, no generic one: a request type added to SessionRequest and not
// handled here does not compile.
void Session::handle(SessionRequest& r) {
    Current& c = *cur_;
    std::visit(
        Overloaded{
            // Source lifecycle (app/session_sources.cpp). Open requests are counted first: every
            // publish from here on says it is done.
            [&](const ConnectDrone& q) {
                ++opens_handled_;
                open_drone(q.address);
            },
            [&](const StartSim& q) {
                ++opens_handled_;
                open_sim(q);
            },
            [&](const OpenReplay& q) {
                ++opens_handled_;
                open_replay(q.path);
            },
            [&](const CloseSource&) {
                const bool had = c.kind != SessionSource::None;
                close_current();
                publish_source();
                publish_replay();
                if (had) message("disconnected");
            },
            // Replay control (app/session_replay.cpp).
            [&](const ReplayPlay& q) { replay_control(q); },
            [&](const ReplayStep& q) { replay_control(q); },
            [&](const ReplaySeek& q) { replay_control(q); },
            [&](const ReplaySpeed& q) { replay_control(q); },
            [&](const ReplayLoop& q) { replay_control(q); },
            // Recording control (app/session_recording.cpp).
            [&](const RecordStart& q) { record_start(q.dir); },
            [&](const RecordStop&) { record_stop(); },
            [&](const AssistRecord& q) { record_assist(q.what); },
            // The classifier.
            [&](const SelectClassifier& q) {
                if (pipeline_.select(q.name)) {
                    publish_classifier();
                    message("classifier: " + q.name);
                } else {
                    publish_classifier("unknown classifier '" + q.name + "'");
                }
            },
            [&](const SetClassifierParam& q) {
                if (!pipeline_.ok()) return;
                const auto st = pipeline_.classifier().set_param(q.name, q.value);
                if (st == vision::ParamStatus::Ok)
                    publish_classifier();
                else
                    publish_classifier(q.name + ": " + vision::to_string(st));
            },
            // Calibration: the mode's worker (vision/calibration_mode.hpp) and its result.
            [&](const CalibrationStart& q) {
                vision::CalibrationMode& w = calibration_worker();
                w.start(q.board);
                // A paused replay sends no new frame: give the mode the one on screen.
                if (auto o = output_.latest(); o && *o && (*o)->source_id == c.id)
                    w.offer((*o)->frame.image, (*o)->frame.index, c.id, /*even_inactive=*/true);
            },
            [&](const CalibrationStop&) {
                if (calibrator_) calibrator_->stop();
            },
            [&](const CalibrationCapture&) { calibration_worker().capture(); },
            [&](const CalibrationUndo&) { calibration_worker().undo(); },
            [&](const CalibrationReset&) { calibration_worker().reset(); },
            [&](const CalibrationAutoCapture& q) { calibration_worker().set_auto_capture(q.on); },
            [&](const CalibrationSave&) { calibration_worker().save(); },
            [&](const ApplyCalibration& q) { apply_calibration(q); },
        },
        r);
}

void Session::run() {
    while (running_) {
        // Requests first: connecting, switching classifier, replay controls.
        while (auto r = requests_.try_pop()) handle(*r);
        if (recorder_) {
            const TimeNs now = clock_.now_ns();
            if (now - last_record_publish_ >= ms_to_ns(100)) publish_recording(now);
        }
        Current& c = *cur_;
        if (c.frames) {
            auto f = c.frames->pop_for(std::chrono::nanoseconds(kIdleWaitNs));
            if (f)
                process(*f, f->recv_ns);
            else
                check_stale(clock_.now_ns());
            continue;
        }
        TimeNs wait = kIdleWaitNs;
        if (c.replay && !opts_.replay_lockstep && replay_tick(wait)) continue;
        if (auto r = requests_.pop_for(std::chrono::nanoseconds(std::max<TimeNs>(wait, 1'000'000))))
            handle(*r);
    }
}

}  // namespace gs::app
