#pragma once
// The window's one rate estimator (packets, frames, bytes): items per second over the last
// second, from a counter sampled at every GuiAdapter::fill(). Unknown until a quarter second is
// measured; a stream that stops reads 0 a second later; a burst after a stall is spread over the
// window; a counter that goes back (a new stream or source) starts over.

#include "drone/core/clock.hpp"
#include "drone/core/unknown.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>

namespace gs::app {

struct SlidingRate {
    static constexpr std::size_t kSamples = 256;
    std::array<std::pair<TimeNs, std::uint64_t>, kSamples> ring{};
    std::size_t head = 0, size = 0;
    double hz = kUnknown;
    double update(std::uint64_t count, TimeNs now);  // app/gui_link.cpp
    void reset() { *this = SlidingRate{}; }
};

}  // namespace gs::app
