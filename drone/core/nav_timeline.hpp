#pragma once
// The drone state at any instant of a navdata stream, by the one rule of docs/dataset.md (docs/):
// the samples around it interpolated, the nearest sample when there is none on one side, and
// nothing (unknown) when no sample is within the allowed gap of it (kFrameNavMaxGapNs for a
// frame). Pure: times are stream times (ns from the start of the flight), no clock.

#include "drone/core/sample.hpp"

#include <cstddef>
#include <limits>
#include <vector>

namespace gs::inline core {

// The recent navdata samples in time order, in a fixed ring (no allocation after construction),
// and the drone state at any instant by the one rule of docs/dataset.md: interpolated between the
// two samples around it, the nearest sample when there is none on one side, unknown when none is
// within the gap the caller allows. Used live (the link's frames) and when recording or replaying
// (NavAligner), so a flight gets the same attitude at a frame's capture time on every path.
// How far from a frame's capture the navdata that gives its attitude may be, live and when
// recording: farther (a navdata blackout, a lost link) the frame's navdata is unknown, so the
// classifier judges it from the images alone instead of from a velocity seconds old. The same
// 0.5 s after which the window shows navdata as stale.
inline constexpr TimeNs kFrameNavMaxGapNs = 500'000'000;

class NavTimeline {
public:
    explicit NavTimeline(std::size_t capacity = 1024);
    // A sample older than the newest is ignored (the link accepts samples in sequence order).
    void push(const NavState& s);
    // The state at `t`. A sample farther than `max_gap_ns` from `t` is not used: with no sample
    // that near, the state is unknown (every field NaN, t_ns = t), never an old one relabelled.
    [[nodiscard]] NavState state_at(TimeNs t, TimeNs max_gap_ns = kNoGapLimit) const;
    static constexpr TimeNs kNoGapLimit = std::numeric_limits<TimeNs>::max();
    bool empty() const { return size_ == 0; }
    std::size_t size() const { return size_; }
    TimeNs newest_t() const;  // 0 when empty
    void clear() { size_ = 0; }

private:
    const NavState& at(std::size_t i) const { return ring_[(head_ + i) % ring_.size()]; }
    std::vector<NavState> ring_;
    std::size_t head_ = 0;  // oldest
    std::size_t size_ = 0;
};

}  // namespace gs::inline core
