#include "ui/history.hpp"

#include <cmath>
#include <numbers>

namespace gs::ui {

TelemetryHistory::TelemetryHistory(std::size_t capacity)
    : altitude_m(capacity),
      battery_pct(capacity),
      roll_deg(capacity),
      pitch_deg(capacity),
      yaw_deg(capacity),
      vz_mps(capacity),
      ground_speed_mps(capacity),
      path(capacity) {}

void TelemetryHistory::clear() {
    for (RingSeries* r : {&altitude_m, &battery_pct, &roll_deg, &pitch_deg, &yaw_deg, &vz_mps,
                          &ground_speed_mps, &path})
        r->clear();
    have_last_ = false;
    px_ = py_ = 0;
    gaps_ = 0;
}

bool TelemetryHistory::path_at(double t_s, double& x, double& y) const {
    // path and altitude_m are pushed together (same capacity): altitude_m's x is the time of
    // each path point, increasing (a jump back in time clears both).
    const std::size_t n = path.size();
    if (n == 0) return false;
    std::size_t lo = 0, hi = n;  // first index with time > t_s
    while (lo < hi) {
        const std::size_t mid = (lo + hi) / 2;
        if (altitude_m.x(mid) <= t_s)
            lo = mid + 1;
        else
            hi = mid;
    }
    const std::size_t i = lo == 0 ? 0 : lo - 1;
    x = path.x(i);
    y = path.y(i);
    return true;
}

void TelemetryHistory::add(const NavState& nav) {
    const double t = static_cast<double>(nav.t_ns) * 1e-9;
    if (have_last_) {
        if (t < last_t_s_)
            clear();
        else if (t == last_t_s_)
            return;
    }
    if (have_last_) {
        const double dt = t - last_t_s_;
        if (dt > kMaxGapS) {
            ++gaps_;
        } else if (known(nav.vx_mps) && known(nav.vy_mps) && known(nav.yaw_deg)) {
            const double psi = nav.yaw_deg * std::numbers::pi / 180.0;
            px_ += (nav.vx_mps * std::cos(psi) - nav.vy_mps * std::sin(psi)) * dt;
            py_ += (nav.vx_mps * std::sin(psi) + nav.vy_mps * std::cos(psi)) * dt;
        }
    }
    path.push(py_, px_);
    have_last_ = true;
    last_t_s_ = t;
    altitude_m.push(t, nav.altitude_m);
    battery_pct.push(t, nav.battery_pct);
    roll_deg.push(t, nav.roll_deg);
    pitch_deg.push(t, nav.pitch_deg);
    yaw_deg.push(t, nav.yaw_deg);
    vz_mps.push(t, nav.vz_mps);
    ground_speed_mps.push(t, (known(nav.vx_mps) && known(nav.vy_mps))
                                 ? std::hypot(nav.vx_mps, nav.vy_mps)
                                 : kUnknown);
}

}  // namespace gs::ui
