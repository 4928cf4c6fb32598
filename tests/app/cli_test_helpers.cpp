#include "cli_test_util.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <mutex>
#include <set>
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

// The scratch roots this process made: removed when it exits with every test passed (kept, and
// named, when one failed, or when GS_KEEP_TEST_OUTPUT is set), so test runs leave nothing in /tmp.
class ScratchRoots {
public:
    void add(const std::filesystem::path& root) {
        const std::lock_guard lock(mu_);
        roots_.insert(root);
    }
    ~ScratchRoots() {
        const auto* unit = ::testing::UnitTest::GetInstance();
        const bool keep =
            std::getenv("GS_KEEP_TEST_OUTPUT") != nullptr || unit->failed_test_count() > 0;
        for (const auto& r : roots_) {
            if (keep) {
                std::cerr << "scratch kept: " << r.string() << "\n";
                continue;
            }
            std::error_code ec;
            std::filesystem::remove_all(r, ec);
        }
    }

private:
    std::mutex mu_;
    std::set<std::filesystem::path> roots_;
};

ScratchRoots& scratch_roots() {
    static ScratchRoots roots;
    return roots;
}
}  // namespace

CmdResult run_cli(const std::string& args) {
    return run_shell(std::string(GS_BINARY) + " " + args + " 2>&1");
}

CmdResult run_cli_stdout(const std::string& args) {
    return run_shell(std::string(GS_BINARY) + " " + args);
}

std::filesystem::path scratch_dir(const std::string& suite, const std::string& name) {
    const auto root =
        std::filesystem::path("/tmp") / ("gs_" + suite + "_" + std::to_string(::getpid()));
    scratch_roots().add(root);
    const auto d = root / name;
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
