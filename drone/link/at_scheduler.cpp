#include "drone/link/at_scheduler.hpp"

#include "drone/protocol/navdata.hpp"

#include <algorithm>
#include <cmath>

namespace gs::link {
namespace {
using protocol::navdata::DroneState;
float clamp1(float v) {
    return std::isfinite(v) ? std::clamp(v, -1.0f, 1.0f) : 0.0f;
}
}  // namespace

const char* to_string(FlyIntent i) {
    switch (i) {
        case FlyIntent::Unknown:
            return "unknown";
        case FlyIntent::Land:
            return "land";
        case FlyIntent::Fly:
            return "fly";
    }
    return "?";
}

AtScheduler::AtScheduler(NavdataIds ids, TimeNs emergency_timeout_ns, TimeNs takeoff_timeout_ns)
    : ids_(std::move(ids)),
      emergency_timeout_ns_(emergency_timeout_ns),
      takeoff_timeout_ns_(takeoff_timeout_ns) {}

void AtScheduler::set_fly(bool fly) {
    if (!fly) {
        intent_ = FlyIntent::Land;
    } else if (lost_) {
        ++counters_.takeoffs_while_lost;
        return;
    } else if (intent_ != FlyIntent::Fly) {
        intent_ = FlyIntent::Fly;
        seen_flying_ = false;
    }
    fly_since_.reset();
}

void AtScheduler::land_intent() {
    intent_ = FlyIntent::Land;
    seen_flying_ = false;
    fly_since_.reset();
}

void AtScheduler::drop_takeoff_intent() {
    land_intent();
    ++counters_.takeoff_intents_dropped;
}

void AtScheduler::check_takeoff_timeout(TimeNs now) {
    if (!fly_since_) fly_since_ = now;
    if (now - *fly_since_ <= takeoff_timeout_ns_) return;
    ++counters_.takeoff_timeouts;  // refused: a later change must not make it take off
    drop_takeoff_intent();
}

void AtScheduler::update_intent(TimeNs now, std::optional<std::uint32_t> drone_state) {
    if (!fly_since_) fly_since_ = now;
    const DroneState st{drone_state.value_or(0)};
    if (drone_state && st.emergency()) {
        drop_takeoff_intent();  // motors cut by the drone: never restart them by ourselves
    } else if (drone_state && st.fly()) {
        seen_flying_ = true;
    } else if (drone_state && seen_flying_) {
        drop_takeoff_intent();  // it flew and landed on its own (battery, com loss, ...)
    } else {
        check_takeoff_timeout(now);
    }
}

void AtScheduler::set_move(const Move& m) {
    move_ = {clamp1(m.roll), clamp1(m.pitch), clamp1(m.gaz), clamp1(m.yaw)};
    moving_ = move_.roll != 0 || move_.pitch != 0 || move_.gaz != 0 || move_.yaw != 0;
}

void AtScheduler::hover() {
    move_ = {};
    moving_ = false;
}

void AtScheduler::request_emergency(bool drone_emergency_now, TimeNs now) {
    emergency_ = EmergencyRequest{drone_emergency_now, now};
    ++counters_.emergency_requests;
    land_intent();
}

void AtScheduler::on_link_lost() {
    if (moving_) ++counters_.stale_moves_dropped;
    hover();
    lost_ = true;
    if (intent_ == FlyIntent::Fly) intent_ = FlyIntent::Unknown;
    seen_flying_ = false;
    fly_since_.reset();
}

void AtScheduler::on_link_restored() {
    lost_ = false;
}

void AtScheduler::on_connected(std::uint32_t drone_state) {
    lost_ = false;
    if (intent_ != FlyIntent::Unknown) return;  // the pilot decided meanwhile
    const DroneState st{drone_state};
    const bool flying = st.fly() && !st.emergency();
    intent_ = flying ? FlyIntent::Fly : FlyIntent::Land;
    seen_flying_ = flying;
    fly_since_.reset();
    if (flying) ++counters_.flying_adopted;
}

void AtScheduler::on_drone_restart() {
    lost_ = false;
    if (moving_) ++counters_.stale_moves_dropped;
    hover();
    emergency_.reset();
    if (intent_ == FlyIntent::Fly) ++counters_.takeoff_intents_dropped;
    land_intent();
}

void AtScheduler::build(TimeNs now, std::optional<std::uint32_t> drone_state,
                        std::vector<std::string>& out) {
    out.clear();
    commands_.clear();
    ++counters_.cycles;

    if (intent_ == FlyIntent::Fly && !lost_) update_intent(now, drone_state);

    bool emergency_bit = false;
    if (emergency_) {
        const bool drone_now = drone_state && DroneState{*drone_state}.emergency();
        if (drone_state && drone_now != emergency_->from) {
            emergency_.reset();  // the drone toggled: release the bit
        } else if (now - emergency_->since > emergency_timeout_ns_) {
            emergency_.reset();
            ++counters_.emergency_timeouts;
        } else {
            emergency_bit = true;
        }
    }
    const bool flight = intent_ != FlyIntent::Unknown || emergency_bit;
    if (flight) {
        commands_.push_back(
            protocol::at::ref(seq_.next(), protocol::at::ref_input(fly(), emergency_bit)));
        if (moving_) {
            commands_.push_back(protocol::at::pcmd(seq_.next(), protocol::at::kPcmdProgressive,
                                                   move_.roll, move_.pitch, move_.gaz, move_.yaw));
        } else {
            commands_.push_back(protocol::at::hover(seq_.next()));
        }
    } else if (lost_) {
        // Lost while the take-off intent was unknown or Fly: PCMD hover alone holds a flying
        // drone in place and feeds its communication watchdog, without a REF that a drone which
        // rebooted meanwhile would take as a take-off (or a flying one as a landing).
        commands_.push_back(protocol::at::hover(seq_.next()));
    }
    // The watchdog bit is answered every cycle while the drone reports it (an answer may be
    // lost); with no flight command to send, AT*COMWDG is the keep-alive. Not while the link
    // is lost: the drone state we hold is stale.
    const bool watchdog = drone_state && DroneState{*drone_state}.com_watchdog() &&
                          !DroneState{*drone_state}.navdata_bootstrap();
    if (!lost_ && (watchdog || !flight)) {
        commands_.push_back(protocol::at::comwdg(seq_.next()));
        ++counters_.comwdg_sent;
    }

    for (const OneShot& s : oneshots_) {
        switch (s.kind) {
            case OneShot::Kind::Config: {
                auto ids = protocol::at::config_ids(seq_.peek(), ids_.session, ids_.profile,
                                                    ids_.application);
                auto cfg = protocol::at::config(seq_.peek() + 1, s.key, s.value);
                if (!ids || !cfg) {
                    ++counters_.encode_errors;
                    break;
                }
                (void)seq_.next();
                (void)seq_.next();
                commands_.push_back(std::move(*ids));
                commands_.push_back(std::move(*cfg));
                break;
            }
            case OneShot::Kind::Ctrl:
                commands_.push_back(protocol::at::ctrl(seq_.next(), s.a, s.b));
                break;
            case OneShot::Kind::Comwdg:
                commands_.push_back(protocol::at::comwdg(seq_.next()));
                break;
            case OneShot::Kind::Ftrim:
                commands_.push_back(protocol::at::ftrim(seq_.next()));
                break;
            case OneShot::Kind::Calib:
                commands_.push_back(protocol::at::calib(seq_.next(), s.a));
                break;
            case OneShot::Kind::Led:
                commands_.push_back(protocol::at::led(seq_.next(), s.a, s.f, s.b));
                break;
            case OneShot::Kind::Anim:
                commands_.push_back(protocol::at::anim(seq_.next(), s.a, s.b));
                break;
        }
    }
    oneshots_.clear();
    if (commands_.empty()) return;
    counters_.commands += commands_.size();
    auto packed = protocol::at::pack_into(commands_, out);
    if (!packed) {
        ++counters_.encode_errors;
        return;
    }
    counters_.datagrams += out.size();
}

}  // namespace gs::link
