#include "drone/dataset/align.hpp"

namespace gs::dataset {

void NavAligner::push_frame(std::int64_t index, TimeNs capture_ns) {
    frames_.push_back({index, capture_ns});
}

bool NavAligner::pop_ready(TimeNs now_ns, std::int64_t& index, NavState& nav) {
    if (frames_.empty()) return false;
    const Pending& f = frames_.front();
    const bool bracketed = !navs_.empty() && navs_.newest_t() >= f.capture_ns;
    if (!bracketed && !finished_ && now_ns - f.capture_ns <= max_wait_ns_) return false;
    index = f.index;
    nav = navs_.state_at(f.capture_ns, kFrameNavMaxGapNs);  // as the live link does
    frames_.pop_front();
    return true;
}

}  // namespace gs::dataset
