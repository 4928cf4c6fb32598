#include "drone/protocol/navdata.hpp"

#include "drone/protocol/navdata_layout.hpp"

#include <cstdio>
#include <string>

namespace gs::protocol::navdata {

const std::array<DroneStateBitInfo, 32> kDroneStateBits = {{
    {"FLY", "flying (0 = landed)"},
    {"VIDEO", "video enabled"},
    {"VISION", "vision processing enabled"},
    {"CONTROL", "angular-speed control (0 = Euler-angle control)"},
    {"ALTITUDE", "altitude control loop active"},
    {"USER_FEEDBACK_START", "start button (REF bit 9) seen"},
    {"COMMAND", "command ACK"},
    {"CAMERA", "camera ready"},
    {"TRAVELLING", "travelling enabled"},
    {"USB", "USB key ready"},
    {"NAVDATA_DEMO", "demo navdata only (0 = all options)"},
    {"NAVDATA_BOOTSTRAP", "bootstrap: no options sent"},
    {"MOTORS", "motor problem"},
    {"COM_LOST", "communication lost"},
    {"SOFTWARE_FAULT", "software fault"},
    {"VBAT_LOW", "battery too low"},
    {"USER_EL", "user emergency landing"},
    {"TIMER_ELAPSED", "timer elapsed"},
    {"MAGNETO_NEEDS_CALIB", "magnetometer needs calibration"},
    {"ANGLES_OUT_OF_RANGE", "attitude out of range"},
    {"WIND", "too much wind"},
    {"ULTRASOUND", "ultrasonic altimeter deaf"},
    {"CUTOUT", "motor cut-out triggered"},
    {"PIC_VERSION", "nav-board PIC version OK"},
    {"ATCODEC_THREAD_ON", "AT codec thread running"},
    {"NAVDATA_THREAD_ON", "navdata thread running"},
    {"VIDEO_THREAD_ON", "video thread running"},
    {"ACQ_THREAD_ON", "acquisition thread running"},
    {"CTRL_WATCHDOG", "control loop late (> 5 ms)"},
    {"ADC_WATCHDOG", "nav-board UART late (> 5 ms)"},
    {"COM_WATCHDOG", "communication watchdog"},
    {"EMERGENCY", "emergency (motors cut)"},
}};

std::string_view to_string(DroneStateBit b) {
    return kDroneStateBits[static_cast<std::size_t>(b) & 31U].name;
}

std::string set_bit_names(DroneState s) {
    std::string out;
    for (unsigned i = 0; i < 32; ++i) {
        if (!s.bit(i)) continue;
        if (!out.empty()) out += ' ';
        out += kDroneStateBits[i].name;
    }
    return out;
}

namespace {
constexpr std::array<std::string_view, 10> kCtrlMajor = {
    "CTRL_DEFAULT",       "CTRL_INIT",         "CTRL_LANDED",        "CTRL_FLYING",
    "CTRL_HOVERING",      "CTRL_TEST",         "CTRL_TRANS_TAKEOFF", "CTRL_TRANS_GOTOFIX",
    "CTRL_TRANS_LANDING", "CTRL_TRANS_LOOPING"};
constexpr std::array<std::string_view, 7> kFlyingMinor = {
    "OK", "LOST_ALT", "LOST_ALT_GO_DOWN", "ALT_OUT_ZONE", "COMBINED_YAW", "BRAKE", "NO_VISION"};
constexpr std::array<std::string_view, 14> kHoveringMinor = {"OK",
                                                             "YAW",
                                                             "YAW_LOST_ALT",
                                                             "YAW_LOST_ALT_GO_DOWN",
                                                             "ALT_OUT_ZONE",
                                                             "YAW_ALT_OUT_ZONE",
                                                             "LOST_ALT",
                                                             "LOST_ALT_GO_DOWN",
                                                             "LOST_COM",
                                                             "LOST_COM_LOST_ALT",
                                                             "LOST_COM_LOST_ALT_TOO_LONG",
                                                             "LOST_COM_ALT_OK",
                                                             "MAGNETO_CALIB",
                                                             "DEMO"};
constexpr std::array<std::string_view, 2> kTakeoffMinor = {"GROUND", "AUTO"};
constexpr std::array<std::string_view, 3> kGotofixMinor = {"OK", "LOST_ALT", "YAW"};
constexpr std::array<std::string_view, 3> kLandingMinor = {"CLOSED_LOOP", "OPEN_LOOP",
                                                           "OPEN_LOOP_FAST"};
constexpr std::array<std::string_view, 3> kLoopingMinor = {"IMPULSION", "OPEN_LOOP_CTRL",
                                                           "PLANIF_CTRL"};

template <std::size_t N>
std::optional<std::string_view> pick(const std::array<std::string_view, N>& t, std::uint16_t i) {
    if (i < N) return t[i];
    return std::nullopt;
}
}  // namespace

std::optional<std::string_view> ctrl_major_name(std::uint16_t major) {
    return pick(kCtrlMajor, major);
}

std::optional<std::string_view> ctrl_minor_name(std::uint16_t major, std::uint16_t minor) {
    switch (static_cast<CtrlMajor>(major)) {
        case CtrlMajor::Flying:
            return pick(kFlyingMinor, minor);
        case CtrlMajor::Hovering:
            return pick(kHoveringMinor, minor);
        case CtrlMajor::TransTakeoff:
            return pick(kTakeoffMinor, minor);
        case CtrlMajor::TransGotofix:
            return pick(kGotofixMinor, minor);
        case CtrlMajor::TransLanding:
            return pick(kLandingMinor, minor);
        case CtrlMajor::TransLooping:
            return pick(kLoopingMinor, minor);
        default:
            return std::nullopt;
    }
}

std::string_view to_string(SkipReason r) {
    switch (r) {
        case SkipReason::UnknownTag:
            return "unknown tag";
        case SkipReason::OpaqueTag27:
            return "tag 27 of unverified size (kept opaque)";
        case SkipReason::TooShort:
            return "shorter than its layout";
        case SkipReason::Duplicate:
            return "duplicate (first one kept)";
    }
    return "?";
}

std::string_view to_string(NavdataErrc e) {
    switch (e) {
        case NavdataErrc::TruncatedHeader:
            return "truncated header";
        case NavdataErrc::BadMagic:
            return "bad magic";
        case NavdataErrc::TruncatedOptionHeader:
            return "truncated option header";
        case NavdataErrc::OptionPastEnd:
            return "option runs past the end of the datagram";
        case NavdataErrc::OptionTooSmall:
            return "option size too small";
        case NavdataErrc::MissingChecksum:
            return "missing checksum option";
        case NavdataErrc::BadChecksum:
            return "bad checksum";
    }
    return "?";
}

std::string to_string(const NavdataError& e) {
    std::string s(to_string(e.code));
    const auto num = [](std::uint32_t v) { return std::to_string(v); };
    switch (e.code) {
        case NavdataErrc::TruncatedHeader:
            s += ": " + num(e.got) + " bytes, need " + num(e.expected);
            break;
        case NavdataErrc::BadMagic: {
            char buf[64];
            std::snprintf(buf, sizeof buf, ", expected: 0x%08X, got: 0x%08X", e.expected, e.got);
            s += buf;
            break;
        }
        case NavdataErrc::TruncatedOptionHeader:
            s += " at offset " + num(e.offset) + ": " + num(e.got) + " bytes left";
            break;
        case NavdataErrc::OptionPastEnd:
            s += ": tag " + num(e.tag) + " at offset " + num(e.offset) + " has size " + num(e.got) +
                 ", only " + num(e.expected) + " bytes left";
            break;
        case NavdataErrc::OptionTooSmall:
            s += ": tag " + num(e.tag) + " at offset " + num(e.offset) + " has size " + num(e.got) +
                 ", minimum " + num(e.expected);
            break;
        case NavdataErrc::MissingChecksum:
            s += " (options end at offset " + num(e.offset) + ")";
            break;
        case NavdataErrc::BadChecksum:
            s += ", expected: " + num(e.expected) + ", got: " + num(e.got);
            break;
    }
    return s;
}

std::uint32_t navdata_checksum(std::span<const std::uint8_t> bytes) {
    std::uint32_t sum = 0;
    for (const std::uint8_t b : bytes) sum += b;
    return sum;
}

std::optional<std::string_view> option_name(std::uint16_t tag) {
    if (tag == kChecksumTag) return "cks";
    if (tag == kTag27) return "zimmu_3000|gps";
    std::optional<std::string_view> out;
    layout::for_each_option_type([&]<class T>(std::type_identity<T>) {
        if (layout::Spec<T>::tag == tag) out = layout::Spec<T>::name;
    });
    return out;
}

std::optional<std::string_view> option_name(std::uint16_t tag, std::uint16_t size) {
    if (tag != kTag27) return option_name(tag);
    if (size == layout::Spec<Zimmu3000>::size) return layout::Spec<Zimmu3000>::name;
    if (size == layout::Spec<Gps>::size) return layout::Spec<Gps>::name;
    return "tag27_opaque";
}

namespace {

std::uint32_t u32_at(std::span<const std::uint8_t> b, std::size_t off) {
    std::uint32_t v = 0;
    layout::load(b.data() + off, v);
    return v;
}
std::uint16_t u16_at(std::span<const std::uint8_t> b, std::size_t off) {
    std::uint16_t v = 0;
    layout::load(b.data() + off, v);
    return v;
}

template <class T>
void decode_fields(std::span<const std::uint8_t> block, T& out) {
    layout::Spec<T>::fields(out, [&](std::size_t off, std::string_view, std::string_view,
                                     auto& field) {
        // The caller checked block.size() >= Spec<T>::size and the layout test proves every
        // field ends within Spec<T>::size; this guard keeps the read bounded regardless.
        if (off + layout::wire_size_v<std::remove_reference_t<decltype(field)>> <= block.size()) {
            layout::load(block.data() + off, field);
        }
    });
}

// Decodes a block of type T into nd.*member; returns why it was skipped, if it was.
template <class T>
std::optional<SkipReason> decode_option(std::span<const std::uint8_t> block, Navdata& nd) {
    using S = layout::Spec<T>;
    auto& slot = nd.*S::member;
    if (slot.has_value()) return SkipReason::Duplicate;
    // Parrot appends fields to grow an option (§3.3 rule 4): larger is fine, shorter is not
    // decoded (its missing fields would otherwise read as 0, which looks like a real value).
    if (block.size() < S::size) return SkipReason::TooShort;
    decode_fields(block, slot.emplace());
    return std::nullopt;
}

std::optional<SkipReason> dispatch(std::uint16_t tag, std::span<const std::uint8_t> block,
                                   Navdata& nd) {
    if (tag == kTag27) {
        if (block.size() == layout::Spec<Zimmu3000>::size) {
            return decode_option<Zimmu3000>(block, nd);
        }
        if (block.size() == layout::Spec<Gps>::size) return decode_option<Gps>(block, nd);
        return SkipReason::OpaqueTag27;
    }
    std::optional<SkipReason> result = SkipReason::UnknownTag;
    layout::for_each_option_type([&]<class T>(std::type_identity<T>) {
        if constexpr (layout::Spec<T>::tag != kTag27) {
            if (layout::Spec<T>::tag == tag) result = decode_option<T>(block, nd);
        }
    });
    return result;
}

NavdataError err(NavdataErrc code, std::size_t offset, std::uint16_t tag = 0,
                 std::uint32_t expected = 0, std::uint32_t got = 0) {
    return NavdataError{code, static_cast<std::uint32_t>(offset), tag, expected, got};
}

}  // namespace

Expected<Navdata, NavdataError> parse_navdata(std::span<const std::uint8_t> bytes) {
    const std::size_t n = bytes.size();
    if (n < 4) {
        return Unexpected{
            err(NavdataErrc::TruncatedHeader, 0, 0, kHeaderSize, static_cast<std::uint32_t>(n))};
    }
    Navdata nd;
    nd.header.magic = u32_at(bytes, 0);
    if (nd.header.magic != kMagic && nd.header.magic != kMagicAlt) {
        return Unexpected{err(NavdataErrc::BadMagic, 0, 0, kMagic, nd.header.magic)};
    }
    if (n < kHeaderSize) {
        return Unexpected{
            err(NavdataErrc::TruncatedHeader, 0, 0, kHeaderSize, static_cast<std::uint32_t>(n))};
    }
    nd.header.drone_state.raw = u32_at(bytes, 4);
    nd.header.sequence = u32_at(bytes, 8);
    nd.header.vision_defined = u32_at(bytes, 12);

    std::uint32_t sum = navdata_checksum(bytes.first(kHeaderSize));
    std::size_t off = kHeaderSize;
    // Each iteration advances off by >= 4 or returns, so the loop ends after <= n/4 steps.
    for (;;) {
        const std::size_t left = n - off;
        if (left == 0) return Unexpected{err(NavdataErrc::MissingChecksum, off)};
        if (left < 4) {
            return Unexpected{err(NavdataErrc::TruncatedOptionHeader, off, 0, 4,
                                  static_cast<std::uint32_t>(left))};
        }
        const std::uint16_t tag = u16_at(bytes, off);
        const std::uint16_t size = u16_at(bytes, off + 2);
        const std::uint32_t min_size = tag == kChecksumTag ? kChecksumSize : 4U;
        if (size < min_size) {
            return Unexpected{err(NavdataErrc::OptionTooSmall, off, tag, min_size, size)};
        }
        if (size > left) {
            return Unexpected{
                err(NavdataErrc::OptionPastEnd, off, tag, static_cast<std::uint32_t>(left), size)};
        }
        const OptionEntry entry{static_cast<std::uint32_t>(off), tag, size};
        nd.options.push_back(entry);
        const auto block = bytes.subspan(off, size);
        if (tag == kChecksumTag) {
            nd.checksum = u32_at(block, 4);
            nd.checksum_offset = static_cast<std::uint32_t>(off);
            nd.trailing_bytes = static_cast<std::uint32_t>(left - size);
            if (nd.checksum != sum) {
                return Unexpected{err(NavdataErrc::BadChecksum, off, tag, sum, nd.checksum)};
            }
            return nd;
        }
        if (const auto skip = dispatch(tag, block, nd)) {
            nd.skipped.push_back(SkippedOption{entry, *skip});
        }
        sum += navdata_checksum(block);
        off += size;
    }
}

NavState to_nav_state(const Navdata& nd, TimeNs t_ns) {
    NavState s;
    s.t_ns = t_ns;
    s.seq = nd.header.sequence;
    s.drone_state = nd.header.drone_state.raw;
    if (nd.demo) {
        const Demo& d = *nd.demo;
        s.pitch_deg = static_cast<double>(d.theta_mdeg) / 1000.0;
        s.roll_deg = static_cast<double>(d.phi_mdeg) / 1000.0;
        s.yaw_deg = static_cast<double>(d.psi_mdeg) / 1000.0;
        s.vx_mps = static_cast<double>(d.vx_mm_s) / 1000.0;
        s.vy_mps = static_cast<double>(d.vy_mm_s) / 1000.0;
        s.vz_mps = -static_cast<double>(d.vz_mm_s) / 1000.0;  // navdata z down, NavState z up
        s.altitude_m = static_cast<double>(d.altitude_mm) / 1000.0;
        s.battery_pct = static_cast<double>(d.vbat_flying_percentage);
        s.ctrl_state = d.ctrl_state.raw;
    }
    return s;
}

}  // namespace gs::protocol::navdata
