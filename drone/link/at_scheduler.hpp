#pragma once
// What the AT sender transmits each 30 ms cycle, as pure logic: the control intent (REF with the
// start bit, PCMD), AT*COMWDG while the drone reports its communication watchdog, plus one-shot
// commands (CONFIG_IDS + CONFIG, CTRL, FTRIM, CALIB, LED, ANIM) queued since the last cycle,
// packed into datagrams of at most 1024 bytes.
//
// Safety lives here. Move inputs are clamped; the emergency bit is asserted only while a requested
// toggle has not yet shown in navdata. The take-off intent (REF bit 9) is only ever sent when it
// rests on something fresh, so no stale command is replayed:
//   Unknown  until the link is Connected; then adopted from the drone's FLY bit (a ground station
//            that connects to a flying drone keeps it flying). No REF is sent while unknown:
//            an AT*COMWDG keep-alive while navdata flows, PCMD hover alone while it is lost.
//   Fly      the pilot pressed Take off (or the drone was flying when adopted). Dropped (→ Land)
//            when the pilot cuts the motors, when the drone reports an emergency, lands on its
//            own after it had flown, or never shows FLY within the take-off timeout.
//   Land     the pilot pressed Land or Emergency, the drone was landed when adopted, or the drone
//            restarted: after a restart the pilot must press Take off again.
// Losing the link drops any Move and turns Fly into Unknown: the sender keeps sending hover, but
// no REF bit 9 goes to a drone we cannot see (it may have rebooted and would take a replayed
// take-off bit as a take-off); the intent is adopted again when navdata returns.

#include "drone/core/clock.hpp"
#include "drone/link/commands.hpp"
#include "drone/link/link_state.hpp"
#include "drone/protocol/at.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace gs::link {

enum class FlyIntent { Unknown, Land, Fly };
const char* to_string(FlyIntent i);

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
    std::uint64_t comwdg_sent = 0;          // AT*COMWDG answers and keep-alives
    std::uint64_t flying_adopted = 0;       // connected to a drone already flying: kept flying
    std::uint64_t takeoffs_while_lost = 0;  // take-off requests ignored while the link was lost
    // Take-off intent dropped without the pilot: the drone reported an emergency, landed on its
    // own, restarted, or never took off within the timeout.
    std::uint64_t takeoff_intents_dropped = 0;
    std::uint64_t takeoff_timeouts = 0;  // of which: no FLY bit within the take-off timeout
};

class AtScheduler {
public:
    explicit AtScheduler(NavdataIds ids = {}, TimeNs emergency_timeout_ns = ms_to_ns(2000),
                         TimeNs takeoff_timeout_ns = ms_to_ns(5000));

    // The pilot's Take off (true) or Land (false). A take-off while the link is lost is ignored
    // (and counted): the drone's state is unknown.
    void set_fly(bool fly);
    bool fly() const { return intent_ == FlyIntent::Fly; }
    FlyIntent intent() const { return intent_; }
    void set_move(const Move& m);  // clamped to [-1, 1]; all zero = hover
    void hover();
    const Move& move() const { return move_; }
    bool moving() const { return moving_; }

    // Toggle the emergency state: REF bit 8 is held until navdata's EMERGENCY bit differs from
    // `drone_emergency_now`, or the timeout passes. Clears the take-off intent either way
    // (cutting the motors, or resetting an emergency, never leads to a take-off by itself).
    void request_emergency(bool drone_emergency_now, TimeNs now);
    bool emergency_pending() const { return emergency_.has_value(); }

    // The link was lost: forget the Move (hover), and a Fly intent becomes Unknown (see above).
    void on_link_lost();
    // Navdata flows again after a loss (the drone may still be configuring).
    void on_link_restored();
    // The link reached Connected with the drone reporting `drone_state`: an Unknown intent is
    // adopted from its FLY bit.
    void on_connected(std::uint32_t drone_state);
    // The drone restarted (navdata sequence and bootstrap again): Land, no Move, no emergency.
    void on_drone_restart();

    void queue(OneShot s) { oneshots_.push_back(std::move(s)); }
    std::size_t queued() const { return oneshots_.size(); }

    // Builds this cycle's datagrams into `out` (cleared first; empty when there is nothing to
    // send). `drone_state` is the newest navdata state, if any.
    void build(TimeNs now, std::optional<std::uint32_t> drone_state, std::vector<std::string>& out);

    const AtCounters& counters() const { return counters_; }
    protocol::at::Seq next_seq() const { return seq_.peek(); }

private:
    void land_intent();          // Land, and forget the take-off being watched
    void drop_takeoff_intent();  // the same, counted: a take-off the drone did not carry out
    // A take-off not shown by the drone within the timeout is dropped (counted).
    void check_takeoff_timeout(TimeNs now);
    // Watches a Fly intent against what the drone reports (nothing yet: only the timeout).
    void update_intent(TimeNs now, std::optional<std::uint32_t> drone_state);

    NavdataIds ids_;
    TimeNs emergency_timeout_ns_;
    TimeNs takeoff_timeout_ns_;
    protocol::at::SeqCounter seq_;
    FlyIntent intent_ = FlyIntent::Unknown;
    bool lost_ = false;                // the link is lost: hover only, no watchdog answers
    bool seen_flying_ = false;         // the drone showed FLY since the intent became Fly
    std::optional<TimeNs> fly_since_;  // first cycle of the current Fly intent
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
