#include "drone/protocol/config.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdio>

namespace gs::protocol {
namespace {
constexpr std::size_t kMaxLine = 4096;

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r'))
        s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
        s.remove_suffix(1);
    return s;
}
}  // namespace

void ConfigMap::set(std::string key, std::string value) {
    for (auto& [k, v] : entries_) {
        if (k == key) {
            v = std::move(value);
            return;
        }
    }
    entries_.emplace_back(std::move(key), std::move(value));
}

std::optional<std::string> ConfigMap::get(std::string_view key) const {
    for (auto it = entries_.rbegin(); it != entries_.rend(); ++it) {
        if (it->first == key) return it->second;
    }
    return std::nullopt;
}

std::string to_string(ConfigError e) {
    switch (e) {
        case ConfigError::LineTooLong:
            return "line too long";
        case ConfigError::DumpTooLarge:
            return "configuration dump too large";
        case ConfigError::MissingEquals:
            return "line without '='";
        case ConfigError::EmptyKey:
            return "empty key";
        case ConfigError::BadKey:
            return "key with invalid characters";
    }
    return "unknown configuration error";
}

Expected<ConfigMap, ConfigParseError> parse_config_dump(std::string_view text) {
    if (auto nul = text.find('\0'); nul != std::string_view::npos) text = text.substr(0, nul);
    ConfigMap out;
    std::size_t line_no = 0;
    while (!text.empty()) {
        ++line_no;
        const std::size_t eol = text.find('\n');
        std::string_view line = text.substr(0, eol);
        text = eol == std::string_view::npos ? std::string_view{} : text.substr(eol + 1);
        if (line.size() > kMaxLine)
            return Unexpected{ConfigParseError{ConfigError::LineTooLong, line_no}};
        line = trim(line);
        if (line.empty()) continue;
        const std::size_t eq = line.find('=');
        if (eq == std::string_view::npos) {
            return Unexpected{ConfigParseError{ConfigError::MissingEquals, line_no}};
        }
        const std::string_view key = trim(line.substr(0, eq));
        const std::string_view value = trim(line.substr(eq + 1));
        if (key.empty()) return Unexpected{ConfigParseError{ConfigError::EmptyKey, line_no}};
        const bool key_ok = std::all_of(key.begin(), key.end(), [](char c) {
            return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == ':' ||
                   c == '.' || c == '-';
        });
        if (!key_ok) return Unexpected{ConfigParseError{ConfigError::BadKey, line_no}};
        out.set(std::string(key), std::string(value));
    }
    return out;
}

std::string format_config_dump(const ConfigMap& config) {
    std::string s;
    for (const auto& [k, v] : config.entries()) {
        s += k;
        s += " = ";
        s += v;
        s += '\n';
    }
    s += '\0';
    return s;
}

std::optional<Expected<ConfigMap, ConfigParseError>> ConfigDumpReader::push(
    std::span<const std::uint8_t> bytes) {
    for (std::size_t i = 0; i < bytes.size(); ++i) {
        if (bytes[i] == 0) {
            auto parsed = parse_config_dump(buf_);
            buf_.assign(reinterpret_cast<const char*>(bytes.data()) + i + 1, bytes.size() - i - 1);
            if (buf_.size() > max_bytes_) buf_.clear();
            return parsed;
        }
        if (buf_.size() >= max_bytes_) {
            buf_.clear();
            return Expected<ConfigMap, ConfigParseError>(
                Unexpected{ConfigParseError{ConfigError::DumpTooLarge, 0}});
        }
        buf_.push_back(static_cast<char>(bytes[i]));
    }
    return std::nullopt;
}

std::optional<bool> config_bool(std::string_view v) {
    v = trim(v);
    if (v == "TRUE") return true;
    if (v == "FALSE") return false;
    return std::nullopt;
}

std::optional<long long> config_int(std::string_view v) {
    v = trim(v);
    long long out = 0;
    auto [p, ec] = std::from_chars(v.data(), v.data() + v.size(), out);
    if (ec != std::errc{} || p != v.data() + v.size() || v.empty()) return std::nullopt;
    return out;
}

std::optional<double> config_float(std::string_view v) {
    v = trim(v);
    double out = 0;
    auto [p, ec] = std::from_chars(v.data(), v.data() + v.size(), out);
    if (ec != std::errc{} || p != v.data() + v.size() || v.empty()) return std::nullopt;
    return out;
}

std::optional<std::vector<double>> config_vector(std::string_view v) {
    v = trim(v);
    if (v.size() < 2 || v.front() != '{' || v.back() != '}') return std::nullopt;
    v = v.substr(1, v.size() - 2);
    std::vector<double> out;
    while (true) {
        v = trim(v);
        if (v.empty()) break;
        const std::size_t sp = v.find_first_of(" \t");
        auto x = config_float(v.substr(0, sp));
        if (!x) return std::nullopt;
        out.push_back(*x);
        if (sp == std::string_view::npos) break;
        v = v.substr(sp);
    }
    return out;
}

std::string config_format_float(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.7e", v);
    return buf;
}

bool config_text_ok(std::string_view s) {
    return std::none_of(s.begin(), s.end(), [](char c) {
        return c == '"' || static_cast<unsigned char>(c) < 0x20 || c == 0x7f;
    });
}

}  // namespace gs::protocol
