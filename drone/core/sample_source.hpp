#pragma once
// The seam between where samples come from (the live link, the virtual drone, a recorded dataset)
// and everything downstream. A source hands out FrameSamples and NavStates when they are due;
// pacing is against a Clock& so tests step a FakeClock instead of sleeping. Calls never block.

#include "drone/core/clock.hpp"
#include "drone/core/sample.hpp"

#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>

namespace gs::inline core {

// Playback speed: recorded speed times `speed` (0.25 to 8), or as fast as the consumer pulls.
struct Pacing {
    bool as_fast_as_possible = false;
    double speed = 1.0;

    static Pacing realtime(double factor = 1.0) {
        return Pacing{false, std::clamp(factor, kMinSpeed, kMaxSpeed)};
    }
    static Pacing fastest() { return Pacing{true, 1.0}; }
    static constexpr double kMinSpeed = 0.25;
    static constexpr double kMaxSpeed = 8.0;
};

enum class SourceStatus {
    Sample,  // `out` holds the next sample
    NotYet,  // nothing due yet: try again in wait_hint_ns()
    Paused,  // paused: use step()
    End,     // no more samples
    Error,   // see last_error()
};
std::string to_string(SourceStatus s);

class SampleSource {
public:
    virtual ~SampleSource() = default;

    // Next video frame when it is due.
    [[nodiscard]] virtual SourceStatus next(FrameSample& out) = 0;
    // Next navdata sample when it is due (a source without its own navdata stream yields the
    // frames' attitude). Navdata up to a frame's capture time comes out before that frame.
    [[nodiscard]] virtual SourceStatus next_nav(NavState& out) = 0;
    // How long until the next frame is due (wall time), when next() said NotYet.
    virtual TimeNs wait_hint_ns() const = 0;

    // Total frames for a finite source; nullopt for a live one.
    virtual std::optional<std::int64_t> frame_count() const = 0;
    // Makes `frame` the next one next()/step() returns. False when not seekable or out of range.
    [[nodiscard]] virtual bool seek(std::int64_t frame) = 0;
    // Next frame now, ignoring pacing and pause (single-stepping).
    [[nodiscard]] virtual SourceStatus step(FrameSample& out) = 0;
    virtual void set_pacing(Pacing p) = 0;
    virtual void set_paused(bool paused) = 0;
    virtual std::string last_error() const = 0;
};

}  // namespace gs::inline core
