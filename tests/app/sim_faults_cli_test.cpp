// Issue 14 point 14: `ardrone-gs sim` takes the fault knobs from the command line, so a faulty link
// can be reproduced against `record` or the window by anyone; a client that goes away is not an
// error of the drone's (issue 14 point 9).
#include "cli_test_util.hpp"
#include "drone/link/drone_link.hpp"
#include "drone/protocol/ports.hpp"
#include "support/wait.hpp"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <functional>
#include <string>
#include <thread>

namespace gs::test::sim_faults {  // named: the app tests are one unity build
namespace {
namespace fs = std::filesystem;
using namespace std::chrono_literals;

TEST(SimCli, FaultKnobsFromTheCommandLineReachTheLink) {
    const auto dir = scratch_dir("sim_faults", "run");
    // Below Linux's ephemeral range (32768-60999), where the other tests' sockets take theirs.
    const int base = 20000 + ::getpid() % 1200 * 10;
    const std::string log = (dir / "sim.txt").string();
    const std::string base_s = std::to_string(base);
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        ::dup2(fd, STDOUT_FILENO);
        ::dup2(fd, STDERR_FILENO);
        ::execl(GS_BINARY, GS_BINARY, "sim", "--port-base", base_s.c_str(), "--seconds", "16",
                "--loss", "0.3", "--reboot-at", "10", "--boot-ms", "400", "--video-reset-every",
                "2", static_cast<char*>(nullptr));
        ::_exit(127);
    }
    link::LinkConfig lc;
    lc.drone_address = lc.bind_address = "127.0.0.1";
    protocol::DronePorts::from_base(base).apply_to(lc);  // the layout `sim --port-base` serves
    {
        link::DroneLink link(lc);
        ASSERT_TRUE(link.start());
        EXPECT_TRUE(
            wait_until([&] { return link.state() == link::ConnectionState::Connected; }, 10s))
            << link.status().reason;
        EXPECT_TRUE(wait_until([&] { return link.status().machine.drone_restarts >= 1; }, 15s))
            << link.status().reason;
        // The video connection was cut (a reset or the reboot) and came back.
        EXPECT_TRUE(wait_until([&] { return link.status().video.connects >= 2; }, 5s));
        const auto st = link.status();
        EXPECT_GT(st.machine.sequence_gaps, 5u);  // --loss 0.3
        link.stop();  // the client goes away while the drone still streams
    }
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0);
    const std::string out = read_text(log);
    EXPECT_NE(out.find("reboots 1"), std::string::npos) << out;
    EXPECT_EQ(out.find("dropped 0,"), std::string::npos) << out;
    EXPECT_EQ(out.find("Connection reset"), std::string::npos) << out;
    EXPECT_EQ(out.find("Broken pipe"), std::string::npos) << out;
}

TEST(SimCli, FaultOptionsAreValidated) {
    auto r = run_cli("sim --loss 1.5");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.out.find("expected a probability in [0, 1], got '1.5'"), std::string::npos)
        << r.out;
    r = run_cli("sim --blackout 5");
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.out.find("got '5'"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace gs::test::sim_faults
