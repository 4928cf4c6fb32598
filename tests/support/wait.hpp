#pragma once
// The one way tests wait: poll a predicate until it holds or a deadline passes (never a fixed
// sleep). `step` runs before each check: a session's or a window's frame, or nothing.

#include <chrono>
#include <optional>
#include <thread>

namespace gs::test {

struct NoStep {
    void operator()() const {}
};

// How long `pred` took to hold, or nullopt when `timeout` passed first.
template <class Pred, class Step = NoStep>
std::optional<std::chrono::milliseconds> wait_until(
    Pred&& pred, std::chrono::milliseconds timeout, Step&& step = {},
    std::chrono::milliseconds poll = std::chrono::milliseconds(5)) {
    const auto t0 = std::chrono::steady_clock::now();
    for (;;) {
        step();
        const auto took = std::chrono::steady_clock::now() - t0;
        if (pred()) return std::chrono::duration_cast<std::chrono::milliseconds>(took);
        if (took >= timeout) return std::nullopt;
        std::this_thread::sleep_for(poll);
    }
}

}  // namespace gs::test
