#pragma once
// Where the program's read-only data lives (camera calibrations, virtual-drone scenes).
//
// Looked up once, in this order:
//   1. $ARDRONE_GS_ASSETS, when set and not empty (an override: used as given);
//   2. <folder of the executable>/../share/ardrone-gs, when it exists (an installed program:
//      `cmake --install` and the Debian package put the assets there);
//   3. the source tree's assets/ folder compiled in (a program run from its build tree).
#include <filesystem>
#include <string_view>

namespace gs::inline core {

inline constexpr const char* kAssetsEnv = "ARDRONE_GS_ASSETS";

enum class AssetsOrigin { Environment, Installed, SourceTree };
std::string_view to_string(AssetsOrigin o);

struct AssetsLocation {
    std::filesystem::path dir;
    AssetsOrigin origin = AssetsOrigin::SourceTree;
};

// The rule above as a pure function (the executable's path and the variable's value given).
AssetsLocation locate_assets(const char* env_value, const std::filesystem::path& executable,
                             const std::filesystem::path& source_tree_assets);

// The rule applied to this process (computed on first use, then fixed for the process).
const AssetsLocation& assets_location();
inline const std::filesystem::path& assets_dir() {
    return assets_location().dir;
}

}  // namespace gs::inline core
