// ardrone-gs: ground station for the Parrot AR.Drone 2.0.
#include "app/command.hpp"
#ifdef GS_HAVE_GUI
#include "app/gui_entry.hpp"
#endif

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
    app.set_version_flag("--version", "ardrone-gs 0.1.0");
    gs::app::add_registered_commands(app);
    app.require_subcommand(0, 1);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
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
