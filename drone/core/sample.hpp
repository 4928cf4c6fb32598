#pragma once
// The one stream every source produces: a live drone, the virtual drone and a recorded dataset
// all yield FrameSamples (a decoded image with the drone state at its capture time) and
// NavSamples. The pipeline and the UI never care which source they came from.

#include "drone/core/clock.hpp"
#include "drone/core/unknown.hpp"

#include <opencv2/core.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

namespace gs::inline core {

// Drone state at one instant, in the units of docs/dataset.md. NaN = unknown (never 0).
struct NavState {
    TimeNs t_ns = 0;              // time from the start of the flight, monotonic
    double roll_deg = kUnknown;   // navdata phi; positive = right side down
    double pitch_deg = kUnknown;  // navdata theta; positive = nose up
    double yaw_deg = kUnknown;    // navdata psi; positive = clockwise seen from above
    double vx_mps = kUnknown;     // body frame, forward positive
    double vy_mps = kUnknown;     // body frame, right positive
    double vz_mps = kUnknown;     // up positive
    double altitude_m = kUnknown;
    double battery_pct = kUnknown;
    std::optional<std::uint32_t> seq;          // navdata sequence number
    std::optional<std::uint32_t> drone_state;  // drone_state bits
    std::optional<std::uint32_t> ctrl_state;   // ctrl_state (major << 16 | minor)
};

// Linear interpolation of the continuous fields between two samples (angles unwrapped for yaw);
// discrete fields come from the nearer sample.
NavState interpolate(const NavState& a, const NavState& b, TimeNs t_ns);

// One decoded video frame with the drone state at its capture time.
struct FrameSample {
    std::int64_t index = 0;  // 0-based index in this stream (display order)
    TimeNs t_ns = 0;         // capture time from the start of the flight
    TimeNs recv_ns = 0;  // when its last byte arrived (monotonic clock of the receiver), 0 if n/a
    // When it was captured, on the same clock: the drone's frame timestamp mapped onto it
    // (drone/video/capture_clock.hpp), never after recv_ns; 0 if n/a. recv_ns - capture_ns is
    // the time the frame spent in the drone's encoder, the air and the queues beyond the
    // fastest frame's: what a decision made on it is older than its arrival says.
    TimeNs capture_ns = 0;
    // PaVE frame_number and timestamp (the drone's clock, ms, arbitrary origin) when it came
    // from a drone.
    std::optional<std::uint32_t> frame_number;
    std::optional<std::uint32_t> pave_timestamp_ms;
    cv::Mat image;  // BGR8, display size; shared, never deep-copied along the pipeline
    NavState nav;   // attitude etc. at capture time
    // Decoded with damage the decoder concealed (lost or corrupt slices filled in from other
    // frames): shown and classified, but trusted less (it cannot raise an alarm by itself).
    bool concealed = false;
    // An intra picture that replaced concealed damage: whole again, but it jumps from the
    // pictures before it where the damage was (trusted less in the same way).
    bool repaired = false;
};

}  // namespace gs::inline core
