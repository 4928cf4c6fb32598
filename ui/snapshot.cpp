#include "ui/snapshot.hpp"

namespace gs::ui {

const char* to_string(LinkState s) {
    switch (s) {
        case LinkState::Disconnected:
            return "Disconnected";
        case LinkState::Connecting:
            return "Connecting";
        case LinkState::Connected:
            return "Connected";
        case LinkState::Lost:
            return "Link lost";
        case LinkState::Replay:
            return "Replay";
    }
    return "?";
}

const char* to_string(SourceKind k) {
    switch (k) {
        case SourceKind::Drone:
            return "drone";
        case SourceKind::Sim:
            return "virtual drone";
        case SourceKind::Replay:
            return "replay";
        case SourceKind::Demo:
            return "demo";
    }
    return "?";
}

const char* to_string(ConfigWriteState s) {
    switch (s) {
        case ConfigWriteState::Pending:
            return "sending";
        case ConfigWriteState::Confirmed:
            return "confirmed";
        case ConfigWriteState::Ignored:
            return "ignored by the drone";
        case ConfigWriteState::Refused:
            return "refused";
        case ConfigWriteState::TimedOut:
            return "no answer";
        case ConfigWriteState::NotConnected:
            return "not connected";
    }
    return "?";
}

namespace {
// Member pointers in bit order, so from_raw/to_raw cannot disagree with the name table.
using Member = bool DroneStateBits::*;
constexpr std::array<Member, 32> kMembers = {
    &DroneStateBits::flying,
    &DroneStateBits::video_enabled,
    &DroneStateBits::vision_enabled,
    &DroneStateBits::angular_speed_control,
    &DroneStateBits::altitude_control,
    &DroneStateBits::user_feedback_start,
    &DroneStateBits::command_ack,
    &DroneStateBits::camera_ready,
    &DroneStateBits::travelling,
    &DroneStateBits::usb_ready,
    &DroneStateBits::navdata_demo,
    &DroneStateBits::navdata_bootstrap,
    &DroneStateBits::motors_problem,
    &DroneStateBits::com_lost,
    &DroneStateBits::software_fault,
    &DroneStateBits::battery_low,
    &DroneStateBits::user_emergency_landing,
    &DroneStateBits::timer_elapsed,
    &DroneStateBits::magneto_needs_calib,
    &DroneStateBits::angles_out_of_range,
    &DroneStateBits::too_much_wind,
    &DroneStateBits::ultrasound_deaf,
    &DroneStateBits::cutout,
    &DroneStateBits::pic_version_ok,
    &DroneStateBits::atcodec_thread_on,
    &DroneStateBits::navdata_thread_on,
    &DroneStateBits::video_thread_on,
    &DroneStateBits::acq_thread_on,
    &DroneStateBits::ctrl_watchdog,
    &DroneStateBits::adc_watchdog,
    &DroneStateBits::com_watchdog,
    &DroneStateBits::emergency,
};
}  // namespace

DroneStateBits DroneStateBits::from_raw(std::uint32_t bits) {
    DroneStateBits s;
    for (std::size_t i = 0; i < kMembers.size(); ++i) s.*kMembers[i] = ((bits >> i) & 1u) != 0;
    return s;
}

std::uint32_t DroneStateBits::to_raw() const {
    std::uint32_t bits = 0;
    for (std::size_t i = 0; i < kMembers.size(); ++i)
        if (this->*kMembers[i]) bits |= 1u << i;
    return bits;
}

const std::array<StateBitName, 32>& drone_state_bit_names() {
    static const std::array<StateBitName, 32> names = {{
        {0, "FLY", "flying"},
        {1, "VIDEO", "video enabled"},
        {2, "VISION", "vision enabled"},
        {3, "CONTROL", "angular-speed control (0: Euler angles)"},
        {4, "ALTITUDE", "altitude control active"},
        {5, "USER_FEEDBACK_START", "start button seen"},
        {6, "COMMAND", "command ACK"},
        {7, "CAMERA", "camera ready"},
        {8, "TRAVELLING", "travelling enabled"},
        {9, "USB", "USB key ready"},
        {10, "NAVDATA_DEMO", "demo navdata only"},
        {11, "NAVDATA_BOOTSTRAP", "bootstrap: no options sent"},
        {12, "MOTORS", "motor problem"},
        {13, "COM_LOST", "communication lost"},
        {14, "SOFTWARE_FAULT", "software fault"},
        {15, "VBAT_LOW", "battery too low"},
        {16, "USER_EL", "user emergency landing"},
        {17, "TIMER_ELAPSED", "timer elapsed"},
        {18, "MAGNETO_NEEDS_CALIB", "magnetometer needs calibration"},
        {19, "ANGLES_OUT_OF_RANGE", "angles out of range"},
        {20, "WIND", "too much wind"},
        {21, "ULTRASOUND", "ultrasound altimeter deaf"},
        {22, "CUTOUT", "motor cut-out triggered"},
        {23, "PIC_VERSION", "nav-board PIC version OK"},
        {24, "ATCODEC_THREAD_ON", "AT codec thread on"},
        {25, "NAVDATA_THREAD_ON", "navdata thread on"},
        {26, "VIDEO_THREAD_ON", "video thread on"},
        {27, "ACQ_THREAD_ON", "acquisition thread on"},
        {28, "CTRL_WATCHDOG", "control loop late"},
        {29, "ADC_WATCHDOG", "nav-board UART late"},
        {30, "COM_WATCHDOG", "communication watchdog"},
        {31, "EMERGENCY", "emergency (motors cut)"},
    }};
    return names;
}

std::string ctrl_state_name(std::uint32_t ctrl_state) {
    static const char* const majors[] = {"DEFAULT", "INIT",    "LANDED",  "FLYING",  "HOVERING",
                                         "TEST",    "TAKEOFF", "GOTOFIX", "LANDING", "LOOPING"};
    static const std::vector<std::vector<const char*>> minors = {
        {},
        {},
        {},
        {"OK", "LOST_ALT", "LOST_ALT_GO_DOWN", "ALT_OUT_ZONE", "COMBINED_YAW", "BRAKE",
         "NO_VISION"},
        {"OK", "YAW", "YAW_LOST_ALT", "YAW_LOST_ALT_GO_DOWN", "ALT_OUT_ZONE", "YAW_ALT_OUT_ZONE",
         "LOST_ALT", "LOST_ALT_GO_DOWN", "LOST_COM", "LOST_COM_LOST_ALT",
         "LOST_COM_LOST_ALT_TOO_LONG", "LOST_COM_ALT_OK", "MAGNETO_CALIB", "DEMO"},
        {},
        {"GROUND", "AUTO"},
        {"OK", "LOST_ALT", "YAW"},
        {"CLOSED_LOOP", "OPEN_LOOP", "OPEN_LOOP_FAST"},
        {"IMPULSION", "OPEN_LOOP_CTRL", "PLANIF_CTRL"},
    };
    const std::uint32_t major = ctrl_state >> 16;
    const std::uint32_t minor = ctrl_state & 0xFFFFu;
    if (major >= std::size(majors)) return std::string("UNKNOWN(") + std::to_string(major) + ")";
    std::string s = majors[major];
    const auto& table = minors[major];
    if (!table.empty()) {
        if (minor < table.size()) {
            if (minor != 0 || major == 6) s += std::string(" / ") + table[minor];
        } else {
            s += " / ?";
            s += std::to_string(minor);
        }
    }
    return s;
}

}  // namespace gs::ui
