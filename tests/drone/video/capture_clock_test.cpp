// CaptureClock: frame capture times from the drone's PaVE timestamps, on the receiver's clock.
#include "drone/video/capture_clock.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace gs {
namespace {

using namespace video;

constexpr TimeNs kMs = kNsPerMs;

// 30 fps frames captured at 33 ms steps (drone clock starting at `drone0_ms`), received after a
// 20 ms floor plus a jitter pattern that is zero every fifth frame, with pairs bunched together
// (two frames read in one go get the same receive time) and a slow first frame.
struct Arrival {
    std::uint32_t drone_ms;
    TimeNs capture_ns, recv_ns;
};
std::vector<Arrival> jittered(int n, std::uint32_t drone0_ms, double drone_rate = 1.0) {
    const TimeNs jitter_ms[5] = {0, 45, 12, 60, 7};
    std::vector<Arrival> out;
    for (int i = 0; i < n; ++i) {
        const TimeNs cap = 1'000 * kMs + i * 33 * kMs;
        TimeNs recv = cap + 20 * kMs + jitter_ms[i % 5] * kMs;
        if (i == 0) recv += 80 * kMs;
        if (i % 5 == 2)
            recv = cap + 33 * kMs + 20 * kMs + jitter_ms[3] * kMs;    // read with the next
        if (!out.empty()) recv = std::max(recv, out.back().recv_ns);  // TCP delivers in order
        const auto dms = static_cast<std::uint32_t>(
            drone0_ms + static_cast<std::uint64_t>(static_cast<double>(i * 33) * drone_rate));
        out.push_back({dms, cap, recv});
    }
    return out;
}

TEST(CaptureClock, JitterAndBunchingAreRemovedOnceTheFastestFrameIsSeen) {
    CaptureClock c;
    const auto frames = jittered(300, 123'456);
    std::vector<TimeNs> out;
    for (std::size_t i = 0; i < frames.size(); ++i) {
        const Arrival& f = frames[i];
        const TimeNs t = c.map(f.drone_ms, f.recv_ns);
        EXPECT_LE(t, f.recv_ns) << i;  // never after the frame arrived
        if (!out.empty()) {
            EXPECT_GE(t, out.back()) << i;
        }  // never backwards
        out.push_back(t);
        // From the first zero-jitter frame on (i = 5), the capture time plus the 20 ms floor,
        // to within the skew allowance (200 ppm of at most 5 frames: 33 µs).
        if (i >= 5) {
            EXPECT_NEAR(static_cast<double>(t - (f.capture_ns + 20 * kMs)), 0.0, 0.05e6) << i;
        }
    }
    EXPECT_EQ(c.anchors(), 1u);
    // Frames 7 and 8 arrived in one read (the same receive time); their capture times are a
    // frame apart, where the receive times said 0 and then 80 ms.
    ASSERT_EQ(frames[7].recv_ns, frames[8].recv_ns);
    EXPECT_NEAR(static_cast<double>(out[8] - out[7]), 33e6, 0.05e6);
    EXPECT_NEAR(static_cast<double>(out[9] - out[8]), 33e6, 0.05e6);
}

TEST(CaptureClock, ASlowDroneClockIsFollowedWithinTheSkewAllowance) {
    // The drone's clock runs 100 ppm slow: the receive - drone offset grows 0.1 ms a second.
    CaptureClock c;
    const auto frames = jittered(18'000, 5'000, 1.0 - 100e-6);  // 10 minutes
    for (std::size_t i = 5; i < frames.size(); ++i) {
        const TimeNs t = c.map(frames[i].drone_ms, frames[i].recv_ns);
        ASSERT_NEAR(static_cast<double>(t - (frames[i].capture_ns + 20 * kMs)), 0.0, 1.0e6) << i;
    }
    EXPECT_EQ(c.anchors(), 1u);
}

TEST(CaptureClock, TheMillisecondCounterWrapsWithoutAJump) {
    CaptureClock c;
    const auto frames = jittered(60, 0xFFFFFFFFu - 500);  // wraps after ~15 frames
    TimeNs prev = 0;
    for (const Arrival& f : frames) {
        const TimeNs t = c.map(f.drone_ms, f.recv_ns);
        EXPECT_GE(t, prev);
        prev = t;
    }
    EXPECT_EQ(c.anchors(), 1u);
    EXPECT_NEAR(static_cast<double>(prev - (frames.back().capture_ns + 20 * kMs)), 0.0, 0.05e6);
}

TEST(CaptureClock, AFrameHeldBackByAStallIsAsOldAsItsTimestamp) {
    // Steady frames (20 ms floor, no jitter), then the air stalls: the next frame arrives 1.5 s
    // late, the frames the drone queued behind it follow in a burst 2 ms apart until delivery
    // has caught up, and then arrive on time again. Each is mapped to its capture (plus the
    // floor): the first frame after the stall is 1.5 s old when it arrives, not new.
    CaptureClock c;
    const TimeNs floor = 20 * kMs, stall = 1'500 * kMs;
    auto capture = [](int i) { return 1'000 * kMs + i * 33 * kMs; };
    auto drone_ms = [](int i) { return static_cast<std::uint32_t>(7'000 + i * 33); };
    for (int i = 0; i < 30; ++i) c.map(drone_ms(i), capture(i) + floor);
    const TimeNs burst = capture(30) + floor + stall;
    int late = 0;
    for (int i = 30; i < 120; ++i) {
        const TimeNs recv = std::max(capture(i) + floor, burst + (i - 30) * 2 * kMs);
        const TimeNs t = c.map(drone_ms(i), recv);
        ASSERT_NEAR(static_cast<double>(t - (capture(i) + floor)), 0.0, 0.5e6) << i;
        late += recv - t > 100 * kMs ? 1 : 0;
    }
    EXPECT_GE(late, 40) << "the burst's frames are mapped as old as they are";
    EXPECT_EQ(c.anchors(), 1u) << "a stall is not a clock jump";
}

TEST(CaptureClock, AClockThatStandsStillFallsBackToTheArrivalCounted) {
    // A drone (or a tool writing PaVE) whose timestamp stands still while frames keep coming
    // every 33 ms: held on its last value, every frame would get the same capture time (no time
    // passes between frames for the classifier, every decision looks as old as the first).
    // After frozen_after_ns each frame is taken as captured when it arrived, counted; once the
    // clock runs again it is anchored anew and followed.
    CaptureClock c;
    const TimeNs floor = 20 * kMs;
    auto capture = [](int i) { return 1'000 * kMs + i * 33 * kMs; };
    for (int i = 0; i < 10; ++i)
        c.map(static_cast<std::uint32_t>(500 + i * 33), capture(i) + floor);
    TimeNs prev = 0;
    int frozen_from = -1;
    for (int i = 10; i < 70; ++i) {  // 2 s stuck at the last value
        const TimeNs recv = capture(i) + floor;
        const TimeNs t = c.map(500 + 9 * 33, recv);
        EXPECT_LE(t, recv);
        EXPECT_GE(t, prev);
        prev = t;
        if (t == recv && frozen_from < 0) frozen_from = i;
    }
    // 200 ms is six frames: from the seventh on, each frame is its arrival.
    EXPECT_EQ(frozen_from, 16);
    EXPECT_EQ(c.frozen_frames(), 70u - 16u);
    EXPECT_EQ(c.anchors(), 1u);
    // The clock runs again (from where it stood): anchored anew, then followed frame by frame.
    for (int i = 70; i < 80; ++i) {
        const TimeNs recv = capture(i) + floor;
        const TimeNs t = c.map(static_cast<std::uint32_t>(500 + 9 * 33 + (i - 69) * 33), recv);
        EXPECT_EQ(t, recv) << i;
        EXPECT_GE(t, prev);
        prev = t;
    }
    EXPECT_EQ(c.anchors(), 2u);
    EXPECT_EQ(c.frozen_frames(), 70u - 16u);
}

TEST(CaptureClock, ARebootOrAJumpReanchorsAndTimeNeverGoesBack) {
    CaptureClock c;
    TimeNs t = 0;
    for (int i = 0; i < 10; ++i) t = c.map(50'000 + i * 33, 10'000 * kMs + i * 33 * kMs);
    // The drone rebooted: its clock starts again near 0.
    const TimeNs r = c.map(40, 10'000 * kMs + 10 * 33 * kMs);
    EXPECT_EQ(c.anchors(), 2u);
    EXPECT_GE(r, t);
    EXPECT_EQ(r, 10'000 * kMs + 10 * 33 * kMs);  // re-anchored on the receive time
    // A timestamp 5 s ahead while 33 ms passed here: a new stream, anchored again.
    c.map(5'073, 10'000 * kMs + 11 * 33 * kMs);
    EXPECT_EQ(c.anchors(), 3u);
    // Steady frames after it keep the anchor.
    c.map(5'106, 10'000 * kMs + 12 * 33 * kMs);
    EXPECT_EQ(c.anchors(), 3u);
    c.reset();
    c.map(1, 20'000 * kMs);
    EXPECT_EQ(c.anchors(), 4u);
}

}  // namespace
}  // namespace gs
