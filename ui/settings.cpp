#include "ui/settings.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <system_error>

namespace gs::ui {

using nlohmann::json;

void Settings::add_recent(const std::string& path) {
    if (path.empty()) return;
    recent_datasets.erase(std::remove(recent_datasets.begin(), recent_datasets.end(), path),
                          recent_datasets.end());
    recent_datasets.insert(recent_datasets.begin(), path);
    if (recent_datasets.size() > kMaxRecent) recent_datasets.resize(kMaxRecent);
}

const char* to_string(LayoutMode m) {
    return m == LayoutMode::Flight ? "flight" : "engineering";
}

const char* to_string(SettingsError e) {
    switch (e) {
        case SettingsError::NotFound:
            return "settings file not found";
        case SettingsError::Unreadable:
            return "settings file unreadable";
        case SettingsError::Malformed:
            return "settings file malformed";
        case SettingsError::Unwritable:
            return "settings file could not be written";
    }
    return "?";
}

std::filesystem::path config_dir() {
    if (const char* x = std::getenv("XDG_CONFIG_HOME"); x && *x)
        return std::filesystem::path(x) / "ardrone-gs";
    if (const char* h = std::getenv("HOME"); h && *h)
        return std::filesystem::path(h) / ".config" / "ardrone-gs";
    return std::filesystem::path(".ardrone-gs");
}

std::string settings_to_json(const Settings& s) {
    json j;
    json keys = json::object();
    for (std::size_t i = 0; i < kPilotKeyCount; ++i) {
        const auto k = static_cast<PilotKey>(i);
        const int code = s.keymap.key(k);
        const std::string name = key_name(code);
        keys[to_string(k)] = code == kNoKey ? json(nullptr)
                             : name.empty() ? json(code)
                                            : json(name);
    }
    j["keymap"] = {{"keys", keys},
                   {"keyboard_gain", s.keymap.keyboard_gain},
                   {"yaw_gain", s.keymap.yaw_gain},
                   {"gaz_gain", s.keymap.gaz_gain},
                   {"dead_zone", s.keymap.dead_zone}};
    j["recent_datasets"] = s.recent_datasets;
    j["drone_address"] = s.drone_address;
    j["use_sim"] = s.use_sim;
    j["sim_scenario"] = s.sim_scenario;
    j["overlay"] = {{"regions", s.overlay.regions},
                    {"trajectories", s.overlay.trajectories},
                    {"center_points", s.overlay.center_points},
                    {"boundaries", s.overlay.boundaries},
                    {"hud", s.overlay.hud},
                    {"undistort", s.overlay.undistort}};
    j["plot_span_s"] = s.plot_span_s;
    j["classifier"] = s.classifier;
    json presets = json::object();
    for (const auto& [name, p] : s.classifier_presets)
        presets[name] = {{"classifier", p.classifier}, {"params", p.params}};
    j["classifier_presets"] = presets;
    j["classifier_params"] = s.classifier_params;
    j["layout"] = to_string(s.layout);
    return j.dump(2);
}

Expected<Settings, SettingsError> settings_from_json(std::string_view text) {
    Settings s;
    try {
        const json j = json::parse(text);
        if (!j.is_object()) return Unexpected{SettingsError::Malformed};
        if (auto km = j.find("keymap"); km != j.end()) {
            if (auto keys = km->find("keys"); keys != km->end()) {
                for (std::size_t i = 0; i < kPilotKeyCount; ++i) {
                    const auto k = static_cast<PilotKey>(i);
                    auto it = keys->find(to_string(k));
                    if (it == keys->end()) continue;
                    if (it->is_null()) {  // deliberately unbound
                        s.keymap.key(k) = kNoKey;
                        continue;
                    }
                    const int code =
                        it->is_string() ? key_from_name(it->get<std::string>()) : it->get<int>();
                    if (code < 0 || code >= 512) return Unexpected{SettingsError::Malformed};
                    s.keymap.key(k) = code;
                }
            }
            for (auto& n : sanitize_keymap(s.keymap)) s.notices.push_back("keymap: " + n);
            s.keymap.keyboard_gain = km->value("keyboard_gain", s.keymap.keyboard_gain);
            s.keymap.yaw_gain = km->value("yaw_gain", s.keymap.yaw_gain);
            s.keymap.gaz_gain = km->value("gaz_gain", s.keymap.gaz_gain);
            s.keymap.dead_zone = km->value("dead_zone", s.keymap.dead_zone);
        }
        s.recent_datasets = j.value("recent_datasets", s.recent_datasets);
        if (s.recent_datasets.size() > Settings::kMaxRecent)
            s.recent_datasets.resize(Settings::kMaxRecent);
        s.drone_address = j.value("drone_address", s.drone_address);
        s.use_sim = j.value("use_sim", s.use_sim);
        s.sim_scenario = j.value("sim_scenario", s.sim_scenario);
        if (auto ov = j.find("overlay"); ov != j.end()) {
            s.overlay.regions = ov->value("regions", true);
            s.overlay.trajectories = ov->value("trajectories", true);
            s.overlay.center_points = ov->value("center_points", true);
            s.overlay.boundaries = ov->value("boundaries", true);
            s.overlay.hud = ov->value("hud", true);
            s.overlay.undistort = ov->value("undistort", false);
        }
        s.plot_span_s = j.value("plot_span_s", s.plot_span_s);
        s.classifier = j.value("classifier", s.classifier);
        if (auto ps = j.find("classifier_presets"); ps != j.end()) {
            for (const auto& [name, p] : ps->items()) {
                ClassifierPreset cp;
                cp.classifier = p.value("classifier", std::string{});
                cp.params = p.value("params", std::map<std::string, double>{});
                s.classifier_presets[name] = cp;
            }
        }
        s.classifier_params = j.value("classifier_params", s.classifier_params);
        const std::string layout = j.value("layout", std::string(to_string(s.layout)));
        if (layout != "flight" && layout != "engineering")
            return Unexpected{SettingsError::Malformed};
        s.layout = layout == "flight" ? LayoutMode::Flight : LayoutMode::Engineering;
    } catch (const json::exception&) {
        return Unexpected{SettingsError::Malformed};
    }
    return s;
}

Expected<Settings, SettingsError> load_settings(const std::filesystem::path& file) {
    std::error_code ec;
    if (!std::filesystem::exists(file, ec)) return Unexpected{SettingsError::NotFound};
    std::ifstream in(file, std::ios::binary);
    if (!in) return Unexpected{SettingsError::Unreadable};
    std::ostringstream ss;
    ss << in.rdbuf();
    return settings_from_json(ss.str());
}

std::optional<SettingsError> save_settings(const Settings& s, const std::filesystem::path& file) {
    std::error_code ec;
    if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path(), ec);
    const std::filesystem::path tmp = file.string() + ".tmp";
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        if (!out) return SettingsError::Unwritable;
        out << settings_to_json(s) << '\n';
        if (!out) return SettingsError::Unwritable;
    }
    std::filesystem::rename(tmp, file, ec);
    if (ec) return SettingsError::Unwritable;
    return std::nullopt;
}

}  // namespace gs::ui
