#pragma once
// Overlay primitives a classifier emits per frame, in raw (as decoded, distorted) image pixels so
// the GUI can draw them over the video as is. Plain structs; draw_overlay renders them with
// OpenCV for video export.

#include <opencv2/core.hpp>

#include <cstdint>
#include <vector>

namespace gs::vision {

struct Rgb {
    std::uint8_t r = 0, g = 0, b = 0;
    bool operator==(const Rgb&) const = default;
};
inline constexpr Rgb kGreen{0, 200, 0};
inline constexpr Rgb kRed{230, 0, 0};
inline constexpr Rgb kYellow{240, 220, 0};
inline constexpr Rgb kWhite{255, 255, 255};
inline constexpr Rgb kGrey{150, 150, 150};
inline constexpr Rgb kSteel{70, 130, 190};  // a still camera's region: neither clear nor unsafe

// OpenCV's channel order.
inline cv::Scalar to_bgr(Rgb c) {
    return {static_cast<double>(c.b), static_cast<double>(c.g), static_cast<double>(c.r)};
}

// Blue at t <= 0 through red at t >= 1 (thesis fig. 3.27).
Rgb blue_to_red(double t);

struct OverlayBar {
    cv::Rect2f rect;
    Rgb colour;
    bool filled = true;
};
struct OverlayPoint {
    cv::Point2f p;
    float radius_px = 3;
    Rgb colour;
    bool filled = false;
};
struct OverlayLine {
    cv::Point2f a, b;
    Rgb colour;
    float thickness_px = 1;
};

struct Overlay {
    std::vector<OverlayBar> bars;
    std::vector<OverlayPoint> points;
    std::vector<OverlayLine> lines;
    void clear() {
        bars.clear();
        points.clear();
        lines.clear();
    }
};

// Draws onto an 8-bit BGR (or grey) image of the size the overlay was made for.
void draw_overlay(cv::Mat& image, const Overlay& overlay);

}  // namespace gs::vision
