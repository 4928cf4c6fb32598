#pragma once
// Subcommands register themselves here, one file per subcommand (app/cmd_*.cpp), so main stays thin.

#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <vector>

namespace gs::app {

// Sets up one subcommand on the root app. The subcommand's callback does the work and
// throws CLI::RuntimeError(code) (after printing the reason to stderr) on failure.
using CommandSetup = std::function<void(CLI::App& root)>;

struct CommandRegistration {
    CommandRegistration(int order, CommandSetup setup);
};

// Every registered subcommand, sorted by `order` (the order `--help` lists them in).
std::vector<CommandSetup> registered_commands();

// Prints "ardrone-gs: <message>" on stderr and returns the exit code to throw.
[[nodiscard]] CLI::RuntimeError fail(const std::string& message, int code = 1);

}  // namespace gs::app
