#pragma once
// Gives each video frame the drone state at its capture time: interpolated between the two
// navdata samples around it (DATASET.md: recordings interpolate), or the nearest sample when the
// stream has nothing on one side. Frames come out in the order they went in. Pure: times are
// stream times (ns from the start of the flight), no clock.

#include "drone/sample.hpp"

#include <cstdint>
#include <deque>
#include <vector>

namespace gs {

// The recent navdata samples in time order, in a fixed ring (no allocation after construction),
// and the drone state at any instant by the one rule of DATASET.md: interpolated between the two
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

class NavAligner {
public:
    // A frame waits at most `max_wait_ns` of stream time for the navdata sample after it; then it
    // takes the latest sample (video can lag navdata, navdata can stop).
    explicit NavAligner(TimeNs max_wait_ns = 500'000'000, std::size_t history = 1024)
        : max_wait_ns_(max_wait_ns), navs_(history) {}

    void push_nav(const NavState& s) { navs_.push(s); }  // in time order
    void push_frame(std::int64_t index, TimeNs capture_ns);
    // The oldest frame whose state is settled, given that the stream has reached `now_ns`.
    [[nodiscard]] bool pop_ready(TimeNs now_ns, std::int64_t& index, NavState& nav);
    // After finish() every pending frame is ready (nearest sample).
    void finish() { finished_ = true; }
    std::size_t pending() const { return frames_.size(); }

private:
    struct Pending {
        std::int64_t index;
        TimeNs capture_ns;
    };
    TimeNs max_wait_ns_;
    NavTimeline navs_;
    std::deque<Pending> frames_;
    bool finished_ = false;
};

}  // namespace gs
