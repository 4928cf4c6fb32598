#pragma once
// The virtual AR.Drone's flight: a quadrotor reduced to what a ground station observes. Attitude
// follows the commanded angles with a first-order lag, tilt accelerates the body against drag,
// vertical speed and yaw rate follow gaz and yaw, all within the drone's configured limits
// (control:euler_angle_max, control:control_vz_max, control:control_yaw, control:altitude_max).
// Take-off, landing and emergency go through the ctrl_state majors a real drone reports
// (docs/protocol.md §3.7). Deterministic: the same inputs and steps give the same trajectory.

#include <cstdint>

namespace gs::sim {

// ctrl_state majors (docs/protocol.md §3.7).
enum class CtrlMajor : std::uint16_t {
    Default = 0,
    Init = 1,
    Landed = 2,
    Flying = 3,
    Hovering = 4,
    Test = 5,
    TakingOff = 6,
    GotoFix = 7,
    Landing = 8,
    Looping = 9,
};

struct FlightLimits {
    double euler_angle_max_rad = 0.2094;  // control:euler_angle_max (12°)
    double control_vz_max_mm_s = 700.0;   // control:control_vz_max
    double control_yaw_rad_s = 1.745;     // control:control_yaw (100°/s)
    double altitude_max_mm = 3000.0;      // control:altitude_max
};

struct FlightParams {
    double attitude_tau_s = 0.12;                  // attitude response time constant
    double vz_tau_s = 0.25;                        // vertical speed response
    double yaw_rate_tau_s = 0.10;                  // yaw rate response
    double drag_per_s = 0.55;                      // linear drag on horizontal speed
    double hover_gain_deg_per_mps = 12.0;          // hover: tilt against residual speed
    double takeoff_height_m = 1.0;                 // height reached by the take-off manoeuvre
    double takeoff_rise_mps = 0.45;                // vertical speed during take-off
    double takeoff_spinup_s = 0.6;                 // motors spin up before lift-off
    double landing_descent_mps = 0.45;             // vertical speed during landing
    double battery_drain_flying_pct_per_s = 0.12;  // ≈ 12 min of flight
    double battery_drain_idle_pct_per_s = 0.005;
    double battery_low_pct = 20.0;      // VBAT_LOW below this (take-off refused)
    double battery_critical_pct = 5.0;  // forced landing below this
    // Disturbances (evaluation flights): constant wind drift, roll wobble, yaw drift.
    double wind_right_mps = 0.0;  // steady drift to the right (world, relative to start heading)
    double wind_forward_mps = 0.0;
    double roll_wobble_deg = 0.0;  // amplitude of a sinusoidal roll disturbance
    double roll_wobble_hz = 0.7;
    double yaw_drift_deg_s = 0.0;
};

// What the drone receives (already decoded from AT commands).
struct FlightInput {
    bool start = false;        // REF bit 9: 1 = take off / stay flying, 0 = land
    bool emergency = false;    // REF bit 8 (a rising edge toggles the emergency)
    bool progressive = false;  // PCMD flag bit 0 (0 = hover)
    double roll = 0, pitch = 0, gaz = 0, yaw = 0;  // PCMD fractions in [-1, 1]
    bool com_lost = false;  // the communication watchdog fired: hover in place
};

struct FlightState {
    double t_s = 0;
    double x_m = 0, y_m = 0, z_m = 0;  // world: x forward (start heading), y right, z up
    double vx_world_mps = 0, vy_world_mps = 0, vz_mps = 0;
    double roll_deg = 0, pitch_deg = 0, yaw_deg = 0;  // docs/dataset.md conventions
    double yaw_rate_deg_s = 0;
    double battery_pct = 100.0;
    CtrlMajor major = CtrlMajor::Landed;
    std::uint16_t minor = 0;
    bool motors_on = false;
    bool emergency = false;    // drone_state bit 31
    bool battery_low = false;  // drone_state bit 15
    bool user_start = false;   // drone_state bit 5 (start as seen by the drone)
    bool cutout = false;       // motors cut by a collision (drone_state CUTOUT and MOTORS)

    bool flying() const {
        return major == CtrlMajor::Flying || major == CtrlMajor::Hovering ||
               major == CtrlMajor::TakingOff || major == CtrlMajor::Landing ||
               major == CtrlMajor::GotoFix;
    }
    // Body-frame velocities (navdata vx forward, vy right).
    double vx_body_mps() const;
    double vy_body_mps() const;
    std::uint32_t ctrl_state() const { return (static_cast<std::uint32_t>(major) << 16) | minor; }
};

class FlightModel {
public:
    explicit FlightModel(FlightParams params = {}, FlightLimits limits = {});

    void set_limits(const FlightLimits& l) { limits_ = l; }
    const FlightLimits& limits() const { return limits_; }
    const FlightParams& params() const { return params_; }
    void set_pose(double x_m, double y_m, double z_m, double yaw_deg);
    void set_battery(double pct) { s_.battery_pct = pct; }

    // Advances by dt_s (the virtual drone steps at 200 Hz, dt 5 ms).
    void step(const FlightInput& in, double dt_s);
    const FlightState& state() const { return s_; }
    // A contact with the scene (drone/sim/collision.hpp): the body moves out along the unit
    // normal (world x, y, z) by depth_m and loses its speed into the surface; a crash also cuts
    // the motors as a hit propeller does (emergency with the cut-out cause), and it falls.
    void touch(double nx, double ny, double nz, double depth_m, bool crash);

private:
    void update_mode(const FlightInput& in, double dt_s);
    double hold_altitude() const;
    FlightParams params_;
    FlightLimits limits_;
    FlightState s_;
    bool prev_emergency_input_ = false;
    double mode_time_s_ = 0;  // time in the current major state
    double hold_z_m_ = 0;     // altitude held while gaz is zero
};

const char* to_string(CtrlMajor m);

}  // namespace gs::sim
