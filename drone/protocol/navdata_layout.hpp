#pragma once
// The navdata field table (docs/protocol.md §3.5): for every option its tag, layout size, name and,
// per field, the byte offset (from the option's tag), the PROTOCOL/SDK name and the unit. The
// decoder, the encoder, the JSON export and `inspect navdata` all walk this one table, so the four
// cannot disagree; tests check that each option's fields tile bytes [4, size) exactly.
//
// Spec<T>::fields(opt, f) calls f(offset, name, unit, field&) for every field in wire order; `opt`
// may be const. Field types: arithmetic, GpsChannel, or (nested) std::array of those.

#include "drone/protocol/navdata.hpp"

#include <bit>
#include <cstring>
#include <string_view>
#include <tuple>
#include <type_traits>

namespace gs::protocol::navdata::layout {

template <class T>
struct Spec;

#define GS_NAVDATA_SPEC(Type, Tag, Size, Name, Member)                                          \
    static constexpr std::uint16_t tag = Tag;                                                   \
    static constexpr std::uint16_t size = Size;                                                 \
    static constexpr std::string_view name = Name;                                              \
    static constexpr auto member = &Navdata::Member;                                            \
    static_assert(std::is_same_v<std::remove_cvref_t<decltype(std::declval<Navdata>().Member)>, \
                                 std::optional<Type>>)

template <>
struct Spec<Demo> {
    GS_NAVDATA_SPEC(Demo, 0, 148, "demo", demo);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "ctrl_state", "", d.ctrl_state.raw);
        f(8, "vbat_flying_percentage", "%", d.vbat_flying_percentage);
        f(12, "theta", "mdeg", d.theta_mdeg);
        f(16, "phi", "mdeg", d.phi_mdeg);
        f(20, "psi", "mdeg", d.psi_mdeg);
        f(24, "altitude", "mm", d.altitude_mm);
        f(28, "vx", "mm/s", d.vx_mm_s);
        f(32, "vy", "mm/s", d.vy_mm_s);
        f(36, "vz", "mm/s", d.vz_mm_s);
        f(40, "num_frames", "", d.num_frames);
        f(44, "detection_camera_rot", "", d.detection_camera_rot);
        f(80, "detection_camera_trans", "", d.detection_camera_trans);
        f(92, "detection_tag_index", "", d.detection_tag_index);
        f(96, "detection_camera_type", "", d.detection_camera_type);
        f(100, "drone_camera_rot", "", d.drone_camera_rot);
        f(136, "drone_camera_trans", "", d.drone_camera_trans);
    }
};

template <>
struct Spec<Time> {
    GS_NAVDATA_SPEC(Time, 1, 8, "time", time);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "time", "raw (s << 21 | us)", d.time.raw);
    }
};

template <>
struct Spec<RawMeasures> {
    GS_NAVDATA_SPEC(RawMeasures, 2, 52, "raw_measures", raw_measures);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "raw_accs", "LSB", d.raw_accs);
        f(10, "raw_gyros", "LSB", d.raw_gyros);
        f(16, "raw_gyros_110", "LSB", d.raw_gyros_110);
        f(20, "vbat_raw", "mV", d.vbat_raw_mv);
        f(24, "us_debut_echo", "", d.us_debut_echo);
        f(26, "us_fin_echo", "", d.us_fin_echo);
        f(28, "us_association_echo", "", d.us_association_echo);
        f(30, "us_distance_echo", "", d.us_distance_echo);
        f(32, "us_courbe_temps", "", d.us_courbe_temps);
        f(34, "us_courbe_valeur", "", d.us_courbe_valeur);
        f(36, "us_courbe_ref", "", d.us_courbe_ref);
        f(38, "flag_echo_ini", "", d.flag_echo_ini);
        f(40, "nb_echo", "", d.nb_echo);
        f(42, "sum_echo", "", d.sum_echo);
        f(46, "alt_temp_raw", "mm", d.alt_temp_raw_mm);
        f(50, "gradient", "", d.gradient);
    }
};

template <>
struct Spec<PhysMeasures> {
    GS_NAVDATA_SPEC(PhysMeasures, 3, 46, "phys_measures", phys_measures);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "accs_temp", "", d.accs_temp);
        f(8, "gyro_temp", "", d.gyro_temp);
        f(10, "phys_accs", "mg", d.phys_accs_mg);
        f(22, "phys_gyros", "deg/s", d.phys_gyros_deg_s);
        f(34, "alim3V3", "", d.alim3V3);
        f(38, "vrefEpson", "", d.vrefEpson);
        f(42, "vrefIDG", "", d.vrefIDG);
    }
};

template <>
struct Spec<GyrosOffsets> {
    GS_NAVDATA_SPEC(GyrosOffsets, 4, 16, "gyros_offsets", gyros_offsets);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "offset_g", "", d.offset_g);
    }
};

template <>
struct Spec<EulerAngles> {
    GS_NAVDATA_SPEC(EulerAngles, 5, 12, "euler_angles", euler_angles);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "theta_a", "", d.theta_a);
        f(8, "phi_a", "", d.phi_a);
    }
};

template <>
struct Spec<References> {
    GS_NAVDATA_SPEC(References, 6, 88, "references", references);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "ref_theta", "mdeg", d.ref_theta_mdeg);
        f(8, "ref_phi", "mdeg", d.ref_phi_mdeg);
        f(12, "ref_theta_I", "", d.ref_theta_I);
        f(16, "ref_phi_I", "", d.ref_phi_I);
        f(20, "ref_pitch", "", d.ref_pitch);
        f(24, "ref_roll", "", d.ref_roll);
        f(28, "ref_yaw", "mdeg/s", d.ref_yaw_mdeg_s);
        f(32, "ref_psi", "", d.ref_psi);
        f(36, "vx_ref", "", d.vx_ref);
        f(40, "vy_ref", "", d.vy_ref);
        f(44, "theta_mod", "", d.theta_mod);
        f(48, "phi_mod", "", d.phi_mod);
        f(52, "k_v_x", "", d.k_v_x);
        f(56, "k_v_y", "", d.k_v_y);
        f(60, "k_mode", "", d.k_mode);
        f(64, "ui_time", "", d.ui_time);
        f(68, "ui_theta", "", d.ui_theta);
        f(72, "ui_phi", "", d.ui_phi);
        f(76, "ui_psi", "", d.ui_psi);
        f(80, "ui_psi_accuracy", "", d.ui_psi_accuracy);
        f(84, "ui_seq", "", d.ui_seq);
    }
};

template <>
struct Spec<Trims> {
    GS_NAVDATA_SPEC(Trims, 7, 16, "trims", trims);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "angular_rates_trim_r", "", d.angular_rates_trim_r);
        f(8, "euler_angles_trim_theta", "", d.euler_angles_trim_theta);
        f(12, "euler_angles_trim_phi", "", d.euler_angles_trim_phi);
    }
};

template <>
struct Spec<RcReferences> {
    GS_NAVDATA_SPEC(RcReferences, 8, 24, "rc_references", rc_references);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "rc_ref_pitch", "", d.rc_ref_pitch);
        f(8, "rc_ref_roll", "", d.rc_ref_roll);
        f(12, "rc_ref_yaw", "", d.rc_ref_yaw);
        f(16, "rc_ref_gaz", "", d.rc_ref_gaz);
        f(20, "rc_ref_ag", "", d.rc_ref_ag);
    }
};

template <>
struct Spec<Pwm> {
    GS_NAVDATA_SPEC(Pwm, 9, 76, "pwm", pwm);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "motor", "PWM", d.motor);
        f(8, "sat_motor", "PWM", d.sat_motor);
        f(12, "gaz_feed_forward", "", d.gaz_feed_forward);
        f(16, "gaz_altitude", "", d.gaz_altitude);
        f(20, "altitude_integral", "", d.altitude_integral);
        f(24, "vz_ref", "", d.vz_ref);
        f(28, "u_pitch", "", d.u_pitch);
        f(32, "u_roll", "", d.u_roll);
        f(36, "u_yaw", "", d.u_yaw);
        f(40, "yaw_u_I", "", d.yaw_u_I);
        f(44, "u_pitch_planif", "", d.u_pitch_planif);
        f(48, "u_roll_planif", "", d.u_roll_planif);
        f(52, "u_yaw_planif", "", d.u_yaw_planif);
        f(56, "u_gaz_planif", "", d.u_gaz_planif);
        f(60, "current_motor", "mA", d.current_motor_ma);
        f(68, "altitude_prop", "", d.altitude_prop);
        f(72, "altitude_der", "", d.altitude_der);
    }
};

template <>
struct Spec<Altitude> {
    GS_NAVDATA_SPEC(Altitude, 10, 56, "altitude", altitude);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "altitude_vision", "mm", d.altitude_vision_mm);
        f(8, "altitude_vz", "mm/s", d.altitude_vz_mm_s);
        f(12, "altitude_ref", "mm", d.altitude_ref_mm);
        f(16, "altitude_raw", "mm", d.altitude_raw_mm);
        f(20, "obs_accZ", "", d.obs_accZ);
        f(24, "obs_alt", "", d.obs_alt);
        f(28, "obs_x", "", d.obs_x);
        f(40, "obs_state", "", d.obs_state);
        f(44, "est_vb", "", d.est_vb);
        f(52, "est_state", "", d.est_state);
    }
};

template <>
struct Spec<VisionRaw> {
    GS_NAVDATA_SPEC(VisionRaw, 11, 16, "vision_raw", vision_raw);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "vision_tx_raw", "", d.vision_tx_raw);
        f(8, "vision_ty_raw", "", d.vision_ty_raw);
        f(12, "vision_tz_raw", "", d.vision_tz_raw);
    }
};

template <>
struct Spec<VisionOf> {
    GS_NAVDATA_SPEC(VisionOf, 12, 44, "vision_of", vision_of);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "of_dx", "", d.of_dx);
        f(24, "of_dy", "", d.of_dy);
    }
};

template <>
struct Spec<Vision> {
    GS_NAVDATA_SPEC(Vision, 13, 92, "vision", vision);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "vision_state", "", d.vision_state);
        f(8, "vision_misc", "", d.vision_misc);
        f(12, "vision_phi_trim", "", d.vision_phi_trim);
        f(16, "vision_phi_ref_prop", "", d.vision_phi_ref_prop);
        f(20, "vision_theta_trim", "", d.vision_theta_trim);
        f(24, "vision_theta_ref_prop", "", d.vision_theta_ref_prop);
        f(28, "new_raw_picture", "", d.new_raw_picture);
        f(32, "theta_capture", "", d.theta_capture);
        f(36, "phi_capture", "", d.phi_capture);
        f(40, "psi_capture", "", d.psi_capture);
        f(44, "altitude_capture", "", d.altitude_capture);
        f(48, "time_capture", "", d.time_capture);
        f(52, "body_v", "mm/s", d.body_v_mm_s);
        f(64, "delta_phi", "", d.delta_phi);
        f(68, "delta_theta", "", d.delta_theta);
        f(72, "delta_psi", "", d.delta_psi);
        f(76, "gold_defined", "", d.gold_defined);
        f(80, "gold_reset", "", d.gold_reset);
        f(84, "gold_x", "", d.gold_x);
        f(88, "gold_y", "", d.gold_y);
    }
};

template <>
struct Spec<VisionPerf> {
    GS_NAVDATA_SPEC(VisionPerf, 14, 108, "vision_perf", vision_perf);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "time_szo", "", d.time_szo);
        f(8, "time_corners", "", d.time_corners);
        f(12, "time_compute", "", d.time_compute);
        f(16, "time_tracking", "", d.time_tracking);
        f(20, "time_trans", "", d.time_trans);
        f(24, "time_update", "", d.time_update);
        f(28, "time_custom", "", d.time_custom);
    }
};

template <>
struct Spec<TrackersSend> {
    GS_NAVDATA_SPEC(TrackersSend, 15, 364, "trackers_send", trackers_send);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "locked", "", d.locked);
        f(124, "point", "", d.point);
    }
};

template <>
struct Spec<VisionDetect> {
    GS_NAVDATA_SPEC(VisionDetect, 16, 328, "vision_detect", vision_detect);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "nb_detected", "", d.nb_detected);
        f(8, "type", "", d.type);
        f(24, "xc", "/1000", d.xc);
        f(40, "yc", "/1000", d.yc);
        f(56, "width", "/1000", d.width);
        f(72, "height", "/1000", d.height);
        f(88, "dist", "cm", d.dist_cm);
        f(104, "orientation_angle", "deg", d.orientation_angle_deg);
        f(120, "rotation", "", d.rotation);
        f(264, "translation", "", d.translation);
        f(312, "camera_source", "", d.camera_source);
    }
};

template <>
struct Spec<Watchdog> {
    GS_NAVDATA_SPEC(Watchdog, 17, 8, "watchdog", watchdog);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "watchdog", "", d.watchdog);
    }
};

template <>
struct Spec<AdcDataFrame> {
    GS_NAVDATA_SPEC(AdcDataFrame, 18, 40, "adc_data_frame", adc_data_frame);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "version", "", d.version);
        f(8, "data_frame", "", d.data_frame);
    }
};

template <>
struct Spec<VideoStream> {
    GS_NAVDATA_SPEC(VideoStream, 19, 65, "video_stream", video_stream);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "quant", "", d.quant);
        f(5, "frame_size", "B", d.frame_size_bytes);
        f(9, "frame_number", "", d.frame_number);
        f(13, "atcmd_ref_seq", "", d.atcmd_ref_seq);
        f(17, "atcmd_mean_ref_gap", "ms", d.atcmd_mean_ref_gap_ms);
        f(21, "atcmd_var_ref_gap", "", d.atcmd_var_ref_gap);
        f(25, "atcmd_ref_quality", "", d.atcmd_ref_quality);
        f(29, "out_bitrate", "", d.out_bitrate);
        f(33, "desired_bitrate", "", d.desired_bitrate);
        f(37, "data", "", d.data);
        f(57, "tcp_queue_level", "", d.tcp_queue_level);
        f(61, "fifo_queue_level", "", d.fifo_queue_level);
    }
};

template <>
struct Spec<Games> {
    GS_NAVDATA_SPEC(Games, 20, 12, "games", games);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "double_tap_counter", "", d.double_tap_counter);
        f(8, "finish_line_counter", "", d.finish_line_counter);
    }
};

template <>
struct Spec<PressureRaw> {
    GS_NAVDATA_SPEC(PressureRaw, 21, 18, "pressure_raw", pressure_raw);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "up", "", d.up);
        f(8, "ut", "", d.ut);
        f(10, "Temperature_meas", "0.1 degC", d.Temperature_meas_0_1C);
        f(14, "Pression_meas", "Pa", d.Pression_meas_Pa);
    }
};

template <>
struct Spec<Magneto> {
    GS_NAVDATA_SPEC(Magneto, 22, 75, "magneto", magneto);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "mx", "", d.mx);
        f(6, "my", "", d.my);
        f(8, "mz", "", d.mz);
        f(10, "magneto_raw", "mG", d.magneto_raw_mG);
        f(22, "magneto_rectified", "mG", d.magneto_rectified_mG);
        f(34, "magneto_offset", "mG", d.magneto_offset_mG);
        f(46, "heading_unwrapped", "", d.heading_unwrapped);
        f(50, "heading_gyro_unwrapped", "", d.heading_gyro_unwrapped);
        f(54, "heading_fusion_unwrapped", "deg", d.heading_fusion_unwrapped_deg);
        f(58, "magneto_calibration_ok", "", d.magneto_calibration_ok);
        f(59, "magneto_state", "", d.magneto_state);
        f(63, "magneto_radius", "", d.magneto_radius);
        f(67, "error_mean", "", d.error_mean);
        f(71, "error_var", "", d.error_var);
    }
};

template <>
struct Spec<WindSpeed> {
    GS_NAVDATA_SPEC(WindSpeed, 23, 56, "wind_speed", wind_speed);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "wind_speed", "m/s", d.wind_speed_m_s);
        f(8, "wind_angle", "", d.wind_angle);
        f(12, "wind_compensation_theta", "", d.wind_compensation_theta);
        f(16, "wind_compensation_phi", "", d.wind_compensation_phi);
        f(20, "state_x", "", d.state_x);
        f(44, "magneto_debug", "", d.magneto_debug);
    }
};

template <>
struct Spec<KalmanPressure> {
    GS_NAVDATA_SPEC(KalmanPressure, 24, 72, "kalman_pressure", kalman_pressure);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "offset_pressure", "", d.offset_pressure);
        f(8, "est_z", "", d.est_z);
        f(12, "est_zdot", "", d.est_zdot);
        f(16, "est_bias_PWM", "", d.est_bias_PWM);
        f(20, "est_biais_pression", "", d.est_biais_pression);
        f(24, "offset_US", "", d.offset_US);
        f(28, "prediction_US", "", d.prediction_US);
        f(32, "cov_alt", "", d.cov_alt);
        f(36, "cov_PWM", "", d.cov_PWM);
        f(40, "cov_vitesse", "", d.cov_vitesse);
        f(44, "bool_effet_sol", "", d.bool_effet_sol);
        f(48, "somme_inno", "", d.somme_inno);
        f(52, "flag_rejet_US", "", d.flag_rejet_US);
        f(56, "u_multisinus", "", d.u_multisinus);
        f(60, "gaz_altitude", "", d.gaz_altitude);
        f(64, "Flag_multisinus", "", d.Flag_multisinus);
        f(68, "Flag_multisinus_debut", "", d.Flag_multisinus_debut);
    }
};

template <>
struct Spec<HdvideoStream> {
    GS_NAVDATA_SPEC(HdvideoStream, 25, 32, "hdvideo_stream", hdvideo_stream);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "hdvideo_state", "", d.hdvideo_state);
        f(8, "storage_fifo_nb_packets", "", d.storage_fifo_nb_packets);
        f(12, "storage_fifo_size", "", d.storage_fifo_size);
        f(16, "usbkey_size", "kB", d.usbkey_size_kb);
        f(20, "usbkey_freespace", "kB", d.usbkey_freespace_kb);
        f(24, "frame_number", "", d.frame_number);
        f(28, "usbkey_remaining_time", "s", d.usbkey_remaining_time_s);
    }
};

template <>
struct Spec<Wifi> {
    GS_NAVDATA_SPEC(Wifi, 26, 8, "wifi", wifi);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "link_quality", "", d.link_quality);
    }
};

template <>
struct Spec<Zimmu3000> {
    GS_NAVDATA_SPEC(Zimmu3000, 27, 12, "zimmu_3000", zimmu_3000);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "vzimmuLSB", "", d.vzimmuLSB);
        f(8, "vzfind", "", d.vzfind);
    }
};

template <>
struct Spec<Gps> {
    GS_NAVDATA_SPEC(Gps, 27, 216, "gps", gps);
    template <class D, class F>
    static void fields(D& d, F&& f) {
        f(4, "latitude", "deg", d.latitude_deg);
        f(12, "longitude", "deg", d.longitude_deg);
        f(20, "elevation", "m", d.elevation_m);
        f(28, "hdop", "", d.hdop);
        f(36, "data_available", "", d.data_available);
        f(40, "zero_validated", "", d.zero_validated);
        f(44, "wpt_validated", "", d.wpt_validated);
        f(48, "lat0", "deg", d.lat0_deg);
        f(56, "lon0", "deg", d.lon0_deg);
        f(64, "lat_fuse", "deg", d.lat_fuse_deg);
        f(72, "lon_fuse", "deg", d.lon_fuse_deg);
        f(80, "gps_state", "", d.gps_state);
        f(84, "x_traj", "", d.x_traj);
        f(88, "x_ref", "", d.x_ref);
        f(92, "y_traj", "", d.y_traj);
        f(96, "y_ref", "", d.y_ref);
        f(100, "theta_p", "", d.theta_p);
        f(104, "phi_p", "", d.phi_p);
        f(108, "theta_i", "", d.theta_i);
        f(112, "phi_i", "", d.phi_i);
        f(116, "theta_d", "", d.theta_d);
        f(120, "phi_d", "", d.phi_d);
        f(124, "vdop", "", d.vdop);
        f(132, "pdop", "", d.pdop);
        f(140, "speed", "m/s", d.speed_m_s);
        f(144, "last_frame_timestamp", "", d.last_frame_timestamp);
        f(148, "degree", "deg", d.degree_deg);
        f(152, "degree_mag", "", d.degree_mag);
        f(156, "ehpe", "", d.ehpe);
        f(160, "ehve", "", d.ehve);
        f(164, "c_n0", "", d.c_n0);
        f(168, "nb_satellites", "", d.nb_satellites);
        f(172, "channels", "(sat,cn0)", d.channels);
        f(196, "gps_plugged", "", d.gps_plugged);
        f(200, "ephemeris_status", "", d.ephemeris_status);
        f(204, "vx_traj", "", d.vx_traj);
        f(208, "vy_traj", "", d.vy_traj);
        f(212, "firmware_status", "", d.firmware_status);
    }
};

#undef GS_NAVDATA_SPEC

// Every option type in tag order (tag 27: zimmu_3000 before gps).
using AllOptions =
    std::tuple<Demo, Time, RawMeasures, PhysMeasures, GyrosOffsets, EulerAngles, References, Trims,
               RcReferences, Pwm, Altitude, VisionRaw, VisionOf, Vision, VisionPerf, TrackersSend,
               VisionDetect, Watchdog, AdcDataFrame, VideoStream, Games, PressureRaw, Magneto,
               WindSpeed, KalmanPressure, HdvideoStream, Wifi, Zimmu3000, Gps>;

// Calls f(std::type_identity<T>{}) for every option type T, in tag order.
template <class F>
constexpr void for_each_option_type(F&& f) {
    [&]<std::size_t... I>(std::index_sequence<I...>) {
        (f(std::type_identity<std::tuple_element_t<I, AllOptions>>{}), ...);
    }
    (std::make_index_sequence<std::tuple_size_v<AllOptions>>{});
}

// ---- wire encoding of one field (little-endian, independent of the host) ----------------------

template <class T>
struct WireSize : std::integral_constant<std::size_t, sizeof(T)> {
    static_assert(std::is_arithmetic_v<T>);
};
template <>
struct WireSize<GpsChannel> : std::integral_constant<std::size_t, 2> {};
template <class E, std::size_t N>
struct WireSize<std::array<E, N>> : std::integral_constant<std::size_t, N * WireSize<E>::value> {};

template <class T>
inline constexpr std::size_t wire_size_v = WireSize<std::remove_cv_t<T>>::value;

template <std::size_t N>
struct UintOf;
template <>
struct UintOf<1> {
    using type = std::uint8_t;
};
template <>
struct UintOf<2> {
    using type = std::uint16_t;
};
template <>
struct UintOf<4> {
    using type = std::uint32_t;
};
template <>
struct UintOf<8> {
    using type = std::uint64_t;
};

// Reads a field at p (caller guarantees wire_size_v<T> readable bytes).
template <class T>
void load(const std::uint8_t* p, T& v) {
    if constexpr (std::is_arithmetic_v<T>) {
        using U = typename UintOf<sizeof(T)>::type;
        U u = 0;
        for (std::size_t i = 0; i < sizeof(T); ++i)
            u |= static_cast<U>(static_cast<U>(p[i]) << (8 * i));
        v = std::bit_cast<T>(u);
    } else if constexpr (std::is_same_v<T, GpsChannel>) {
        v.sat = p[0];
        v.cn0 = p[1];
    } else {
        using E = typename T::value_type;
        for (std::size_t i = 0; i < v.size(); ++i) load(p + i * wire_size_v<E>, v[i]);
    }
}

// Writes a field at p (caller guarantees wire_size_v<T> writable bytes).
template <class T>
void store(std::uint8_t* p, const T& v) {
    if constexpr (std::is_arithmetic_v<T>) {
        using U = typename UintOf<sizeof(T)>::type;
        const U u = std::bit_cast<U>(v);
        for (std::size_t i = 0; i < sizeof(T); ++i) p[i] = static_cast<std::uint8_t>(u >> (8 * i));
    } else if constexpr (std::is_same_v<T, GpsChannel>) {
        p[0] = v.sat;
        p[1] = v.cn0;
    } else {
        using E = typename T::value_type;
        for (std::size_t i = 0; i < v.size(); ++i) store(p + i * wire_size_v<E>, v[i]);
    }
}

}  // namespace gs::protocol::navdata::layout
