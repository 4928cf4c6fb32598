// ardrone-gs: ground station for the Parrot AR.Drone 2.0.
#include "app/command.hpp"
#include "drone/core/assets.hpp"
#include "drone/core/version.hpp"
#ifdef GS_HAVE_GUI
#include "app/gui_entry.hpp"
#endif

#include <filesystem>
#include <iostream>
#include <map>
#include <string>

namespace gs::app {
namespace {
struct Entry {
    std::string parent, parent_description;
    CommandSetup setup;
};
std::multimap<int, Entry>& registry() {
    static std::multimap<int, Entry> r;
    return r;
}
}  // namespace

CommandRegistration::CommandRegistration(int order, CommandSetup setup) {
    registry().emplace(order, Entry{{}, {}, std::move(setup)});
}

CommandRegistration::CommandRegistration(int order, std::string parent,
                                         std::string parent_description, CommandSetup setup) {
    registry().emplace(order,
                       Entry{std::move(parent), std::move(parent_description), std::move(setup)});
}

void add_registered_commands(CLI::App& root) {
    std::map<std::string, CLI::App*> parents;
    for (auto& [order, e] : registry()) {
        if (e.parent.empty()) {
            e.setup(root);
            continue;
        }
        CLI::App*& parent = parents[e.parent];
        if (parent == nullptr) {
            parent = root.add_subcommand(e.parent, e.parent_description);
            parent->require_subcommand(1);
        }
        e.setup(*parent);
    }
}

CLI::RuntimeError fail(const std::string& message, int code) {
    std::cerr << "ardrone-gs: " << message << '\n';
    return CLI::RuntimeError(code);
}

}  // namespace gs::app

int main(int argc, char** argv) {
    CLI::App app{"ardrone-gs: ground station for the Parrot AR.Drone 2.0"};
    app.set_version_flag("--version", [] {
        const auto& where = gs::assets_location();
        return std::string("ardrone-gs ") + gs::kVersion + "\nassets: " + where.dir.string() +
               " (" + std::string(gs::to_string(where.origin)) + ")";
    });
    app.footer(std::string("Assets (camera calibrations, scenes) are read from $") +
               gs::kAssetsEnv +
               " when set, else from ../share/ardrone-gs beside the installed program; "
               "--version shows which folder is used.");
    gs::app::add_registered_commands(app);
    app.require_subcommand(0, 1);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    if (const auto& where = gs::assets_location(); where.origin == gs::AssetsOrigin::Environment) {
        std::error_code ec;
        if (!std::filesystem::is_directory(where.dir, ec)) {
            std::cerr << "ardrone-gs: " << gs::kAssetsEnv << "=" << where.dir.string()
                      << " is not a folder (unset it to use the installed assets)\n";
            return 2;
        }
    }
    if (app.get_subcommands().empty()) {
#ifdef GS_HAVE_GUI
        return gs::app::run_gui();
#else
        std::cout << app.help();
        return 0;
#endif
    }
    return 0;
}
