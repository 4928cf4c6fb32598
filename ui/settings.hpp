#pragma once
// What the window remembers between runs, as JSON in the user's config directory
// ($XDG_CONFIG_HOME/ardrone-gs or ~/.config/ardrone-gs): keymap, recent datasets, connection
// choice, overlay toggles, classifier settings and presets. (Window positions and sizes go to
// imgui.ini in the same directory, written by ImGui itself.)

#include "drone/core/expected.hpp"
#include "ui/pilot_input.hpp"

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace gs::ui {

struct ClassifierPreset {
    std::string classifier;
    std::map<std::string, double> params;
    friend bool operator==(const ClassifierPreset&, const ClassifierPreset&) = default;
};

struct OverlayToggles {
    bool regions = true, trajectories = true, center_points = true, boundaries = true, hud = true;
    bool undistort = false;  // video window: show the undistorted image (preview)
    friend bool operator==(const OverlayToggles&, const OverlayToggles&) = default;
};

struct Settings {
    Keymap keymap = Keymap::defaults();
    std::vector<std::string> recent_datasets;  // newest first, at most kMaxRecent
    std::string drone_address = "192.168.1.1";
    bool use_sim = false;
    std::string sim_scenario;
    OverlayToggles overlay;
    double plot_span_s = 30.0;
    std::string classifier;                                      // last selected classifier
    std::map<std::string, ClassifierPreset> classifier_presets;  // by preset name
    std::map<std::string, std::map<std::string, double>> classifier_params;  // last values

    static constexpr std::size_t kMaxRecent = 10;
    // Moves `path` to the front of recent_datasets (no duplicates, bounded).
    void add_recent(const std::string& path);
};

enum class SettingsError { NotFound, Unreadable, Malformed, Unwritable };
const char* to_string(SettingsError e);

// $XDG_CONFIG_HOME/ardrone-gs, else $HOME/.config/ardrone-gs, else ./.ardrone-gs.
std::filesystem::path config_dir();

std::string settings_to_json(const Settings& s);
// Unknown keys are ignored and missing keys keep their defaults (older/newer files still load);
// a key of the wrong type is Malformed.
[[nodiscard]] Expected<Settings, SettingsError> settings_from_json(std::string_view text);
[[nodiscard]] Expected<Settings, SettingsError> load_settings(const std::filesystem::path& file);
// nullopt on success. Writes to a temporary file and renames, so a crash never leaves half a file.
[[nodiscard]] std::optional<SettingsError> save_settings(const Settings& s,
                                                         const std::filesystem::path& file);

}  // namespace gs::ui
