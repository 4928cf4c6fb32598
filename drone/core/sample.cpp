#include "drone/core/sample.hpp"

namespace gs::inline core {
namespace {
double lerp(double a, double b, double w) {
    if (!known(a)) return b;
    if (!known(b)) return a;
    return a + (b - a) * w;
}
double lerp_deg(double a, double b, double w) {
    if (!known(a) || !known(b)) return lerp(a, b, w);
    double d = std::remainder(b - a, 360.0);  // shortest way round
    double v = a + d * w;
    return std::remainder(v, 360.0);
}
}  // namespace

NavState interpolate(const NavState& a, const NavState& b, TimeNs t_ns) {
    const TimeNs span = b.t_ns - a.t_ns;
    double w = span > 0 ? static_cast<double>(t_ns - a.t_ns) / static_cast<double>(span) : 0.0;
    w = std::clamp(w, 0.0, 1.0);
    NavState r = w < 0.5 ? a : b;
    r.t_ns = t_ns;
    r.roll_deg = lerp(a.roll_deg, b.roll_deg, w);
    r.pitch_deg = lerp(a.pitch_deg, b.pitch_deg, w);
    r.yaw_deg = lerp_deg(a.yaw_deg, b.yaw_deg, w);
    r.vx_mps = lerp(a.vx_mps, b.vx_mps, w);
    r.vy_mps = lerp(a.vy_mps, b.vy_mps, w);
    r.vz_mps = lerp(a.vz_mps, b.vz_mps, w);
    r.altitude_m = lerp(a.altitude_m, b.altitude_m, w);
    r.battery_pct = lerp(a.battery_pct, b.battery_pct, w);
    return r;
}

}  // namespace gs::inline core
