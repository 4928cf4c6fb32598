#pragma once
// Navdata (UDP 5554, drone -> client) decoder: one datagram in, a typed Navdata or a typed error
// out (docs/protocol.md §3). Pure function over bytes, no allocation: every option is a fixed-size
// struct held in a std::optional, and the option/skip lists have a fixed capacity with an overflow
// count. Field names are the SDK identifiers with the unit appended where the unit is established
// (docs/protocol.md §3.8/§3.9/§10); fields whose unit is disputed keep the bare SDK name.

#include "drone/core/expected.hpp"
#include "drone/core/sample.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace gs::protocol::navdata {

inline constexpr std::uint32_t kMagic = 0x55667788;     // SDK NAVDATA_HEADER
inline constexpr std::uint32_t kMagicAlt = 0x55667789;  // accepted by NODE; accepted here too
inline constexpr std::size_t kHeaderSize = 16;
inline constexpr std::uint16_t kChecksumTag = 0xFFFF;
inline constexpr std::uint16_t kChecksumSize = 8;
inline constexpr std::uint16_t kTag27 = 27;  // zimmu_3000 or gps, dispatched on size (§3.6)

// ---- drone_state (§3.2) -------------------------------------------------------------------------

enum class DroneStateBit : std::uint8_t {
    Fly = 0,
    Video,
    Vision,
    Control,
    Altitude,
    UserFeedbackStart,
    Command,
    Camera,
    Travelling,
    Usb,
    NavdataDemo,
    NavdataBootstrap,
    Motors,
    ComLost,
    SoftwareFault,
    VbatLow,
    UserEl,
    TimerElapsed,
    MagnetoNeedsCalib,
    AnglesOutOfRange,
    Wind,
    Ultrasound,
    Cutout,
    PicVersion,
    AtcodecThreadOn,
    NavdataThreadOn,
    VideoThreadOn,
    AcqThreadOn,
    CtrlWatchdog,
    AdcWatchdog,
    ComWatchdog,
    Emergency
};

struct DroneStateBitInfo {
    std::string_view name;     // SDK name without the ARDRONE_ prefix / _MASK suffix, e.g. "FLY"
    std::string_view meaning;  // what a set bit means
};
// Name and meaning of every bit 0..31.
extern const std::array<DroneStateBitInfo, 32> kDroneStateBits;

struct DroneState {
    std::uint32_t raw = 0;

    constexpr bool test(DroneStateBit b) const {
        return ((raw >> static_cast<unsigned>(b)) & 1U) != 0;
    }
    constexpr bool bit(unsigned i) const { return i < 32 && ((raw >> i) & 1U) != 0; }
    constexpr bool fly() const { return test(DroneStateBit::Fly); }
    constexpr bool video() const { return test(DroneStateBit::Video); }
    constexpr bool vision() const { return test(DroneStateBit::Vision); }
    constexpr bool control() const { return test(DroneStateBit::Control); }
    constexpr bool altitude() const { return test(DroneStateBit::Altitude); }
    constexpr bool user_feedback_start() const { return test(DroneStateBit::UserFeedbackStart); }
    constexpr bool command() const { return test(DroneStateBit::Command); }
    constexpr bool camera() const { return test(DroneStateBit::Camera); }
    constexpr bool travelling() const { return test(DroneStateBit::Travelling); }
    constexpr bool usb() const { return test(DroneStateBit::Usb); }
    constexpr bool navdata_demo() const { return test(DroneStateBit::NavdataDemo); }
    constexpr bool navdata_bootstrap() const { return test(DroneStateBit::NavdataBootstrap); }
    constexpr bool motors() const { return test(DroneStateBit::Motors); }
    constexpr bool com_lost() const { return test(DroneStateBit::ComLost); }
    constexpr bool software_fault() const { return test(DroneStateBit::SoftwareFault); }
    constexpr bool vbat_low() const { return test(DroneStateBit::VbatLow); }
    constexpr bool user_el() const { return test(DroneStateBit::UserEl); }
    constexpr bool timer_elapsed() const { return test(DroneStateBit::TimerElapsed); }
    constexpr bool magneto_needs_calib() const { return test(DroneStateBit::MagnetoNeedsCalib); }
    constexpr bool angles_out_of_range() const { return test(DroneStateBit::AnglesOutOfRange); }
    constexpr bool wind() const { return test(DroneStateBit::Wind); }
    constexpr bool ultrasound() const { return test(DroneStateBit::Ultrasound); }
    constexpr bool cutout() const { return test(DroneStateBit::Cutout); }
    constexpr bool pic_version() const { return test(DroneStateBit::PicVersion); }
    constexpr bool atcodec_thread_on() const { return test(DroneStateBit::AtcodecThreadOn); }
    constexpr bool navdata_thread_on() const { return test(DroneStateBit::NavdataThreadOn); }
    constexpr bool video_thread_on() const { return test(DroneStateBit::VideoThreadOn); }
    constexpr bool acq_thread_on() const { return test(DroneStateBit::AcqThreadOn); }
    constexpr bool ctrl_watchdog() const { return test(DroneStateBit::CtrlWatchdog); }
    constexpr bool adc_watchdog() const { return test(DroneStateBit::AdcWatchdog); }
    constexpr bool com_watchdog() const { return test(DroneStateBit::ComWatchdog); }
    constexpr bool emergency() const { return test(DroneStateBit::Emergency); }

    constexpr void set(DroneStateBit b, bool on) {
        const std::uint32_t m = 1U << static_cast<unsigned>(b);
        raw = on ? (raw | m) : (raw & ~m);
    }
};

std::string_view to_string(DroneStateBit b);
// Names of the set bits, space separated, e.g. "ALTITUDE COMMAND CAMERA ...". Allocates (display).
std::string set_bit_names(DroneState s);

// ---- ctrl_state (§3.7)
// ---------------------------------------------------------------------------

enum class CtrlMajor : std::uint16_t {
    Default = 0,
    Init,
    Landed,
    Flying,
    Hovering,
    Test,
    TransTakeoff,
    TransGotofix,
    TransLanding,
    TransLooping
};

struct CtrlState {
    std::uint32_t raw = 0;
    constexpr std::uint16_t major() const { return static_cast<std::uint16_t>(raw >> 16); }
    constexpr std::uint16_t minor() const { return static_cast<std::uint16_t>(raw & 0xFFFFU); }
    static constexpr CtrlState make(CtrlMajor major, std::uint16_t minor) {
        return CtrlState{(static_cast<std::uint32_t>(major) << 16) | minor};
    }
};

// "CTRL_LANDED", ...; nullopt for a major outside 0..9.
std::optional<std::string_view> ctrl_major_name(std::uint16_t major);
// Major-specific minor name ("OK", "LOST_ALT", ...); nullopt when that major has no table or the
// minor is outside it (NODE's mistake of always using the FLYING table is not repeated).
std::optional<std::string_view> ctrl_minor_name(std::uint16_t major, std::uint16_t minor);

// ---- time (§3.9)
// ---------------------------------------------------------------------------------

// Drone "TSECDEC" time: bits 31..21 whole seconds (wraps at 2048 s), bits 20..0 microseconds.
struct DroneTime {
    std::uint32_t raw = 0;
    constexpr std::uint32_t seconds() const { return raw >> 21; }
    constexpr std::uint32_t microseconds() const { return raw & 0x1FFFFFU; }
    constexpr std::int64_t total_us() const {
        return static_cast<std::int64_t>(seconds()) * 1000000 + microseconds();
    }
    constexpr double total_s() const { return static_cast<double>(total_us()) * 1e-6; }
    // seconds is taken modulo 2048, microseconds modulo 2^21 (the wire fields' widths).
    static constexpr DroneTime make(std::uint32_t s, std::uint32_t us) {
        return DroneTime{((s & 0x7FFU) << 21) | (us & 0x1FFFFFU)};
    }
};

// ---- options (§3.5)
// ------------------------------------------------------------------------------ Offsets, wire
// types and names of every field are in drone/navdata_layout.hpp.

using F3 = std::array<float, 3>;
using F9 = std::array<float, 9>;

struct Demo {  // tag 0
    CtrlState ctrl_state;
    std::uint32_t vbat_flying_percentage = 0;     // %, not mV (§10.2)
    float theta_mdeg = 0;                         // pitch, nose up positive
    float phi_mdeg = 0;                           // roll, right side down positive
    float psi_mdeg = 0;                           // yaw, clockwise positive, ±180000
    std::int32_t altitude_mm = 0;                 // mm, not cm (§10.1)
    float vx_mm_s = 0, vy_mm_s = 0, vz_mm_s = 0;  // body frame: x fwd, y right, z down
    std::uint32_t num_frames = 0;
    F9 detection_camera_rot{};
    F3 detection_camera_trans{};
    std::uint32_t detection_tag_index = 0;
    std::uint32_t detection_camera_type = 0;
    F9 drone_camera_rot{};
    F3 drone_camera_trans{};
};

struct Time {  // tag 1
    DroneTime time;
};

struct RawMeasures {  // tag 2
    std::array<std::uint16_t, 3> raw_accs{};
    std::array<std::int16_t, 3> raw_gyros{};
    std::array<std::int16_t, 2> raw_gyros_110{};
    std::uint32_t vbat_raw_mv = 0;
    std::uint16_t us_debut_echo = 0, us_fin_echo = 0, us_association_echo = 0, us_distance_echo = 0,
                  us_courbe_temps = 0, us_courbe_valeur = 0, us_courbe_ref = 0, flag_echo_ini = 0,
                  nb_echo = 0;
    std::uint32_t sum_echo = 0;
    std::int32_t alt_temp_raw_mm = 0;
    std::int16_t gradient = 0;
};

struct PhysMeasures {     // tag 3
    float accs_temp = 0;  // unit unverified (NODE says K)
    std::uint16_t gyro_temp = 0;
    F3 phys_accs_mg{};
    F3 phys_gyros_deg_s{};
    std::uint32_t alim3V3 = 0, vrefEpson = 0, vrefIDG = 0;
};

struct GyrosOffsets {  // tag 4
    F3 offset_g{};
};

struct EulerAngles {  // tag 5; millidegrees is NODE's guess only
    float theta_a = 0, phi_a = 0;
};

struct References {  // tag 6
    std::int32_t ref_theta_mdeg = 0, ref_phi_mdeg = 0, ref_theta_I = 0, ref_phi_I = 0,
                 ref_pitch = 0, ref_roll = 0, ref_yaw_mdeg_s = 0, ref_psi = 0;
    float vx_ref = 0, vy_ref = 0, theta_mod = 0, phi_mod = 0, k_v_x = 0, k_v_y = 0;
    std::uint32_t k_mode = 0;
    float ui_time = 0, ui_theta = 0, ui_phi = 0, ui_psi = 0, ui_psi_accuracy = 0;
    std::int32_t ui_seq = 0;
};

struct Trims {  // tag 7
    float angular_rates_trim_r = 0, euler_angles_trim_theta = 0, euler_angles_trim_phi = 0;
};

struct RcReferences {  // tag 8
    std::int32_t rc_ref_pitch = 0, rc_ref_roll = 0, rc_ref_yaw = 0, rc_ref_gaz = 0, rc_ref_ag = 0;
};

struct Pwm {                                  // tag 9
    std::array<std::uint8_t, 4> motor{};      // motor1..4, PWM 0..255
    std::array<std::uint8_t, 4> sat_motor{};  // sat_motor1..4
    float gaz_feed_forward = 0, gaz_altitude = 0, altitude_integral = 0, vz_ref = 0;
    std::int32_t u_pitch = 0, u_roll = 0, u_yaw = 0;
    float yaw_u_I = 0;
    std::int32_t u_pitch_planif = 0, u_roll_planif = 0, u_yaw_planif = 0;
    float u_gaz_planif = 0;
    std::array<std::uint16_t, 4> current_motor_ma{};  // current_motor1..4
    float altitude_prop = 0, altitude_der = 0;
};

struct Altitude {  // tag 10
    std::int32_t altitude_vision_mm = 0;
    float altitude_vz_mm_s = 0;
    std::int32_t altitude_ref_mm = 0;
    std::int32_t altitude_raw_mm = 0;  // sonar
    float obs_accZ = 0, obs_alt = 0;
    F3 obs_x{};
    std::uint32_t obs_state = 0;
    std::array<float, 2> est_vb{};
    std::uint32_t est_state = 0;
};

struct VisionRaw {  // tag 11
    float vision_tx_raw = 0, vision_ty_raw = 0, vision_tz_raw = 0;
};

struct VisionOf {  // tag 12
    std::array<float, 5> of_dx{}, of_dy{};
};

struct Vision {  // tag 13
    std::uint32_t vision_state = 0;
    std::int32_t vision_misc = 0;
    float vision_phi_trim = 0, vision_phi_ref_prop = 0, vision_theta_trim = 0,
          vision_theta_ref_prop = 0;
    std::int32_t new_raw_picture = 0;
    float theta_capture = 0, phi_capture = 0, psi_capture = 0;
    std::int32_t altitude_capture = 0;
    std::uint32_t time_capture = 0;  // unit unresolved (§10.13)
    F3 body_v_mm_s{};
    float delta_phi = 0, delta_theta = 0, delta_psi = 0;
    std::uint32_t gold_defined = 0, gold_reset = 0;
    float gold_x = 0, gold_y = 0;
};

struct VisionPerf {  // tag 14
    float time_szo = 0, time_corners = 0, time_compute = 0, time_tracking = 0, time_trans = 0,
          time_update = 0;
    std::array<float, 20> time_custom{};
};

struct TrackersSend {  // tag 15: 30 trackers (6x5 grid)
    std::array<std::int32_t, 30> locked{};
    std::array<std::array<std::int32_t, 2>, 30> point{};  // (x, y)
};

struct VisionDetect {  // tag 16: up to 4 detections
    std::uint32_t nb_detected = 0;
    std::array<std::uint32_t, 4> type{};  // bits 0-7 tag type, bits 16-23 camera source
    std::array<std::uint32_t, 4> xc{}, yc{}, width{}, height{};  // 0..1000 normalised
    std::array<std::uint32_t, 4> dist_cm{};
    std::array<float, 4> orientation_angle_deg{};
    std::array<F9, 4> rotation{};
    std::array<F3, 4> translation{};
    std::array<std::uint32_t, 4> camera_source{};
};

struct Watchdog {  // tag 17
    std::int32_t watchdog = 0;
};

struct AdcDataFrame {  // tag 18
    std::uint32_t version = 0;
    std::array<std::uint8_t, 32> data_frame{};
};

struct VideoStream {  // tag 19 (65 bytes: the options after it are unaligned)
    std::uint8_t quant = 0;
    std::uint32_t frame_size_bytes = 0;
    std::uint32_t frame_number = 0;  // = PaVE frame_number
    std::uint32_t atcmd_ref_seq = 0;
    std::uint32_t atcmd_mean_ref_gap_ms = 0;
    float atcmd_var_ref_gap = 0;
    std::uint32_t atcmd_ref_quality = 0;
    std::uint32_t out_bitrate = 0, desired_bitrate = 0;
    std::array<std::int32_t, 5> data{};  // data1..5
    std::uint32_t tcp_queue_level = 0, fifo_queue_level = 0;
};

struct Games {  // tag 20
    std::uint32_t double_tap_counter = 0, finish_line_counter = 0;
};

struct PressureRaw {  // tag 21
    std::int32_t up = 0;
    std::int16_t ut = 0;
    std::int32_t Temperature_meas_0_1C = 0;  // tenths of a degree Celsius
    std::int32_t Pression_meas_Pa = 0;
};

struct Magneto {  // tag 22 (75 bytes)
    std::int16_t mx = 0, my = 0, mz = 0;
    F3 magneto_raw_mG{}, magneto_rectified_mG{}, magneto_offset_mG{};
    float heading_unwrapped = 0, heading_gyro_unwrapped = 0;
    float heading_fusion_unwrapped_deg = 0;
    std::uint8_t magneto_calibration_ok = 0;
    std::uint32_t magneto_state = 0;
    float magneto_radius = 0, error_mean = 0, error_var = 0;
};

struct WindSpeed {  // tag 23
    float wind_speed_m_s = 0;
    float wind_angle = 0;  // rad per SDK, deg per NODE (§10.14)
    float wind_compensation_theta = 0, wind_compensation_phi = 0;
    std::array<float, 6> state_x{};  // state_x1..x6
    F3 magneto_debug{};              // magneto_debug1..3
};

struct KalmanPressure {  // tag 24; the SDK bool_t fields are 4 bytes (§10.11)
    float offset_pressure = 0, est_z = 0, est_zdot = 0, est_bias_PWM = 0, est_biais_pression = 0,
          offset_US = 0, prediction_US = 0, cov_alt = 0, cov_PWM = 0, cov_vitesse = 0;
    std::int32_t bool_effet_sol = 0;
    float somme_inno = 0;
    std::int32_t flag_rejet_US = 0;
    float u_multisinus = 0, gaz_altitude = 0;
    std::int32_t Flag_multisinus = 0, Flag_multisinus_debut = 0;
};

struct HdvideoStream {  // tag 25
    std::uint32_t hdvideo_state = 0;
    std::uint32_t storage_fifo_nb_packets = 0, storage_fifo_size = 0;
    std::uint32_t usbkey_size_kb = 0, usbkey_freespace_kb = 0;
    std::uint32_t frame_number = 0;
    std::uint32_t usbkey_remaining_time_s = 0;
};

struct Wifi {                        // tag 26
    std::uint32_t link_quality = 0;  // raw u32 as the SDK declares it (§10.12)
};

struct Zimmu3000 {  // tag 27, 12 bytes (SDK 2.0.1 / 2012 firmware)
    std::int32_t vzimmuLSB = 0;
    float vzfind = 0;
};

struct GpsChannel {
    std::uint8_t sat = 0;
    std::uint8_t cn0 = 0;
};

struct Gps {  // tag 27, 216 bytes (firmware 2.4.8 layout)
    double latitude_deg = 0, longitude_deg = 0, elevation_m = 0, hdop = 0;
    std::int32_t data_available = 0, zero_validated = 0, wpt_validated = 0;
    double lat0_deg = 0, lon0_deg = 0, lat_fuse_deg = 0, lon_fuse_deg = 0;
    std::uint32_t gps_state = 0;
    float x_traj = 0, x_ref = 0, y_traj = 0, y_ref = 0, theta_p = 0, phi_p = 0, theta_i = 0,
          phi_i = 0, theta_d = 0, phi_d = 0;
    double vdop = 0, pdop = 0;
    float speed_m_s = 0;
    std::uint32_t last_frame_timestamp = 0;  // opaque (§10.15)
    float degree_deg = 0;                    // course
    float degree_mag = 0;
    float ehpe = 0, ehve = 0, c_n0 = 0;
    std::uint32_t nb_satellites = 0;
    std::array<GpsChannel, 12> channels{};
    std::int32_t gps_plugged = 0;
    std::uint32_t ephemeris_status = 0;
    float vx_traj = 0, vy_traj = 0;
    std::uint32_t firmware_status = 0;
};

// ---- the datagram
// --------------------------------------------------------------------------------

struct Header {
    std::uint32_t magic = kMagic;
    DroneState drone_state;
    std::uint32_t sequence = 0;
    std::uint32_t vision_defined = 0;  // bool_t "vision flag"
};

// One option block as found on the wire.
struct OptionEntry {
    std::uint32_t offset = 0;  // of the tag, from the start of the datagram
    std::uint16_t tag = 0;
    std::uint16_t size = 0;  // including the 4 header bytes
};

// An option block that was not decoded into a typed struct, and why.
enum class SkipReason : std::uint8_t {
    UnknownTag,   // tag not in §3.4
    OpaqueTag27,  // tag 27 with a size that is neither 12 nor 216 (e.g. fw 2.4.7's 480 bytes)
    TooShort,     // known tag, block smaller than its layout (nothing decoded from it)
    Duplicate,    // the same option appeared earlier in this datagram; the first one is kept
};
std::string_view to_string(SkipReason r);

struct SkippedOption {
    OptionEntry option;
    SkipReason reason = SkipReason::UnknownTag;
};

// Fixed-capacity list: no heap allocation; entries past the capacity are counted, not stored.
template <class T, std::size_t N>
class BoundedList {
public:
    void push_back(const T& v) {
        if (size_ < N) {
            items_[size_++] = v;
        } else {
            ++overflow_;
        }
    }
    std::size_t size() const { return size_; }
    bool empty() const { return size_ == 0; }
    std::size_t overflow() const { return overflow_; }  // entries that did not fit
    const T& operator[](std::size_t i) const { return items_[i]; }
    const T* begin() const { return items_.data(); }
    const T* end() const { return items_.data() + size_; }

private:
    std::array<T, N> items_{};
    std::size_t size_ = 0;
    std::size_t overflow_ = 0;
};

struct Navdata {
    Header header;

    std::optional<Demo> demo;
    std::optional<Time> time;
    std::optional<RawMeasures> raw_measures;
    std::optional<PhysMeasures> phys_measures;
    std::optional<GyrosOffsets> gyros_offsets;
    std::optional<EulerAngles> euler_angles;
    std::optional<References> references;
    std::optional<Trims> trims;
    std::optional<RcReferences> rc_references;
    std::optional<Pwm> pwm;
    std::optional<Altitude> altitude;
    std::optional<VisionRaw> vision_raw;
    std::optional<VisionOf> vision_of;
    std::optional<Vision> vision;
    std::optional<VisionPerf> vision_perf;
    std::optional<TrackersSend> trackers_send;
    std::optional<VisionDetect> vision_detect;
    std::optional<Watchdog> watchdog;
    std::optional<AdcDataFrame> adc_data_frame;
    std::optional<VideoStream> video_stream;
    std::optional<Games> games;
    std::optional<PressureRaw> pressure_raw;
    std::optional<Magneto> magneto;
    std::optional<WindSpeed> wind_speed;
    std::optional<KalmanPressure> kalman_pressure;
    std::optional<HdvideoStream> hdvideo_stream;
    std::optional<Wifi> wifi;
    std::optional<Zimmu3000> zimmu_3000;  // tag 27, size 12
    std::optional<Gps> gps;               // tag 27, size 216

    // Filled by the parser (ignored by the writer).
    BoundedList<OptionEntry, 64> options;  // every block in wire order, checksum block included
    BoundedList<SkippedOption, 32> skipped;
    std::uint32_t checksum = 0;         // value of the cks option (verified equal to the byte sum)
    std::uint32_t checksum_offset = 0;  // offset of the cks block
    std::uint32_t trailing_bytes = 0;   // bytes after the cks block (not covered by the checksum)
};

// ---- errors
// ----------------------------------------------------------------------------------------

enum class NavdataErrc : std::uint8_t {
    TruncatedHeader,        // fewer than 16 bytes (or fewer than 4: not even a magic)
    BadMagic,               // expected = kMagic, got = what was there
    TruncatedOptionHeader,  // 1..3 bytes left where an option header should start
    OptionPastEnd,          // block size runs past the datagram (expected = bytes left, got = size)
    OptionTooSmall,         // size < 4 (incl. 0: would loop forever) or a cks block < 8
    MissingChecksum,        // options end exactly at the datagram end without a cks block
    BadChecksum,            // expected = byte sum computed here, got = cks in the packet
};
std::string_view to_string(NavdataErrc e);

struct NavdataError {
    NavdataErrc code = NavdataErrc::TruncatedHeader;
    std::uint32_t offset = 0;  // where the problem was found
    std::uint16_t tag = 0;     // option tag when the error concerns an option
    std::uint32_t expected = 0;
    std::uint32_t got = 0;
};
// Human message, e.g. "bad checksum, expected: 36359, got: 36358". Allocates (display path).
std::string to_string(const NavdataError& e);

// ---- API
// -------------------------------------------------------------------------------------------

// Decodes one navdata datagram. Never reads outside `bytes`, never loops on a malformed size.
[[nodiscard]] Expected<Navdata, NavdataError> parse_navdata(std::span<const std::uint8_t> bytes);

// 32-bit wrapping sum of `bytes` (the navdata checksum of the bytes preceding the cks block).
[[nodiscard]] std::uint32_t navdata_checksum(std::span<const std::uint8_t> bytes);

// Name of an option tag as in §3.4 ("demo", "gps" ...); tag 27 is "zimmu_3000|gps" since it
// depends on the size; "cks" for 0xFFFF; nullopt for unknown tags.
std::optional<std::string_view> option_name(std::uint16_t tag);
// Name of a concrete block (resolves tag 27 by size): "zimmu_3000", "gps", "tag27_opaque".
std::optional<std::string_view> option_name(std::uint16_t tag, std::uint16_t size);

// Conversion to the shared NavState, at flight-relative time `t_ns`. Attitude in degrees from
// millidegrees, velocities in m/s from mm/s (vz negated: navdata z is down, NavState z is up),
// altitude in metres from mm (§10.1), battery %. Fields without a demo option stay NaN.
[[nodiscard]] NavState to_nav_state(const Navdata& nd, TimeNs t_ns);

}  // namespace gs::protocol::navdata
