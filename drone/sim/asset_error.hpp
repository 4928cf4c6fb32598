#pragma once
// Errors from loading the simulator's JSON assets (scenes, calibrations): they name the file and
// the key so a hand-edited scene can be fixed without reading the loader.

#include <string>

namespace gs::sim {

enum class AssetErrorKind { FileNotFound, ParseError, MissingKey, BadValue };

struct AssetError {
    AssetErrorKind kind = AssetErrorKind::BadValue;
    std::string file;    // path as given
    std::string key;     // JSON path, e.g. "obstacles[2].size_m"; empty for file-level errors
    std::string detail;  // what was wrong
};

std::string to_string(AssetErrorKind k);
// "<file>: <key>: <detail>" (key omitted when empty).
std::string to_string(const AssetError& e);

}  // namespace gs::sim
