#include "app/pilot_path.hpp"

#include <cstdio>

namespace gs::app {

namespace {

FlightCommand path_flight_of(const std::optional<link::Move>& m) {
    if (!m) return FlightCommand{};
    return FlightCommand{true, m->roll, m->pitch, m->gaz, m->yaw};
}

std::optional<link::Move> path_move_of(const FlightCommand& c) {
    if (!c.progressive) return std::nullopt;  // hover: PilotCommands sends one Hover
    return link::Move{c.roll, c.pitch, c.gaz, c.yaw};
}

std::string path_command_text(const FlightCommand& c) {
    if (!c.progressive) return "hover";
    char buf[96];
    std::snprintf(buf, sizeof buf, "roll %+.2f pitch %+.2f gaz %+.2f yaw %+.2f", double{c.roll},
                  double{c.pitch}, double{c.gaz}, double{c.yaw});
    return buf;
}

}  // namespace

void PilotPath::reset() {
    gate_.reset();
    pilot_.reset();
    dry_ = false;
    replay_now_ns_ = 0;
    taken_ = gate_.intervention_count();
}

void PilotPath::on_output(const PipelineOutput& out) {
    if (out.camera != CameraId::Front) return;
    // The age of a decision is measured from its frame's capture: the obstacle stood where the
    // frame shows it then, and the drone has flown on since. Live: the capture time on the link's
    // clock (the drone's timestamp mapped onto it), so a frame the air or a queue held back
    // arrives as old as it is (and goes stale while it waited, not only after it arrived); its
    // arrival when the source has no capture clock; replay: the frame's own time (the dry
    // run's clock; a replayed frame has no receive time, FrameSample::recv_ns 0).
    const bool replay = out.frame.recv_ns <= 0;
    const TimeNs t = replay                     ? out.frame.t_ns
                     : out.frame.capture_ns > 0 ? out.frame.capture_ns
                                                : out.frame.recv_ns;
    gate_.on_decision(out.result, t, out.classifier == "flow", out.frame.frame_number);
    if (replay) replay_now_ns_ = out.frame.t_ns;
}

void PilotPath::on_navdata(const NavState& nav) {
    // drone_state bit 0 (FLY); a dataset without drone_state (the thesis' own) counts as flying.
    const bool flying = nav.drone_state ? (*nav.drone_state & 1u) != 0 : true;
    gate_.on_navdata(nav, flying);
}

AssistOutput PilotPath::run(const std::optional<link::Move>& input, TimeNs now_ns) {
    return gate_.apply(path_flight_of(input), now_ns);
}

std::optional<link::Command> PilotPath::step(const std::optional<link::Move>& input,
                                             TimeNs now_ns) {
    dry_ = false;
    const AssistOutput out = run(input, now_ns);
    // The pilot not steering and nothing to enforce: nothing to send (after the one Hover).
    return pilot_.next(input || out.intervened ? path_move_of(out.command) : std::nullopt);
}

void PilotPath::dry_run(const std::optional<link::Move>& input) {
    dry_ = true;
    (void)run(input, replay_now_ns_);
}

AssistStatus PilotPath::status() const {
    AssistStatus s;
    const AssistOutput& o = gate_.last();
    s.enabled = gate_.enabled();
    s.override_held = gate_.override_held();
    s.dry_run = dry_;
    s.interventions = gate_.intervention_count();
    s.unknown = s.enabled && !s.override_held && o.unknown_ahead;
    std::string line;
    switch (o.action) {
        case AssistAction::Off:
            s.action = "OFF";
            line = "ASSIST OFF";
            break;
        case AssistAction::Override:
            s.action = "OVERRIDE";
            line = "OVERRIDE: assist bypassed while held";
            break;
        case AssistAction::Braking:
        case AssistAction::Holding:
        case AssistAction::Probing:
            s.action = to_string(o.action);
            s.acting = true;
            line = o.reason;
            break;
        case AssistAction::LimitLeft:
        case AssistAction::LimitRight:
        case AssistAction::LimitSides: {
            s.acting = true;
            const char* side = o.action == AssistAction::LimitLeft    ? "LEFT"
                               : o.action == AssistAction::LimitRight ? "RIGHT"
                                                                      : "SIDES";
            s.action = std::string(side) + " BLOCKED";
            line = s.action + ": obstacle " +
                   (o.action == AssistAction::LimitSides
                        ? std::string("on both sides")
                        : std::string(o.action == AssistAction::LimitLeft ? "left" : "right")) +
                   ", no movement toward it";
            break;
        }
        case AssistAction::SteerLeft:
        case AssistAction::SteerRight:
            s.acting = true;
            s.action = o.action == AssistAction::SteerLeft ? "STEERING LEFT" : "STEERING RIGHT";
            line = o.reason;  // "STEERING right: obstacle left, contact in 1.7 s"
            break;
        case AssistAction::Confirming:
            s.action = "CONFIRMING";
            s.confirming = true;
            line = o.reason;  // "CONFIRMING: centre alarm, contact in 2.8 s, braking if it holds"
            break;
        case AssistAction::Watching:
        case AssistAction::Approaching:
            if (s.unknown) {
                s.action = "UNKNOWN";
                line = o.centre == RegionState::Stale
                           ? "UNKNOWN: classifier stale, no evidence ahead, not braking"
                           : "UNKNOWN: no evidence ahead, not braking";
            } else if (o.action == AssistAction::Approaching) {
                s.action = "APPROACHING";
                line = o.reason;
            } else {
                s.action = "WATCHING";
                line = "ASSIST ON";
            }
            break;
    }
    // A brake pending behind a side's steering or limit: both, the side's first (it acts now).
    if (!o.pending.empty() && o.action != AssistAction::Confirming) {
        s.confirming = true;
        line += "; " + o.pending;
    }
    s.line = (dry_ ? "DRY RUN (replay, nothing sent): " : "") + line;
    s.brief = (dry_ ? "DRY RUN: " : "") + s.action +
              (s.confirming && o.action != AssistAction::Confirming ? "; BRAKE PENDING" : "");
    return s;
}

std::vector<Intervention> PilotPath::take_new() {
    std::vector<Intervention> out;
    const std::uint64_t total = gate_.intervention_count();
    const auto& log = gate_.interventions();
    const std::uint64_t fresh = total - taken_;
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(fresh, log.size()));
    out.assign(log.end() - static_cast<std::ptrdiff_t>(n), log.end());
    taken_ = total;
    return out;
}

std::string describe(const Intervention& i) {
    std::string s =
        std::string("assist ") + to_string(i.action) + " (" + vision::to_string(i.region) +
        (i.frame >= 0 ? ", frame " + std::to_string(i.frame) : std::string()) + "): " + i.reason +
        "; " + path_command_text(i.before) + " -> " + path_command_text(i.after);
    return s;
}

}  // namespace gs::app
