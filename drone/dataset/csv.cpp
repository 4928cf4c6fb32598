#include "drone/dataset/csv.hpp"
#include "drone/core/unknown.hpp"

#include "drone/dataset/value_rules.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>

namespace gs::dataset::csv {
namespace {

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
    return s;
}

// Splits one line (no newline) into fields. Returns false on an unterminated quote.
bool split_line(std::string_view line, std::vector<std::string_view>& out) {
    out.clear();
    std::size_t i = 0;
    while (true) {
        // skip leading blanks to see a quote
        std::size_t start = i;
        while (start < line.size() && (line[start] == ' ' || line[start] == '\t')) ++start;
        if (start < line.size() && line[start] == '"') {
            std::size_t j = start + 1;
            while (true) {
                if (j >= line.size()) return false;
                if (line[j] == '"') {
                    if (j + 1 < line.size() && line[j + 1] == '"') {
                        j += 2;
                        continue;
                    }
                    break;
                }
                ++j;
            }
            out.push_back(line.substr(start + 1, j - start - 1));
            std::size_t k = j + 1;
            while (k < line.size() && line[k] != ',') ++k;
            if (k >= line.size()) return true;
            i = k + 1;
            continue;
        }
        std::size_t comma = line.find(',', i);
        if (comma == std::string_view::npos) {
            out.push_back(line.substr(i));
            return true;
        }
        out.push_back(line.substr(i, comma - i));
        i = comma + 1;
    }
}

std::string shown(std::string_view f) {
    constexpr std::size_t kMax = 40;
    std::string s(f.substr(0, kMax));
    for (char& c : s)
        if (static_cast<unsigned char>(c) < 0x20) c = '?';
    if (f.size() > kMax) s += "...";
    return s;
}

}  // namespace

Expected<Table, FileError> Table::parse(std::string text, std::string file,
                                        bool tolerate_cut_tail) {
    Table t;
    t.text_ = std::make_shared<const std::string>(std::move(text));
    t.file_ = std::move(file);
    std::string_view all(*t.text_);
    if (all.find('\0') != std::string_view::npos) {
        return Unexpected(FileError{FileErrorCode::Malformed, t.file_, 0, 0,
                                    "binary data (NUL byte) in a text file"});
    }
    std::vector<std::string_view> fields;
    bool have_header = false;
    int line_no = 0;
    std::size_t pos = 0;
    while (pos < all.size()) {
        std::size_t nl = all.find('\n', pos);
        std::string_view line =
            all.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos);
        pos = nl == std::string_view::npos ? all.size() : nl + 1;
        ++line_no;
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        if (trim(line).empty()) continue;
        if (!split_line(line, fields)) {
            return Unexpected(FileError{FileErrorCode::Malformed, t.file_, line_no, 0,
                                        "unterminated quoted field"});
        }
        if (!have_header) {
            for (std::size_t c = 0; c < fields.size(); ++c) {
                std::string name(trim(fields[c]));
                if (name.empty()) {
                    return Unexpected(FileError{FileErrorCode::Malformed, t.file_, line_no,
                                                static_cast<int>(c + 1),
                                                "empty column name in the header"});
                }
                for (const auto& h : t.header_) {
                    if (h == name) {
                        return Unexpected(FileError{FileErrorCode::Malformed, t.file_, line_no,
                                                    static_cast<int>(c + 1),
                                                    "duplicate column '" + name + "'"});
                    }
                }
                t.header_.push_back(std::move(name));
            }
            have_header = true;
            continue;
        }
        if (fields.size() != t.header_.size()) {
            if (tolerate_cut_tail && nl == std::string_view::npos) {
                t.cut_tail_warning_ = t.file_ + ":" + std::to_string(line_no) +
                                      ": incomplete last line (" + std::to_string(fields.size()) +
                                      " of " + std::to_string(t.header_.size()) +
                                      " fields, no newline) ignored: the recording was cut short";
                break;
            }
            return Unexpected(
                FileError{FileErrorCode::Malformed, t.file_, line_no,
                          static_cast<int>(std::min(fields.size(), t.header_.size()) + 1),
                          "expected " + std::to_string(t.header_.size()) + " fields, got " +
                              std::to_string(fields.size())});
        }
        t.rows_.push_back(Row{line_no, fields});
        t.last_unterminated_ = nl == std::string_view::npos;
    }
    if (!have_header) {
        return Unexpected(FileError{FileErrorCode::Malformed, t.file_, 0, 0,
                                    "empty file (expected a header row)"});
    }
    return t;
}

std::optional<std::size_t> Table::column(std::string_view name) const {
    for (std::size_t i = 0; i < header_.size(); ++i)
        if (header_[i] == name) return i;
    return std::nullopt;
}

FileError Table::error_at(std::size_t row, std::size_t col, std::string message) const {
    return FileError{FileErrorCode::Malformed, file_, rows_[row].line, static_cast<int>(col + 1),
                     header_[col] + ": " + std::move(message)};
}

Expected<double, FileError> Table::number(std::size_t row, std::size_t col) const {
    std::string_view f = trim(field(row, col));
    if (f.empty()) return kUnknown;
    std::string_view g = f;
    if (g.size() > 1 && g.front() == '+') g.remove_prefix(1);
    double v = 0.0;
    auto [p, ec] = std::from_chars(g.data(), g.data() + g.size(), v);
    if (ec == std::errc::result_out_of_range && p == g.data() + g.size())
        return Unexpected(error_at(row, col, "'" + shown(f) + "' is out of the range of a double"));
    if (ec != std::errc() || p != g.data() + g.size()) {
        return Unexpected(error_at(row, col, "expected a number, got '" + shown(f) + "'"));
    }
    // docs/dataset.md 1.1: nan and inf are malformed (an empty cell is how unknown is written).
    if (!std::isfinite(v))
        return Unexpected(error_at(
            row, col,
            "expected a finite number, got '" + shown(f) + "' (leave the cell empty for unknown)"));
    if (auto b = value_bounds(header_[col]); b && (v < b->lo || v > b->hi)) {
        auto e = error_at(row, col,
                          shown(f) + " is outside [" + format_number(b->lo) + ", " +
                              format_number(b->hi) + "] " + std::string(b->unit));
        e.code = FileErrorCode::OutOfRange;
        return Unexpected(e);
    }
    return v;
}

Expected<std::int64_t, FileError> Table::integer(std::size_t row, std::size_t col) const {
    std::string_view f = trim(field(row, col));
    if (f.empty()) return Unexpected(error_at(row, col, "expected an integer, got an empty field"));
    std::int64_t v = 0;
    auto [p, ec] = std::from_chars(f.data(), f.data() + f.size(), v);
    if (ec != std::errc() || p != f.data() + f.size()) {
        return Unexpected(error_at(row, col, "expected an integer, got '" + shown(f) + "'"));
    }
    return v;
}

Expected<std::optional<std::uint32_t>, FileError> Table::u32(std::size_t row, std::size_t col,
                                                             bool allow_hex,
                                                             bool require_hex) const {
    std::string_view f = trim(field(row, col));
    if (f.empty()) return std::optional<std::uint32_t>{};
    const bool hex = f.size() > 2 && f[0] == '0' && (f[1] == 'x' || f[1] == 'X');
    if (hex && !allow_hex) {
        return Unexpected(error_at(row, col, "expected a decimal integer, got '" + shown(f) + "'"));
    }
    if (!hex && require_hex) {
        return Unexpected(
            error_at(row, col, "expected 0x-prefixed hexadecimal, got '" + shown(f) + "'"));
    }
    std::string_view digits = hex ? f.substr(2) : f;
    std::uint32_t v = 0;
    auto [p, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), v, hex ? 16 : 10);
    if (ec != std::errc() || p != digits.data() + digits.size()) {
        return Unexpected(error_at(row, col,
                                   std::string("expected a 32-bit ") +
                                       (hex ? "hexadecimal" : "unsigned") + " integer, got '" +
                                       shown(f) + "'"));
    }
    return std::optional<std::uint32_t>{v};
}

std::string format_number(double v) {
    if (std::isnan(v)) return {};
    char buf[64];
    auto [p, ec] = std::to_chars(buf, buf + sizeof buf, v);
    if (ec != std::errc()) return {};
    return std::string(buf, p);
}

std::string format_ms(std::int64_t t_ns) {
    const bool neg = t_ns < 0;
    // magnitude in unsigned to survive INT64_MIN
    std::uint64_t m = neg ? 0 - static_cast<std::uint64_t>(t_ns) : static_cast<std::uint64_t>(t_ns);
    char buf[48];
    std::snprintf(buf, sizeof buf, "%s%llu.%06llu", neg ? "-" : "",
                  static_cast<unsigned long long>(m / 1000000),
                  static_cast<unsigned long long>(m % 1000000));
    std::string s(buf);
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
    return s;
}

std::int64_t ms_to_ns_rounded(double ms) {
    const double ns = ms * 1e6;
    constexpr double kLim = 9.0e18;
    if (!(ns > -kLim && ns < kLim))
        return ns < 0 ? -static_cast<std::int64_t>(kLim) : static_cast<std::int64_t>(kLim);
    return std::llround(ns);
}

}  // namespace gs::dataset::csv
