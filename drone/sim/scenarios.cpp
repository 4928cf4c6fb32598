#include "drone/sim/scenarios.hpp"

#include "drone/core/assets.hpp"

#include <algorithm>
#include <filesystem>

namespace gs::sim {

std::string scenes_dir() {
    return (assets_dir() / "scenes").string();
}

std::vector<std::string> list_scenes() {
    std::vector<std::string> names;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(scenes_dir(), ec)) {
        if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
    }
    std::sort(names.begin(), names.end());
    return names;
}

Expected<Scene, AssetError> resolve_scene(const std::string& name_or_path) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(name_or_path, ec)) return load_scene(name_or_path);
    const std::string path = scenes_dir() + "/" + name_or_path + ".json";
    if (std::filesystem::is_regular_file(path, ec)) return load_scene(path);
    std::string known;
    for (const auto& n : list_scenes()) known += (known.empty() ? "" : ", ") + n;
    return Unexpected{
        AssetError{AssetErrorKind::FileNotFound,
                   name_or_path,
                   {},
                   "no such scene file or shipped scenario (shipped: " + known + ")"}};
}

}  // namespace gs::sim
