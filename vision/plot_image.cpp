#include "vision/plot_image.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace gs::vision {

std::vector<double> nice_ticks(double lo, double hi, int target) {
    std::vector<double> t;
    if (!std::isfinite(lo) || !std::isfinite(hi) || target < 1) return t;
    if (hi < lo) std::swap(lo, hi);
    double span = hi - lo;
    if (span <= 0) span = std::max(std::abs(lo), 1.0) * 0.1;
    const double raw = span / target;
    const double mag = std::pow(10.0, std::floor(std::log10(raw)));
    const double f = raw / mag;
    const double step = (f < 1.5 ? 1 : f < 3.5 ? 2 : f < 7.5 ? 5 : 10) * mag;
    const double first = std::ceil(lo / step - 1e-9) * step;
    for (double v = first; v <= hi + step * 1e-9 && t.size() < 64; v += step)
        t.push_back(std::abs(v) < step * 1e-9 ? 0.0 : v);
    return t;
}

namespace {

std::string tick_label(double v, double step) {
    char b[32];
    const int decimals =
        step >= 1 ? 0 : std::min(6, static_cast<int>(std::ceil(-std::log10(step))));
    if (std::abs(v) >= 1e5 || (std::abs(v) > 0 && std::abs(v) < 1e-4))
        std::snprintf(b, sizeof b, "%.2g", v);
    else
        std::snprintf(b, sizeof b, "%.*f", decimals, v);
    return b;
}

}  // namespace

cv::Mat render_plot(const PlotSpec& spec) {
    const int W = std::max(200, spec.width), H = std::max(120, spec.height);
    cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
    const int font = cv::FONT_HERSHEY_SIMPLEX;
    const double fs = 0.42;
    const cv::Scalar ink(40, 40, 40), grid(225, 225, 225);

    double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
    for (const PlotLine& l : spec.lines)
        for (std::size_t i = 0; i < std::min(l.x.size(), l.y.size()); ++i) {
            if (!std::isfinite(l.x[i]) || !std::isfinite(l.y[i])) continue;
            x0 = std::min(x0, l.x[i]);
            x1 = std::max(x1, l.x[i]);
            y0 = std::min(y0, l.y[i]);
            y1 = std::max(y1, l.y[i]);
        }
    const cv::Rect area(64, 28, W - 64 - 16, H - 28 - 44);
    cv::putText(img, spec.title, {area.x, 18}, font, 0.5, ink, 1, cv::LINE_AA);
    if (!std::isfinite(x0)) {
        cv::rectangle(img, area, grid, 1);
        cv::putText(img, "no data", {area.x + area.width / 2 - 30, area.y + area.height / 2}, font,
                    0.5, cv::Scalar(140, 140, 140), 1, cv::LINE_AA);
        return img;
    }
    if (x1 <= x0) x1 = x0 + 1;
    if (y1 <= y0) {
        const double pad = std::max(std::abs(y0) * 0.05, 1e-6);
        y0 -= pad;
        y1 += pad;
    }
    const double ypad = (y1 - y0) * 0.06;
    y0 -= ypad;
    y1 += ypad;
    auto px = [&](double x) { return area.x + (x - x0) / (x1 - x0) * area.width; };
    auto py = [&](double y) { return area.y + area.height - (y - y0) / (y1 - y0) * area.height; };

    const auto xt = nice_ticks(x0, x1, 8), yt = nice_ticks(y0, y1, 5);
    const double xs = xt.size() > 1 ? xt[1] - xt[0] : 1, ys = yt.size() > 1 ? yt[1] - yt[0] : 1;
    for (double v : xt) {
        const int x = static_cast<int>(std::lround(px(v)));
        cv::line(img, {x, area.y}, {x, area.y + area.height}, grid, 1);
        const std::string s = tick_label(v, xs);
        int base = 0;
        const cv::Size ts = cv::getTextSize(s, font, fs, 1, &base);
        cv::putText(img, s, {x - ts.width / 2, area.y + area.height + 16}, font, fs, ink, 1,
                    cv::LINE_AA);
    }
    for (double v : yt) {
        const int y = static_cast<int>(std::lround(py(v)));
        cv::line(img, {area.x, y}, {area.x + area.width, y}, grid, 1);
        const std::string s = tick_label(v, ys);
        int base = 0;
        const cv::Size ts = cv::getTextSize(s, font, fs, 1, &base);
        cv::putText(img, s, {area.x - ts.width - 6, y + ts.height / 2}, font, fs, ink, 1,
                    cv::LINE_AA);
    }
    cv::rectangle(img, area, ink, 1);
    if (!spec.x_label.empty()) {
        int base = 0;
        const cv::Size ts = cv::getTextSize(spec.x_label, font, fs, 1, &base);
        cv::putText(img, spec.x_label, {area.x + area.width / 2 - ts.width / 2, H - 8}, font, fs,
                    ink, 1, cv::LINE_AA);
    }
    if (!spec.y_label.empty())
        cv::putText(img, spec.y_label, {4, 18}, font, fs, ink, 1, cv::LINE_AA);

    cv::Mat plot = img(area);
    for (const PlotLine& l : spec.lines) {
        const cv::Scalar c = to_bgr(l.colour);
        bool have = false;
        cv::Point prev;
        int seg = 0;
        for (std::size_t i = 0; i < std::min(l.x.size(), l.y.size()); ++i) {
            if (!std::isfinite(l.x[i]) || !std::isfinite(l.y[i])) {
                have = false;
                continue;
            }
            // Sub-pixel precision (shift 4) keeps dense series smooth.
            const cv::Point p(static_cast<int>(std::lround((px(l.x[i]) - area.x) * 16)),
                              static_cast<int>(std::lround((py(l.y[i]) - area.y) * 16)));
            if (l.markers) {
                cv::circle(plot, p, 2 * 16, c, cv::FILLED, cv::LINE_AA, 4);
            } else if (have && (!l.dashed || (seg++ / 3) % 2 == 0)) {
                cv::line(plot, prev, p, c, 1, cv::LINE_AA, 4);
            }
            prev = p;
            have = true;
        }
    }

    if (spec.legend) {
        int y = area.y + 14, shown = 0;
        int widest = 0;
        for (const PlotLine& l : spec.lines) {
            int base = 0;
            widest = std::max(widest, cv::getTextSize(l.label, font, fs, 1, &base).width);
        }
        const int lx = area.x + area.width - widest - 34;
        for (const PlotLine& l : spec.lines) {
            if (l.label.empty()) continue;
            if (shown++ >= spec.max_legend_entries) break;
            cv::rectangle(img, {lx - 4, y - 11}, {area.x + area.width - 4, y + 4},
                          cv::Scalar(255, 255, 255), cv::FILLED);
            cv::line(img, {lx, y - 4}, {lx + 20, y - 4}, to_bgr(l.colour), 2, cv::LINE_AA);
            cv::putText(img, l.label, {lx + 26, y}, font, fs, ink, 1, cv::LINE_AA);
            y += 16;
        }
    }
    return img;
}

}  // namespace gs::vision
