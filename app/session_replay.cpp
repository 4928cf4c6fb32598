// Replay control: the requests that play, pause, step, seek, pace and loop a replayed dataset,
// and pulling its frames while it plays.
#include "app/session_current.hpp"

#include <algorithm>

namespace gs::app {

// ---- Requests (ignored, and said so, without a replay) ---------------------------------------

bool Session::replay_open() {
    if (cur_->replay) return true;
    message("no replay open");
    return false;
}

void Session::replay_control(const ReplayPlay& q) {
    if (!replay_open()) return;
    Current& c = *cur_;
    if (q.play && c.rinfo.ended) {
        (void)c.replay->seek(0);
        reset_vision();
        c.rinfo.ended = false;
    }
    c.replay->set_paused(!q.play);
    c.rinfo.playing = q.play;
    publish_replay();
}

void Session::replay_control(const ReplayStep& q) {
    if (!replay_open()) return;
    Current& c = *cur_;
    c.replay->set_paused(true);
    c.rinfo.playing = false;
    (void)replay_step(q.delta);
    publish_replay();
}

void Session::replay_control(const ReplaySeek& q) {
    if (!replay_open()) return;
    Current& c = *cur_;
    const auto f = std::clamp<std::int64_t>(q.frame, 0, c.rinfo.frame_count - 1);
    if (c.replay->seek(f)) {
        reset_vision();  // the classifier's history is of other frames
        c.rinfo.ended = false;
        if (!c.rinfo.playing) (void)replay_step(0);
    }
    publish_replay();
}

void Session::replay_control(const ReplaySpeed& q) {
    if (!replay_open()) return;
    Current& c = *cur_;
    const double s = std::clamp(q.speed, Pacing::kMinSpeed, Pacing::kMaxSpeed);
    if (!opts_.replay_lockstep) c.replay->set_pacing(Pacing::realtime(s));
    c.rinfo.speed = s;
    publish_replay();
}

void Session::replay_control(const ReplayLoop& q) {
    if (!replay_open()) return;
    cur_->rinfo.loop = q.loop;
    publish_replay();
}

// ---- Frames ----------------------------------------------------------------------------------

// Shows one frame while paused: delta +1 the next, -1 the previous, 0 the one at the position.
bool Session::replay_step(int delta) {
    Current& c = *cur_;
    dataset::DatasetSource& src = *c.replay;
    std::int64_t target = src.position();
    if (delta < 0) {
        target = c.rinfo.frame - 1;
        if (target < 0) return false;
    }
    if (delta <= 0 && target != src.position()) {
        if (!src.seek(target)) return false;
        reset_vision();
    }
    FrameSample f;
    const SourceStatus st = src.step(f);
    if (st == SourceStatus::End) {
        c.rinfo.ended = true;
        return false;
    }
    if (st != SourceStatus::Sample) {
        c.rinfo.error = src.last_error();
        return false;
    }
    replay_nav_.publish(f.nav);
    process(f, clock_.now_ns());  // handed over now: its latency is the processing's
    return true;
}

// Pulls what is due from a playing replay. Returns true when a frame was processed; `wait_ns`
// says how long nothing will be due.
bool Session::replay_tick(TimeNs& wait_ns) {
    Current& c = *cur_;
    dataset::DatasetSource& src = *c.replay;
    NavState nav;
    bool have_nav = false;
    while (src.next_nav(nav) == SourceStatus::Sample) have_nav = true;
    if (have_nav) replay_nav_.publish(nav);
    FrameSample f;
    const SourceStatus st = src.next(f);
    switch (st) {
        case SourceStatus::Sample:
            process(f, clock_.now_ns());  // handed over now: its latency is the processing's
            return true;
        case SourceStatus::NotYet:
            wait_ns = std::clamp<TimeNs>(src.wait_hint_ns(), 0, kIdleWaitNs);
            return false;
        case SourceStatus::End:
            if (c.rinfo.loop && c.rinfo.frame_count > 0) {
                (void)src.seek(0);
                reset_vision();
                return false;
            }
            if (!c.rinfo.ended) {
                c.rinfo.ended = true;
                c.rinfo.playing = false;
                src.set_paused(true);
                publish_replay();
                message("replay: end of the flight");
            }
            wait_ns = kIdleWaitNs;
            return false;
        case SourceStatus::Error:
            c.rinfo.error = src.last_error();
            c.rinfo.playing = false;
            src.set_paused(true);
            publish_replay();
            message("replay: " + c.rinfo.error);
            wait_ns = kIdleWaitNs;
            return false;
        case SourceStatus::Paused:
            wait_ns = kIdleWaitNs;
            return false;
    }
    return false;
}

}  // namespace gs::app
