#include "app/assist.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace gs::app {
namespace {

bool known(double v) {
    return std::isfinite(v);
}

double heading_change_deg(double from, double to) {
    return std::abs(std::remainder(to - from, 360.0));
}

std::string contact_text(const RegionEvidence& e) {
    if (!known(e.ttc_s) || e.ttc_s <= 0) return "";
    char buf[48];
    std::snprintf(buf, sizeof buf, ", contact in %.1f s", e.ttc_s);
    return buf;
}

}  // namespace

const vision::ParamTable<AssistParams>& assist_param_table() {
    using P = AssistParams;
    static const vision::ParamTable<P> t = [] {
        vision::ParamTable<P> x;
        x.add("moving_forward_mps", &P::moving_forward_mps, 0, 2,
              "faster than this forward (m/s) counts as moving forward: a centre alarm brakes")
            .add("brake_release_mps", &P::brake_release_mps, 0, 2,
                 "braking: full nose-up until the forward speed is under this (m/s)")
            .add("max_brake_s", &P::max_brake_s, 0, 10,
                 "the braking pitch never lasts longer than this (s), then hover")
            .add("release_turn_deg", &P::release_turn_deg, 0, 180,
                 "holding: turned this far (deg) from the braking heading releases the hold")
            .add("stale_after_s", &P::stale_after_s, 0, 5,
                 "a decision older than this (s) is stale: no evidence, never brakes")
            .add("default_obstacle_m", &P::default_obstacle_m, 0, 20,
                 "where a braked-for obstacle is remembered when no time to contact is known (m)")
            .add("hold_gap_m", &P::hold_gap_m, 0, 10,
                 "after a brake, the remembered obstacle is never farther than this ahead of the "
                 "stop (m)")
            .add("sight_far_bound", &P::sight_far_bound, 0, 1,
                 "in sight is judged at the farthest place the remembered obstacle may be (the "
                 "time to contact's, not the hold_gap_m cap)")
            .add("forget_after_clear_s", &P::forget_after_clear_s, 0, 10,
                 "the remembered obstacle is forgotten after the centre read clear this long (s) "
                 "while in sight")
            .add("clear_while_braking", &P::clear_while_braking, 0, 1,
                 "a clear centre read during a brake counts toward forgetting the obstacle (0: "
                 "readings made in the manoeuvre prove nothing)")
            .add("detect_ttc_s", &P::detect_ttc_s, 0, 20,
                 "in sight: the remembered obstacle's time to contact at the present speed under "
                 "this (s)")
            .add("evidence_min_mps", &P::evidence_min_mps, 0, 2,
                 "in sight also needs at least this forward speed (m/s): slower, the classifier "
                 "takes the drone for hovering and reads clear")
            .add("evidence_window_s", &P::evidence_window_s, 0, 2,
                 "in sight is judged at the slowest forward speed over this long (s) before the "
                 "reading's frame (the classifier's fit window; 0: the speed now)")
            .add("rebrake_mps", &P::rebrake_mps, 0, 3,
                 "holding and faster than this toward the obstacle (m/s): brake again")
            .add("react_s", &P::react_s, 0, 2,
                 "stopping distance: the reaction time allowed for (s)")
            .add("brake_decel_mps2", &P::brake_decel_mps2, 0.1, 10,
                 "stopping distance: the deceleration assumed (m/s^2)")
            .add("hold_creep_mps", &P::hold_creep_mps, 0, 1,
                 "holding: faster than this forward (m/s), a nose-up in proportion to the speed")
            .add("hold_gain", &P::hold_gain, 0, 10,
                 "holding: that nose-up, fraction of the maximum tilt per m/s")
            .add("probe_stop_mps", &P::probe_stop_mps, 0, 1,
                 "probing: the held drone counts as stopped under this forward speed (m/s)")
            .add("probe_wait_s", &P::probe_wait_s, 0, 30,
                 "probing starts after the stopped drone read the centre clear this long (s)")
            .add("probe_pitch", &P::probe_pitch, 0, 1,
                 "probing: the forward pitch cap, fraction of the maximum tilt")
            .add("probe_ttc_s", &P::probe_ttc_s, 0.1, 20,
                 "probing: speed = remaining distance / this (s), within the min and max below")
            .add("probe_min_mps", &P::probe_min_mps, 0, 2, "probing: the lowest speed cap (m/s)")
            .add("probe_max_mps", &P::probe_max_mps, 0, 2, "probing: the highest speed cap (m/s)")
            .add("probe_min_gap_m", &P::probe_min_gap_m, 0, 10,
                 "probing, once the centre has read clear with the obstacle in sight: never "
                 "closer to it than this plus the stopping distance (m)")
            .add(
                "probe_blind_gap_m", &P::probe_blind_gap_m, 0, 10,
                "probing: the gap kept until the centre reads clear with the obstacle in sight (m)")
            .add("probe_seen_s", &P::probe_seen_s, 0, 10,
                 "probing: clear in sight this long before the nearer gap applies (s)")
            .add("probe_rebrake_margin_mps", &P::probe_rebrake_margin_mps, 0, 3,
                 "probing: brake again above the probe speed plus this (m/s)")
            .add("confirm_s", &P::confirm_s, 0, 5,
                 "free flight: a centre alarm brakes once it has read unsafe this long in all (s; "
                 "0: at once)")
            .add("confirm_clear_s", &P::confirm_clear_s, 0, 5,
                 "a centre alarm being confirmed is dropped after the centre read clear this long "
                 "(s)")
            .add("confirm_gap_m", &P::confirm_gap_m, 0, 10,
                 "a centre alarm brakes at once when waiting would stop the drone nearer than "
                 "this to the obstacle its time to contact places ahead (m)")
            .add("confirm_recall_s", &P::confirm_recall_s, 0, 10,
                 "a centre alarm within this long (s) of the last unsafe reading of one dropped "
                 "unconfirmed brakes at once")
            .add("ttc_trust", &P::ttc_trust, 0, 1,
                 "the remembered distance is this fraction of time to contact x speed")
            .add("side_blocks_unknown_centre", &P::side_blocks_unknown_centre, 0, 1,
                 "a side unsafe while the centre reads unknown counts as a centre alarm")
            .add("side_nudge", &P::side_nudge, 0, 1,
                 "a side unsafe: the roll away from it, fraction of the maximum tilt (0: none)")
            .add("side_away_mps", &P::side_away_mps, 0, 3,
                 "the roll away stops above this lateral speed away (m/s)")
            .add("side_shift_max_m", &P::side_shift_max_m, 0, 5,
                 "the roll away from one side's obstacle ends after this much sideways movement "
                 "since the side last read unsafe (m)")
            .add("side_settle_decel_mps2", &P::side_settle_decel_mps2, 0.1, 10,
                 "after a push away from a side: the sideways deceleration a counter-roll of "
                 "side_nudge is taken to give (m/s^2; the push ends while the drone can stop "
                 "within side_shift_max_m)")
            .add("side_settle_mps", &P::side_settle_mps, 0, 2,
                 "after a push away from a side: the counter-roll stops the drift until it is "
                 "under this (m/s)")
            .add("side_settle_yield_roll", &P::side_settle_yield_roll, 0, 1,
                 "after a push away from a side: a pilot's roll on away from it beyond this "
                 "(fraction of the maximum tilt) ends the counter-roll")
            .add("default_side_m", &P::default_side_m, 0, 20,
                 "where a side obstacle is assumed to be ahead when its time to contact is "
                 "unknown (m)")
            .add("side_hull_half_m", &P::side_hull_half_m, 0, 2,
                 "a side obstacle reaching into the path: the drone's half-width (m; 0: such a "
                 "side never brakes)")
            .add("side_reach_clear_m", &P::side_reach_clear_m, -1, 5,
                 "a side obstacle reaching into the path brakes when its edge, less the "
                 "half-width and the push that can still be made before it, would pass nearer "
                 "than this (m)")
            .add("side_reach_confirm_s", &P::side_reach_confirm_s, 0, 5,
                 "a side obstacle reaching into the path brakes only once the side has read "
                 "unsafe this long without a break (s)")
            .add("side_pass_margin_m", &P::side_pass_margin_m, 0, 10,
                 "the roll toward a side stays zeroed until this far past where it was seen (m)");
        return x;
    }();
    return t;
}

std::optional<std::string> apply_assist_overrides(AssistParams& p,
                                                  const std::vector<std::string>& set) {
    return vision::apply_param_overrides(assist_param_table(), p, set, "--assist-set", "--assist");
}

const char* to_string(RegionState s) {
    switch (s) {
        case RegionState::Unknown:
            return "unknown";
        case RegionState::Clear:
            return "clear";
        case RegionState::Unsafe:
            return "unsafe";
        case RegionState::Stale:
            return "stale";
    }
    return "?";
}

const char* to_string(AssistAction a) {
    switch (a) {
        case AssistAction::Off:
            return "OFF";
        case AssistAction::Override:
            return "OVERRIDE";
        case AssistAction::Watching:
            return "WATCHING";
        case AssistAction::Braking:
            return "BRAKING";
        case AssistAction::Holding:
            return "HOLDING";
        case AssistAction::LimitLeft:
            return "LIMIT LEFT";
        case AssistAction::LimitRight:
            return "LIMIT RIGHT";
        case AssistAction::LimitSides:
            return "LIMIT SIDES";
        case AssistAction::SteerLeft:
            return "STEER LEFT";
        case AssistAction::SteerRight:
            return "STEER RIGHT";
        case AssistAction::Approaching:
            return "APPROACHING";
        case AssistAction::Probing:
            return "PROBING";
        case AssistAction::Confirming:
            return "CONFIRMING";
    }
    return "?";
}

bool is_intervention(AssistAction a) {
    return a != AssistAction::Off && a != AssistAction::Override && a != AssistAction::Watching &&
           a != AssistAction::Approaching && a != AssistAction::Confirming;
}

double Assist::placed_ahead_m(const RegionEvidence& e, double vx_mps) const {
    // Time to contact at the frame's capture, less what was flown since it was captured.
    if (!known(e.ttc_s) || !known(vx_mps) || vx_mps <= 0.2) return kUnknown;
    const double age = known(e.age_s) ? std::max(e.age_s, 0.0) : 0.0;
    return p_.ttc_trust * std::max(e.ttc_s - age, 0.0) * vx_mps;
}

void Assist::keep_speed(double t_s, double vx_mps) {
    auto& r = st_.speeds;
    if (!known(vx_mps)) {
        r.clear();  // a gap: what came before no longer says what the classifier saw
        return;
    }
    // One sample per 10 ms at most: however often the caller steps, the ring holds over a
    // second, more than the window plus a decision's age.
    if (!r.empty() && !(t_s >= r.back().t_s + 0.01)) return;
    r.push({t_s, vx_mps});
}

double Assist::window_speed(double captured_s) const {
    const auto& r = st_.speeds;
    if (r.empty()) return kUnknown;
    const double from = captured_s - p_.evidence_window_s;
    // The samples must reach back to the window's start (one step's slack).
    if (r[0].t_s > from + 0.05) return kUnknown;
    double slowest = kUnknown;
    for (std::size_t k = 0; k < r.size(); ++k) {
        const auto& s = r[k];
        if (s.t_s >= from - 1e-9 && s.t_s <= captured_s + 1e-9)
            slowest = known(slowest) ? std::min(slowest, s.vx_mps) : s.vx_mps;
    }
    return slowest;
}

double Assist::stopping_m(double v_mps) const {
    return v_mps * p_.react_s + v_mps * v_mps / (2 * p_.brake_decel_mps2);
}

RegionState Assist::effective(const RegionEvidence& e) const {
    if (e.state == RegionState::Stale) return RegionState::Stale;
    if (e.state != RegionState::Unknown && known(e.age_s) && e.age_s > p_.stale_after_s)
        return RegionState::Stale;
    return e.state;
}

bool Assist::confirm_centre(const AssistInput& in, RegionState centre, double dt) {
    const bool moving = known(in.vx_mps) && in.vx_mps > p_.moving_forward_mps;
    if (!moving || p_.confirm_s <= 0) {
        st_.pending = false;
        return centre == RegionState::Unsafe;
    }
    if (centre == RegionState::Unsafe) {
        // How long the brake may wait: until the drone, braking then, would stop confirm_gap_m
        // short of where this reading's time to contact places the obstacle. Nothing to place it
        // by (no time to contact, too slow for one to mean a distance): no wait.
        const RegionEvidence& c = in.regions[1];
        const double ahead = placed_ahead_m(c, in.vx_mps);
        const double slack_s =
            known(ahead) ? (ahead - stopping_m(in.vx_mps) - p_.confirm_gap_m) / in.vx_mps : 0.0;
        // Recurring within confirm_recall_s of an alarm dropped unconfirmed: confirmed.
        const bool recurs = !st_.pending && known(st_.last_unsafe_t_s) &&
                            in.t_s - st_.last_unsafe_t_s <= p_.confirm_recall_s;
        st_.last_unsafe_t_s = in.t_s;
        if (recurs) return true;
        if (!st_.pending) {
            st_.pending = true;
            st_.pending_unsafe_s = 0;
            st_.pending_deadline_s = in.t_s + slack_s;
        } else {
            st_.pending_unsafe_s += dt;
            st_.pending_deadline_s = std::min(st_.pending_deadline_s, in.t_s + slack_s);
        }
        st_.pending_clear_s = 0;
        st_.pending_evidence = c;
        return st_.pending_unsafe_s >= p_.confirm_s || in.t_s >= st_.pending_deadline_s;
    }
    if (!st_.pending) return false;
    if (centre == RegionState::Clear) {
        st_.pending_clear_s += dt;
        if (st_.pending_clear_s >= p_.confirm_clear_s) {
            st_.pending = false;
            return false;
        }
    }
    // Unknown, stale or briefly clear: the deadline stands.
    return in.t_s >= st_.pending_deadline_s;
}

bool Assist::side_in_path(const AssistInput& in, std::size_t i) const {
    const RegionEvidence& e = in.regions[i];
    const double since = st_.side_unsafe_since_s[i == 0 ? 0 : 1];
    if (!(p_.side_hull_half_m > 0) || !known(e.edge_m) || effective(e) != RegionState::Unsafe ||
        !known(in.vx_mps) || in.vx_mps <= p_.moving_forward_mps || !known(since) ||
        in.t_s - since < p_.side_reach_confirm_s)
        return false;
    // The hull's clearance if the drone held its course (the edge is measured square to the
    // direction of travel), and what a push away could add before the drone is there.
    const double pass_m = e.edge_m - p_.side_hull_half_m;
    const double age = known(e.age_s) ? std::max(e.age_s, 0.0) : 0.0;
    const double left_s =
        known(e.ttc_s) ? p_.ttc_trust * e.ttc_s - age : p_.default_side_m / in.vx_mps;
    const double t = std::max(0.0, left_s - p_.react_s);
    const RegionEvidence& other = in.regions[2 - i];
    const bool may_push = p_.side_nudge > 0 && effective(other) == RegionState::Clear;
    const double push_m =
        may_push ? std::min(p_.side_shift_max_m, 0.5 * p_.side_settle_decel_mps2 * t * t) : 0.0;
    return pass_m + push_m < p_.side_reach_clear_m;
}

AssistOutput Assist::step(const AssistInput& in) {
    // A side's reading stands in for the centre's (the nearer such side's when both):
    //  - a side unsafe beside a centre with no evidence (side_blocks_unknown_centre);
    //  - a side unsafe whose obstacle reaches into the path beyond what a push clears in time.
    for (const std::size_t i : {0u, 2u}) {
        double& since = st_.side_unsafe_since_s[i == 0 ? 0 : 1];
        if (effective(in.regions[i]) != RegionState::Unsafe)
            since = kUnknown;
        else if (!known(since))
            since = in.t_s;
    }
    int beside = -1;
    StandIn why = StandIn::None;
    if (in.enabled && !in.override && in.flying) {
        const RegionState centre = effective(in.regions[1]);
        const bool centre_unknown = centre == RegionState::Unknown;
        for (const int i : {0, 2}) {
            if (centre == RegionState::Unsafe) break;  // the centre's own alarm
            const auto si = static_cast<std::size_t>(i);
            if (effective(in.regions[si]) != RegionState::Unsafe) continue;
            StandIn reason = StandIn::None;
            if (side_in_path(in, si))
                reason = StandIn::InThePath;
            else if (p_.side_blocks_unknown_centre && centre_unknown)
                reason = StandIn::CentreUnknown;
            if (reason == StandIn::None) continue;
            const double ttc = in.regions[si].ttc_s;
            const double best =
                beside < 0 ? kUnknown : in.regions[static_cast<std::size_t>(beside)].ttc_s;
            if (beside < 0 || (known(ttc) && (!known(best) || ttc < best))) {
                beside = i;
                why = reason;
            }
        }
    }
    if (beside < 0) return step_as_given(in, vision::Region::Centre, StandIn::None);
    AssistInput taken = in;
    taken.regions[1] = in.regions[static_cast<std::size_t>(beside)];
    AssistOutput out =
        step_as_given(taken, beside == 0 ? vision::Region::Left : vision::Region::Right, why);
    // The centre as it read (unknown, or clear beside an obstacle reaching into the path).
    out.centre = effective(in.regions[1]);
    return out;
}

AssistOutput Assist::step_as_given(const AssistInput& in, vision::Region acted_for, StandIn why) {
    AssistOutput out;
    // What the centre's actions are for: the centre's own alarm, or a side's standing in for it
    // (then the record, the log and the banner name that side, and why).
    const std::string side_name = acted_for == vision::Region::Left ? "left" : "right";
    const std::string side_why = why == StandIn::InThePath       ? " reaching into the path"
                                 : why == StandIn::CentreUnknown ? ", nothing seen ahead"
                                                                 : "";
    const std::string obstacle =
        why != StandIn::None ? "obstacle " + side_name + side_why : "obstacle ahead";
    const std::string alarm_text =
        why != StandIn::None ? side_name + " alarm" + side_why : "centre alarm";
    out.command = in.pilot;
    using Phase = State::Phase;
    auto finish = [&](AssistOutput& o) -> AssistOutput {
        o.intervened = !(o.command == in.pilot);
        o.changed = st_.first || o.action != st_.last_action || o.region != st_.last_region;
        st_.first = false;
        st_.last_action = o.action;
        st_.last_region = o.region;
        return o;
    };
    if (!in.enabled || in.override || !in.flying) {
        // Whatever was going on is forgotten: switching it back on starts afresh.
        st_.phase = Phase::Free;
        st_.probing = false;
        st_.stopped_clear_s = 0;
        st_.side_left_m = {kUnknown, kUnknown};
        st_.side_shift_m = {0, 0};
        st_.side_pushed = {false, false};
        st_.pending = false;
        st_.last_unsafe_t_s = kUnknown;
        keep_speed(in.t_s, in.vx_mps);
        out.action = !in.enabled   ? AssistAction::Off
                     : in.override ? AssistAction::Override
                                   : AssistAction::Watching;
        out.reason = !in.enabled   ? "assist off"
                     : in.override ? "override held: commands pass unchanged"
                                   : "on the ground";
        return finish(out);
    }

    const RegionState left = effective(in.regions[0]);
    const RegionState centre = effective(in.regions[1]);
    const RegionState right = effective(in.regions[2]);
    const RegionEvidence& c = in.regions[1];
    out.centre = centre;
    const bool vx_known = known(in.vx_mps);
    const bool moving_forward = vx_known && in.vx_mps > p_.moving_forward_mps;
    const bool pilot_forward = in.pilot.progressive && in.pilot.pitch < 0;

    // Forward travel since the brake (navdata velocity integrated over the caller's clock).
    const double dt = known(st_.last_t_s) ? std::clamp(in.t_s - st_.last_t_s, 0.0, 0.5) : 0.0;
    st_.last_t_s = in.t_s;
    if (vx_known) st_.travelled_m += in.vx_mps * dt;
    keep_speed(in.t_s, in.vx_mps);
    auto remember = [&](const RegionEvidence& e) {
        const double d = placed_ahead_m(e, in.vx_mps);
        const double est = known(d) ? d : p_.default_obstacle_m;
        const double remaining = known(st_.obstacle_m) ? st_.obstacle_m - st_.travelled_m : 1e9;
        st_.obstacle_m = std::min(est, remaining);
        // The far bound: the new reading's place; without one (no time to contact), the one
        // already remembered, else the default.
        const double far_before =
            known(st_.obstacle_far_m) ? st_.obstacle_far_m - st_.travelled_m : kUnknown;
        st_.obstacle_far_m = std::max(known(d)            ? d
                                      : known(far_before) ? far_before
                                                          : p_.default_obstacle_m,
                                      st_.obstacle_m);
        st_.travelled_m = 0;
        st_.heading_deg = in.yaw_deg;
        st_.clear_seen_s = 0;
    };

    // Centre: confirm, brake, hold, release. In free flight an alarm brakes once confirmed (or
    // its deadline come); one braked for at its deadline, no longer read unsafe, is remembered
    // where its last unsafe reading placed it.
    bool alarm = centre == RegionState::Unsafe;
    RegionEvidence alarm_evidence = c;
    if (st_.phase == Phase::Free) {
        alarm = confirm_centre(in, centre, dt);
        if (alarm && centre != RegionState::Unsafe) {
            alarm_evidence = st_.pending_evidence;
            alarm_evidence.age_s = (known(alarm_evidence.age_s) ? alarm_evidence.age_s : 0.0) +
                                   in.t_s - st_.last_unsafe_t_s;
        }
    }
    if (alarm || st_.phase != Phase::Free) st_.pending = false;
    if (alarm && (moving_forward || pilot_forward) &&
        (st_.phase == Phase::Free || (st_.phase == Phase::Holding && moving_forward))) {
        remember(alarm_evidence);
        st_.braked_for = obstacle;
        st_.phase = moving_forward ? Phase::Braking : Phase::Holding;
        st_.since_s = in.t_s;
    } else if (centre == RegionState::Unsafe && st_.phase == Phase::Holding) {
        // Not while braking: a time to contact fitted over frames from before the brake,
        // times the falling speed, places the obstacle much nearer than it is.
        remember(c);
    }
    // The remembered obstacle's distance ahead now (unknown when there is none).
    double remaining = known(st_.obstacle_m) ? st_.obstacle_m - st_.travelled_m : kUnknown;
    // ... and the farthest it may be (sight_far_bound): the cap after a stop placed it nearer.
    auto far_bound = [&] {
        return p_.sight_far_bound && known(st_.obstacle_far_m) && known(remaining)
                   ? std::max(st_.obstacle_far_m - st_.travelled_m, remaining)
                   : remaining;
    };
    if (st_.phase != Phase::Free) {
        const bool turned = known(st_.heading_deg) && known(in.yaw_deg) &&
                            heading_change_deg(st_.heading_deg, in.yaw_deg) >= p_.release_turn_deg;
        // "Clear" is evidence only when the classifier could have seen the remembered obstacle:
        // its time to contact at this speed under the classifier's threshold. A stopped or
        // creeping drone sees no expansion, so its "clear" says nothing about what is ahead.
        // Judged where the obstacle may be farthest (sight_far_bound): nearer, the cap put it.
        const double far = far_bound();
        // Both at the speed of the frames the reading was made on (evidence_window_s), where the
        // obstacle stood when the last of them was captured.
        const double age = known(c.age_s) ? std::max(c.age_s, 0.0) : 0.0;
        const double v_seen = p_.evidence_window_s > 0 ? window_speed(in.t_s - age) : in.vx_mps;
        const double far_seen = p_.evidence_window_s > 0
                                    ? far + (vx_known ? std::max(in.vx_mps, 0.0) : 0.0) * age
                                    : far;
        const bool in_sight = moving_forward && known(v_seen) && v_seen >= p_.evidence_min_mps &&
                              known(far_seen) && far_seen < p_.detect_ttc_s * v_seen;
        // Unknown pauses the count (no evidence either way: at a probe's speed the classifier
        // often cannot judge the centre); only an unsafe reading starts it again.
        if (centre == RegionState::Unsafe) {
            st_.clear_seen_s = 0;
        } else if (centre == RegionState::Clear && in_sight &&
                   (p_.clear_while_braking || st_.phase != Phase::Braking)) {
            st_.clear_seen_s += dt;
        }
        const bool forgotten = st_.clear_seen_s >= p_.forget_after_clear_s;
        if (turned || forgotten) {
            st_.phase = Phase::Free;
            st_.obstacle_m = kUnknown;
            st_.obstacle_far_m = kUnknown;
            remaining = kUnknown;
        }
    }
    // Holding: forward allowed while the remembered obstacle stays more than the gap away once
    // the drone has stopped from its present speed (reaction time, then the braking deceleration).
    const double v_fwd = vx_known ? std::max(in.vx_mps, 0.0) : 0.0;
    const double stop_m = stopping_m(v_fwd);
    auto room = [&] {
        return st_.phase == Phase::Holding && vx_known && known(remaining) &&
               remaining - stop_m > p_.hold_gap_m && centre != RegionState::Unsafe;
    };
    // Probing (see AssistParams): held with no room to approach, stopped, the centre clear for
    // a while: creep toward the obstacle slowly enough for the classifier to see it again.
    const double probe_mps = known(remaining) ? std::clamp(remaining / p_.probe_ttc_s,
                                                           p_.probe_min_mps, p_.probe_max_mps)
                                              : p_.probe_min_mps;
    const double probe_gap_m =
        st_.clear_seen_s >= p_.probe_seen_s ? p_.probe_min_gap_m : p_.probe_blind_gap_m;
    const bool probe_room = known(remaining) && remaining - stop_m > probe_gap_m;
    // A probe goes on while the centre reads unknown: slower than about half a metre per second
    // the direction of travel is too uncertain for the classifier to judge the centre, which is
    // what a probe is for. It stops on stale evidence (no decisions), and brakes on unsafe.
    const bool probe_evidence =
        centre == RegionState::Clear || (st_.probing && centre == RegionState::Unknown);
    if (st_.phase != Phase::Holding || !probe_evidence || !vx_known || !probe_room || room()) {
        st_.probing = false;
        st_.stopped_clear_s = 0;
    } else if (!st_.probing) {
        st_.stopped_clear_s = in.vx_mps < p_.probe_stop_mps ? st_.stopped_clear_s + dt : 0.0;
        st_.probing = st_.stopped_clear_s >= p_.probe_wait_s;
    }
    // A brake that ran out its time without the navdata speed falling means the speed is not to
    // be trusted (frozen navdata, a wrong sample): no further nose-up on it until it reads slow.
    if (vx_known && in.vx_mps < p_.brake_release_mps) st_.speed_trusted = true;
    const double rebrake_mps =
        st_.probing ? probe_mps + p_.probe_rebrake_margin_mps : p_.rebrake_mps;
    if (st_.phase == Phase::Holding && st_.speed_trusted && vx_known && in.vx_mps > rebrake_mps &&
        !room()) {
        // Held, yet still (or again) moving toward it: the hover's slow decay, a gust, the end of
        // an approach. Brake again.
        st_.phase = Phase::Braking;
        st_.since_s = in.t_s;
    }
    if (st_.phase != Phase::Holding) {
        st_.probing = false;
        st_.stopped_clear_s = 0;
    }
    if (st_.phase == Phase::Braking) {
        const bool slow = vx_known && in.vx_mps < p_.brake_release_mps;
        const bool timed_out = in.t_s - st_.since_s > p_.max_brake_s;
        if (slow || !vx_known || timed_out) {
            st_.phase = Phase::Holding;
            // The time to contact the brake was for reads the classifier's threshold when the
            // obstacle came into its view late (a doorway's edge, someone stepping in): then it
            // is much nearer than time to contact x speed. Stopped, the drone may go on toward it
            // only by probing, never by a free approach: no more than the gap ahead of the stop.
            if (known(st_.obstacle_m)) {
                st_.obstacle_m = std::min(st_.obstacle_m, st_.travelled_m + p_.hold_gap_m);
                remaining = st_.obstacle_m - st_.travelled_m;
            }
        }
        if (timed_out && !slow) st_.speed_trusted = false;
    }
    const bool room_ahead = room();

    FlightCommand& cmd = out.command;
    const bool pilot_backing = in.pilot.progressive && in.pilot.pitch > 0;
    if (st_.phase == Phase::Braking) {
        // Full nose-up, yaw and climb kept; backing away harder than that is the pilot's.
        cmd.progressive = true;
        cmd.pitch = 1.0f;
        if (!in.pilot.progressive) cmd.roll = cmd.gaz = cmd.yaw = 0;
        out.action = AssistAction::Braking;
        // A time to contact only from an unsafe reading: a clear centre's (9 s on a replay's
        // dry run, whose drone never slows) is not the obstacle's.
        // Read no longer unsafe: what it braked for, not what this step's regions would say
        // (a side's stand-in comes and goes with its reading).
        out.reason = centre == RegionState::Unsafe
                         ? "BRAKING: " + obstacle + contact_text(c)
                         : "BRAKING: " + st_.braked_for + " (centre now " + to_string(centre) +
                               "), until stopped";
    } else if (st_.phase == Phase::Holding && room_ahead) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "APPROACHING: obstacle remembered %.1f m ahead", remaining);
        out.action = AssistAction::Approaching;
        out.reason = buf;
    } else if (st_.phase == Phase::Holding && st_.probing) {
        if (!pilot_backing && in.vx_mps > probe_mps) {
            // Faster than a probe: nose-up in proportion to the excess (the drone's hover alone
            // bleeds a few tenths of a metre per second over seconds).
            if (!cmd.progressive) cmd = FlightCommand{true, 0, 0, 0, 0};
            cmd.pitch =
                static_cast<float>(std::clamp(p_.hold_gain * (in.vx_mps - probe_mps), 0.0, 1.0));
        } else if (cmd.progressive && double{cmd.pitch} < -p_.probe_pitch) {
            cmd.pitch = static_cast<float>(-p_.probe_pitch);
        }
        char buf[192];
        // With the far bound out beyond the near one (as shown, to 0.1 m), both: the pilot sees
        // why it holds on.
        char where[48];
        const double far = far_bound();
        if (known(far) && std::lround(far * 10) > std::lround(remaining * 10))
            std::snprintf(where, sizeof where, "%.1f-%.1f m", remaining, far);
        else
            std::snprintf(where, sizeof where, "%.1f m", remaining);
        std::snprintf(buf, sizeof buf,
                      "PROBING: obstacle remembered %s ahead, not seen now: forward limited to "
                      "%.2f m/s until it is seen again or forgotten",
                      where, probe_mps);
        out.action = AssistAction::Probing;
        out.reason = buf;
    } else if (st_.pending) {
        out.action = AssistAction::Confirming;
        out.reason =
            "CONFIRMING: " + alarm_text +
            (centre == RegionState::Unsafe ? contact_text(c)
                                           : std::string(" (now ") + to_string(centre) + ")") +
            ", braking if it holds";
        out.pending = out.reason;
    } else if (st_.phase == Phase::Holding) {
        if (!vx_known && !pilot_backing) {
            cmd = FlightCommand{};  // no velocity to hold against: the drone's own hover
        } else if (!pilot_backing && st_.speed_trusted && in.vx_mps > p_.hold_creep_mps) {
            // Still creeping toward it: the AR.Drone's hover lets a few tenths of a metre per
            // second decay over seconds (half a metre travelled). Hold the forward speed at zero
            // with a nose-up in proportion to it; the drone's own hover once it is under the creep.
            if (!cmd.progressive) cmd = FlightCommand{true, 0, 0, 0, 0};
            cmd.pitch = static_cast<float>(std::clamp(p_.hold_gain * in.vx_mps, 0.0, 1.0));
        } else if (cmd.progressive && cmd.pitch < 0) {
            cmd.pitch = 0;
        }
        out.action = AssistAction::Holding;
        out.reason = centre == RegionState::Unsafe
                         ? "HOLDING: " + obstacle + ", forward held at zero" + contact_text(c)
                     : centre == RegionState::Clear
                         ? std::string(
                               "HOLDING: stopped short of the obstacle, forward held at "
                               "zero (turn away, back off or override)")
                         : std::string("HOLDING: centre ") + to_string(centre) +
                               " since the brake (no evidence), forward held at zero until it "
                               "is seen clear";
    }
    if (out.action != AssistAction::Watching) out.region = acted_for;

    // Sides: remember where an unsafe side's obstacle is (ahead by its time to contact x speed)
    // and keep the roll toward it at zero until the drone is past it; push away while it is seen.
    const std::array<RegionState, 2> side_state{left, right};
    std::array<bool, 2> limited{false, false};
    // The sideways speed away from side i (right is +vy; 0 unknown).
    const auto away_mps = [&](std::size_t i) {
        return known(in.vy_mps) ? (i == 0 ? in.vy_mps : -in.vy_mps) : 0.0;
    };
    for (int i = 0; i < 2; ++i) {
        const RegionEvidence& e = in.regions[i == 0 ? 0 : 2];
        double& ahead = st_.side_left_m[i];
        if (known(ahead) && vx_known) ahead -= in.vx_mps * dt;
        if (side_state[i] == RegionState::Unsafe) {
            const double d = known(e.ttc_s) && vx_known && in.vx_mps > 0.2 ? e.ttc_s * in.vx_mps
                                                                           : p_.default_side_m;
            ahead = std::max(known(ahead) ? ahead : 0.0, d + p_.side_pass_margin_m);
        } else if (known(ahead) && (ahead <= 0 || !vx_known)) {
            ahead = kUnknown;  // past it (or no velocity to know: only what is seen counts)
        }
        limited[i] = side_state[i] == RegionState::Unsafe || known(ahead);
        // Movement away from this side since its obstacle was last seen (right is +vy): a side
        // that still reads unsafe holds an obstacle in the flight corridor, however far the
        // drone has moved already (seed 41's ahead-doorway-right-1.5-35: a wall whose edge
        // stood 0.2 m inside the path read unsafe for the last 1.4 m while the spent push held
        // the roll at zero, and the drone flew into the edge).
        double& shift = st_.side_shift_m[i];
        if (!limited[i] || side_state[i] == RegionState::Unsafe)
            shift = 0;
        else
            shift += std::max(0.0, away_mps(static_cast<std::size_t>(i))) * dt;
    }
    // Roll > 0 is right: the left side (0) limits negative roll, the right (1) positive roll.
    // Push away from a side obstacle until the drone is abreast of where it was seen, not only
    // while it is seen: a side alarm flickers (a pillar reads unsafe, then clear, then unsafe as
    // its points come and go), and the few frames it reads unsafe move the drone a few
    // centimetres sideways. Nothing is pushed toward a side that is itself limited.
    const auto still_ahead = [&](int i) {
        return side_state[i] == RegionState::Unsafe ||
               (known(st_.side_left_m[i]) && st_.side_left_m[i] > p_.side_pass_margin_m);
    };
    // (side_nudge 0: no steering at all, only the limits; never a STEERING line that pushes
    // nothing.)
    const bool may_nudge = p_.side_nudge > 0 && moving_forward && known(in.vy_mps);
    // The push's budget for side i is spent once the drone, drifting on at its speed away until
    // a counter-roll stops it, would pass side_shift_max_m.
    const auto budget_spent = [&](std::size_t i) {
        const double v = std::max(0.0, away_mps(i));
        const double drift_m = v * p_.react_s + v * v / (2 * p_.side_settle_decel_mps2);
        return st_.side_shift_m[i] + drift_m >= p_.side_shift_max_m;
    };
    // Only toward a side that reads clear, and no farther than side_shift_max_m past where the
    // side last read unsafe, the drift the push leaves included.
    const auto may_push_away_from = [&](std::size_t i) {
        const std::size_t other = 1 - i;
        return may_nudge && still_ahead(static_cast<int>(i)) && !limited[other] &&
               side_state[other] == RegionState::Clear && !budget_spent(i);
    };
    const bool nudge_right = may_push_away_from(0) && in.vy_mps < p_.side_away_mps;
    const bool nudge_left = may_push_away_from(1) && -in.vy_mps < p_.side_away_mps;
    const bool limit_left = limited[0] && cmd.progressive && cmd.roll < 0;
    const bool limit_right = limited[1] && cmd.progressive && cmd.roll > 0;
    if (limit_left || limit_right) cmd.roll = 0;
    const auto nudge = static_cast<float>(p_.side_nudge);
    if (nudge_right || nudge_left) {
        if (!cmd.progressive) cmd = FlightCommand{true, 0, 0, 0, 0};
        cmd.roll = nudge_right ? std::max(cmd.roll, nudge) : std::min(cmd.roll, -nudge);
    }
    // The budget spent ends the push for this obstacle: resumed as the drift slows, it would
    // alternate with the counter-roll below.
    for (std::size_t i = 0; i < 2; ++i)
        if (st_.side_pushed[i] && budget_spent(i))
            st_.side_shift_m[i] = std::max(st_.side_shift_m[i], p_.side_shift_max_m);
    if (nudge_right) st_.side_pushed[0] = true;
    if (nudge_left) st_.side_pushed[1] = true;
    // A push ended: the drift it left is stopped by a roll against it (never past a stop: in
    // proportion to the speed, hold_gain per m/s, at most side_nudge), unless the pilot rolls
    // away from the side more than side_settle_yield_roll; that, or a drift under
    // side_settle_mps, leaves the drone to the pilot.
    bool settle_left = false, settle_right = false;
    for (std::size_t i = 0; i < 2; ++i) {
        // Not while the push may go on (held back only by side_away_mps, it resumes as the
        // drift slows).
        if (!st_.side_pushed[i] || may_push_away_from(i)) continue;
        const double v = away_mps(i);
        const double pilot_away = i == 0 ? in.pilot.roll : -in.pilot.roll;
        if (pilot_away > p_.side_settle_yield_roll || !(v > p_.side_settle_mps)) {
            st_.side_pushed[i] = false;
            continue;
        }
        // Pushed away from the other side now; or hovering (a brake's end, the pilot's hands
        // off), where the AR.Drone holds its position itself, the drift included.
        if (nudge_right || nudge_left || !cmd.progressive) continue;
        const auto r = static_cast<float>(std::min(p_.side_nudge, p_.hold_gain * v));
        cmd.roll = i == 0 ? std::min(cmd.roll, -r) : std::max(cmd.roll, r);
        (i == 0 ? settle_left : settle_right) = true;
    }
    if (st_.phase == Phase::Free && (settle_left || settle_right)) {
        // Rolling toward the side the drone was pushed from, to stop the drift away from it.
        const std::string from = settle_left ? "left" : "right";
        out.action = settle_left ? AssistAction::SteerLeft : AssistAction::SteerRight;
        out.region = settle_left ? vision::Region::Left : vision::Region::Right;
        out.reason =
            "STEERING " + from + ": stopping the drift away from the obstacle seen " + from;
    } else if (st_.phase == Phase::Free &&
               (limit_left || limit_right || nudge_left || nudge_right)) {
        const bool toward_left = nudge_right || (limit_left && !nudge_left);
        const int side = toward_left ? 0 : 2;
        out.region = toward_left ? vision::Region::Left : vision::Region::Right;
        const std::string where = toward_left ? "left" : "right";
        // Seen this frame (with its time to contact), or only remembered while passing it.
        const bool seen = side_state[toward_left ? 0 : 1] == RegionState::Unsafe;
        if (nudge_left || nudge_right) {
            out.action = nudge_right ? AssistAction::SteerRight : AssistAction::SteerLeft;
            out.reason = "STEERING " + std::string(nudge_right ? "right" : "left") +
                         (seen ? ": obstacle " + where + contact_text(in.regions[side])
                               : ": passing the obstacle seen " + where);
        } else {
            out.action = limit_left && limit_right ? AssistAction::LimitSides
                         : limit_left              ? AssistAction::LimitLeft
                                                   : AssistAction::LimitRight;
            out.reason =
                seen ? "LIMITING: obstacle " + where + ", no movement toward it" +
                           contact_text(in.regions[side])
                     : "LIMITING: passing the obstacle seen " + where + ", no movement toward it";
        }
    }
    // A move with nothing left in it is a hover: the drone holds its position itself.
    if (cmd.progressive && cmd.roll == 0 && cmd.pitch == 0 && cmd.gaz == 0 && cmd.yaw == 0 &&
        !(in.pilot == cmd))
        cmd.progressive = false;

    if (st_.phase != Phase::Free) out.obstacle_m = remaining;
    // Say what is not known: an unknown region is never a reason to brake.
    out.unknown_ahead =
        pilot_forward && (centre == RegionState::Unknown || centre == RegionState::Stale) &&
        (out.action == AssistAction::Watching || out.action == AssistAction::Approaching);
    if (out.action == AssistAction::Watching) {
        if (out.unknown_ahead)
            out.reason = std::string("centre ") + to_string(centre) + ": no evidence, not braking";
        else if (!vx_known)
            out.reason = "watching (no velocity from navdata)";
        else
            out.reason = "watching";
    }
    return finish(out);
}

}  // namespace gs::app
