#include "drone/link/at_scheduler.hpp"

#include <algorithm>
#include <cmath>

namespace gs::link {
namespace {
constexpr std::uint32_t kEmergencyBit = 1u << 31;
float clamp1(float v) {
    return std::isfinite(v) ? std::clamp(v, -1.0f, 1.0f) : 0.0f;
}
}  // namespace

AtScheduler::AtScheduler(NavdataIds ids, TimeNs emergency_timeout_ns)
    : ids_(std::move(ids)), emergency_timeout_ns_(emergency_timeout_ns) {}

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
}

void AtScheduler::on_link_lost() {
    if (moving_) ++counters_.stale_moves_dropped;
    hover();
}

void AtScheduler::build(TimeNs now, std::optional<std::uint32_t> drone_state,
                        std::vector<std::string>& out) {
    out.clear();
    commands_.clear();
    ++counters_.cycles;

    bool emergency_bit = false;
    if (emergency_) {
        const bool drone_now = drone_state && (*drone_state & kEmergencyBit);
        if (drone_state && drone_now != emergency_->from) {
            emergency_.reset();  // the drone toggled: release the bit
        } else if (now - emergency_->since > emergency_timeout_ns_) {
            emergency_.reset();
            ++counters_.emergency_timeouts;
        } else {
            emergency_bit = true;
        }
    }
    commands_.push_back(at::ref(seq_.next(), at::ref_input(fly_, emergency_bit)));
    if (moving_) {
        commands_.push_back(at::pcmd(seq_.next(), at::kPcmdProgressive, move_.roll, move_.pitch,
                                     move_.gaz, move_.yaw));
    } else {
        commands_.push_back(at::hover(seq_.next()));
    }

    for (const OneShot& s : oneshots_) {
        switch (s.kind) {
            case OneShot::Kind::Config: {
                auto ids =
                    at::config_ids(seq_.peek(), ids_.session, ids_.profile, ids_.application);
                auto cfg = at::config(seq_.peek() + 1, s.key, s.value);
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
                commands_.push_back(at::ctrl(seq_.next(), s.a, s.b));
                break;
            case OneShot::Kind::Comwdg:
                commands_.push_back(at::comwdg(seq_.next()));
                break;
            case OneShot::Kind::Ftrim:
                commands_.push_back(at::ftrim(seq_.next()));
                break;
            case OneShot::Kind::Calib:
                commands_.push_back(at::calib(seq_.next(), s.a));
                break;
            case OneShot::Kind::Led:
                commands_.push_back(at::led(seq_.next(), s.a, s.f, s.b));
                break;
            case OneShot::Kind::Anim:
                commands_.push_back(at::anim(seq_.next(), s.a, s.b));
                break;
        }
    }
    oneshots_.clear();
    counters_.commands += commands_.size();
    auto packed = at::pack_into(commands_, out);
    if (!packed) {
        ++counters_.encode_errors;
        return;
    }
    counters_.datagrams += out.size();
}

}  // namespace gs::link
