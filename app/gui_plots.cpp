#ifdef GS_HAVE_GUI

// Plot series assembly: the classifier's named series laid out for the Plots window.

#include "app/gui_views.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

namespace gs::app {

namespace {

const vision::PlotSeries* find(const vision::FrameResult& r, std::string_view name) {
    return r.find_series(name);
}

bool any_finite(const vision::PlotSeries& s) {
    for (std::size_t i = 0; i < s.points.size(); ++i)
        if (std::isfinite(s.points[i].y)) return true;
    return false;
}

ui::SeriesData series_data(const vision::PlotSeries& ps, std::string name) {
    ui::SeriesData sd;
    sd.name = std::move(name);
    const std::size_t n = ps.points.size();
    sd.x.resize(n);
    sd.y.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        sd.x[i] = ps.points[i].x;
        sd.y[i] = ps.points[i].y;
    }
    return sd;
}

// Last finite value of a series (a threshold drawn as a line).
double last_value(const vision::PlotSeries* ps) {
    if (!ps) return kUnknown;
    for (std::size_t i = ps->points.size(); i-- > 0;)
        if (std::isfinite(ps->points[i].y)) return ps->points[i].y;
    return kUnknown;
}

constexpr std::array<const char*, 3> kSeriesPrefix = {"left", "centre", "right"};

}  // namespace

void plot_series(const vision::FrameResult& r, double fit_window,
                 std::vector<ui::PlotData>& plots) {
    // Plots: the named ones the plots window knows, then any other series.
    plots.clear();
    std::vector<const vision::PlotSeries*> used;
    auto take = [&](std::string_view name) {
        const vision::PlotSeries* ps = find(r, name);
        if (ps) used.push_back(ps);
        return ps;
    };
    ui::PlotData scores{"scores", "Region scores", "frame", "score", {}, {}};
    for (std::size_t i = 0; i < 3; ++i) {
        const std::string p = kSeriesPrefix[i];
        if (const auto* s = take(p + ".score"))
            scores.series.push_back(series_data(*s, kRegionNames[i]));
        const double thr = last_value(take(p + ".threshold"));
        if (!std::isfinite(thr)) continue;
        // Left and right usually share one threshold: one "side" line instead of two labels.
        bool merged = false;
        for (auto& t : scores.thresholds)
            if (std::fabs(t.y - thr) < 1e-9) {
                t.name = i == 2 && t.name == "left threshold" ? "side threshold" : t.name;
                merged = true;
            }
        if (!merged)
            scores.thresholds.push_back({std::string(kRegionNames[i]) + " threshold", thr, 0});
    }
    if (!scores.series.empty()) plots.push_back(std::move(scores));

    ui::PlotData scale{"center_scale", "Centre scale", "frame", "ratio", {}, {}};
    // flow: the corridor points' expansion rate, and the outline's and the homography's when
    // those channels are on.
    const bool rates = find(r, "centre.points_rate") != nullptr;
    if (rates) {
        scale.title = "Centre expansion rate";
        scale.y_label = "1/s";
    }
    for (const char* n :
         {"centre.scale_raw", "centre.scale_filtered", "centre.scale_fitted", "centre.points_rate",
          "centre.outline_rate", "centre.homography_rate", "centre.rate_raw"})
        if (const auto* s = take(n); s && any_finite(*s))  // a channel switched off stays out
            scale.series.push_back(series_data(*s, std::string(n).substr(7)));
    // The centre threshold, where it shares the plot's units. The thesis classifier flags the
    // centre when the fitted curve's tangent slope exceeds the threshold (per sample): drawn as a
    // line of that slope ending at the newest fitted point, over the fit window (a fitted curve
    // climbing more steeply than it is unsafe). The flow classifier compares the expansion rate
    // (1/s) with it: a horizontal line against its rates.
    const double cthr = last_value(find(r, "centre.threshold"));
    if (std::isfinite(cthr)) {
        const auto* fitted = find(r, "centre.scale_fitted");
        if (rates || find(r, "centre.rate_raw"))
            scale.thresholds.push_back({"centre threshold [1/s]", cthr, 0});
        if (fitted) {
            std::optional<vision::PlotPoint> last;
            for (std::size_t i = fitted->points.size(); i-- > 0;)
                if (std::isfinite(fitted->points[i].y)) {
                    last = fitted->points[i];
                    break;
                }
            if (last) {
                ui::SeriesData th;
                th.name = "threshold slope";
                th.rgba = ui::rgba(235, 65, 55, 230);
                const double w = std::max(2.0, fit_window);
                th.x = {last->x - w, last->x};
                th.y = {last->y - cthr * w, last->y};
                scale.series.push_back(std::move(th));
                char t[96];
                std::snprintf(t, sizeof t, "Centre scale (slope %.4f, thr %.4f)",
                              r.regions[1].score, cthr);
                if (std::isfinite(r.regions[1].score)) scale.title = t;
            }
        }
    }
    if (!scale.series.empty()) plots.push_back(std::move(scale));

    ui::PlotData traj{"trajectories_x", "Trajectory x over frames", "frame", "px", {}, {}};
    const std::size_t n_traces = std::min<std::size_t>(r.traces.size(), 16);
    for (std::size_t k = 0; k < n_traces; ++k) {
        const vision::TrajectoryTrace& t = r.traces[k];
        ui::SeriesData sd;
        sd.name = "track " + std::to_string(t.id);
        for (int i = 0; i < t.count; ++i) {
            sd.x.push_back(static_cast<double>(t.last_frame - t.count + 1 + i));
            sd.y.push_back(static_cast<double>(t.x[static_cast<std::size_t>(i)]));
        }
        traj.series.push_back(std::move(sd));
    }
    if (!traj.series.empty()) plots.push_back(std::move(traj));

    ui::PlotData more{"classifier_other", "Other classifier series", "frame", "", {}, {}};
    for (const auto& ps : r.series)
        if (std::find(used.begin(), used.end(), &ps) == used.end() && ps.points.size() > 0)
            more.series.push_back(series_data(ps, ps.name));
    if (!more.series.empty()) plots.push_back(std::move(more));
}

}  // namespace gs::app

#endif  // GS_HAVE_GUI
