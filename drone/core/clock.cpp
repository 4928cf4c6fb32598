#include "drone/core/clock.hpp"

#include <algorithm>
#include <thread>

namespace gs::inline core {

TimeNs SteadyClock::now_ns() const {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

SteadyClock& SteadyClock::instance() {
    static SteadyClock c;
    return c;
}

bool is_stepped(const Clock& clock) {
    return dynamic_cast<const SteadyClock*>(&clock) == nullptr;
}

bool sleep_until(const Clock& clock, TimeNs t, const std::atomic<bool>& keep_going) {
    const bool stepped = is_stepped(clock);
    while (keep_going.load()) {
        const TimeNs wait = t - clock.now_ns();
        if (wait <= 0) return true;
        std::this_thread::sleep_for(
            std::chrono::nanoseconds(stepped ? std::min<TimeNs>(wait, 1'000'000) : wait));
        if (!stepped) return keep_going.load();
    }
    return false;
}

}  // namespace gs::inline core
