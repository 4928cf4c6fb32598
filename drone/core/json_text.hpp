#pragma once
// The one place JSON text read from a file is parsed (flight.json, labels.json, calibration files,
// the thesis folder's imu_meta.json). nlohmann throws more than parse_error (a number that
// overflows a double is out_of_range.406, a wrong type in get<>() is type_error): every one of its
// exceptions is caught here or in json_boundary() and becomes a FileError naming the file, the
// key being read and its position, in words without the library's "[json.exception...]" prefix.

#include "drone/core/expected.hpp"
#include "drone/core/file_error.hpp"

#include <nlohmann/json.hpp>

#include <exception>
#include <string>

namespace gs::inline core {

// Parses `text` (the contents of `file`); the error carries file, line, column and the key path
// ("calibration.fx") that was being read when a value was refused.
[[nodiscard]] Expected<nlohmann::json, FileError> parse_json_text(const std::string& text,
                                                                  const std::string& file);

// nlohmann's message without its "[json.exception.<kind>.<id>] " and "parse error at line L,
// column C: " prefixes (the position is given by the FileError's line and column).
std::string json_message(const std::exception& e);

// Runs `read` (which reads values out of an already parsed document) and turns any nlohmann
// exception it lets through into a Malformed error for `file`: a reader never aborts the program.
template <class F>
auto json_boundary(const std::string& file, F&& read) -> decltype(read()) {
    try {
        return read();
    } catch (const nlohmann::json::exception& e) {
        return Unexpected(
            FileError{FileErrorCode::Malformed, file, 0, 0, "invalid value: " + json_message(e)});
    }
}

}  // namespace gs::inline core
