#pragma once
// The drone state at any instant of a navdata stream, by the one rule of docs/dataset.md (docs/): the
// samples around it interpolated, the nearest sample when there is none on one side. Pure: times
// are stream times (ns from the start of the flight), no clock.

#include "drone/core/sample.hpp"

#include <cstddef>
#include <vector>

namespace gs::inline core {

// The recent navdata samples in time order, in a fixed ring (no allocation after construction),
// and the drone state at any instant by the one rule of docs/dataset.md: interpolated between the two
// samples around it, the nearest sample when there is none on one side. Used live (the link's
// frames) and when recording or replaying (NavAligner), so a flight gets the same attitude at a
// frame's capture time on every path.
class NavTimeline {
public:
    explicit NavTimeline(std::size_t capacity = 1024);
    // A sample older than the newest is ignored (the link accepts samples in sequence order).
    void push(const NavState& s);
    [[nodiscard]] NavState state_at(TimeNs t) const;
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
