#include "drone/core/assets.hpp"

#include <cstdlib>
#include <system_error>

namespace gs::inline core {

std::string_view to_string(AssetsOrigin o) {
    switch (o) {
        case AssetsOrigin::Environment:
            return "environment";
        case AssetsOrigin::Installed:
            return "installed";
        case AssetsOrigin::SourceTree:
            return "source tree";
    }
    return "?";
}

AssetsLocation locate_assets(const char* env_value, const std::filesystem::path& executable,
                             const std::filesystem::path& source_tree_assets) {
    if (env_value != nullptr && *env_value != '\0')
        return {std::filesystem::path(env_value), AssetsOrigin::Environment};
    if (!executable.empty()) {
        std::error_code ec;
        const auto installed =
            (executable.parent_path() / ".." / "share" / "ardrone-gs").lexically_normal();
        if (std::filesystem::is_directory(installed, ec))
            return {installed, AssetsOrigin::Installed};
    }
    return {source_tree_assets, AssetsOrigin::SourceTree};
}

const AssetsLocation& assets_location() {
    static const AssetsLocation where = [] {
        std::error_code ec;
        auto exe = std::filesystem::read_symlink("/proc/self/exe", ec);
        if (ec) exe.clear();
        return locate_assets(std::getenv(kAssetsEnv), exe, GS_ASSETS_DIR);
    }();
    return where;
}

}  // namespace gs::inline core
