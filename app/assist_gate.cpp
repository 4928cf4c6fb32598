#include "app/assist_gate.hpp"

#include <cmath>

namespace gs::app {

std::array<RegionEvidence, 3> evidence_of(const vision::FrameResult& r, bool flow) {
    std::array<RegionEvidence, 3> e{};
    for (std::size_t i = 0; i < 3; ++i) {
        const vision::RegionDecision& d = r.regions[i];
        // A still camera's region (approach_only: nothing approaching, what stands ahead not
        // judged) is clear to the assist: it starts a probe from a hold, and the assist's
        // evidence window never lets a reading made that slowly forget an obstacle.
        e[i].state = !d.valid   ? RegionState::Unknown
                     : d.unsafe ? RegionState::Unsafe
                                : RegionState::Clear;
        if (flow && d.valid && std::isfinite(d.score) && d.score > 0) e[i].ttc_s = 1.0 / d.score;
        if (flow && d.valid) e[i].edge_m = d.edge_m;
    }
    return e;
}

void AssistGate::on_decision(const vision::FrameResult& r, TimeNs capture_ns, bool flow,
                             std::optional<std::uint32_t> pave_frame) {
    regions_ = evidence_of(r, flow);
    decision_capture_ns_ = capture_ns;
    decision_frame_ = r.frame_index;
    decision_pave_ = pave_frame;
}

void AssistGate::on_navdata(const NavState& nav, bool flying) {
    nav_ = nav;
    flying_ = flying;
}

void AssistGate::reset() {
    assist_.reset();
    regions_ = {};
    decision_capture_ns_ = -1;
    decision_frame_ = -1;
    decision_pave_.reset();
    nav_ = NavState{};
    flying_ = false;
    last_ = AssistOutput{};
}

AssistOutput AssistGate::apply(const FlightCommand& pilot, TimeNs now_ns) {
    AssistInput in;
    in.t_s = static_cast<double>(now_ns) * 1e-9;
    in.pilot = pilot;
    in.regions = regions_;
    if (decision_capture_ns_ >= 0)
        for (auto& r : in.regions)
            r.age_s = static_cast<double>(now_ns - decision_capture_ns_) * 1e-9;
    in.vx_mps = nav_.vx_mps;
    in.vy_mps = nav_.vy_mps;
    in.yaw_deg = nav_.yaw_deg;
    in.flying = flying_;
    in.enabled = enabled_;
    in.override = override_;
    last_ = assist_.step(in);
    const AssistAction a = last_.action;
    if (last_.changed && is_intervention(a)) {
        ++count_;
        log_.push_back({now_ns, decision_frame_, decision_pave_,
                        decision_capture_ns_ < 0 ? 0 : decision_capture_ns_, a, last_.region,
                        last_.reason, pilot, last_.command});
        if (log_.size() > kLogSize) log_.pop_front();
    }
    return last_;
}

}  // namespace gs::app
