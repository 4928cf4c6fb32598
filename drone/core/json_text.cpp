#include "drone/core/json_text.hpp"

#include <vector>

namespace gs::inline core {

std::string json_message(const std::exception& e) {
    std::string what = e.what();
    if (what.rfind("[json.exception.", 0) == 0) {
        const auto close = what.find("] ");
        if (close != std::string::npos) what.erase(0, close + 2);
    }
    if (what.rfind("parse error", 0) == 0) {
        const auto colon = what.find(": ");
        if (colon != std::string::npos) what.erase(0, colon + 2);
    }
    return what;
}

Expected<nlohmann::json, FileError> parse_json_text(const std::string& text,
                                                    const std::string& file) {
    using nlohmann::json;
    // The key path being read, kept by the parser callback: an overflowing number is refused
    // before its value is handed over, so the path names the key it belongs to.
    std::vector<std::string> path;
    const json::parser_callback_t track = [&path](int depth, json::parse_event_t event,
                                                  json& parsed) {
        if (event == json::parse_event_t::key && depth >= 1 && parsed.is_string()) {
            path.resize(static_cast<std::size_t>(depth - 1));
            path.push_back(parsed.get<std::string>());
        }
        return true;
    };
    auto key_path = [&path] {
        std::string s;
        for (const auto& k : path) s += (s.empty() ? "" : ".") + k;
        return s;
    };
    try {
        return json::parse(text, track);
    } catch (const json::parse_error& e) {
        auto [line, col] = text_line_col(text, e.byte > 0 ? e.byte - 1 : 0);
        const std::string key = key_path();
        return Unexpected(FileError{
            FileErrorCode::Malformed, file, line, col,
            "invalid JSON" + (key.empty() ? "" : " in '" + key + "'") + ": " + json_message(e)});
    } catch (const json::exception& e) {
        const std::string key = key_path();
        auto [line, col] = path.empty() ? std::pair{0, 0} : locate_json_key(text, path.back());
        const bool overflow = e.id == 406;
        return Unexpected(FileError{
            overflow ? FileErrorCode::OutOfRange : FileErrorCode::Malformed, file, line, col,
            (key.empty() ? std::string() : "'" + key + "': ") +
                (overflow ? std::string() : "invalid JSON: ") + json_message(e)});
    }
}

}  // namespace gs::inline core
