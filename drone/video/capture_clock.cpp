#include "drone/video/capture_clock.hpp"

#include <algorithm>

namespace gs::video {

TimeNs CaptureClock::map(std::uint32_t drone_ms, TimeNs recv_ns) {
    bool anchor = !have_;
    if (have_) {
        // Modular difference: a 32-bit millisecond counter wraps every 49.7 days.
        const auto step_ms = static_cast<std::int32_t>(drone_ms - last_ms_);
        const TimeNs d_drone = static_cast<TimeNs>(step_ms) * kNsPerMs;
        const TimeNs d_recv = recv_ns - last_recv_ns_;
        if (step_ms == 0 && (frozen_ || recv_ns - advanced_recv_ns_ > p_.frozen_after_ns)) {
            // The drone's clock stands still while frames keep coming: its timestamps say
            // nothing, and the frame is as old as its arrival says (the best left to know).
            frozen_ = true;
            ++frozen_frames_;
            last_recv_ns_ = recv_ns;
            last_out_ns_ = std::max(last_out_ns_, recv_ns);
            return last_out_ns_;
        }
        if (step_ms != 0) advanced_recv_ns_ = recv_ns;
        // Late (d_recv beyond d_drone) is a delivery stall, not a clock jump: no re-anchor. A
        // clock that stood still and runs again is anchored anew.
        if (step_ms < 0 || d_drone - d_recv > p_.max_jump_ns || frozen_) {
            anchor = true;
        } else {
            drone_ns_ += d_drone;
            const auto creep = static_cast<TimeNs>(
                static_cast<double>(std::max<TimeNs>(d_recv, 0)) * p_.max_skew_ppm * 1e-6);
            offset_ns_ = std::min(offset_ns_ + creep, recv_ns - drone_ns_);
        }
    }
    if (anchor) {
        drone_ns_ = static_cast<TimeNs>(drone_ms) * kNsPerMs;
        offset_ns_ = recv_ns - drone_ns_;
        ++anchors_;
        have_ = true;
        frozen_ = false;
        advanced_recv_ns_ = recv_ns;
        last_out_ns_ = recv_ns;
        last_ms_ = drone_ms;
        last_recv_ns_ = recv_ns;
        return recv_ns;
    }
    last_ms_ = drone_ms;
    last_recv_ns_ = recv_ns;
    last_out_ns_ = std::min(std::max(drone_ns_ + offset_ns_, last_out_ns_), recv_ns);
    return last_out_ns_;
}

}  // namespace gs::video
