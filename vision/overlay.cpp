#include "vision/overlay.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace gs::vision {

Rgb blue_to_red(double t) {
    if (std::isnan(t)) t = 0;
    t = std::clamp(t, 0.0, 1.0);
    const auto r = static_cast<std::uint8_t>(std::lround(255 * t));
    const auto b = static_cast<std::uint8_t>(std::lround(255 * (1 - t)));
    return {r, 0, b};
}

void draw_overlay(cv::Mat& image, const Overlay& o) {
    constexpr int kShift = 4;  // sub-pixel drawing
    constexpr float kOne = 1 << kShift;
    auto fix = [&](cv::Point2f p) {
        return cv::Point(static_cast<int>(std::lround(p.x * kOne)),
                         static_cast<int>(std::lround(p.y * kOne)));
    };
    for (const OverlayBar& b : o.bars) {
        const cv::Point2f br(b.rect.x + b.rect.width, b.rect.y + b.rect.height);
        cv::rectangle(image, fix(b.rect.tl()), fix(br), to_bgr(b.colour), b.filled ? cv::FILLED : 1,
                      cv::LINE_8, kShift);
    }
    for (const OverlayLine& l : o.lines)
        cv::line(image, fix(l.a), fix(l.b), to_bgr(l.colour),
                 std::max(1, static_cast<int>(std::lround(l.thickness_px))), cv::LINE_AA, kShift);
    for (const OverlayPoint& p : o.points)
        cv::circle(image, fix(p.p), static_cast<int>(std::lround(p.radius_px * kOne)),
                   to_bgr(p.colour), p.filled ? cv::FILLED : 1, cv::LINE_AA, kShift);
}

}  // namespace gs::vision
