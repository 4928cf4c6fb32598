#include "drone/core/clock.hpp"

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

}  // namespace gs::inline core
