#include "drone/dataset/error.hpp"

namespace gs {

std::string to_string(DatasetErrorCode c) {
    switch (c) {
        case DatasetErrorCode::Missing:
            return "missing";
        case DatasetErrorCode::Malformed:
            return "malformed";
        case DatasetErrorCode::Inconsistent:
            return "inconsistent";
        case DatasetErrorCode::OutOfRange:
            return "out of range";
        case DatasetErrorCode::UnsafePath:
            return "unsafe path";
        case DatasetErrorCode::Io:
            return "i/o error";
        case DatasetErrorCode::Unsupported:
            return "unsupported";
    }
    return "unknown";
}

std::string to_string(const DatasetError& e) {
    std::string s = e.file.empty() ? std::string("<dataset>") : e.file;
    if (e.line > 0) {
        s += ':' + std::to_string(e.line);
        if (e.column > 0) s += ':' + std::to_string(e.column);
    }
    s += ": ";
    s += e.message;
    return s;
}

}  // namespace gs
