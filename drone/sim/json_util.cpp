#include "drone/sim/json_util.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

namespace gs::sim {

std::string to_string(AssetErrorKind k) {
    switch (k) {
        case AssetErrorKind::FileNotFound:
            return "file not found";
        case AssetErrorKind::ParseError:
            return "JSON parse error";
        case AssetErrorKind::MissingKey:
            return "missing key";
        case AssetErrorKind::BadValue:
            return "bad value";
    }
    return "unknown";
}

std::string to_string(const AssetError& e) {
    std::string s = e.file + ": ";
    if (!e.key.empty()) s += e.key + ": ";
    return s + e.detail;
}

Expected<nlohmann::json, AssetError> read_json_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return Unexpected{AssetError{AssetErrorKind::FileNotFound, path, "", "cannot open"}};
    std::stringstream ss;
    ss << in.rdbuf();
    nlohmann::json j = nlohmann::json::parse(ss.str(), nullptr, /*allow_exceptions=*/false,
                                             /*ignore_comments=*/true);
    if (j.is_discarded())
        return Unexpected{AssetError{AssetErrorKind::ParseError, path, "", "not valid JSON"}};
    if (!j.is_object())
        return Unexpected{
            AssetError{AssetErrorKind::ParseError, path, "", "top level is not an object"}};
    return j;
}

std::string json_path(const std::string& prefix, const std::string& key) {
    if (prefix.empty()) return key;
    if (key.empty()) return prefix;
    return prefix + "." + key;
}

void JsonReader::fail(AssetErrorKind kind, const std::string& key, const std::string& detail) {
    if (!error_) error_ = AssetError{kind, file_, key, detail};
}

const nlohmann::json* JsonReader::find(const nlohmann::json& obj, const std::string& prefix,
                                       const std::string& key, bool required) {
    if (failed()) return nullptr;
    if (!obj.is_object()) {
        fail(AssetErrorKind::BadValue, prefix, "expected an object");
        return nullptr;
    }
    auto it = obj.find(key);
    if (it == obj.end()) {
        if (required) fail(AssetErrorKind::MissingKey, json_path(prefix, key), "required");
        return nullptr;
    }
    return &*it;
}

double JsonReader::get_number(const nlohmann::json& obj, const std::string& prefix,
                              const std::string& key, std::optional<double> def) {
    const auto* v = find(obj, prefix, key, !def.has_value());
    if (!v) return def.value_or(0.0);
    if (!v->is_number()) {
        fail(AssetErrorKind::BadValue, json_path(prefix, key), "expected a number");
        return def.value_or(0.0);
    }
    const double d = v->get<double>();
    if (!std::isfinite(d)) fail(AssetErrorKind::BadValue, json_path(prefix, key), "not finite");
    return d;
}

int JsonReader::get_int(const nlohmann::json& obj, const std::string& prefix,
                        const std::string& key, std::optional<int> def) {
    const auto* v = find(obj, prefix, key, !def.has_value());
    if (!v) return def.value_or(0);
    if (!v->is_number_integer()) {
        fail(AssetErrorKind::BadValue, json_path(prefix, key), "expected an integer");
        return def.value_or(0);
    }
    const auto i = v->get<std::int64_t>();
    if (i < -1000000000 || i > 1000000000) {
        fail(AssetErrorKind::BadValue, json_path(prefix, key), "integer out of range");
        return def.value_or(0);
    }
    return static_cast<int>(i);
}

std::string JsonReader::get_string(const nlohmann::json& obj, const std::string& prefix,
                                   const std::string& key, std::optional<std::string> def) {
    const auto* v = find(obj, prefix, key, !def.has_value());
    if (!v) return def.value_or("");
    if (!v->is_string()) {
        fail(AssetErrorKind::BadValue, json_path(prefix, key), "expected a string");
        return def.value_or("");
    }
    return v->get<std::string>();
}

bool JsonReader::get_bool(const nlohmann::json& obj, const std::string& prefix,
                          const std::string& key, bool def) {
    const auto* v = find(obj, prefix, key, false);
    if (!v) return def;
    if (!v->is_boolean()) {
        fail(AssetErrorKind::BadValue, json_path(prefix, key), "expected true or false");
        return def;
    }
    return v->get<bool>();
}

std::vector<double> JsonReader::get_numbers(const nlohmann::json& obj, const std::string& prefix,
                                            const std::string& key, std::size_t min_n,
                                            std::size_t max_n) {
    std::vector<double> out;
    const auto* v = find(obj, prefix, key, true);
    if (!v) return out;
    const std::string where = json_path(prefix, key);
    const std::string want = min_n == max_n ? "an array of " + std::to_string(min_n) + " numbers"
                                            : "an array of " + std::to_string(min_n) + " to " +
                                                  std::to_string(max_n) + " numbers";
    if (!v->is_array() || v->size() < min_n || v->size() > max_n) {
        fail(AssetErrorKind::BadValue, where, "expected " + want);
        return out;
    }
    for (const auto& e : *v) {
        if (!e.is_number() || !std::isfinite(e.get<double>())) {
            fail(AssetErrorKind::BadValue, where, "expected " + want);
            return {};
        }
        out.push_back(e.get<double>());
    }
    return out;
}

const nlohmann::json* JsonReader::get_object(const nlohmann::json& obj, const std::string& prefix,
                                             const std::string& key, bool required) {
    const auto* v = find(obj, prefix, key, required);
    if (v && !v->is_object()) {
        fail(AssetErrorKind::BadValue, json_path(prefix, key), "expected an object");
        return nullptr;
    }
    return v;
}

const nlohmann::json* JsonReader::get_array(const nlohmann::json& obj, const std::string& prefix,
                                            const std::string& key, bool required) {
    const auto* v = find(obj, prefix, key, required);
    if (v && !v->is_array()) {
        fail(AssetErrorKind::BadValue, json_path(prefix, key), "expected an array");
        return nullptr;
    }
    return v;
}

}  // namespace gs::sim
