#include "drone/sim/flight_model.hpp"
#include "drone/core/geometry.hpp"
#include "drone/sim/units.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace gs::sim {
namespace {
constexpr double kG = 9.81;
constexpr double kRad = geom::kRadPerDeg;

// First-order lag of `v` toward `target` with time constant tau over dt (exact discretisation).
double approach(double v, double target, double tau, double dt) {
    if (tau <= 0) return target;
    return target + (v - target) * std::exp(-dt / tau);
}
double clamp1(double v) {
    return std::isfinite(v) ? std::clamp(v, -1.0, 1.0) : 0.0;
}
}  // namespace

namespace {
// The horizontal velocity along the heading (forward, right).
geom::Vec2 level_velocity(const FlightState& s) {
    return geom::world_from_heading(s.yaw_deg).inverse() *
           geom::Vec2(s.vx_world_mps, s.vy_world_mps);
}
}  // namespace

double FlightState::vx_body_mps() const {
    return level_velocity(*this).x();
}
double FlightState::vy_body_mps() const {
    return level_velocity(*this).y();
}

FlightModel::FlightModel(FlightParams params, FlightLimits limits)
    : params_(params), limits_(limits) {}

void FlightModel::set_pose(double x_m, double y_m, double z_m, double yaw_deg) {
    s_.x_m = x_m;
    s_.y_m = y_m;
    s_.z_m = std::max(0.0, z_m);
    s_.yaw_deg = yaw_deg;
    hold_z_m_ = s_.z_m;
    if (s_.z_m > 0.05) {  // placed in the air: it is hovering there
        s_.major = CtrlMajor::Hovering;
        s_.motors_on = true;
    }
}

void FlightModel::update_mode(const FlightInput& in, double dt) {
    mode_time_s_ += dt;
    auto enter = [&](CtrlMajor m, std::uint16_t minor = 0) {
        if (s_.major != m) mode_time_s_ = 0;
        s_.major = m;
        s_.minor = minor;
    };

    // Emergency toggles on the rising edge of REF bit 8: cuts the motors when they run, clears
    // an existing emergency otherwise.
    const bool edge = in.emergency && !prev_emergency_input_;
    prev_emergency_input_ = in.emergency;
    if (edge) {
        if (s_.emergency) {
            if (s_.z_m <= 0.0) s_.emergency = s_.cutout = false;
        } else {
            s_.emergency = true;
            s_.motors_on = false;
            enter(CtrlMajor::Landed);
        }
    }
    s_.user_start = in.start;
    s_.battery_low = s_.battery_pct < params_.battery_low_pct;

    if (s_.emergency) {
        s_.motors_on = false;
        enter(CtrlMajor::Landed);
        return;
    }
    switch (s_.major) {
        case CtrlMajor::Default:
        case CtrlMajor::Init:
        case CtrlMajor::Test:
        case CtrlMajor::Looping:
        case CtrlMajor::Landed:
            s_.motors_on = false;
            if (in.start && !s_.battery_low) {
                s_.motors_on = true;
                enter(CtrlMajor::TakingOff, 0);
            } else if (s_.major != CtrlMajor::Landed) {
                enter(CtrlMajor::Landed);
            }
            break;
        case CtrlMajor::TakingOff:
            if (!in.start)
                enter(CtrlMajor::Landing, 0);
            else if (s_.z_m >= params_.takeoff_height_m)
                enter(CtrlMajor::Hovering, 0);
            else
                s_.minor = mode_time_s_ < params_.takeoff_spinup_s ? 0 : 1;  // GROUND, AUTO
            break;
        case CtrlMajor::Flying:
        case CtrlMajor::Hovering:
        case CtrlMajor::GotoFix: {
            if (!in.start || s_.battery_pct < params_.battery_critical_pct) {
                enter(CtrlMajor::Landing, 0);
                break;
            }
            const bool moving = in.progressive && !in.com_lost &&
                                (in.roll != 0 || in.pitch != 0 || in.gaz != 0 || in.yaw != 0);
            if (in.com_lost)
                enter(CtrlMajor::Hovering, 8);  // HOVERING_LOST_COM
            else if (moving)
                enter(CtrlMajor::Flying, 0);
            else
                enter(CtrlMajor::Hovering, 0);
            break;
        }
        case CtrlMajor::Landing:
            if (s_.z_m <= 0.0) {
                s_.motors_on = false;
                enter(CtrlMajor::Landed);
            }
            break;
    }
}

double FlightModel::hold_altitude() const {
    const double vmax = limits_.control_vz_max_mm_s / 1000.0;
    return std::clamp(2.0 * (hold_z_m_ - s_.z_m), -vmax, vmax);
}

void FlightModel::step(const FlightInput& raw, double dt) {
    if (!(dt > 0)) return;
    FlightInput in = raw;
    in.roll = clamp1(in.roll);
    in.pitch = clamp1(in.pitch);
    in.gaz = clamp1(in.gaz);
    in.yaw = clamp1(in.yaw);
    update_mode(in, dt);
    s_.t_s += dt;

    const double max_tilt_deg = limits_.euler_angle_max_rad * kDegPerRad;
    double roll_cmd = 0, pitch_cmd = 0, vz_cmd = 0, yaw_rate_cmd = 0;
    const bool airborne = s_.motors_on && s_.z_m > 0.0;
    switch (s_.major) {
        case CtrlMajor::Flying:
            roll_cmd = in.roll * max_tilt_deg;
            pitch_cmd = in.pitch * max_tilt_deg;
            yaw_rate_cmd = in.yaw * limits_.control_yaw_rad_s * kDegPerRad;
            if (in.gaz != 0) {
                vz_cmd = in.gaz * limits_.control_vz_max_mm_s / 1000.0;
                hold_z_m_ = s_.z_m;
            } else {
                vz_cmd = hold_altitude();
            }
            break;
        case CtrlMajor::Hovering:
        case CtrlMajor::GotoFix:
        case CtrlMajor::Landing:
        case CtrlMajor::TakingOff: {
            // Hold position: tilt against the residual body speed (nose up brakes forward motion).
            const double k = params_.hover_gain_deg_per_mps;
            pitch_cmd = std::clamp(k * s_.vx_body_mps(), -max_tilt_deg, max_tilt_deg);
            roll_cmd = std::clamp(-k * s_.vy_body_mps(), -max_tilt_deg, max_tilt_deg);
            vz_cmd = hold_altitude();
            if (s_.major == CtrlMajor::Landing) vz_cmd = -params_.landing_descent_mps;
            if (s_.major == CtrlMajor::TakingOff) {
                hold_z_m_ = params_.takeoff_height_m;
                vz_cmd = s_.minor == 1 ? params_.takeoff_rise_mps : 0.0;
            }
            break;
        }
        default:
            break;
    }
    if (!airborne && s_.major != CtrlMajor::TakingOff) {
        roll_cmd = pitch_cmd = yaw_rate_cmd = 0;
    }

    // Attitude (plus the evaluation's roll wobble, a disturbance the drone reports as it is).
    const double wobble =
        params_.roll_wobble_deg * std::sin(2 * std::numbers::pi * params_.roll_wobble_hz * s_.t_s);
    s_.roll_deg =
        approach(s_.roll_deg, roll_cmd + (airborne ? wobble : 0.0), params_.attitude_tau_s, dt);
    s_.pitch_deg = approach(s_.pitch_deg, pitch_cmd, params_.attitude_tau_s, dt);
    s_.yaw_rate_deg_s = approach(s_.yaw_rate_deg_s, yaw_rate_cmd, params_.yaw_rate_tau_s, dt);
    if (airborne) s_.yaw_deg += (s_.yaw_rate_deg_s + params_.yaw_drift_deg_s) * dt;
    s_.yaw_deg = std::remainder(s_.yaw_deg, 360.0);

    // Horizontal: tilt accelerates the body; drag acts on the speed relative to the air (wind).
    if (airborne) {
        // Thrust tilted by pitch (nose up brakes) and roll (right side down goes right), along
        // the heading, then turned into the world.
        const geom::Vec2 a_level(-kG * std::tan(s_.pitch_deg * kRad),
                                 kG * std::tan(s_.roll_deg * kRad));
        const geom::Vec2 a_world = geom::world_from_heading(s_.yaw_deg) * a_level;
        s_.vx_world_mps +=
            (a_world.x() - params_.drag_per_s * (s_.vx_world_mps - params_.wind_forward_mps)) * dt;
        s_.vy_world_mps +=
            (a_world.y() - params_.drag_per_s * (s_.vy_world_mps - params_.wind_right_mps)) * dt;
    } else {
        s_.vx_world_mps = s_.vy_world_mps = 0;
    }

    // Vertical.
    if (s_.emergency && s_.z_m > 0) {
        s_.vz_mps -= kG * dt;  // motors cut: it falls
    } else if (s_.motors_on) {
        s_.vz_mps = approach(s_.vz_mps, vz_cmd, params_.vz_tau_s, dt);
    } else {
        s_.vz_mps = 0;
    }
    s_.x_m += s_.vx_world_mps * dt;
    s_.y_m += s_.vy_world_mps * dt;
    s_.z_m += s_.vz_mps * dt;
    const double alt_max_m = limits_.altitude_max_mm / 1000.0;
    if (s_.z_m > alt_max_m) {
        s_.z_m = alt_max_m;
        s_.vz_mps = std::min(s_.vz_mps, 0.0);
    }
    if (s_.z_m <= 0.0) {
        s_.z_m = 0.0;
        s_.vz_mps = 0.0;
        if (!s_.motors_on || s_.major == CtrlMajor::Landing) {
            s_.vx_world_mps = s_.vy_world_mps = 0;
            s_.roll_deg = s_.pitch_deg = 0;
            s_.yaw_rate_deg_s = 0;
        }
    }

    s_.battery_pct -= (s_.motors_on ? params_.battery_drain_flying_pct_per_s
                                    : params_.battery_drain_idle_pct_per_s) *
                      dt;
    s_.battery_pct = std::max(0.0, s_.battery_pct);
}

void FlightModel::touch(double nx, double ny, double nz, double depth_m, bool crash) {
    s_.x_m += nx * depth_m;
    s_.y_m += ny * depth_m;
    s_.z_m = std::max(0.0, s_.z_m + nz * depth_m);
    const double into = s_.vx_world_mps * nx + s_.vy_world_mps * ny + s_.vz_mps * nz;
    if (into < 0) {
        s_.vx_world_mps -= into * nx;
        s_.vy_world_mps -= into * ny;
        s_.vz_mps -= into * nz;
    }
    if (!crash || s_.emergency) return;
    s_.emergency = s_.cutout = true;
    s_.motors_on = false;
    s_.major = CtrlMajor::Landed;
    s_.minor = 0;
    mode_time_s_ = 0;
}

const char* to_string(CtrlMajor m) {
    switch (m) {
        case CtrlMajor::Default:
            return "DEFAULT";
        case CtrlMajor::Init:
            return "INIT";
        case CtrlMajor::Landed:
            return "LANDED";
        case CtrlMajor::Flying:
            return "FLYING";
        case CtrlMajor::Hovering:
            return "HOVERING";
        case CtrlMajor::Test:
            return "TEST";
        case CtrlMajor::TakingOff:
            return "TAKEOFF";
        case CtrlMajor::GotoFix:
            return "GOTOFIX";
        case CtrlMajor::Landing:
            return "LANDING";
        case CtrlMajor::Looping:
            return "LOOPING";
    }
    return "?";
}

}  // namespace gs::sim
