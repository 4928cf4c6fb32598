#pragma once
// What the tests that run the real program offscreen share: running a command with its output in a
// log, reading the screenshot a run wrote with the layout JSON beside it, and checking the region
// bars' colours at the rectangles that JSON reports.

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include <filesystem>
#include <string>

namespace gs::ui::test {

// `cmd` run under a private Xvfb display (Mesa's software GL). Under the sanitizer build the
// child's leak check is off: Mesa's software driver is dlopen'ed and unloaded before exit and leaks
// 240 bytes LSan cannot attribute or suppress ("<unknown module>"). Our own code's leaks are
// checked in-process by the headless tests.
std::string under_xvfb(const std::string& cmd);

// The exit code of `cmd` run by the shell (stdout and stderr into `log`) and what it wrote there.
struct Proc {
    int code = -1;
    std::string output;
};
Proc run_logged(const std::string& cmd, const std::filesystem::path& log);

// The screenshot `frame_<n>.png` in `out` and its layout `frame_<n>.json` (empty when missing).
struct Shot {
    cv::Mat png;
    nlohmann::json layout;
};
Shot read_shot(const std::filesystem::path& out, int n);

// The three region bars of `shot` (each wider than `min_width_px`): the left one flagged and red,
// the centre and right ones clear and green, sampled near their left ends at mid height.
void expect_left_bar_red_others_green(const Shot& shot, double min_width_px);

}  // namespace gs::ui::test
