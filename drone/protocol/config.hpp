#pragma once
// The drone's configuration as text (docs/protocol.md §5): the dump the drone writes on TCP 5559
// after `AT*CTRL=…,4,0` (`section:key = value` lines, ended by a NUL byte), parsed into ordered
// key/values, and the value formats (TRUE/FALSE, integers, %e floats, `{ a b c }` vectors).

#include "drone/core/expected.hpp"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace gs::protocol {

// Ordered key/values (the dump order is meaningful to a human reader; keys may repeat per
// category section, the last one wins in get()).
class ConfigMap {
public:
    void set(std::string key, std::string value);
    std::optional<std::string> get(std::string_view key) const;
    bool contains(std::string_view key) const { return get(key).has_value(); }
    const std::vector<std::pair<std::string, std::string>>& entries() const { return entries_; }
    std::size_t size() const { return entries_.size(); }
    bool empty() const { return entries_.empty(); }

private:
    std::vector<std::pair<std::string, std::string>> entries_;
};

enum class ConfigError { LineTooLong, DumpTooLarge, MissingEquals, EmptyKey, BadKey };
std::string to_string(ConfigError e);

struct ConfigParseError {
    ConfigError error = ConfigError::LineTooLong;
    std::size_t line = 0;  // 1-based
};

// Parses a complete dump (with or without its terminating NUL). Blank lines and CRs are ignored.
Expected<ConfigMap, ConfigParseError> parse_config_dump(std::string_view text);

// The dump a drone writes: one `key = value\n` per entry, then a NUL byte.
std::string format_config_dump(const ConfigMap& config);

// Streaming reader for TCP 5559: bytes in any chunking until the NUL that ends a dump. Bounded:
// a dump larger than `max_bytes` is an error (the drone's is ≈ 4-8 KiB).
class ConfigDumpReader {
public:
    explicit ConfigDumpReader(std::size_t max_bytes = 256 * 1024) : max_bytes_(max_bytes) {}
    // Returns a parsed dump when this chunk completed one; leftover bytes after the NUL start the
    // next dump.
    std::optional<Expected<ConfigMap, ConfigParseError>> push(std::span<const std::uint8_t> bytes);
    void reset() { buf_.clear(); }
    std::size_t buffered() const { return buf_.size(); }

private:
    std::size_t max_bytes_;
    std::string buf_;
};

// Value formats.
std::optional<bool> config_bool(std::string_view v);                   // TRUE / FALSE
std::optional<long long> config_int(std::string_view v);               // decimal
std::optional<double> config_float(std::string_view v);                // decimal or %e
std::optional<std::vector<double>> config_vector(std::string_view v);  // { a b c }
std::string config_format_float(double v);                             // as the drone prints: %e

// True when a key or value can be sent in AT*CONFIG (no quote, CR, LF or other control char).
bool config_text_ok(std::string_view s);

}  // namespace gs::protocol
