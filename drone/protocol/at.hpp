#pragma once
// AT command encoder (docs/protocol.md §2): pure functions that return the exact, CR-terminated
// command strings the drone parses on UDP 5556, a sequence counter and a datagram packer. No
// sockets here; the link owns a SeqCounter and sends what pack() returns.

#include "drone/core/expected.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace gs::protocol::at {

// Sequence number carried by every command. The drone parses it as a signed 32-bit int.
using Seq = std::uint32_t;

// Whole datagram limit: the drone rejects longer datagrams entirely (§2.1).
inline constexpr std::size_t kMaxDatagramBytes = 1024;

// ---- AT*REF bit field (§2.5) ----------------------------------------------------------------
// Bits 18, 20, 22, 24, 28 must always be set: they are the neutral values of legacy pad fields and
// a REF without them can write bad trim files on the drone.
inline constexpr std::uint32_t kRefBase =
    (1u << 18) | (1u << 20) | (1u << 22) | (1u << 24) | (1u << 28);  // 290717696
inline constexpr std::uint32_t kRefEmergencyBit = 1u << 8;
inline constexpr std::uint32_t kRefTakeoffBit = 1u << 9;
static_assert(kRefBase == 290717696u);

// REF input with the base bits: takeoff = stay flying (0 = land), emergency = toggle request.
constexpr std::uint32_t ref_input(bool takeoff, bool emergency) {
    return kRefBase | (takeoff ? kRefTakeoffBit : 0u) | (emergency ? kRefEmergencyBit : 0u);
}

// ---- AT*PCMD flags (§2.6) -------------------------------------------------------------------
inline constexpr std::int32_t kPcmdProgressive = 1 << 0;      // 0 = ignore the values and hover
inline constexpr std::int32_t kPcmdCombinedYaw = 1 << 1;      // roll and yaw coupled
inline constexpr std::int32_t kPcmdAbsoluteControl = 1 << 2;  // PCMD_MAG: relative to psi

// ---- AT*CTRL modes (§2.7) -------------------------------------------------------------------
enum class CtrlMode : std::int32_t {
    NoControl = 0,
    ArdroneUpdate = 1,
    PicUpdate = 2,
    LogsGet = 3,
    CfgGet = 4,        // drone writes its configuration on TCP 5559
    Ack = 5,           // clears navdata drone_state bit 6
    CustomCfgGet = 6,  // drone writes the custom configuration ids on TCP 5559
};

// Calibration device of AT*CALIB; the magnetometer is the only one.
inline constexpr std::int32_t kCalibMagnetometer = 0;

enum class AtError {
    ForbiddenCharacter,  // '"', CR, LF or another control character in a string argument
    BadName,             // command name not [A-Z0-9_]+
    BadConfigId,         // CONFIG_IDS id is not exactly 8 hex digits
    CommandTooLong,      // one command is longer than a datagram may be
    Unterminated,        // packer got a string that is not one CR-terminated command
};
[[nodiscard]] std::string_view to_string(AtError e);

// ---- Floats (§2.3) --------------------------------------------------------------------------
// The IEEE-754 single bit pattern read as a signed int32 (what the drone expects for float
// arguments). -0 is sent as 0, like every peer that gets it right.
[[nodiscard]] std::int32_t float_to_int(float v);
[[nodiscard]] float int_to_float(std::int32_t bits);

// ---- Sequence counter (§2.2) ----------------------------------------------------------------
// First number is 1 (1 also makes the drone restart its counter); every command takes one number.
// Wraps from INT32_MAX back to 1, which the drone accepts as a restart. Not thread-safe: the link
// thread owns it.
class SeqCounter {
public:
    SeqCounter() = default;
    // Starts at `next` (0 or a value past INT32_MAX start at 1), e.g. to resume a stream.
    explicit SeqCounter(Seq next) : next_(next == 0 || next > kMaxSeq ? 1 : next) {}
    static constexpr Seq kMaxSeq = 2147483647;  // INT32_MAX

    [[nodiscard]] Seq next();
    // Number the next call to next() will return.
    [[nodiscard]] Seq peek() const { return next_; }
    void reset() { next_ = 1; }

private:
    Seq next_ = 1;
};

// ---- Commands (§2.4) ------------------------------------------------------------------------
[[nodiscard]] std::string ref(Seq seq, std::uint32_t input);
// Motion values are fractions of the configured maxima. They are clamped to [-1, 1] and NaN is
// sent as 0: a motion command must never carry garbage to a flying drone.
[[nodiscard]] std::string pcmd(Seq seq, std::int32_t flags, float roll, float pitch, float gaz,
                               float yaw);
// "Hover": flag 0 and all values zero.
[[nodiscard]] std::string hover(Seq seq);
// PCMD with the controller heading psi and its accuracy, both in [-1, 1] (clamped as above).
[[nodiscard]] std::string pcmd_mag(Seq seq, std::int32_t flags, float roll, float pitch, float gaz,
                                   float yaw, float psi, float psi_accuracy);
[[nodiscard]] std::string ftrim(Seq seq);
[[nodiscard]] std::string calib(Seq seq, std::int32_t device = kCalibMagnetometer);
[[nodiscard]] std::string comwdg(Seq seq);
[[nodiscard]] std::string ctrl(Seq seq, CtrlMode mode, std::int32_t arg = 0);
[[nodiscard]] std::string ctrl(Seq seq, std::int32_t mode, std::int32_t arg = 0);
[[nodiscard]] std::string led(Seq seq, std::int32_t anim_id, float freq_hz,
                              std::int32_t duration_s);
[[nodiscard]] std::string anim(Seq seq, std::int32_t anim_id, std::int32_t duration_ms);

// Key and value are sent inside double quotes with no escaping, so '"' and control characters
// (CR/LF would end the command) are rejected; so is a command that cannot fit in a datagram.
[[nodiscard]] Expected<std::string, AtError> config(Seq seq, std::string_view key,
                                                    std::string_view value);
// Ids are exactly 8 hex digits (§2.8); "00000000" is the default configuration.
[[nodiscard]] Expected<std::string, AtError> config_ids(Seq seq, std::string_view session_id,
                                                        std::string_view user_id,
                                                        std::string_view application_id);

// Values for the CONFIG keys that replaced AT*LED / AT*ANIM on firmware 2 (§2.9).
[[nodiscard]] std::string leds_anim_value(std::int32_t anim_id, float freq_hz,
                                          std::int32_t duration_s);  // "leds:leds_anim"
[[nodiscard]] std::string flight_anim_value(std::int32_t anim_id,
                                            std::int32_t duration_ms);  // "control:flight_anim"

// A command name as the drone knows them: upper-case letters, digits and '_', not empty.
[[nodiscard]] bool valid_command_name(std::string_view name);

// Any other command (AT*PMODE, AT*MISC, AT*AFLIGHT ...). Raw arguments are printed as they are
// (no ',', '"' or control characters); quoted ones inside double quotes.
struct RawArg {
    std::string_view text;
};
struct QuotedArg {
    std::string_view text;
};
using Arg = std::variant<std::int32_t, float, RawArg, QuotedArg>;
[[nodiscard]] Expected<std::string, AtError> command(Seq seq, std::string_view name,
                                                     std::span<const Arg> args);

// ---- Datagram packing (§2.1) ----------------------------------------------------------------
// Packs commands, in order, into as few datagrams as possible, each <= max_bytes, never splitting
// a command. Each input must be exactly one CR-terminated command. `out` is reused (its strings
// keep their capacity); returns the number of datagrams written to out[0..n).
[[nodiscard]] Expected<std::size_t, AtError> pack_into(std::span<const std::string> commands,
                                                       std::vector<std::string>& out,
                                                       std::size_t max_bytes = kMaxDatagramBytes);
[[nodiscard]] Expected<std::vector<std::string>, AtError> pack(
    std::span<const std::string> commands, std::size_t max_bytes = kMaxDatagramBytes);

}  // namespace gs::protocol::at
