#pragma once
// Time is an argument: everything time-dependent takes a Clock& (or a `now`), so tests can use a
// FakeClock and step it instead of sleeping.

#include <atomic>
#include <chrono>
#include <cstdint>

namespace gs::inline core {

using Duration = std::chrono::nanoseconds;
// Monotonic time point in nanoseconds since an arbitrary epoch (steady clock).
using TimeNs = std::int64_t;

class Clock {
public:
    virtual ~Clock() = default;
    virtual TimeNs now_ns() const = 0;
};

class SteadyClock final : public Clock {
public:
    TimeNs now_ns() const override;
    static SteadyClock& instance();
};

class FakeClock final : public Clock {
public:
    explicit FakeClock(TimeNs start = 0) : now_(start) {}
    TimeNs now_ns() const override { return now_.load(); }
    void advance(Duration d) { now_ += d.count(); }
    void set(TimeNs t) { now_ = t; }

private:
    std::atomic<TimeNs> now_;
};

inline constexpr TimeNs kNsPerMs = 1'000'000;
constexpr TimeNs ms_to_ns(double ms) {
    return static_cast<TimeNs>(ms * 1e6);
}
constexpr double ns_to_ms(TimeNs ns) {
    return static_cast<double>(ns) * 1e-6;
}

}  // namespace gs::inline core
