#pragma once
// The assist between the pilot and the AT sender, for any source: it keeps the classifier's
// newest decision (with its capture time) and the newest navdata, runs the Assist on every pilot
// command, and logs each change of action as an intervention (for the log, the HUD and the
// dataset's assist.csv). Pure: the caller passes the times; the same gate serves the live drone,
// the virtual drone and, as a dry run (nothing sent, only shown), a replay.

#include "app/assist.hpp"
#include "drone/core/clock.hpp"
#include "drone/core/sample.hpp"
#include "vision/classifier.hpp"

#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>

namespace gs::app {

// Region evidence from one classifier result: valid decisions are unsafe or clear, the others
// unknown; `flow`: the score is 1/TTC, so a time to contact is known.
std::array<RegionEvidence, 3> evidence_of(const vision::FrameResult& r, bool flow);

struct Intervention {
    TimeNs t_ns = 0;
    std::int64_t frame = -1;  // the newest classified frame then (-1: none yet)
    // That frame's PaVE frame number (live) and capture time (the link's clock: the drone's
    // timestamp mapped onto it; 0: none): a recording maps the number to its own frame index
    // (app/session_recording.cpp), and the capture time is that frame's t_ms there.
    std::optional<std::uint32_t> pave_frame;
    TimeNs decision_ns = 0;
    AssistAction action = AssistAction::Watching;
    vision::Region region = vision::Region::Centre;
    std::string reason;
    FlightCommand before, after;
};

class AssistGate {
public:
    explicit AssistGate(AssistParams p = {}) : assist_(p) {}

    // The classifier's newest result, made on the frame captured at capture_ns (link clock).
    void on_decision(const vision::FrameResult& r, TimeNs capture_ns, bool flow,
                     std::optional<std::uint32_t> pave_frame = std::nullopt);
    // The newest navdata (NaN fields unknown); `flying`: drone_state FLY.
    void on_navdata(const NavState& nav, bool flying);

    // What to send for the pilot's command at `now` (link clock).
    AssistOutput apply(const FlightCommand& pilot, TimeNs now_ns);

    void set_enabled(bool on) { enabled_ = on; }
    bool enabled() const { return enabled_; }
    void set_override(bool held) { override_ = held; }
    bool override_held() const { return override_; }
    void reset();  // a new source: forget decisions, navdata and state

    const AssistOutput& last() const { return last_; }
    // The newest interventions (actions other than watching / off), oldest first.
    const std::deque<Intervention>& interventions() const { return log_; }
    std::uint64_t intervention_count() const { return count_; }
    static constexpr std::size_t kLogSize = 256;

private:
    Assist assist_;
    std::array<RegionEvidence, 3> regions_{};
    TimeNs decision_capture_ns_ = -1;
    std::int64_t decision_frame_ = -1;
    std::optional<std::uint32_t> decision_pave_;
    NavState nav_;
    bool flying_ = false;
    bool enabled_ = true;
    bool override_ = false;
    AssistOutput last_;
    std::deque<Intervention> log_;
    std::uint64_t count_ = 0;
};

}  // namespace gs::app
