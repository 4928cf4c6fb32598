#pragma once
// Whole-file reads with a size bound and atomic whole-file writes, with errors that name the file
// (FileError). Every reader of a dataset, a calibration or a scene goes through these.

#include "drone/core/expected.hpp"
#include "drone/core/file_error.hpp"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace gs::inline core {

// Reads a whole file, refusing more than `max_bytes`. `name` is what errors call it.
Expected<std::string, FileError> read_text_file(const std::filesystem::path& path,
                                                const std::string& name, std::uintmax_t max_bytes);

// Writes `text` to `path` through a temporary file and a rename (never half a file).
[[nodiscard]] std::optional<FileError> write_file_atomic(const std::filesystem::path& path,
                                                         std::string_view text,
                                                         const std::string& name);

}  // namespace gs::inline core
