#include "drone/dataset/align.hpp"

#include <algorithm>

namespace gs::dataset {

void NavAligner::push_nav(const NavState& s) {
    if (!navs_.empty() && s.t_ns < navs_.back().t_ns) return;  // out of order: ignored
    navs_.push_back(s);
    // Keep enough history for frames that arrive late, but bounded.
    while (navs_.size() > history_cap_) navs_.pop_front();
}

void NavAligner::push_frame(std::int64_t index, TimeNs capture_ns) {
    frames_.push_back({index, capture_ns});
}

NavState NavAligner::state_at(TimeNs t) const {
    if (navs_.empty()) {
        NavState none;
        none.t_ns = t;
        return none;
    }
    auto after = std::lower_bound(navs_.begin(), navs_.end(), t,
                                  [](const NavState& s, TimeNs v) { return s.t_ns < v; });
    if (after == navs_.end()) {
        NavState r = navs_.back();
        r.t_ns = t;
        return r;
    }
    if (after == navs_.begin() || after->t_ns == t) {
        NavState r = *after;
        r.t_ns = t;
        return r;
    }
    return interpolate(*(after - 1), *after, t);
}

bool NavAligner::pop_ready(TimeNs now_ns, std::int64_t& index, NavState& nav) {
    if (frames_.empty()) return false;
    const Pending& f = frames_.front();
    const bool bracketed = !navs_.empty() && navs_.back().t_ns >= f.capture_ns;
    if (!bracketed && !finished_ && now_ns - f.capture_ns <= max_wait_ns_) return false;
    index = f.index;
    nav = state_at(f.capture_ns);
    frames_.pop_front();
    return true;
}

}  // namespace gs::dataset
