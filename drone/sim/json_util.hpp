#pragma once
// Internal helpers for reading the simulator's JSON assets: typed getters that remember the first
// error with the file and the JSON path, so loaders read straight through and check once.

#include "drone/core/expected.hpp"
#include "drone/sim/asset_error.hpp"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace gs::sim {

// Reads and parses a JSON file (no exceptions escape).
[[nodiscard]] Expected<nlohmann::json, AssetError> read_json_file(const std::string& path);

std::string json_path(const std::string& prefix, const std::string& key);

class JsonReader {
public:
    explicit JsonReader(std::string file) : file_(std::move(file)) {}

    // Required when no default is given.
    double get_number(const nlohmann::json& obj, const std::string& prefix, const std::string& key,
                      std::optional<double> def = std::nullopt);
    int get_int(const nlohmann::json& obj, const std::string& prefix, const std::string& key,
                std::optional<int> def = std::nullopt);
    std::string get_string(const nlohmann::json& obj, const std::string& prefix,
                           const std::string& key, std::optional<std::string> def = std::nullopt);
    bool get_bool(const nlohmann::json& obj, const std::string& prefix, const std::string& key,
                  bool def);
    // An array of min_n..max_n numbers (required).
    std::vector<double> get_numbers(const nlohmann::json& obj, const std::string& prefix,
                                    const std::string& key, std::size_t min_n, std::size_t max_n);
    // Present and an object / array? Reports MissingKey/BadValue when required.
    const nlohmann::json* get_object(const nlohmann::json& obj, const std::string& prefix,
                                     const std::string& key, bool required);
    const nlohmann::json* get_array(const nlohmann::json& obj, const std::string& prefix,
                                    const std::string& key, bool required);

    void fail(AssetErrorKind kind, const std::string& key, const std::string& detail);
    bool failed() const { return error_.has_value(); }
    const AssetError& error() const { return *error_; }
    const std::string& file() const { return file_; }

private:
    const nlohmann::json* find(const nlohmann::json& obj, const std::string& prefix,
                               const std::string& key, bool required);
    std::string file_;
    std::optional<AssetError> error_;
};

}  // namespace gs::sim
