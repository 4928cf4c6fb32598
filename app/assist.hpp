#pragma once
// The collision-prevention assist (issue 16): between the pilot's inputs and the AT sender, it
// limits the commands that would fly the drone into a region the obstacle classifier reports
// unsafe. A pure unit: no sockets, no clock (times come in with the input), no threads; the
// session calls it on every pilot change and classifier decision, the evaluation on every step.
//
// Rules:
//  - Centre unsafe while the drone moves forward: first CONFIRM, when there is time to. A centre
//    alarm that lasts a frame or two is mostly a false one (the first metres of a flight, the
//    drone pitching to accelerate), and a brake in open space is what makes a pilot switch an
//    assist off. So in free flight an alarm brakes once the centre has read unsafe for
//    `confirm_s` in all, or at once when waiting would leave less than `confirm_gap_m` between
//    where the drone would stop (reaction time, then `brake_decel_mps2`) and the obstacle its
//    time to contact places ahead (at `ttc_trust`), or when it comes with no time to contact or
//    no velocity. It is dropped after the centre has read clear for `confirm_clear_s`, but
//    another alarm within `confirm_recall_s` of its last unsafe reading brakes at once; the
//    deadline is kept whatever the centre reads meanwhile (unknown is no reason to wait longer).
//    The pilot's commands pass unchanged while confirming, and the HUD says so.
//    Then BRAKE. With a navdata velocity: full nose-up
//    pitch until the forward speed is under `brake_release_mps`, then the drone's own hover (on
//    the AR.Drone's dynamics this stops shorter than hover alone: the hover controller tilts in
//    proportion to the residual speed, so its last half metre per second decays slowly; see
//    tests/app/assist_test.cpp, which measures both on the virtual drone's flight model). Without a
//    velocity: hover at once. Then HOLD: the forward command stays at zero until the centre is
//    clear (a valid, safe decision) or the drone has turned away (`release_turn_deg`).
//    The obstacle is remembered ahead (from the time to contact, and once stopped never farther
//    than `hold_gap_m`: a threshold time to contact may come from an obstacle seen late). "Clear"
//    releases the hold only when the classifier could have seen it (see `detect_ttc_s`): a
//    stopped drone sees no expansion. So a held drone, stopped with the centre clear for
//    `probe_wait_s`, may PROBE: creep toward it at a capped speed, never closer than
//    `probe_blind_gap_m` plus its stopping distance until the centre has read clear with the
//    obstacle in sight (then `probe_min_gap_m`); seen again, it brakes; seen clear while in
//    sight, it is forgotten (a false alarm no longer holds the drone for the rest of a flight).
//    What the centre reads during a brake never counts as clear (`clear_while_braking`).
//  - A side unsafe while the centre reads unknown is a centre alarm, at the side's time to
//    contact (`side_blocks_unknown_centre`): the side's unsafe points lie in the flight corridor,
//    and nothing says the obstacle stops short of a centre with no evidence (a plain surface).
//    The banner says so ("BRAKING: obstacle left, nothing seen ahead, contact in 2.2 s").
//    So is a side unsafe whose obstacle reaches into the path (the classifier places its inner
//    edge, `edge_m`) farther than the push away could clear in the time left before the drone
//    gets there (`side_hull_half_m`, `side_reach_clear_m`), once the side has read unsafe for
//    `side_reach_confirm_s` without a break: "BRAKING: obstacle right reaching into the path,
//    contact in 0.9 s".
//  - Left / right unsafe: the roll command toward that side is zeroed, and stays zeroed until the
//    drone has flown past where the obstacle was seen (its time to contact x speed, plus
//    `side_pass_margin_m`): the side of a pass goes out of the camera's view before the drone is
//    past it, and a pilot holding a line would otherwise steer back into it. From the first
//    frame a side is unsafe until the drone is abreast of where it was seen (whether the side
//    still reads unsafe or not: a side alarm flickers, and a few frames of push move the drone
//    a few centimetres), while the other side is not limited and the drone moves forward, the
//    assist also rolls away from it (`side_nudge`, up to `side_away_mps` of lateral speed away):
//    zeroing alone leaves a drone that drifts or holds a line close to a pillar passing it at a
//    few centimetres. With both sides unsafe (a corridor, a doorway) nothing is nudged; nor
//    toward a side that does not read clear (unknown or stale: no evidence that the way is
//    free), nor farther than `side_shift_max_m` sideways past where the side last read unsafe
//    (a side that reads unsafe again still holds its obstacle in the corridor), the drift the push
//    leaves included: the push ends while the drone can still stop within that shift
//    (`side_settle_decel_mps2`, after `react_s`), and then, while the pilot does not roll, the
//    assist rolls against the sideways speed it gave until it is under `side_settle_mps` (unless
//    the pilot rolls on away from it, `side_settle_yield_roll`). A level AR.Drone keeps most of its
//    lateral speed for seconds: a 0.7 s push at 0.5 carried a drone 1.05 m sideways, twice
//    side_shift_max_m, across the line of the obstacle it had not yet seen on the other side (seed
//    41's side-person-left-0.6-06 under --realism).
//  - Never limited: yaw, climb and descent, backing away (nose-up pitch), roll away from a side.
//  - Unknown or stale regions (no evidence) never brake by themselves; the output says so.
//  - Emergency and landing are not commands the assist sees: they go straight to the link. The
//    override (a held key) passes the pilot's command through unchanged; so does the assist
//    switched off.

#include "drone/core/unknown.hpp"
#include "vision/classifier.hpp"
#include "vision/params.hpp"
#include "vision/plot_series.hpp"

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace gs::app {

// What the pilot asks for: a progressive move (fractions of the configured maxima, link::Move
// conventions: pitch < 0 forward, roll > 0 right, gaz > 0 up, yaw > 0 clockwise) or hover.
struct FlightCommand {
    bool progressive = false;  // false: hover (the drone holds its position)
    float roll = 0, pitch = 0, gaz = 0, yaw = 0;
    bool operator==(const FlightCommand&) const = default;
};

enum class RegionState : std::uint8_t { Unknown, Clear, Unsafe, Stale };
const char* to_string(RegionState s);  // "unknown", "clear", "unsafe", "stale"

// The classifier's latest decision on one region as the assist sees it.
struct RegionEvidence {
    RegionState state = RegionState::Unknown;
    double age_s = kUnknown;  // since the frame it was made on
    double ttc_s = kUnknown;  // time to contact, when the classifier estimates one
    // A side's obstacle: how far beside the flight line its inner edge is, toward that side (m;
    // negative: across the line; vision::RegionDecision::edge_m), when the classifier places it.
    double edge_m = kUnknown;
};

struct AssistInput {
    double t_s = 0;  // the caller's clock, seconds (only differences matter)
    FlightCommand pilot;
    std::array<RegionEvidence, 3> regions{};  // vision::Region order: left, centre, right
    // Navdata: body velocity (forward, right; m/s) and heading; NaN = unknown.
    double vx_mps = kUnknown, vy_mps = kUnknown, yaw_deg = kUnknown;
    bool flying = true;     // airborne (navdata FLY); on the ground nothing is limited
    bool enabled = true;    // the toggle
    bool override = false;  // the override key is held
};

enum class AssistAction : std::uint8_t {
    Off,         // switched off: everything passes
    Override,    // the pilot holds the override key
    Watching,    // on, nothing to limit
    Braking,     // stopping forward motion (centre unsafe)
    Holding,     // forward held at zero (centre was unsafe, not yet clear)
    LimitLeft,   // lateral command toward the left zeroed
    LimitRight,  // toward the right
    LimitSides,  // both
    // Rolling left: away from an obstacle on the right (and limiting toward it), or stopping
    // the drift right its push left away from one on the left.
    SteerLeft,
    SteerRight,  // rolling right: the mirror image
    // Held for an obstacle still remembered ahead but with room to stop short of it: the pilot's
    // commands pass unchanged (not an intervention; shown so the pilot knows it is remembered).
    Approaching,
    // Stopped short of a remembered obstacle that the centre has since read clear: the pilot may
    // creep toward it slowly enough for the classifier to see it again (forward pitch capped).
    Probing,
    // A centre alarm being confirmed (see the rules above): the pilot's commands pass unchanged,
    // the brake comes when it holds or its deadline comes (not an intervention).
    Confirming,
};
const char* to_string(AssistAction a);  // "OFF", "OVERRIDE", "WATCHING", "BRAKING" ...
// The assist acts on the pilot's commands (braking, holding, limiting, steering).
bool is_intervention(AssistAction a);

struct AssistParams {
    double moving_forward_mps = 0.15;  // faster than this forward = moving forward
    double brake_release_mps = 0.25;   // full nose-up until the forward speed is under this
    double max_brake_s = 2.0;          // the braking pitch never lasts longer (then hover)
    double release_turn_deg = 45.0;    // turned this far from the braking heading: hold released
    double stale_after_s = 0.5;        // an older decision is stale (no evidence)
    // The obstacle a brake was for is remembered ahead (at time-to-contact x speed, or this far
    // when no time to contact is known) and the drone is let forward only while it stays more
    // than `hold_gap_m` from it: a drone that has stopped sees no expansion, so "clear" from the
    // classifier alone would let it creep into what it just braked for.
    double default_obstacle_m = 1.5;
    double hold_gap_m = 1.0;
    // That cap makes the remembered place a near bound: the obstacle may be as far as its time
    // to contact placed it (the far bound). With this on, "in sight" (below) is judged at the
    // far bound: a clear reading counts, toward forgetting the obstacle and toward the probe's
    // nearer gap, only when the classifier could have flagged the obstacle wherever it may be.
    // Off, at the near bound: seed 11's clutter-target-1.5, held 1.0 m ahead of its stop with
    // the target 2.6 m ahead, was forgotten by a probe reading clear at 0.4 m/s, which says
    // nothing of 2.6 m, and flew on into it. An obstacle placed beyond what a probe can see is
    // then held until the pilot turns away, backs off or overrides. (Letting each clear reading
    // move the near bound out as far as it proves, so a probe creeps on and speeds up, brought
    // two collisions in closed loop: at a probe's speed, and speeding up, the classifier flags
    // a real obstacle far later than its threshold: README, Collision assist.)
    bool sight_far_bound = true;
    // The remembered obstacle is forgotten after the centre has been clear this long while the
    // drone moved toward it fast enough for the classifier to see it: its time to contact under
    // `detect_ttc_s` (the flow classifier flags below 3.3 s).
    double forget_after_clear_s = 0.7;
    double detect_ttc_s = 3.3;
    // ... and not while braking: the readings made in the manoeuvre are of frames flown pitching
    // up hard, as the speed falls fast, in which a plain obstacle's few tracked points and its
    // outline are lost, and the centre then reads clear on what is left (the far background).
    // Seed 7's clutter-target-2.0-57 (realism on, the outline channel on) braked 2.7 m short of
    // a plain target for four unsafe frames, read clear through the whole brake, forgot the
    // target as the drone slowed through 0.18 m/s and let the pilot fly on into it. A brake is
    // called on an alarm confirmed over confirm_s; the forgetting is left to readings made in
    // steady flight toward the obstacle (an approach, a probe). Unsafe readings while braking
    // still count. (1: as before session 38.)
    bool clear_while_braking = false;
    // ... and at least this fast: slower, the flow classifier takes the drone for hovering (its
    // min_speed_mps, 0.2, and the navdata's noise) and reads "clear" whatever is ahead.
    double evidence_min_mps = 0.3;
    // Both judged at the speed the classifier saw: the slowest forward speed over this long
    // before the reading's frame was captured. It fits each point's rate over its last frames
    // (velocity_window, 10 frames = 0.33 s), and a reading made while the speed changed proves
    // no more than the slowest of them: speeding up from a stop it takes the drone for hovering
    // and reads clear whatever is ahead; slowing down in a brake its rates lag the falling speed
    // and read long. Seed 11's ahead-pillar-0.6 read clear through its brake from 0.6 m/s with
    // the pillar 0.6 m ahead; counted, those readings gave the probe that followed the nearer
    // gap, and it came within 0.17 m. 0: the speed now, as before.
    double evidence_window_s = 0.35;
    double rebrake_mps = 0.35;  // holding and faster than this toward the obstacle: brake again
    // The stopping distance allowed for when letting a held drone approach: reaction (the video
    // and decision latency) then this deceleration (full nose-up on the AR.Drone 2 gives about
    // 2 m/s^2; less is assumed).
    double react_s = 0.2;
    double brake_decel_mps2 = 1.5;
    // Holding: faster than this forward, a nose-up of hold_gain x speed (fraction of the maximum
    // tilt per m/s) instead of the drone's hover, whose last few tenths of a metre per second
    // decay over seconds.
    double hold_creep_mps = 0.05;
    double hold_gain = 2.0;
    // Probing: a held drone that has stopped (forward speed under `probe_stop_mps`) with the
    // centre read clear for `probe_wait_s` may creep toward the remembered obstacle. A stopped
    // drone sees no expansion, so its "clear" proves nothing; moving slowly toward the obstacle,
    // the classifier sees it again if it is there (and brakes the drone once more), or keeps
    // reading clear while the obstacle is in sight and so forgets it (a false alarm: the take-off
    // climb, the first metres from hover). The forward pitch is capped at `probe_pitch` up to a
    // speed that puts the remembered obstacle `probe_ttc_s` ahead, well within the classifier's
    // time to contact (remaining / probe_ttc_s, kept in [probe_min_mps, probe_max_mps]); faster
    // than that, nose-up. Never closer than `probe_min_gap_m` plus the stopping distance.
    double probe_stop_mps = 0.1;
    double probe_wait_s = 1.0;
    double probe_pitch = 0.3;
    double probe_ttc_s = 2.2;
    double probe_min_mps = 0.3;
    double probe_max_mps = 0.6;
    double probe_min_gap_m = 0.5;
    // ... until the centre has read clear for `probe_seen_s` while the remembered obstacle was
    // in sight, never closer than `probe_blind_gap_m`: the remembered obstacle can lie 0.4 m
    // nearer than placed (seed 11's ahead-pillar-0.6 was flagged 0.70 m away with a time to
    // contact of 2.5 s for a true 1.17 s, and remembered 1.0 m ahead of a stop 0.58 m short of
    // it), and a probe is often blind (at 0.3-0.4 m/s the centre of a near, plain surface reads
    // unknown in most frames: too few tracked points). That probe came within 0.16 m with one
    // gap of 0.5 m, 0.35 m with this (README). A probe the classifier sees through keeps the
    // nearer gap: it needs the room to read clear long enough to forget a false alarm.
    // `probe_seen_s` 0.3 s (it was 0.1): the same flight, with the placement that now reads
    // 2.2 s, read the pillar 0.6 m ahead clear for 0.12 s right after the alarm it braked for (a
    // flicker, on frames flown at speed), which gave its blind probe the nearer gap: 0.17 m.
    // 1.0 m, as hold_gap_m (it was 0.75): a stop that cap placed the obstacle for says only that
    // it is no farther, so a blind probe does not go into that metre. From the cap it had 0.25 m
    // of room, too little to read clear in sight and forget (the evidence window and
    // probe_seen_s take 0.23 m at 0.35 m/s), so it only crept: seed 11's ahead-pillar-1.0,
    // braked for a 2.2 s reading of a pillar 1.04 m ahead (the rates read low) and held 1.0 m
    // short of where it truly stood 0.73 m, crept to 0.26 m of it (0.44 m now). A probe still goes
    // on toward an obstacle remembered farther (no cap: a placement beyond it).
    double probe_blind_gap_m = 1.0;
    double probe_seen_s = 0.3;
    double probe_rebrake_margin_mps = 0.35;  // probing: brake again above probe speed + this
    // Confirming a centre alarm in free flight (see the rules above). 0.25 s: on the closed-loop
    // suite, most false alarms in open space last under that (one to eight frames), true ones
    // 1-3 s; waiting costs 0.25 s x speed of clearance, never below confirm_gap_m.
    double confirm_s = 0.25;
    double confirm_clear_s = 0.2;
    double confirm_gap_m = 1.0;
    // An alarm within this long of the last unsafe reading of one dropped unconfirmed brakes at
    // once: a true obstacle can be flagged a frame at a time, a second apart (seed 11's
    // ahead-pillar-1.5 read unsafe for 3 frames, clear for 0.27 s, unsafe for 1 frame, then clear
    // until 0.6 s before contact), and a recurring alarm is evidence enough.
    double confirm_recall_s = 1.0;
    // The flow classifier's time to contact reads long while the obstacle grows (a fit over past
    // frames): 3.1 s for a true 2.45 s, 2.4 s for 1.74 s on the suite's ahead flights. The
    // remembered distance is this fraction of time to contact x speed.
    double ttc_trust = 0.75;
    // Sides: the roll away while a side is unsafe (a fraction of the maximum tilt, as commands
    // are), the lateral speed away beyond which it stops pushing, where a side obstacle is
    // assumed to be when its time to contact is unknown, and how far past it the limit lasts.
    // 0.5: about 6 degrees of roll at the AR.Drone's default 12 degree limit, 1 m/s^2 sideways,
    // so a side obstacle seen 1-2 s ahead is passed 0.2-0.3 m wider (0.15 gave 0.3 m/s^2, a few
    // centimetres in that time; eval-assist, README "Collision assist").
    double side_nudge = 0.5;
    double side_away_mps = 0.4;
    // The push away from one side's obstacle ends after this much sideways movement (m) since
    // the side last read unsafe: a brief false side alarm, or one seen while braking (the drone
    // then never flies past it), must not carry the drone across the room.
    double side_shift_max_m = 0.5;
    // After a push: stopping its sideways drift (see the rules above). The deceleration a roll of
    // side_nudge gives the AR.Drone sideways, less its attitude lag (about 1 m/s^2 at 0.5 of a
    // 12 degree limit), and the drift under which the drone is left to the pilot again.
    double side_settle_decel_mps2 = 0.8;
    double side_settle_mps = 0.1;
    // A pilot rolling on away from the side beyond this (stick fraction) takes over; less is a
    // held stick's wobble.
    double side_settle_yield_roll = 0.1;
    double default_side_m = 1.5;
    double side_pass_margin_m = 0.8;
    // A side unsafe while the centre reads unknown counts as a centre alarm (confirmed, braked
    // for and held as one, at the side's time to contact). The side's points that rate unsafe lie
    // in the flight corridor, and with no evidence for the centre (a plain surface gives it too
    // few tracked points) nothing says the obstacle stops short of it: seed 2027's
    // clutter-target-0.6-10 flew at a plain grey pillar whose centre read unknown for 2 s while
    // its left edge read unsafe (contact in 1.9-2.5 s); steered right but not braked, it passed
    // 0.08 m from it. A centre read clear (evidence of a free way) keeps the side rules alone.
    bool side_blocks_unknown_centre = true;
    // A side unsafe whose obstacle reaches so far into the path (its edge_m) that the drone's hull
    // would pass it nearer than side_reach_clear_m, even after the push away it could still make
    // before getting there, counts as a centre alarm too (confirmed, braked for and held as one).
    // The push can add, from rest, after react_s, at most side_settle_decel_mps2 x t^2 / 2 in the
    // time t the side's time to contact (at ttc_trust) leaves, and never more than
    // side_shift_max_m; nothing when the other side does not read clear. Seed 41's
    // ahead-doorway-right-1.5-35: a wall whose edge stood 0.2 m inside the path read unsafe on
    // the right only, 1.4 m before it, and the push carried the drone past it 0.23 m clear.
    // 0 (side_hull_half_m): off.
    double side_hull_half_m = 0.26;   // the AR.Drone 2's half-width with the indoor hull
    double side_reach_clear_m = 0.3;  // the clearance the assist aims for (issue 16)
    // ... and only once the side has read unsafe this long without a break (s): the push away is
    // already under way, and a side's false alarms come a frame or two at a time (seed 67's
    // open-none-0.6-12 under --realism: two frames' right alarm, contact in 0.9 s, its edge 0.1 m
    // off the line, braked an open flight).
    double side_reach_confirm_s = 0.25;
};

// Every AssistParams member by name, with its range and meaning: `eval-assist --assist-set
// KEY=VALUE` and `params --assist` read this table.
const vision::ParamTable<AssistParams>& assist_param_table();
// Applies KEY=VALUE overrides to `p`; the error names the first bad one and why (unknown key,
// out of range with the range, not a number). `p` is unchanged on error.
[[nodiscard]] std::optional<std::string> apply_assist_overrides(
    AssistParams& p, const std::vector<std::string>& set);

struct AssistOutput {
    FlightCommand command;  // what goes to the drone
    AssistAction action = AssistAction::Watching;
    bool intervened = false;  // command differs from the pilot's
    // The region acted on (for the record), Centre when braking or holding.
    vision::Region region = vision::Region::Centre;
    // One line for the status bar and the HUD: "BRAKING: obstacle ahead, contact in 1.8 s",
    // "HOLDING: obstacle ahead, forward held at zero", "centre unknown: no evidence, not braking".
    std::string reason;
    bool changed = false;  // action or region changed since the previous step: log it
    RegionState centre = RegionState::Unknown;  // the centre as the assist took it (aged)
    // The pilot flies forward with no evidence about what is ahead (centre unknown or stale):
    // the assist cannot brake for what it cannot see, and says so.
    bool unknown_ahead = false;
    double obstacle_m = kUnknown;  // the remembered obstacle ahead, metres (holding, probing)
    // A centre alarm being confirmed ("CONFIRMING: centre alarm, contact in 2.8 s, braking if it
    // holds"), whatever `action` is: steering away from a side obstacle takes the action and
    // its line, and the pilot must still see that a brake may come. Empty when none is pending.
    std::string pending;
};

class Assist {
public:
    explicit Assist(AssistParams p = {}) : p_(p) {}
    AssistOutput step(const AssistInput& in);
    void reset() { st_ = {}; }
    const AssistParams& params() const { return p_; }

private:
    struct State {
        enum class Phase : std::uint8_t { Free, Braking, Holding } phase = Phase::Free;
        double since_s = 0;
        double heading_deg = kUnknown;
        double last_t_s = kUnknown;
        double obstacle_m = kUnknown;      // remembered obstacle ahead, from the brake's position
        double obstacle_far_m = kUnknown;  // ... and how far it may be (uncapped), same origin
        double travelled_m = 0;            // forward since then
        double clear_seen_s = 0;           // clear while the remembered obstacle was in sight
        // The forward speed of the last steps, oldest first: what the classifier saw.
        struct Speed {
            double t_s = 0, vx_mps = 0;
        };
        vision::RingBuffer<Speed> speeds{128};
        double stopped_clear_s = 0;  // held, stopped and the centre clear: towards a probe
        bool probing = false;
        bool speed_trusted = true;  // false after a brake timed out with the speed still high
        AssistAction last_action = AssistAction::Watching;
        vision::Region last_region = vision::Region::Centre;
        bool first = true;
        // Per side (left, right): how much farther forward the limit toward it lasts.
        std::array<double, 2> side_left_m{kUnknown, kUnknown};
        // Per side: how far the drone has moved away from that side's obstacle while pushed.
        std::array<double, 2> side_shift_m{0, 0};
        // Per side: the drone was pushed away from that side's obstacle, and its drift away has
        // not yet been stopped.
        std::array<bool, 2> side_pushed{false, false};
        // A centre alarm being confirmed: unsafe and clear time so far, the time by which it
        // brakes whatever happens, and the last unsafe reading to brake for (at
        // last_unsafe_t_s).
        bool pending = false;
        double pending_unsafe_s = 0;
        double pending_clear_s = 0;
        double pending_deadline_s = 0;
        RegionEvidence pending_evidence{};
        double last_unsafe_t_s = kUnknown;  // the centre's last unsafe reading (free flight)
        std::string braked_for = "obstacle ahead";  // what the brake under way is for
        // Per side (left, right): since when it has read unsafe without a break (NaN: not now).
        std::array<double, 2> side_unsafe_since_s{kUnknown, kUnknown};
    };
    // Whether a centre alarm in free flight brakes now (see the rules above).
    bool confirm_centre(const AssistInput& in, RegionState centre, double dt);
    // One step with the regions as given; `acted_for` is the region the centre's actions are for
    // (Centre, or the side whose alarm stands in for an unknown centre).
    // Why a side's reading stands in for the centre's.
    enum class StandIn : std::uint8_t { None, CentreUnknown, InThePath };
    AssistOutput step_as_given(const AssistInput& in, vision::Region acted_for, StandIn why);
    // Side region i (0 left, 2 right) unsafe with an obstacle that reaches into the path farther
    // than a push can clear in time (side_hull_half_m, side_reach_clear_m).
    bool side_in_path(const AssistInput& in, std::size_t i) const;
    RegionState effective(const RegionEvidence& e) const;
    // Where a reading's time to contact places its obstacle ahead (x ttc_trust, less what was
    // flown since its frame), or unknown (no time to contact, or too slow for one to mean a
    // distance).
    double placed_ahead_m(const RegionEvidence& e, double vx_mps) const;
    // The slowest forward speed over the evidence window before `captured_s`, or unknown when the
    // speeds kept do not cover it (a gap in the navdata velocity, the first steps).
    double window_speed(double captured_s) const;
    void keep_speed(double t_s, double vx_mps);
    // Stopping distance from this forward speed: the reaction time, then brake_decel_mps2.
    double stopping_m(double v_mps) const;
    AssistParams p_;
    State st_;
};

}  // namespace gs::app
