#pragma once
// The one error type of the dataset module: what went wrong, in which file of the dataset, at
// which line and column (1-based; 0 = not applicable), printed as "frames.csv:12:3: message".

#include <string>
#include <utility>

namespace gs::inline core {

enum class FileErrorCode {
    Missing,       // a required file, key or column is absent
    Malformed,     // syntax or type error in a file
    Inconsistent,  // files disagree (row counts, frame indices, ...)
    OutOfRange,    // an absurd value (size, fps, record length ...)
    UnsafePath,    // a path that would leave the dataset directory
    Io,            // the operating system refused (open, read, write)
    Unsupported,   // valid but not handled by this build (format version, codec)
};

std::string to_string(FileErrorCode c);

struct FileError {
    FileErrorCode code = FileErrorCode::Malformed;
    std::string file;  // path relative to the dataset directory ("frames.csv", "frames/000003.png")
    int line = 0;
    int column = 0;
    std::string message;
};

// "file:line:column: message" (line/column left out when 0).
std::string to_string(const FileError& e);

// 1-based line and column of byte offset `pos` in `text` (clamped to its end).
std::pair<int, int> text_line_col(const std::string& text, std::size_t pos);
// Where a key is first written in a JSON text ("key"), for error positions; {0, 0} if nowhere.
std::pair<int, int> locate_json_key(const std::string& text, const std::string& key);

}  // namespace gs::inline core
