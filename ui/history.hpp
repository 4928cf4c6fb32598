#pragma once
// Telemetry history kept by the window for its scrolling plots, plus the flight path seen from
// above: navdata body velocities rotated by yaw and integrated (thesis eq. 6.2):
//   x += (vx cos(psi) - vy sin(psi)) dt,   y += (vx sin(psi) + vy cos(psi)) dt
// x along the initial heading, y to its right, psi clockwise seen from above.

#include "drone/core/sample.hpp"
#include "ui/plot.hpp"

namespace gs::ui {

class TelemetryHistory {
public:
    explicit TelemetryHistory(std::size_t capacity = 4096);

    // Adds a sample when its time moved forward. A time jump backwards (replay seek, new flight)
    // clears everything; a gap longer than max_gap_s is not integrated (counted in path_gaps()).
    void add(const NavState& nav);
    void clear();

    static constexpr double kMaxGapS = 0.5;

    RingSeries altitude_m, battery_pct, roll_deg, pitch_deg, yaw_deg, vz_mps, ground_speed_mps;
    RingSeries path;  // x = right (y of eq. 6.2), y = forward (x of eq. 6.2): a map, north-up

    // Where the path was at flight time t_s (plot coordinates: x right, y forward): the point
    // of the last sample at or before t_s (the first one when all are later). False when empty.
    bool path_at(double t_s, double& x, double& y) const;

    double path_x_m() const { return px_; }
    double path_y_m() const { return py_; }
    std::uint64_t path_gaps() const { return gaps_; }
    double last_t_s() const { return last_t_s_; }

private:
    bool have_last_ = false;
    double last_t_s_ = 0;
    double px_ = 0, py_ = 0;  // eq. 6.2 x (forward) and y (right)
    std::uint64_t gaps_ = 0;
};

}  // namespace gs::ui
