#include "offscreen_shot.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace gs::ui::test {

std::string under_xvfb(const std::string& cmd) {
    return "ASAN_OPTIONS=detect_leaks=0 xvfb-run -a -s '-screen 0 1920x1080x24' " + cmd;
}

Proc run_logged(const std::string& cmd, const std::filesystem::path& log) {
    const int st = std::system((cmd + " >" + log.string() + " 2>&1").c_str());
    Proc r;
    r.code = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    std::ifstream in(log);
    std::stringstream ss;
    ss << in.rdbuf();
    r.output = ss.str();
    return r;
}

Shot read_shot(const std::filesystem::path& out, int n) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06d", n);
    Shot s;
    s.png = cv::imread((out / (std::string(name) + ".png")).string(), cv::IMREAD_COLOR);
    std::ifstream js(out / (std::string(name) + ".json"));
    if (js) s.layout = nlohmann::json::parse(js, nullptr, false);
    return s;
}

void expect_left_bar_red_others_green(const Shot& shot, double min_width_px) {
    ASSERT_FALSE(shot.png.empty());
    ASSERT_TRUE(shot.layout.is_object());
    const auto& bars = shot.layout.at("region_bars");
    ASSERT_EQ(bars.size(), 3u);
    for (const auto& b : bars) {
        const auto rc = b.at("rect");
        const double x0 = rc[0], y0 = rc[1], x1 = rc[2], y1 = rc[3];
        ASSERT_GT(x1 - x0, min_width_px);
        // Near the left end of the bar (its label is centred) at mid height, a few samples (BGR).
        int red = 0, green = 0;
        for (double x = x0 + 3; x < x0 + 13; x += 2) {
            const cv::Vec3b p =
                shot.png.at<cv::Vec3b>(static_cast<int>(0.5 * (y0 + y1)), static_cast<int>(x));
            if (p[2] > 170 && p[1] < 90 && p[0] < 90) ++red;
            if (p[1] > 150 && p[2] < 110 && p[0] < 130) ++green;
        }
        if (b.at("name") == "left") {
            EXPECT_TRUE(b.at("flagged").get<bool>());
            EXPECT_EQ(red, 5) << "left bar not red";
        } else {
            EXPECT_FALSE(b.at("flagged").get<bool>()) << b.at("name");
            EXPECT_EQ(green, 5) << b.at("name") << " bar not green";
        }
    }
}

}  // namespace gs::ui::test
