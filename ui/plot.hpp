#pragma once
// A compact line-plot widget drawn with ImDrawList (Debian 12 has no ImPlot): several series,
// axes with "nice" ticks, grid, legend outside the data area (click an entry to hide the
// series), hover read-out, autoscale, dashed horizontal threshold lines, optional equal aspect
// (a map seen from above).
// Series are read in place from spans or from a RingSeries (fixed-capacity scrolling history).

#include <imgui.h>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace gs::ui {

// Fixed-capacity ring of (x, y) points: push is O(1), never allocates after construction.
class RingSeries {
public:
    explicit RingSeries(std::size_t capacity = 2048);
    void push(double x, double y);
    void clear() { head_ = count_ = 0; }
    std::size_t size() const { return count_; }
    std::size_t capacity() const { return xs_.size(); }
    // i = 0 is the oldest point.
    double x(std::size_t i) const { return xs_[index(i)]; }
    double y(std::size_t i) const { return ys_[index(i)]; }
    double last_x() const { return x(count_ - 1); }
    double last_y() const { return y(count_ - 1); }

private:
    std::size_t index(std::size_t i) const {
        return (head_ + xs_.size() - count_ + i) % xs_.size();
    }
    std::vector<double> xs_, ys_;
    std::size_t head_ = 0, count_ = 0;
};

// One series as seen by the plot: either spans (x may be empty: x = index) or a ring.
struct PlotSeriesView {
    std::string_view name;
    std::uint32_t rgba = 0;  // 0 = palette colour by position
    std::span<const double> x, y;
    const RingSeries* ring = nullptr;
    float thickness = 1.5f;
    bool markers = false;               // draw a dot on every point (sparse data)
    double x_offset = 0, y_offset = 0;  // added to every point (a path placed on a map)

    std::size_t size() const { return ring ? ring->size() : y.size(); }
    double px(std::size_t i) const {
        return x_offset + (ring ? ring->x(i) : (x.empty() ? static_cast<double>(i) : x[i]));
    }
    double py(std::size_t i) const { return y_offset + (ring ? ring->y(i) : y[i]); }
};

struct PlotThresholdView {
    std::string_view name;
    double y = 0;
    std::uint32_t rgba = 0;  // 0 = amber
};

struct PlotSpec {
    std::string_view title, x_label, y_label;
    std::vector<PlotSeriesView> series;
    std::vector<PlotThresholdView> thresholds;
    std::optional<double> x_min, x_max, y_min, y_max;  // fixed limits; unset = autoscale
    bool equal_aspect = false;                         // same units per pixel on both axes
    // Equal aspect: the smaller axis shows at least this span (data units), so that noise of a
    // few millimetres does not fill the map and read as a path. 0: none.
    double min_span = 0;
    bool show_legend = true;
};

// What draw_plot laid out (screen pixels) and the ranges it used.
struct PlotResult {
    ImVec2 frame_min, frame_max;  // the whole widget
    ImVec2 area_min, area_max;    // the data area
    double x_lo = 0, x_hi = 1, y_lo = 0, y_hi = 1;
    ImVec2 legend_min, legend_max;  // the legend's bounds (empty when there is none)
    bool hovered = false;
};

struct Range {
    double lo = 0, hi = 1;
};

// Tick step from {1, 2, 5} x 10^k giving at most max_ticks ticks over `range`.
double nice_step(double range, int max_ticks);
// Ticks (multiples of nice_step) inside [lo, hi].
std::vector<double> nice_ticks(double lo, double hi, int max_ticks);
// Autoscale: min/max of the finite values, padded by `pad` of the span; a flat or empty set gets
// a unit-wide range around its value (or [0, 1]).
Range autoscale(double data_min, double data_max, double pad = 0.05);
// An axis: autoscale(), with a fixed limit replacing its side; the free side still stays `pad`
// of the shown range away from the data (nothing sits on the border opposite a fixed limit).
Range axis_range(double data_min, double data_max, std::optional<double> lo,
                 std::optional<double> hi, double pad);
// Colour of the i-th series when none is given (distinct on a dark background).
std::uint32_t palette_color(std::size_t i);
// Text for a tick value given the tick step (enough decimals to tell neighbours apart).
std::string format_tick(double v, double step);

// Draws the plot as one ImGui item of `size` (<= 0: fill the available width/height).
PlotResult draw_plot(const char* id, const PlotSpec& spec, ImVec2 size);

}  // namespace gs::ui
