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

NavState NavTimeline::state_at(TimeNs t, TimeNs max_gap_ns) const {
    NavState none;
    none.t_ns = t;
    if (size_ == 0) return none;
    // First sample at or after t (binary search over the ring's logical order).
    std::size_t lo = 0, hi = size_;
    while (lo < hi) {
        const std::size_t mid = lo + (hi - lo) / 2;
        if (at(mid).t_ns < t)
            lo = mid + 1;
        else
            hi = mid;
    }
    auto gap = [t](const NavState& s) { return s.t_ns > t ? s.t_ns - t : t - s.t_ns; };
    auto nearest = [&](const NavState& s) {
        if (gap(s) > max_gap_ns) return none;
        NavState r = s;
        r.t_ns = t;
        return r;
    };
    if (lo == size_) return nearest(at(size_ - 1));
    if (lo == 0 || at(lo).t_ns == t) return nearest(at(lo));
    const NavState& before = at(lo - 1);
    const NavState& after = at(lo);
    if (gap(before) <= max_gap_ns && gap(after) <= max_gap_ns) return interpolate(before, after, t);
    return nearest(gap(before) <= gap(after) ? before : after);
}

}  // namespace gs::inline core
