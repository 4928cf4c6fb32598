#include "drone/sim/drone_core.hpp"
#include "drone/sim/units.hpp"

#include "drone/sim/navdata_writer.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace gs::sim {
namespace {
constexpr TimeNs kStepNs = ms_to_ns(5);
constexpr double kStepS = 0.005;

double config_number(const protocol::ConfigMap& c, const char* key, double fallback) {
    auto v = c.get(key);
    if (!v) return fallback;
    auto f = protocol::config_float(*v);
    return f ? *f : fallback;
}
}  // namespace

protocol::ConfigMap default_drone_config() {
    protocol::ConfigMap c;
    auto f = [](double v) { return protocol::config_format_float(v); };
    c.set("general:num_version_config", "1");
    c.set("general:num_version_mb", "33");
    c.set("general:num_version_soft", "2.4.8");
    c.set("general:drone_serial", "VIRTUAL000001");
    c.set("general:soft_build_date", "2026-11-22 00:00");
    c.set("general:ardrone_name", "ardrone-gs virtual drone");
    c.set("general:flying_time", "0");
    c.set("general:navdata_demo", "FALSE");
    c.set("general:navdata_options", "65537");
    c.set("general:com_watchdog", "2");
    c.set("general:video_enable", "TRUE");
    c.set("general:vision_enable", "TRUE");
    c.set("general:vbat_min", "9000");
    c.set("control:altitude_max", "3000");
    c.set("control:altitude_min", "50");
    c.set("control:euler_angle_max", f(0.2094395));
    c.set("control:control_vz_max", f(700.0));
    c.set("control:control_yaw", f(1.745329));
    c.set("control:control_iphone_tilt", f(0.3490659));
    c.set("control:control_level", "0");
    c.set("control:outdoor", "FALSE");
    c.set("control:flight_without_shell", "FALSE");
    c.set("control:indoor_euler_angle_max", f(0.2094395));
    c.set("control:indoor_control_vz_max", f(700.0));
    c.set("control:indoor_control_yaw", f(1.745329));
    c.set("control:outdoor_euler_angle_max", f(0.3490659));
    c.set("control:outdoor_control_vz_max", f(1000.0));
    c.set("control:outdoor_control_yaw", f(3.490659));
    c.set("control:manual_trim", "FALSE");
    c.set("control:autonomous_flight", "FALSE");
    c.set("control:flying_mode", "0");
    c.set("control:hovering_range", "1000");
    c.set("control:flight_anim", "0,0");
    c.set("network:ssid_single_player", "ardrone2_virtual");
    c.set("network:wifi_mode", "0");
    c.set("network:owner_mac", "00:00:00:00:00:00");
    c.set("pic:ultrasound_freq", "8");
    c.set("pic:ultrasound_watchdog", "3");
    c.set("video:video_codec", "129");
    c.set("video:codec_fps", "30");
    c.set("video:bitrate", "1000");
    c.set("video:max_bitrate", "1000");
    c.set("video:bitrate_ctrl_mode", "0");
    c.set("video:bitrate_storage", "4000");
    c.set("video:video_channel", "0");
    c.set("video:video_on_usb", "TRUE");
    c.set("video:video_file_index", "1");
    c.set("leds:leds_anim", "0,0,0");
    c.set("detect:detect_type", "3");
    c.set("detect:enemy_colors", "1");
    c.set("detect:enemy_without_shell", "0");
    c.set("userbox:userbox_cmd", "0");
    c.set("gps:latitude", f(500.0));
    c.set("gps:longitude", f(500.0));
    c.set("gps:altitude", f(0.0));
    c.set("custom:application_id", "00000000");
    c.set("custom:profile_id", "00000000");
    c.set("custom:session_id", "00000000");
    c.set("custom:application_desc", "Default application configuration");
    c.set("custom:profile_desc", "Default profile configuration");
    c.set("custom:session_desc", "Default session configuration");
    c.set("syslog:output", "7");
    c.set("syslog:max_size", "102400");
    c.set("syslog:nb_files", "5");
    return c;
}

void DroneCore::reset_config() {
    config_ = default_drone_config();
    config_.set("video:bitrate", std::to_string(options_.video_bitrate_kbps));
    config_.set("video:max_bitrate", std::to_string(std::max(options_.video_bitrate_kbps, 1000)));
    video_codec_ = 129;
    video_bitrate_kbps_ = options_.video_bitrate_kbps;
}

DroneCore::DroneCore(DroneCoreOptions options)
    : options_(std::move(options)), model_(options_.flight), rng_(options_.seed) {
    reset_config();
    model_.set_pose(options_.start.x_m, options_.start.y_m, options_.start.z_m,
                    options_.start.yaw_deg);
    model_.set_battery(options_.battery_pct);
    navdata_options_ = 65537;
    ap_active_ = options_.autopilot_enabled && !options_.autopilot.empty();
    apply_config("control:euler_angle_max", *config_.get("control:euler_angle_max"));
    update_bits();
}

Pose DroneCore::pose() const {
    const FlightState& s = model_.state();
    return {s.x_m, s.y_m, s.z_m, s.roll_deg, s.pitch_deg, s.yaw_deg};
}

int DroneCore::video_channel() const {
    auto v = config_.get("video:video_channel");
    auto n = v ? protocol::config_int(*v) : std::nullopt;
    return n && *n == 1 ? 1 : 0;
}

bool DroneCore::autopilot_done() const {
    return !options_.autopilot.empty() && ap_step_ >= options_.autopilot.size();
}

void DroneCore::on_navdata_trigger(const transport::Endpoint& from, TimeNs now) {
    now_ = std::max(now_, now);
    if (booting(now)) return;
    navdata_client_ = from;
}

void DroneCore::on_at(std::span<const std::uint8_t> datagram, const transport::Endpoint& from,
                      TimeNs now) {
    if (booting(now)) {
        ++counters_.at_while_booting;
        return;
    }
    ++counters_.at_datagrams;
    last_at_ns_ = now;
    auto parsed = at::parse_datagram(datagram);
    if (!parsed) {
        ++counters_.at_too_long;
        return;
    }
    counters_.at_skipped += parsed->skipped.size();
    for (const at::Command& c : parsed->commands) {
        if (!seq_filter_.accept(from, c.seq)) {
            ++counters_.at_rejected_seq;
            continue;
        }
        ++counters_.at_commands;
        apply_command(c, now);
    }
    update_bits();
}

void DroneCore::apply_command(const at::Command& c, TimeNs now) {
    (void)now;
    struct V {
        DroneCore& d;
        void operator()(const at::Ref& r) {
            const bool start = r.input & at::kRefTakeoffBit;
            const bool emergency = r.input & at::kRefEmergencyBit;
            if (d.input_.start && !start && d.model_.state().flying()) {
                d.autopilot_yield("land");
            }
            if (emergency && !d.input_.emergency) d.autopilot_yield("emergency");
            d.input_.start = start;
            d.input_.emergency = emergency;
        }
        void operator()(const at::Pcmd& p) { set(p.flags, p.roll, p.pitch, p.gaz, p.yaw); }
        void operator()(const at::PcmdMag& p) { set(p.flags, p.roll, p.pitch, p.gaz, p.yaw); }
        void set(std::int32_t flags, float roll, float pitch, float gaz, float yaw) {
            if (flags & at::kPcmdProgressive) d.autopilot_yield("manual move");
            d.input_.progressive = flags & at::kPcmdProgressive;
            d.input_.roll = static_cast<double>(roll);
            d.input_.pitch = static_cast<double>(pitch);
            d.input_.gaz = static_cast<double>(gaz);
            d.input_.yaw = static_cast<double>(yaw);
        }
        void operator()(const at::Ftrim&) {
            if (!d.model_.state().flying()) ++d.counters_.ftrims;
        }
        void operator()(const at::Calib&) {
            if (d.model_.state().flying()) {
                d.autopilot_yield("calibration");  // it yaws a full turn for the pilot
                ++d.counters_.calibrations;
                d.calibration_yaw_left_deg_ = 360.0;
            }
        }
        void operator()(const at::Config& c) {
            ++d.counters_.configs;
            if (!d.ids_pending_) ++d.counters_.configs_without_ids;
            d.ids_pending_ = false;
            d.apply_config(c.key, c.value);
            d.ack_ = true;
        }
        void operator()(const at::ConfigIds&) { d.ids_pending_ = true; }
        void operator()(const at::Comwdg&) {
            ++d.counters_.comwdg;
            d.com_watchdog_ = false;
        }
        void operator()(const at::Ctrl& c) {
            if (c.mode == static_cast<std::int32_t>(at::CtrlMode::Ack)) {
                d.ack_ = false;
            } else if (c.mode == static_cast<std::int32_t>(at::CtrlMode::CfgGet)) {
                d.pending_dump_ = protocol::format_config_dump(d.config_);
                d.ack_ = true;
            }
        }
        void operator()(const at::Led& l) {
            ++d.counters_.leds;
            d.config_.set("leds:leds_anim",
                          at::leds_anim_value(l.anim_id, l.freq_hz, l.duration_s));
        }
        void operator()(const at::Anim& a) {
            d.autopilot_yield("animation");
            ++d.counters_.anims;
            d.config_.set("control:flight_anim", at::flight_anim_value(a.anim_id, a.duration_ms));
        }
    };
    std::visit(V{*this}, c.body);
}

void DroneCore::apply_config(const std::string& key, const std::string& value) {
    auto current = config_.get(key);
    if (!current) {
        ++counters_.configs_unknown;  // acknowledged, silently ignored: as a real drone does
        return;
    }
    // Typed keys keep their type: a value that does not parse is ignored.
    const bool is_bool = protocol::config_bool(*current).has_value();
    const bool is_number = protocol::config_float(*current).has_value();
    if (is_bool && !protocol::config_bool(value)) return;
    if (!is_bool && is_number && !protocol::config_float(value)) return;
    // What the firmware bounds (docs/protocol.md section 5.4) is kept inside its range, and a video
    // codec this drone cannot stream is refused: the read-back shows what it took.
    struct Range {
        const char* key;
        double lo, hi;
    };
    static constexpr Range kRanges[] = {{"control:altitude_max", 500, 10000},
                                        {"control:euler_angle_max", 0.0, 0.5236},
                                        {"control:control_vz_max", 200, 2000},
                                        {"control:control_yaw", 0.698, 6.11},
                                        {"video:bitrate", 250, 4000}};
    std::string stored = value;
    for (const Range& r : kRanges) {
        if (key != r.key) continue;
        const double v = *protocol::config_float(value);
        const double c = std::clamp(v, r.lo, r.hi);
        if (c != v) {
            ++counters_.configs_clamped;
            stored = key == "control:altitude_max" || key == "video:bitrate"
                         ? std::to_string(static_cast<long>(c))
                         : protocol::config_format_float(c);
        }
    }
    if (key == "video:video_codec") {
        const auto codec = protocol::config_int(value);
        if (!codec || (*codec != 129 && *codec != 131)) {
            ++counters_.configs_refused;  // H.264 360p and 720p only (docs/protocol.md section 4.5)
            return;
        }
        video_codec_ = *codec;
    }
    if (key == "video:bitrate")
        video_bitrate_kbps_ = static_cast<int>(*protocol::config_float(stored));
    config_.set(key, stored);
    // Switching indoor/outdoor loads that mode's maxima, as the firmware does.
    if (key == "control:outdoor") {
        const std::string mode =
            *protocol::config_bool(value) ? "control:outdoor_" : "control:indoor_";
        for (const char* k : {"euler_angle_max", "control_vz_max", "control_yaw"})
            if (auto m = config_.get(mode + k)) config_.set(std::string("control:") + k, *m);
    }

    if (key == "control:flight_anim") {
        autopilot_yield("animation");
        ++counters_.anims;
    } else if (key == "leds:leds_anim") {
        ++counters_.leds;
    }
    if (key == "general:navdata_demo") {
        demo_ = *protocol::config_bool(value);
        bootstrap_ = false;
    } else if (key == "general:navdata_options") {
        navdata_options_ = static_cast<std::uint32_t>(protocol::config_int(value).value_or(65537));
    }
    FlightLimits l;
    l.euler_angle_max_rad = config_number(config_, "control:euler_angle_max", 0.2094);
    l.control_vz_max_mm_s = config_number(config_, "control:control_vz_max", 700);
    l.control_yaw_rad_s = config_number(config_, "control:control_yaw", 1.745);
    l.altitude_max_mm = config_number(config_, "control:altitude_max", 3000);
    model_.set_limits(l);
}

std::optional<std::string> DroneCore::take_config_dump() {
    auto d = std::move(pending_dump_);
    pending_dump_.reset();
    return d;
}

void DroneCore::blackout(TimeNs from, TimeNs until) {
    blackout_from_ = from;
    blackout_until_ = until;
}

void DroneCore::reboot(TimeNs now, TimeNs boot_ns) {
    ++counters_.reboots;
    booted_at_ns_ = now + boot_ns;
    ap_active_ = false;  // a rebooted drone waits on the ground for a pilot
    reset_config();
    seq_filter_ = at::SeqFilter{};
    navdata_client_.reset();
    pending_dump_.reset();
    held_.reset();
    seq_ = 0;
    bootstrap_ = true;
    demo_ = false;
    navdata_options_ = 65537;
    ack_ = com_watchdog_ = com_lost_ = false;
    input_ = {};
    last_at_ns_ = 0;
    boot_ns_ = now;
    // The drone comes back on the ground where it was.
    const FlightState s = model_.state();
    FlightModel fresh(options_.flight);
    fresh.set_pose(s.x_m, s.y_m, 0.0, s.yaw_deg);
    fresh.set_battery(s.battery_pct);
    model_ = fresh;
    apply_config("control:euler_angle_max", *config_.get("control:euler_angle_max"));
    update_bits();
}

void DroneCore::autopilot_yield(const char* reason) {
    if (!ap_active_) return;
    ap_active_ = false;
    ap_yield_reason_ = reason;
    ++counters_.autopilot_yields;
}

FlightInput DroneCore::autopilot_input() {
    FlightInput in;
    in.start = true;
    const FlightState& s = model_.state();
    while (ap_step_ < options_.autopilot.size()) {
        const AutopilotStep& st = options_.autopilot[ap_step_];
        bool done = false;
        if (st.action == "takeoff") {
            done = s.major == CtrlMajor::Hovering || s.major == CtrlMajor::Flying;
        } else if (st.action == "land") {
            in.start = false;
            done = s.major == CtrlMajor::Landed;
        } else {
            done = ap_step_time_s_ >= st.duration_s;
        }
        if (!done) break;
        ++ap_step_;
        ap_step_time_s_ = 0;
    }
    if (ap_step_ >= options_.autopilot.size()) {
        const bool landed_last =
            !options_.autopilot.empty() && options_.autopilot.back().action == "land";
        in.start = !landed_last;
        return in;  // script over: hover (or stay landed)
    }
    const AutopilotStep& st = options_.autopilot[ap_step_];
    if (st.action == "land") in.start = false;
    if (st.action != "move") return in;

    // Velocity tracking as the drone's own optical-flow velocity loop would: feed-forward tilt
    // for the drag at the target speed plus a proportional term.
    const FlightLimits& l = model_.limits();
    const double max_tilt_deg = l.euler_angle_max_rad * kDegPerRad;
    const double drag = options_.flight.drag_per_s;
    auto ff = [&](double v) { return std::atan(drag * v / 9.81) * kDegPerRad; };
    const double k = 8.0;  // deg per m/s of error
    const double pitch_deg = -(ff(st.vx_mps) + k * (st.vx_mps - s.vx_body_mps()));
    const double roll_deg = ff(st.vy_mps) + k * (st.vy_mps - s.vy_body_mps());
    in.progressive = true;
    in.pitch = std::clamp(pitch_deg / max_tilt_deg, -1.0, 1.0);
    in.roll = std::clamp(roll_deg / max_tilt_deg, -1.0, 1.0);
    in.gaz = std::clamp(st.vz_mps / (l.control_vz_max_mm_s / 1000.0), -1.0, 1.0);
    in.yaw = std::clamp(st.yaw_rate_dps / (l.control_yaw_rad_s * kDegPerRad), -1.0, 1.0);
    return in;
}

void DroneCore::advance(TimeNs now, std::vector<OutDatagram>& out) {
    if (!started_) {
        started_ = true;
        boot_ns_ = now;
        sim_ns_ = now;
        last_nav_ns_ = now;
    }
    now_ = std::max(now_, now);
    while (sim_ns_ + kStepNs <= now) {
        sim_ns_ += kStepNs;
        if (last_at_ns_ != 0) {
            const TimeNs silent = sim_ns_ - last_at_ns_;
            if (silent > options_.watchdog_after_ns && !com_watchdog_) {
                com_watchdog_ = true;
                ++counters_.watchdog_events;
            }
            const double limit_s = config_number(config_, "general:com_watchdog", 2.0);
            com_lost_ = static_cast<double>(silent) > limit_s * 1e9;
        }
        FlightInput in = ap_active_ ? autopilot_input() : input_;
        if (ap_active_) {
            in.emergency = input_.emergency;  // a pilot's emergency always wins
            ap_step_time_s_ += kStepS;
        }
        // The watchdog bit (50 ms without a command) only reports: commands that resume are
        // obeyed (node-ar-drone never sends AT*COMWDG and flies real drones). Losing the link
        // for general:com_watchdog seconds is what makes the drone hover on its own.
        in.com_lost = com_lost_ && !ap_active_;
        if (calibration_yaw_left_deg_ > 0) {
            in.progressive = true;
            in.roll = in.pitch = in.gaz = 0;
            in.yaw = 0.5;
            calibration_yaw_left_deg_ -= std::abs(model_.state().yaw_rate_deg_s) * kStepS;
        }
        model_.step(in, kStepS);
        collide();
        update_bits();

        if (!navdata_client_) continue;
        const TimeNs period =
            (bootstrap_ || demo_) ? options_.bootstrap_period_ns : options_.full_period_ns;
        if (sim_ns_ - last_nav_ns_ >= period) {
            last_nav_ns_ = sim_ns_;
            emit_navdata(out);
        }
    }
}

void DroneCore::collide() {
    if (!options_.collider) return;
    const FlightState& s = model_.state();
    const auto c = options_.collider->contact(s.x_m, s.y_m, s.z_m, s.yaw_deg);
    if (!c || c->kind == ContactKind::Floor) {  // the flight model lands on the floor
        in_contact_ = false;
        return;
    }
    const double approach = -(s.vx_world_mps * c->nx + s.vy_world_mps * c->ny + s.vz_mps * c->nz);
    const bool crash = approach >= options_.collider->params().crash_speed_mps;
    // A drone whose motors are already cut (falling after a crash) only slides off the surface.
    const bool counted = !in_contact_ && s.motors_on;
    in_contact_ = true;
    if (counted) {
        CollisionEvent e;
        e.t_ns = sim_ns_;
        e.t_s = s.t_s;
        e.crash = crash;
        e.kind = c->kind;
        e.what = c->what;
        e.x_m = s.x_m;
        e.y_m = s.y_m;
        e.z_m = s.z_m;
        e.speed_mps = std::sqrt(s.vx_world_mps * s.vx_world_mps + s.vy_world_mps * s.vy_world_mps +
                                s.vz_mps * s.vz_mps);
        e.approach_mps = approach;
        ++(crash ? counters_.collisions : counters_.bumps);
        if (collisions_.size() == kMaxCollisionEvents) collisions_.erase(collisions_.begin());
        collisions_.push_back(std::move(e));
        if (crash) autopilot_yield("collision");
    }
    model_.touch(c->nx, c->ny, c->nz, c->depth_m, crash && counted);
}

void DroneCore::update_bits() {
    using B = navdata::DroneStateBit;
    const FlightState& s = model_.state();
    navdata::DroneState b;
    // Always on: video, vision, camera, the PIC version and the firmware's four threads.
    for (B on : {B::Video, B::Vision, B::Camera, B::PicVersion, B::AtcodecThreadOn,
                 B::NavdataThreadOn, B::VideoThreadOn, B::AcqThreadOn})
        b.set(on, true);
    b.set(B::Fly, s.flying());
    b.set(B::Altitude, s.flying());
    b.set(B::UserFeedbackStart, s.user_start);
    b.set(B::Command, ack_);
    b.set(B::NavdataDemo, demo_);
    b.set(B::NavdataBootstrap, bootstrap_);
    b.set(B::ComLost, com_lost_);
    b.set(B::VbatLow, s.battery_low);
    b.set(B::Emergency, s.emergency);
    // A user's emergency sets USER_EL; a crash the cut-out cause: CUTOUT and MOTORS (a blocked
    // propeller), as a real drone reports them (docs/protocol.md section 3.2).
    b.set(B::Cutout, s.cutout);
    b.set(B::Motors, s.cutout);
    b.set(B::UserEl, s.emergency && !s.cutout);
    b.set(B::ComWatchdog, com_watchdog_);
    state_bits_ = b.raw;
}

void DroneCore::emit_navdata(std::vector<OutDatagram>& out) {
    ++seq_;
    if (sim_ns_ >= blackout_from_ && sim_ns_ < blackout_until_) return;  // lost in the air
    navdata::Header h;
    h.drone_state.raw = state_bits_;
    h.sequence = seq_;
    h.vision_defined = 1;
    std::vector<std::uint8_t> bytes;
    if (bootstrap_) {
        navdata::write_bootstrap(h, bytes);
        send(std::move(bytes), out);
        return;
    }
    const FlightState& s = model_.state();
    nav_ = navdata::Navdata{};
    nav_.header = h;
    auto want = [&](int tag) {
        return demo_ ? (tag == 0 || tag == 16) : (navdata_options_ >> tag) & 1u;
    };
    if (want(0)) {
        navdata::Demo d;
        d.ctrl_state.raw = s.ctrl_state();
        d.vbat_flying_percentage = static_cast<std::uint32_t>(std::lround(s.battery_pct));
        d.theta_mdeg = static_cast<float>(s.pitch_deg * 1000.0);
        d.phi_mdeg = static_cast<float>(s.roll_deg * 1000.0);
        d.psi_mdeg = static_cast<float>(s.yaw_deg * 1000.0);
        d.altitude_mm = static_cast<std::int32_t>(std::lround(s.z_m * 1000.0));
        d.vx_mm_s = static_cast<float>(s.vx_body_mps() * 1000.0);
        d.vy_mm_s = static_cast<float>(s.vy_body_mps() * 1000.0);
        d.vz_mm_s = static_cast<float>(-s.vz_mps * 1000.0);  // navdata z is down
        d.num_frames = video_frame_number_;
        d.detection_camera_type = 3;
        nav_.demo = d;
    }
    if (want(1)) {
        const TimeNs up = sim_ns_ - boot_ns_;
        const auto secs = static_cast<std::uint32_t>(up / 1'000'000'000) & 0x7FFu;
        const auto usecs = static_cast<std::uint32_t>((up / 1000) % 1'000'000);
        nav_.time = navdata::Time{navdata::DroneTime{(secs << 21) | usecs}};
    }
    if (want(2)) {
        navdata::RawMeasures r;
        r.vbat_raw_mv = static_cast<std::uint32_t>(10200 + s.battery_pct * 22.0);
        r.alt_temp_raw_mm = static_cast<std::int32_t>(std::lround(s.z_m * 1000.0));
        nav_.raw_measures = r;
    }
    if (want(5)) {
        navdata::EulerAngles e;
        e.theta_a = static_cast<float>(s.pitch_deg * 1000.0);
        e.phi_a = static_cast<float>(s.roll_deg * 1000.0);
        nav_.euler_angles = e;
    }
    if (want(9)) {
        navdata::Pwm p;
        const std::uint8_t m = s.motors_on ? 180 : 0;
        p.motor = {m, m, m, m};
        nav_.pwm = p;
    }
    if (want(10)) {
        navdata::Altitude a;
        a.altitude_vision_mm = static_cast<std::int32_t>(std::lround(s.z_m * 1000.0));
        a.altitude_raw_mm = a.altitude_vision_mm;
        a.altitude_vz_mm_s = static_cast<float>(s.vz_mps * 1000.0);
        nav_.altitude = a;
    }
    if (want(16)) nav_.vision_detect = navdata::VisionDetect{};
    if (want(17)) nav_.watchdog = navdata::Watchdog{};
    if (want(19)) {
        navdata::VideoStream v;
        v.frame_number = video_frame_number_;
        v.frame_size_bytes = video_frame_size_;
        nav_.video_stream = v;
    }
    if (want(21)) {
        navdata::PressureRaw p;
        p.Pression_meas_Pa = static_cast<std::int32_t>(101325 - 12 * s.z_m);
        p.Temperature_meas_0_1C = 250;
        nav_.pressure_raw = p;
    }
    if (want(22)) {
        navdata::Magneto m;
        m.heading_fusion_unwrapped_deg = static_cast<float>(s.yaw_deg);
        m.magneto_calibration_ok = 1;
        nav_.magneto = m;
    }
    if (want(26)) nav_.wifi = navdata::Wifi{};
    navdata::write_navdata(nav_, bytes);
    send(std::move(bytes), out);
}

void DroneCore::send(std::vector<std::uint8_t> bytes, std::vector<OutDatagram>& out) {
    const NavdataFaults& f = options_.faults;
    std::uniform_real_distribution<double> u(0.0, 1.0);
    const transport::Endpoint to = *navdata_client_;
    if (f.loss > 0 && u(rng_) < f.loss) {
        ++counters_.navdata_dropped;
        return;
    }
    if (f.corrupt_checksum > 0 && u(rng_) < f.corrupt_checksum && bytes.size() >= 4) {
        ++bytes[bytes.size() - 4];  // low byte of the cks value
        ++counters_.navdata_corrupted;
    }
    if (f.reorder > 0 && !held_ && u(rng_) < f.reorder) {
        held_ = OutDatagram{to, std::move(bytes)};
        ++counters_.navdata_reordered;
        return;
    }
    const bool dup = f.duplicate > 0 && u(rng_) < f.duplicate;
    out.push_back({to, bytes});
    ++counters_.navdata_sent;
    if (dup) {
        out.push_back({to, std::move(bytes)});
        ++counters_.navdata_duplicated;
    }
    if (held_) {
        out.push_back(std::move(*held_));
        held_.reset();
        ++counters_.navdata_sent;
    }
}

}  // namespace gs::sim
