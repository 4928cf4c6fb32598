#pragma once
// Finding the virtual drone's scenarios: a name from assets/scenes/ ("warehouse") or a path to a
// scene JSON file.

#include "drone/core/expected.hpp"
#include "drone/sim/asset_error.hpp"
#include "drone/sim/scene.hpp"

#include <string>
#include <vector>

namespace gs::sim {

// The folder holding the shipped scenes (assets/scenes).
std::string scenes_dir();

// Names of the shipped scenes, sorted.
std::vector<std::string> list_scenes();

// Loads `name_or_path`: an existing file path, else assets/scenes/<name>.json.
[[nodiscard]] Expected<Scene, AssetError> resolve_scene(const std::string& name_or_path);

}  // namespace gs::sim
