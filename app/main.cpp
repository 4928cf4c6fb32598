// ardrone-gs: ground station for the Parrot AR.Drone 2.0.
#include "app/command.hpp"

#include <algorithm>
#include <iostream>
#include <map>

namespace gs::app {
namespace {
std::multimap<int, CommandSetup>& registry() {
    static std::multimap<int, CommandSetup> r;
    return r;
}
}  // namespace

CommandRegistration::CommandRegistration(int order, CommandSetup setup) {
    registry().emplace(order, std::move(setup));
}

std::vector<CommandSetup> registered_commands() {
    std::vector<CommandSetup> out;
    for (auto& [order, setup] : registry()) out.push_back(setup);
    return out;
}

CLI::RuntimeError fail(const std::string& message, int code) {
    std::cerr << "ardrone-gs: " << message << '\n';
    return CLI::RuntimeError(code);
}

}  // namespace gs::app

int main(int argc, char** argv) {
    CLI::App app{"ardrone-gs: ground station for the Parrot AR.Drone 2.0"};
    app.set_version_flag("--version", "ardrone-gs 0.1.0");
    for (auto& setup : gs::app::registered_commands()) setup(app);
    app.require_subcommand(0, 1);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    if (app.get_subcommands().empty()) {
        std::cout << app.help();
        return 0;
    }
    return 0;
}
