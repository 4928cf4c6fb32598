#pragma once
// The drone side of the AT channel (docs/protocol.md §2), for the virtual drone: parses one UDP
// datagram into typed commands and applies the drone's sequence-number rules. Pure: bytes in,
// values out. Malformed commands are skipped like the real drone does, but never silently: each
// one is reported with a reason.

#include "drone/core/expected.hpp"
#include "drone/protocol/at.hpp"
#include "drone/transport/endpoint.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace gs::sim::at {

// The drone side of protocol::at: its vocabulary (Seq, the REF bits, ...) is this one's.
using namespace gs::protocol::at;  // NOLINT(google-build-using-namespace)

struct Ref {
    std::uint32_t input = 0;  // bit field, §2.5
    friend bool operator==(const Ref&, const Ref&) = default;
};
struct Pcmd {
    std::int32_t flags = 0;
    float roll = 0, pitch = 0, gaz = 0, yaw = 0;  // fractions of the configured maxima
    friend bool operator==(const Pcmd&, const Pcmd&) = default;
};
struct PcmdMag {
    std::int32_t flags = 0;
    float roll = 0, pitch = 0, gaz = 0, yaw = 0, psi = 0, psi_accuracy = 0;
    friend bool operator==(const PcmdMag&, const PcmdMag&) = default;
};
struct Ftrim {
    friend bool operator==(const Ftrim&, const Ftrim&) = default;
};
struct Calib {
    std::int32_t device = 0;
    friend bool operator==(const Calib&, const Calib&) = default;
};
struct Config {
    std::string key, value;
    friend bool operator==(const Config&, const Config&) = default;
};
struct ConfigIds {
    std::string session_id, user_id, application_id;
    friend bool operator==(const ConfigIds&, const ConfigIds&) = default;
};
struct Comwdg {
    friend bool operator==(const Comwdg&, const Comwdg&) = default;
};
struct Ctrl {
    std::int32_t mode = 0, arg = 0;
    friend bool operator==(const Ctrl&, const Ctrl&) = default;
};
struct Led {
    std::int32_t anim_id = 0;
    float freq_hz = 0;
    std::int32_t duration_s = 0;
    friend bool operator==(const Led&, const Led&) = default;
};
struct Anim {
    std::int32_t anim_id = 0, duration_ms = 0;
    friend bool operator==(const Anim&, const Anim&) = default;
};

using CommandBody =
    std::variant<Ref, Pcmd, PcmdMag, Ftrim, Calib, Config, ConfigIds, Comwdg, Ctrl, Led, Anim>;

struct Command {
    Seq seq = 0;
    CommandBody body;
    friend bool operator==(const Command&, const Command&) = default;
};

// Why a command was skipped.
enum class SkipReason {
    NotAtCommand,    // does not start with "AT*NAME="
    UnknownCommand,  // a name this parser does not model (AT*PMODE, AT*MISC, ...)
    BadSequence,     // sequence number missing or not a decimal in 0..INT32_MAX
    BadNumber,       // integer argument missing, not decimal, or outside int32
    BadString,       // quoted argument unterminated, unquoted, or with a control character
    WrongArgCount,   // more or fewer arguments than the command takes
    Unterminated,    // bytes after the last CR/LF of the datagram
};
inline constexpr std::size_t kSkipReasonCount = 7;
[[nodiscard]] std::string_view to_string(SkipReason r);

struct Skipped {
    SkipReason reason;
    std::size_t offset;  // byte offset of the skipped command in the datagram
    friend bool operator==(const Skipped&, const Skipped&) = default;
};

enum class DatagramError {
    TooLong,  // over 1024 bytes: the drone drops the whole datagram
};
[[nodiscard]] std::string_view to_string(DatagramError e);

struct ParsedDatagram {
    std::vector<Command> commands;  // in datagram order
    std::vector<Skipped> skipped;
};

// Commands end with CR or LF (empty lines between terminators are ignored, so CRLF works); a
// no-argument command may carry a trailing comma ("AT*FTRIM=5,"). Numbers must fit in int32;
// float arguments are int32 bit patterns (§2.3).
[[nodiscard]] Expected<ParsedDatagram, DatagramError> parse_datagram(
    std::span<const std::uint8_t> bytes);
[[nodiscard]] Expected<ParsedDatagram, DatagramError> parse_datagram(std::string_view text);
// Same, reusing `out`'s storage (cleared first). Returns the number of commands parsed.
[[nodiscard]] Expected<std::size_t, DatagramError> parse_datagram_into(
    std::span<const std::uint8_t> bytes, ParsedDatagram& out);

// The drone's sequence rules (§2.2), per command: a number not greater than the last accepted one
// is ignored; 1 always restarts the counter; a different client (address:port) starts afresh, like
// a restarted ground station. The counter starts at 0, so a first command numbered 0 is ignored.
class SeqFilter {
public:
    [[nodiscard]] bool accept(const transport::Endpoint& client, Seq seq);

    [[nodiscard]] Seq last_accepted() const { return last_; }
    [[nodiscard]] std::uint64_t accepted() const { return accepted_; }
    [[nodiscard]] std::uint64_t rejected() const { return rejected_; }
    // Times the counter restarted: seq 1 after another number, or a new client.
    [[nodiscard]] std::uint64_t restarts() const { return restarts_; }

private:
    bool has_client_ = false;
    transport::Endpoint client_{};
    Seq last_ = 0;
    std::uint64_t accepted_ = 0, rejected_ = 0, restarts_ = 0;
};

}  // namespace gs::sim::at
