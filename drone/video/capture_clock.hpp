#pragma once
// Capture times for video frames on the receiver's clock, from the drone's own frame timestamps.
//
// A frame's receive time carries the network, the drone's encoder queue and the receiving
// thread's scheduling: frames arrive bunched (two in one TCP read get the same time) or late
// under load, and a classifier that measures image motion per second sees that jitter as motion.
// The PaVE header's timestamp is the drone's capture clock (ms). CaptureClock maps it onto the
// receiver's monotonic clock by the smallest observed delay (the frame that came fastest tells the
// offset best, as NTP and PX4's timesync do), allowed to creep up by a bounded clock skew so that
// a drone clock running slow is followed; a timestamp going backwards or running ahead of the
// receive time (a drone reboot, a new stream) re-anchors it, counted. A frame that arrives late
// (the air or a queue held it back, however long) does not: it is as old as its timestamp says,
// and a decision made on it must know that (re-anchored on it, a frame held up 1.5 s by a Wi-Fi
// stall would read as captured when it arrived). Pure: times are arguments.
#include "drone/core/clock.hpp"

#include <cstdint>

namespace gs::video {

struct CaptureClockParams {
    // How fast the offset may grow (drone clock slower than ours): 200 µs per second (200 ppm,
    // ten times a crystal's tolerance).
    double max_skew_ppm = 200;
    // A drone time step this far ahead of the receive time step re-anchors (a new stream, a
    // clock set forward); a step back always does (a reboot).
    TimeNs max_jump_ns = 1'000'000'000;
    // A drone timestamp that stands still this long while frames keep arriving (a camera clock
    // advances every frame): the clock says nothing, and each frame is taken as captured when it
    // arrived, counted, until it runs again (then anchored anew).
    TimeNs frozen_after_ns = 200'000'000;
};

class CaptureClock {
public:
    explicit CaptureClock(CaptureClockParams p = {}) : p_(p) {}

    // The capture time of a frame stamped `drone_ms` by the drone and received at `recv_ns`:
    // never after `recv_ns`, never before the previous result.
    TimeNs map(std::uint32_t drone_ms, TimeNs recv_ns);
    void reset() {
        have_ = false;
        frozen_ = false;
    }

    std::uint64_t anchors() const { return anchors_; }  // re-anchorings, the first one included
    // Frames taken as captured when they arrived because the drone's timestamp stood still.
    std::uint64_t frozen_frames() const { return frozen_frames_; }
    TimeNs offset_ns() const { return offset_ns_; }  // receiver time - drone time

private:
    CaptureClockParams p_;
    bool have_ = false;
    std::uint32_t last_ms_ = 0;
    TimeNs drone_ns_ = 0;  // unwrapped drone time of the last frame
    TimeNs last_recv_ns_ = 0;
    TimeNs last_out_ns_ = 0;
    TimeNs offset_ns_ = 0;
    TimeNs advanced_recv_ns_ = 0;  // receive time of the last frame whose drone time advanced
    bool frozen_ = false;
    std::uint64_t anchors_ = 0;
    std::uint64_t frozen_frames_ = 0;
};

}  // namespace gs::video
