#pragma once
// Gives each video frame the drone state at its capture time: interpolated between the two
// navdata samples around it (docs/dataset.md: recordings interpolate), or the nearest sample when
// the stream has nothing on one side. Frames come out in the order they went in. Pure: times are
// stream times (ns from the start of the flight), no clock.

#include "drone/core/nav_timeline.hpp"
#include "drone/core/sample.hpp"

#include <cstdint>
#include <deque>
#include <vector>

namespace gs::dataset {

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

}  // namespace gs::dataset
