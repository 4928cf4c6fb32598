#pragma once
// Line plots rendered to an image with OpenCV, for headless output (`replay --plots`): axes with
// "nice" ticks, a legend, NaN gaps, optional horizontal reference lines (thresholds). The GUI has
// its own interactive widget (ui/plot.hpp); this one draws files.

#include "vision/overlay.hpp"

#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace gs::vision {

struct PlotLine {
    std::string label;
    Rgb colour;
    std::vector<double> x, y;  // same length; NaN y = gap
    bool dashed = false;
    bool markers = false;  // small dots instead of a line (scattered samples)
};

struct PlotSpec {
    std::string title;
    std::string x_label, y_label;
    std::vector<PlotLine> lines;
    int width = 900, height = 360;
    bool legend = true;
    int max_legend_entries = 8;
};

// "Nice" tick positions covering [lo, hi] (about `target` of them), step 1, 2 or 5 x 10^k.
std::vector<double> nice_ticks(double lo, double hi, int target = 6);

// Renders the plot (white background, BGR8). Autoscaled to the finite data; an empty plot says
// "no data".
cv::Mat render_plot(const PlotSpec& spec);

}  // namespace gs::vision
