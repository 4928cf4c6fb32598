#include "cli_test_util.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace gs::test {

namespace {
CmdResult run_shell(const std::string& cmd) {
    CmdResult r;
    FILE* p = popen(cmd.c_str(), "r");
    if (p == nullptr) return r;
    std::array<char, 4096> buf{};
    std::size_t n = 0;
    while ((n = std::fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
    const int status = pclose(p);
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}
}  // namespace

CmdResult run_cli(const std::string& args) {
    return run_shell(std::string(GS_BINARY) + " " + args + " 2>&1");
}

CmdResult run_cli_stdout(const std::string& args) {
    return run_shell(std::string(GS_BINARY) + " " + args);
}

std::filesystem::path scratch_dir(const std::string& suite, const std::string& name) {
    const auto d =
        std::filesystem::path("/tmp") / ("gs_" + suite + "_" + std::to_string(::getpid())) / name;
    std::filesystem::remove_all(d);
    std::filesystem::create_directories(d);
    return d;
}

std::string read_text(const std::filesystem::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

}  // namespace gs::test
