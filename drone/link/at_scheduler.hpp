#pragma once
// What the AT sender transmits each 30 ms cycle, as pure logic: the control intent (REF with the
// start bit, PCMD) always, plus one-shot commands (CONFIG_IDS + CONFIG, CTRL, COMWDG, FTRIM,
// CALIB, LED, ANIM) queued since the last cycle, packed into datagrams of at most 1024 bytes.
// Safety lives here: Move inputs are clamped, the emergency bit is asserted only while a
// requested toggle has not yet shown in navdata, and losing the link drops any Move so no stale
// command is replayed when it returns.

#include "drone/at.hpp"
#include "drone/clock.hpp"
#include "drone/link/commands.hpp"
#include "drone/link/link_state.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace gs::link {

struct OneShot {
    enum class Kind { Config, Ctrl, Comwdg, Ftrim, Calib, Led, Anim };
    Kind kind = Kind::Comwdg;
    std::string key, value;  // Config
    int a = 0, b = 0;        // Ctrl mode/arg, Calib device, Led anim/duration, Anim id/duration
    float f = 0;             // Led frequency
};

struct AtCounters {
    std::uint64_t cycles = 0;
    std::uint64_t datagrams = 0;
    std::uint64_t commands = 0;
    std::uint64_t emergency_requests = 0;
    std::uint64_t emergency_timeouts = 0;   // the drone never showed the toggle
    std::uint64_t stale_moves_dropped = 0;  // Move intents dropped because the link was lost
    std::uint64_t encode_errors = 0;        // one-shots refused by the encoder (bad characters)
};

class AtScheduler {
public:
    explicit AtScheduler(NavdataIds ids = {}, TimeNs emergency_timeout_ns = ms_to_ns(2000));

    void set_fly(bool fly) { fly_ = fly; }
    bool fly() const { return fly_; }
    void set_move(const Move& m);  // clamped to [-1, 1]; all zero = hover
    void hover();
    const Move& move() const { return move_; }
    bool moving() const { return moving_; }

    // Toggle the emergency state: REF bit 8 is held until navdata's EMERGENCY bit differs from
    // `drone_emergency_now`, or the timeout passes.
    void request_emergency(bool drone_emergency_now, TimeNs now);
    bool emergency_pending() const { return emergency_.has_value(); }

    // The link was lost: hover, and forget the Move so it is not replayed on reconnection.
    void on_link_lost();

    void queue(OneShot s) { oneshots_.push_back(std::move(s)); }
    std::size_t queued() const { return oneshots_.size(); }

    // Builds this cycle's datagrams into `out` (cleared first). `drone_state` is the newest
    // navdata state, if any.
    void build(TimeNs now, std::optional<std::uint32_t> drone_state, std::vector<std::string>& out);

    const AtCounters& counters() const { return counters_; }
    at::Seq next_seq() const { return seq_.peek(); }

private:
    NavdataIds ids_;
    TimeNs emergency_timeout_ns_;
    at::SeqCounter seq_;
    bool fly_ = false;
    Move move_{};
    bool moving_ = false;
    struct EmergencyRequest {
        bool from;  // the drone's EMERGENCY bit when requested
        TimeNs since;
    };
    std::optional<EmergencyRequest> emergency_;
    std::vector<OneShot> oneshots_;
    std::vector<std::string> commands_;  // reused
    AtCounters counters_;
};

}  // namespace gs::link
