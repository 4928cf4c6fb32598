#include "drone/core/nav_timeline.hpp"

namespace gs::inline core {

NavTimeline::NavTimeline(std::size_t capacity) : ring_(capacity == 0 ? 1 : capacity) {}

void NavTimeline::push(const NavState& s) {
    if (size_ > 0 && s.t_ns < at(size_ - 1).t_ns) return;  // out of order: ignored
    if (size_ == ring_.size()) {                           // full: the oldest goes
        ring_[head_] = s;
        head_ = (head_ + 1) % ring_.size();
        return;
    }
    ring_[(head_ + size_) % ring_.size()] = s;
    ++size_;
}

TimeNs NavTimeline::newest_t() const {
    return size_ == 0 ? 0 : at(size_ - 1).t_ns;
}

NavState NavTimeline::state_at(TimeNs t) const {
    if (size_ == 0) {
        NavState none;
        none.t_ns = t;
        return none;
    }
    // First sample at or after t (binary search over the ring's logical order).
    std::size_t lo = 0, hi = size_;
    while (lo < hi) {
        const std::size_t mid = lo + (hi - lo) / 2;
        if (at(mid).t_ns < t)
            lo = mid + 1;
        else
            hi = mid;
    }
    if (lo == size_ || lo == 0 || at(lo).t_ns == t) {
        NavState r = lo == size_ ? at(size_ - 1) : at(lo);
        r.t_ns = t;
        return r;
    }
    return interpolate(at(lo - 1), at(lo), t);
}

}  // namespace gs::inline core
