#include "drone/core/file_error.hpp"

#include <algorithm>

namespace gs::inline core {

std::string to_string(FileErrorCode c) {
    switch (c) {
        case FileErrorCode::Missing:
            return "missing";
        case FileErrorCode::Malformed:
            return "malformed";
        case FileErrorCode::Inconsistent:
            return "inconsistent";
        case FileErrorCode::OutOfRange:
            return "out of range";
        case FileErrorCode::UnsafePath:
            return "unsafe path";
        case FileErrorCode::Io:
            return "i/o error";
        case FileErrorCode::Unsupported:
            return "unsupported";
    }
    return "unknown";
}

std::string to_string(const FileError& e) {
    std::string s = e.file.empty() ? std::string("<dataset>") : e.file;
    if (e.line > 0) {
        s += ':' + std::to_string(e.line);
        if (e.column > 0) s += ':' + std::to_string(e.column);
    }
    s += ": ";
    s += e.message;
    return s;
}

std::pair<int, int> text_line_col(const std::string& text, std::size_t pos) {
    pos = std::min(pos, text.size());
    int line = 1, col = 1;
    for (std::size_t i = 0; i < pos; ++i) {
        if (text[i] == '\n') {
            ++line;
            col = 1;
        } else {
            ++col;
        }
    }
    return {line, col};
}

std::pair<int, int> locate_json_key(const std::string& text, const std::string& key) {
    const std::size_t p = key.empty() ? std::string::npos : text.find('"' + key + '"');
    if (p == std::string::npos) return {0, 0};
    return text_line_col(text, p);
}

}  // namespace gs::inline core
