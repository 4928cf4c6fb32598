#pragma once
// The pilot's path to the drone with the collision-prevention assist in it (issue 16), for any
// source and headless (the window's adapter, the offscreen runs and the tests drive it the same
// way). Once per window frame the caller gives it the pilot's stick input (nullopt: not
// steering), the newest classifier output and navdata of the source, and what the pilot asked of
// the assist (toggle, override held); it returns the command for the AT sender, if any:
//
//   stick input -> AssistGate (app/assist_gate.hpp: the Assist unit on the newest decisions)
//               -> PilotCommands (a Move when what is sent changes, one Hover on release)
//               -> DroneLink::submit
//
// It runs on every frame, also while the input does not change, so a new obstacle brakes a held
// "forward". Emergency, landing and take-off never come here: the adapter submits them to the
// link directly, before the stick input of the same frame, so nothing here can delay them.
//
// Stale decisions (issue 16): a decision older than AssistParams::stale_after_s (0.5 s, 15 frames
// at 30 fps; the session also republishes a stalled video's regions as unknown after kGapNs) is
// no evidence. It never starts a brake and never counts as clear: a brake under way still ends
// once the drone has slowed (at most max_brake_s), then forward stays held at zero against the
// obstacle the brake was for (the drone may close to hold_gap_m of where it was remembered)
// until the centre is seen clear again, the drone has turned away, or the pilot overrides or
// switches the assist off. The status line says "stale" throughout.
//
// Replay: the same gate runs as a dry run on the dataset's decisions and navdata (the recorded
// velocity stands for "moving forward"); it shows what it would have done and sends nothing.

#include "app/assist_gate.hpp"
#include "app/pilot_commands.hpp"
#include "app/session.hpp"

#include <optional>
#include <string>
#include <vector>

namespace gs::app {

// What the window shows of the assist (status bar, HUD, offscreen JSON).
struct AssistStatus {
    bool enabled = true;
    bool override_held = false;
    bool dry_run = false;     // a replay: shown, nothing sent
    bool acting = false;      // braking, holding or limiting a side now
    bool unknown = false;     // the pilot flies forward into an unknown or stale centre
    bool confirming = false;  // a centre alarm being confirmed: not acting yet, about to (also
                              // while a side is steered away from: `line` then says both)
    std::string action;       // "BRAKING", "HOLDING", "LEFT BLOCKED", "WATCHING", "OFF" ...
    std::string line;         // "BRAKING: obstacle ahead, contact in 1.8 s", "ASSIST OFF" ...
    // The action words alone, for where `line` does not fit: "STEERING LEFT; BRAKE PENDING",
    // "DRY RUN: BRAKING". They still say both an action and a brake pending behind it.
    std::string brief;
    std::uint64_t interventions = 0;
};

class PilotPath {
public:
    explicit PilotPath(AssistParams p = {}) : gate_(p) {}

    // A new source: decisions, navdata and the command state are forgotten (the toggle stays).
    void reset();

    // The source's newest classifier output (front camera only; others are ignored) and navdata.
    // A replayed dataset's frames have no receive time (recv_ns 0): their decisions are timed by
    // the frames' own time, the dry run's clock.
    void on_output(const PipelineOutput& out);
    void on_navdata(const NavState& nav);

    void set_enabled(bool on) { gate_.set_enabled(on); }
    bool enabled() const { return gate_.enabled(); }
    void set_override(bool held) { gate_.set_override(held); }

    // One window frame, live: the command to submit now, if any. `now_ns` on the clock of the
    // outputs' recv_ns (the link's).
    std::optional<link::Command> step(const std::optional<link::Move>& input, TimeNs now_ns);
    // One window frame on a replay: the assist on the dataset's decisions, at the replayed
    // frame's time; nothing to send.
    void dry_run(const std::optional<link::Move>& input);

    AssistStatus status() const;
    const AssistOutput& last() const { return gate_.last(); }
    // Interventions since the previous call, oldest first (for the log and the recording).
    std::vector<Intervention> take_new();

    std::uint64_t moves() const { return pilot_.moves(); }
    std::uint64_t hovers() const { return pilot_.hovers(); }

private:
    AssistOutput run(const std::optional<link::Move>& input, TimeNs now_ns);

    AssistGate gate_;
    PilotCommands pilot_;
    bool dry_ = false;
    TimeNs replay_now_ns_ = 0;  // the newest replayed frame's time
    std::uint64_t taken_ = 0;   // interventions handed out by take_new()
};

// One line per intervention for the message log:
// "assist BRAKING (centre, frame 412): BRAKING: obstacle ahead ...; pitch -0.30 -> +1.00".
std::string describe(const Intervention& i);

}  // namespace gs::app
