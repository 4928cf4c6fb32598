#pragma once
// Running the ardrone-gs program (GS_BINARY) from the app tests, and scratch directories.

#include <filesystem>
#include <string>

namespace gs::test {

struct CmdResult {
    int exit_code = -1;
    std::string out;  // stdout and stderr
};

// Runs `ardrone-gs ARGS` through the shell, stderr merged into stdout.
CmdResult run_cli(const std::string& args);
// The same, stdout only (stderr goes to the test's own): for output parsed as JSON.
CmdResult run_cli_stdout(const std::string& args);
// A fresh, empty directory /tmp/gs_<suite>_<pid>/<name>; /tmp/gs_<suite>_<pid> is removed when
// the test program exits with every test passed (kept when one failed, or GS_KEEP_TEST_OUTPUT is
// set).
std::filesystem::path scratch_dir(const std::string& suite, const std::string& name);
std::string read_text(const std::filesystem::path& p);

}  // namespace gs::test
