#include "drone/link/link_state.hpp"

#include <algorithm>
#include <cmath>

namespace gs::link {

using protocol::navdata::DroneState;

namespace {

// How far back a packet may come late or twice (80 ms of 200 Hz navdata; loopback and Wi-Fi
// reorder by one or two). A step back further than this is the drone starting again.
constexpr std::uint32_t kReorderWindow = 16;

std::string trimmed(std::string s) {
    auto sp = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
    while (!s.empty() && sp(s.back())) s.pop_back();
    s.erase(s.begin(), std::find_if(s.begin(), s.end(), [&](char c) { return !sp(c); }));
    return s;
}

// Same configuration value, as the drone prints it back: floats in %e, booleans in capitals.
bool same_value(const std::string& written, const std::string& read) {
    const std::string a = trimmed(written), b = trimmed(read);
    if (a == b) return true;
    auto ba = protocol::config_bool(a), bb = protocol::config_bool(b);
    if (ba && bb) return *ba == *bb;
    auto fa = protocol::config_float(a), fb = protocol::config_float(b);
    if (fa && fb) return std::abs(*fa - *fb) <= 1e-6 * std::max(1.0, std::abs(*fa));
    return false;
}
}  // namespace

const char* to_string(ConnectionState s) {
    switch (s) {
        case ConnectionState::Disconnected:
            return "Disconnected";
        case ConnectionState::Bootstrapping:
            return "Bootstrapping";
        case ConnectionState::Configuring:
            return "Configuring";
        case ConnectionState::Connected:
            return "Connected";
        case ConnectionState::LinkLost:
            return "LinkLost";
    }
    return "?";
}

const char* to_string(ConfigOutcome o) {
    switch (o) {
        case ConfigOutcome::Acked:
            return "acked";
        case ConfigOutcome::Verified:
            return "verified";
        case ConfigOutcome::Ignored:
            return "ignored by the drone";
        case ConfigOutcome::Timeout:
            return "not acknowledged (timeout)";
        case ConfigOutcome::Cancelled:
            return "cancelled";
    }
    return "?";
}

void LinkActions::clear() {
    send_trigger = send_ctrl_ack = send_ctrl_get_config = false;
    configs.clear();
    done.clear();
    link_lost = link_restored = drone_restarted = false;
    connected.reset();
}

LinkStateMachine::LinkStateMachine(LinkSetup setup) : setup_(std::move(setup)) {}

void LinkStateMachine::enter(ConnectionState s, std::string reason) {
    state_ = s;
    reason_ = std::move(reason);
}

void LinkStateMachine::enter_connected(std::string reason, LinkActions& out) {
    enter(ConnectionState::Connected, std::move(reason));
    out.connected = last_state_.value_or(0);
}

void LinkStateMachine::start(TimeNs now, LinkActions& out) {
    started_ns_ = now;
    last_trigger_ns_ = now;
    last_navdata_ns_ = 0;
    last_seq_.reset();
    restart_allowed_ = false;
    last_state_.reset();
    configured_ = false;
    out.send_trigger = true;
    ++counters_.triggers_sent;
    enter(ConnectionState::Bootstrapping, std::string(kBootstrappingReason));
}

void LinkStateMachine::stop(LinkActions& out) {
    cancel_jobs(out);
    enter(ConnectionState::Disconnected, "stopped");
}

void LinkStateMachine::cancel_jobs(LinkActions& out) {
    for (auto& j : jobs_) {
        if (!j.internal) {
            out.done.push_back({j.id, ConfigOutcome::Cancelled, j.key, j.value, "link down"});
        }
    }
    jobs_.clear();
}

bool LinkStateMachine::ack_bit() const {
    return last_state_ && DroneState{*last_state_}.command();
}

std::uint64_t LinkStateMachine::write_config(std::string key, std::string value, bool verify) {
    // The navdata mode asked for becomes the one the link configures from now on (after a loss
    // or a drone restart too), and the one it waits for.
    if (key == "general:navdata_demo")
        if (auto demo = protocol::config_bool(value)) setup_.navdata_demo = *demo;
    Job j;
    j.kind = JobKind::Write;
    j.id = next_id_++;
    j.key = std::move(key);
    j.value = std::move(value);
    j.verify = verify;
    jobs_.push_back(std::move(j));
    return jobs_.back().id;
}

void LinkStateMachine::request_config_dump() {
    Job j;
    j.kind = JobKind::ReadDump;
    j.id = next_id_++;
    jobs_.push_back(std::move(j));
}

void LinkStateMachine::begin_configuration() {
    // Drop a previous, unfinished configuration sequence; user jobs stay queued behind.
    jobs_.erase(std::remove_if(jobs_.begin(), jobs_.end(), [](const Job& j) { return j.internal; }),
                jobs_.end());
    std::vector<std::pair<std::string, std::string>> seq;
    if (!setup_.ids.is_default()) {
        seq.emplace_back("custom:session_id", setup_.ids.session);
        seq.emplace_back("custom:profile_id", setup_.ids.profile);
        seq.emplace_back("custom:application_id", setup_.ids.application);
    }
    seq.emplace_back("general:navdata_demo", setup_.navdata_demo ? "TRUE" : "FALSE");
    if (!setup_.navdata_demo && setup_.navdata_options != 0) {
        seq.emplace_back("general:navdata_options", std::to_string(setup_.navdata_options));
    }
    for (auto it = seq.rbegin(); it != seq.rend(); ++it) {
        Job j;
        j.id = next_id_++;
        j.key = it->first;
        j.value = it->second;
        j.internal = true;
        jobs_.push_front(std::move(j));
    }
    configured_ = false;
    enter(ConnectionState::Configuring, "writing " + jobs_.front().key);
}

bool LinkStateMachine::on_navdata(const NavdataHeaderInfo& nav, TimeNs now, LinkActions& out) {
    if (state_ == ConnectionState::Disconnected) return false;
    const bool bootstrap = DroneState{nav.drone_state}.navdata_bootstrap();
    const bool comwdg_bit = DroneState{nav.drone_state}.com_watchdog();
    if (last_seq_ && nav.sequence <= *last_seq_) {
        // The drone starts its sequence again when it restarts (bootstrap after configuration)
        // or when it re-opens the navdata stream after losing us (the SDK resets its expectation
        // whenever the COM_WATCHDOG bit is set). A step back of a few packets is still a late or
        // duplicated packet, whatever the bits say: a restart goes back further. After a link
        // loss any sequence is taken, as the SDK does after its receive timeout: whatever
        // happened in the silence, a drone that talks again must not be refused for ever.
        const bool restarted = (bootstrap && configured_) || restart_allowed_ ||
                               (comwdg_bit && *last_seq_ - nav.sequence >= kReorderWindow);
        if (!restarted) {
            ++counters_.out_of_order;
            return false;
        }
        last_seq_.reset();
        ++counters_.sequence_resets;
    }
    // The expectation is kept across a watchdog event or a link loss: if the sequence goes on,
    // what is missing from it was lost on the way and is counted.
    if (last_seq_ && nav.sequence > *last_seq_ + 1) {
        counters_.sequence_gaps += nav.sequence - *last_seq_ - 1;
    }
    last_seq_ = nav.sequence;
    restart_allowed_ = false;
    last_state_ = nav.drone_state;
    last_navdata_ns_ = now;
    ++counters_.packets_accepted;

    // The AT sender answers the bit with AT*COMWDG every cycle while it is set.
    const bool comwdg = comwdg_bit && !bootstrap;
    if (comwdg && !prev_comwdg_) ++counters_.com_watchdog_events;
    prev_comwdg_ = comwdg;

    switch (state_) {
        case ConnectionState::Bootstrapping:
            begin_configuration();
            break;
        case ConnectionState::LinkLost:
            out.link_restored = true;
            if (bootstrap && configured_) {
                ++counters_.drone_restarts;
                out.drone_restarted = true;
                begin_configuration();
            } else if (configured_) {
                enter_connected("navdata flows again", out);
            } else {
                begin_configuration();
            }
            break;
        case ConnectionState::Connected:
            if (bootstrap) {
                ++counters_.drone_restarts;
                out.drone_restarted = true;
                begin_configuration();
            }
            break;
        default:
            break;
    }
    run_jobs(now, out);
    return true;
}

void LinkStateMachine::on_config_dump(const protocol::ConfigMap& dump, TimeNs now,
                                      LinkActions& out) {
    pending_dump_ = dump;
    run_jobs(now, out);
}

void LinkStateMachine::finish_job(ConfigOutcome o, std::string detail, TimeNs now,
                                  LinkActions& out) {
    Job j = std::move(jobs_.front());
    jobs_.pop_front();
    if (!j.internal) {
        out.done.push_back({j.id, o, j.key, j.value, std::move(detail)});
        return;
    }
    if (o == ConfigOutcome::Timeout || o == ConfigOutcome::Ignored) {
        reason_ = j.key + " " + to_string(o) + "; retrying the configuration";
        begin_configuration();
        return;
    }
    const bool more_internal =
        std::any_of(jobs_.begin(), jobs_.end(), [](const Job& x) { return x.internal; });
    if (!more_internal) {
        configured_ = true;
        configured_at_ns_ = now;
        reason_ = "configured; waiting for navdata with options";
    } else {
        reason_ = "writing " + jobs_.front().key;
    }
}

void LinkStateMachine::run_jobs(TimeNs now, LinkActions& out) {
    if (state_ != ConnectionState::Configuring && state_ != ConnectionState::Connected) return;
    const LinkTiming& t = setup_.timing;
    // A few phase changes can happen in one call; bounded so a bad sequence can never spin.
    for (int guard = 0; guard < 8 && !jobs_.empty(); ++guard) {
        Job& j = jobs_.front();
        const Phase before = j.phase;
        switch (j.phase) {
            case Phase::ClearBefore:
                if (!j.started) {
                    j.started = true;
                    j.phase_start = now;
                    j.last_ctrl = now - t.ctrl_ack_resend_ns;
                }
                // A previous exchange left the ACK bit up: clear it first, or give up waiting.
                if (!ack_bit() || now - j.phase_start > t.ack_timeout_ns) {
                    j.phase = Phase::Send;
                } else if (now - j.last_ctrl >= t.ctrl_ack_resend_ns) {
                    out.send_ctrl_ack = true;
                    j.last_ctrl = now;
                }
                break;
            case Phase::Send:
                if (j.kind == JobKind::Write && !j.acked) {
                    out.configs.emplace_back(j.key, j.value);
                    ++counters_.configs_sent;
                    ++j.attempts;
                    j.phase = Phase::WaitAck;
                } else {
                    pending_dump_.reset();
                    out.send_ctrl_get_config = true;
                    j.phase = Phase::WaitDump;
                }
                j.phase_start = now;
                break;
            case Phase::WaitAck:
                if (ack_bit()) {
                    j.acked = true;
                    j.phase = Phase::ClearAfter;
                    j.phase_start = now;
                    out.send_ctrl_ack = true;
                    j.last_ctrl = now;
                } else if (now - j.phase_start > t.ack_timeout_ns) {
                    if (j.attempts < t.config_attempts) {
                        j.phase = Phase::Send;
                    } else {
                        ++counters_.config_timeouts;
                        finish_job(ConfigOutcome::Timeout,
                                   "no ACK after " + std::to_string(j.attempts) + " attempts", now,
                                   out);
                        continue;
                    }
                }
                break;
            case Phase::ClearAfter:
                if (!ack_bit() || now - j.phase_start > t.ack_timeout_ns) {
                    if (j.verify) {
                        j.phase = Phase::Send;  // acked: the next send is the read-back request
                    } else {
                        finish_job(ConfigOutcome::Acked, ack_bit() ? "ACK bit stayed set" : "", now,
                                   out);
                        continue;
                    }
                } else if (now - j.last_ctrl >= t.ctrl_ack_resend_ns) {
                    out.send_ctrl_ack = true;
                    j.last_ctrl = now;
                }
                break;
            case Phase::WaitDump:
                if (pending_dump_) {
                    if (ack_bit()) out.send_ctrl_ack = true;  // the dump request raised it
                    if (j.kind == JobKind::ReadDump) {
                        finish_job(ConfigOutcome::Verified, "", now, out);
                        continue;
                    }
                    auto v = pending_dump_->get(j.key);
                    if (!v) {
                        finish_job(ConfigOutcome::Ignored, "the drone has no key " + j.key, now,
                                   out);
                    } else if (!same_value(j.value, *v)) {
                        finish_job(ConfigOutcome::Ignored,
                                   "the drone reports " + j.key + " = " + *v, now, out);
                    } else {
                        finish_job(ConfigOutcome::Verified, "", now, out);
                    }
                    continue;
                }
                if (now - j.phase_start > t.config_dump_timeout_ns) {
                    finish_job(ConfigOutcome::Timeout, "no configuration dump on the control port",
                               now, out);
                    continue;
                }
                break;
        }
        if (j.phase == before) break;  // waiting on the drone
    }
}

void LinkStateMachine::tick(TimeNs now, LinkActions& out) {
    if (state_ == ConnectionState::Disconnected) return;
    const LinkTiming& t = setup_.timing;
    const TimeNs since = last_navdata_ns_ ? now - last_navdata_ns_ : now - started_ns_;
    const bool waiting = state_ == ConnectionState::Bootstrapping ||
                         state_ == ConnectionState::LinkLost || since > t.trigger_resend_ns;
    if (waiting && now - last_trigger_ns_ >= t.trigger_resend_ns) {
        out.send_trigger = true;
        last_trigger_ns_ = now;
        ++counters_.triggers_sent;
    }
    if ((state_ == ConnectionState::Configuring || state_ == ConnectionState::Connected) &&
        last_navdata_ns_ != 0 && since > t.link_lost_after_ns) {
        ++counters_.link_losses;
        out.link_lost = true;
        restart_allowed_ = true;
        cancel_jobs(out);
        configured_ = configured_ && state_ == ConnectionState::Connected;
        // No running figure here: the reason stays while the link is lost, and the window shows
        // the live age beside it ("LOST 6.8 s"); "504 ms" would soon be untrue.
        enter(
            ConnectionState::LinkLost,
            "no navdata for more than " + std::to_string(t.link_lost_after_ns / 1'000'000) + " ms");
        return;
    }
    if (state_ == ConnectionState::Bootstrapping) {
        reason_ =
            "waiting for navdata (" + std::to_string(counters_.triggers_sent) + " wake-ups sent)";
    }
    run_jobs(now, out);
    if (state_ == ConnectionState::Configuring && configured_ && last_state_) {
        const bool bootstrap = DroneState{*last_state_}.navdata_bootstrap();
        const bool demo = DroneState{*last_state_}.navdata_demo();
        const bool settled = now - configured_at_ns_ > t.settle_ns;
        if (!bootstrap && demo == setup_.navdata_demo) {
            enter_connected("navdata " + std::string(demo ? "demo" : "full"), out);
        } else if (!bootstrap && settled) {
            enter_connected(std::string("navdata ") + (demo ? "demo" : "full") + " although " +
                                (setup_.navdata_demo ? "demo" : "full") + " was configured",
                            out);
        } else if (settled) {
            begin_configuration();  // still in bootstrap: the write did not take; again
            reason_ = "still in bootstrap mode after configuring; writing again";
        }
    }
}

}  // namespace gs::link
