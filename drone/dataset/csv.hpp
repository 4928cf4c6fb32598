#pragma once
// Minimal CSV reading and number formatting for the dataset files: header-addressed columns (any
// order, unknown ones ignored), 1-based line/column positions for errors, exact round trips for
// doubles (shortest representation), empty field = unknown (NaN).

#include "drone/core/expected.hpp"
#include "drone/core/file_error.hpp"

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace gs::dataset::csv {

// A parsed CSV text: a header and rows of fields (views into the owned text).

class Table {
public:
    // `file` names the file in errors. Accepts LF or CRLF, a trailing newline or not, blank lines
    // (skipped) and double-quoted fields. A row with a different field count than the header is
    // an error naming its line.
    //
    // With `tolerate_cut_tail` (files a recording cut short may end mid-line: docs/dataset.md 1.1's
    // navdata.csv), a last line that has no newline and the wrong number of fields is left out
    // and described by cut_tail_warning() instead of refusing the file.
    static Expected<Table, FileError> parse(std::string text, std::string file,
                                            bool tolerate_cut_tail = false);
    // "navdata.csv:220: incomplete last line (3 of 12 fields, no newline) ignored", or empty.
    const std::string& cut_tail_warning() const { return cut_tail_warning_; }
    // True when the last row's line has no newline (the file may have been cut inside it).
    bool last_row_unterminated() const { return last_unterminated_; }

    // Index of a header column, or nullopt when absent.
    std::optional<std::size_t> column(std::string_view name) const;
    const std::vector<std::string>& header() const { return header_; }
    std::size_t rows() const { return rows_.size(); }
    std::string_view field(std::size_t row, std::size_t col) const {
        return rows_[row].fields[col];
    }
    int line_of(std::size_t row) const { return rows_[row].line; }
    const std::string& file() const { return file_; }

    // Field as a double: empty = NaN (unknown); otherwise the whole field must be a finite
    // decimal number within the column's physical bounds (docs/dataset.md 1.1, value_rules.hpp):
    // "nan", "inf" and numbers overflowing a double are refused. Errors carry file:line:column.
    Expected<double, FileError> number(std::size_t row, std::size_t col) const;
    // Field as a signed integer (required, no fraction).
    Expected<std::int64_t, FileError> integer(std::size_t row, std::size_t col) const;
    // Field as an unsigned 32-bit value: decimal, or hex with a 0x prefix when `allow_hex`;
    // `require_hex` rejects decimal. Empty = nullopt.
    Expected<std::optional<std::uint32_t>, FileError> u32(std::size_t row, std::size_t col,
                                                          bool allow_hex, bool require_hex) const;

    FileError error_at(std::size_t row, std::size_t col, std::string message) const;

private:
    struct Row {
        int line = 0;
        std::vector<std::string_view> fields;
    };
    // The fields are views into this text: held by pointer so that they stay valid when the table
    // is moved or copied (a moved std::string short enough for its inline buffer changes address).
    std::shared_ptr<const std::string> text_;
    std::string file_;
    std::vector<std::string> header_;
    std::vector<Row> rows_;
    std::string cut_tail_warning_;
    bool last_unterminated_ = false;
};

// Shortest text that reads back to exactly `v`; empty for NaN.
std::string format_number(double v);
// Milliseconds from nanoseconds, exact (integer part, '.', six digits).
std::string format_ms(std::int64_t t_ns);
// Parses milliseconds text back to nanoseconds (rounded to the nearest ns).
std::int64_t ms_to_ns_rounded(double ms);

}  // namespace gs::dataset::csv
