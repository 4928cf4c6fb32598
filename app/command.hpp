#pragma once
// Subcommands register themselves here, one file per subcommand (app/cmd_*.cpp), so main stays
// thin.

#include <CLI/CLI.hpp>

#include <functional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace gs::app {

// Sets up one subcommand on the root app. The subcommand's callback does the work and
// throws CLI::RuntimeError(code) (after printing the reason to stderr) on failure.
using CommandSetup = std::function<void(CLI::App& root)>;

// A top-level subcommand: `setup` receives the root app and adds its subcommand to it.
// A nested one (parent non-empty, e.g. "inspect"): `setup` receives the parent subcommand, which
// main creates once with `parent_description`.
struct CommandRegistration {
    CommandRegistration(int order, CommandSetup setup);
    CommandRegistration(int order, std::string parent, std::string parent_description,
                        CommandSetup setup);
};

// Adds every registered subcommand to `root`, sorted by `order` (the order `--help` lists them in).
void add_registered_commands(CLI::App& root);

// Makes `run` the subcommand's action. `run` returns the exit code (0: success; any other code
// leaves main with it) or nothing; either way it reports a failure by throwing fail(...).
template <class Run>
void set_action(CLI::App& sub, Run run) {
    sub.callback([run = std::move(run)] {
        if constexpr (std::is_void_v<std::invoke_result_t<const Run&>>) {
            run();
        } else if (const int rc = run(); rc != 0) {
            throw CLI::RuntimeError(rc);
        }
    });
}

// Prints "ardrone-gs: <message>" on stderr and returns the exit code to throw.
[[nodiscard]] CLI::RuntimeError fail(const std::string& message, int code = 1);

}  // namespace gs::app
