#include "ui/windows.hpp"

#include "ui/plot.hpp"

#include <algorithm>

namespace gs::ui {

namespace {

const PlotData* find_plot(const GuiSnapshot& s, std::string_view name) {
    for (const auto& p : s.classifier.plots)
        if (p.name == name) return &p;
    return nullptr;
}

void draw_data(const char* id, const PlotData* p, std::string_view fallback_title, ImVec2 size,
               const char* msg = "no classifier data") {
    PlotSpec spec;
    if (!p) {
        spec.title = fallback_title;
        const PlotResult r = draw_plot(id, spec, size);
        const ImVec2 ts = ImGui::CalcTextSize(msg);
        ImGui::GetWindowDrawList()->AddText({0.5f * (r.area_min.x + r.area_max.x - ts.x),
                                             0.5f * (r.area_min.y + r.area_max.y - ts.y)},
                                            colors::kDim, msg);
        return;
    }
    spec.title = p->title;
    spec.x_label = p->x_label;
    spec.y_label = p->y_label;
    for (const auto& sd : p->series) {
        PlotSeriesView sv;
        sv.name = sd.name;
        sv.rgba = sd.rgba;
        sv.x = sd.x;
        sv.y = sd.y;
        spec.series.push_back(sv);
    }
    for (const auto& t : p->thresholds) spec.thresholds.push_back({t.name, t.y, t.rgba});
    // Many trajectories: a legend would cover the plot.
    spec.show_legend = p->series.size() <= 6;
    draw_plot(id, spec, size);
}

void time_plot(const char* id, std::string_view title, std::string_view unit,
               std::initializer_list<std::pair<std::string_view, const RingSeries*>> series,
               const ViewState& v, ImVec2 size, std::optional<double> ymin = {},
               std::optional<double> ymax = {}, std::vector<PlotThresholdView> th = {}) {
    PlotSpec spec;
    spec.title = title;
    spec.y_label = unit;
    spec.x_label = "t [s]";
    for (const auto& [name, ring] : series) {
        PlotSeriesView sv;
        sv.name = name;
        sv.ring = ring;
        spec.series.push_back(sv);
    }
    const double t1 = v.history.last_t_s();
    spec.x_max = t1;
    spec.x_min = t1 - v.settings.plot_span_s;
    spec.y_min = ymin;
    spec.y_max = ymax;
    spec.thresholds = std::move(th);
    spec.show_legend = series.size() > 1;
    draw_plot(id, spec, size);
}

// Plot pixel of a point in the plot's data coordinates.
ImVec2 to_screen(const PlotResult& r, double x, double y) {
    return {r.area_min.x + static_cast<float>((x - r.x_lo) / (r.x_hi - r.x_lo)) *
                               (r.area_max.x - r.area_min.x),
            r.area_max.y - static_cast<float>((y - r.y_lo) / (r.y_hi - r.y_lo)) *
                               (r.area_max.y - r.area_min.y)};
}

constexpr std::uint32_t kNavPathColor = IM_COL32(86, 180, 233, 255);
constexpr std::uint32_t kOdoPathColor = IM_COL32(240, 130, 60, 255);

// The navdata path (velocities x heading, eq. 6.2) and, while the bottom camera's odometry runs,
// its visual path from where the navdata path was when the odometry started, on one map with
// equal scales.
void flight_path(const GuiSnapshot& s, ViewState& v, ImVec2 size) {
    PlotSpec spec;
    spec.title = "Flight path (top view, eq. 6.2)";
    spec.x_label = "right [m]";
    spec.y_label = "m";
    spec.equal_aspect = true;
    PlotSeriesView nav;
    nav.name = "navdata";
    nav.ring = &v.history.path;
    nav.rgba = kNavPathColor;
    spec.series.push_back(nav);
    const OdometryView& o = s.odometry;
    const bool odo = o.active && !o.path_x.empty();
    if (odo) {
        PlotSeriesView vo;
        vo.name = "visual odometry";
        vo.x = o.path_x;
        vo.y = o.path_y;
        vo.rgba = kOdoPathColor;
        double ax = 0, ay = 0;
        if (known(o.start_t_s) && v.history.path_at(o.start_t_s, ax, ay)) {
            vo.x_offset = ax;
            vo.y_offset = ay;
        }
        spec.series.push_back(vo);
    }
    spec.show_legend = odo;
    const PlotResult r = draw_plot("path", spec, size);
    LayoutReport::FlightPath& lf = v.layout.flight_path;
    lf.drawn = true;
    for (const auto& sv : spec.series) lf.series.emplace_back(sv.name);
    lf.legend = r.legend_max.x > r.legend_min.x;
    lf.area = {r.area_min.x, r.area_min.y, r.area_max.x, r.area_max.y};
    lf.x_per_px = (r.x_hi - r.x_lo) / static_cast<double>(r.area_max.x - r.area_min.x);
    lf.y_per_px = (r.y_hi - r.y_lo) / static_cast<double>(r.area_max.y - r.area_min.y);
    if (odo) {
        lf.odometry_x0 = spec.series.back().px(0);
        lf.odometry_y0 = spec.series.back().py(0);
        lf.odometry_points = spec.series.back().size();
    }
    ImDrawList* dl = ImGui::GetWindowDrawList();
    dl->PushClipRect(r.area_min, r.area_max, true);
    // Current positions.
    if (v.history.path.size() > 0)
        dl->AddCircleFilled(to_screen(r, v.history.path.last_x(), v.history.path.last_y()), 4.0f,
                            IM_COL32(255, 200, 40, 255));
    if (odo) {
        const PlotSeriesView& vo = spec.series.back();
        const std::size_t n = vo.size();
        dl->AddCircleFilled(to_screen(r, vo.px(n - 1), vo.py(n - 1)), 4.0f, kOdoPathColor);
        dl->AddCircle(to_screen(r, vo.px(0), vo.py(0)), 4.0f, kOdoPathColor, 0, 1.5f);
    }
    dl->PopClipRect();
}

}  // namespace

void PlotsWindow::draw(const GuiSnapshot& s, ViewState& v) {
    if (!ImGui::Begin("Plots", &v.open.plots)) {
        ImGui::End();
        return;
    }
    const float sp = ImGui::GetStyle().ItemSpacing.x;
    const char* tabs[] = {"All", "Classifier", "Flight"};
    for (int i = 0; i < 3; ++i) {
        if (i) ImGui::SameLine();
        const bool sel = v.plot_tab == i;
        if (sel)
            ImGui::PushStyleColor(ImGuiCol_Button, ImGui::GetStyleColorVec4(ImGuiCol_ButtonActive));
        if (ImGui::SmallButton(tabs[i])) v.plot_tab = i;
        if (sel) ImGui::PopStyleColor();
    }
    ImGui::SameLine();
    ImGui::SetNextItemWidth(ImGui::GetFontSize() * 9);
    float span = static_cast<float>(v.settings.plot_span_s);
    if (ImGui::SliderFloat("window", &span, 5.0f, 300.0f, "%.0f s", ImGuiSliderFlags_Logarithmic)) {
        v.settings.plot_span_s = static_cast<double>(span);
        v.settings_dirty = true;
    }
    const ImVec2 avail = ImGui::GetContentRegionAvail();
    auto cell = [&](int cols, int rows) {
        return ImVec2{(avail.x - sp * static_cast<float>(cols - 1)) / static_cast<float>(cols),
                      (avail.y - ImGui::GetStyle().ItemSpacing.y * static_cast<float>(rows - 1)) /
                          static_cast<float>(rows)};
    };
    // On the bottom camera the classifier does not run: say so instead of "no data".
    const char* empty =
        s.classifier.not_running.empty() ? "no classifier data" : "not run on the bottom camera";
    auto classifier_plots = [&](ImVec2 sz) {
        draw_data("traj", find_plot(s, "trajectories_x"), "Trajectory x over frames", sz, empty);
        ImGui::SameLine();
        draw_data("scale", find_plot(s, "center_scale"), "Centre scale", sz, empty);
        ImGui::SameLine();
        draw_data("scores", find_plot(s, "scores"), "Region scores", sz, empty);
    };
    auto flight_plots = [&](ImVec2 sz) {
        flight_path(s, v, sz);
        ImGui::SameLine();
        time_plot("alt", "Altitude", "m", {{"altitude", &v.history.altitude_m}}, v, sz, 0.0);
        ImGui::SameLine();
        time_plot("att", "Attitude", "deg",
                  {{"roll", &v.history.roll_deg}, {"pitch", &v.history.pitch_deg}}, v, sz);
        ImGui::SameLine();
        time_plot("bat", "Battery", "%", {{"battery", &v.history.battery_pct}}, v, sz, 0.0, 100.0,
                  {{"low", s.telemetry.battery_low_pct, IM_COL32(235, 65, 55, 220)}});
    };
    if (v.plot_tab == 0) {
        const ImVec2 c3 = cell(3, 2), c4 = cell(4, 2);
        classifier_plots(c3);
        flight_plots(c4);
    } else if (v.plot_tab == 1) {
        const ImVec2 c = cell(3, 1);
        classifier_plots(c);
    } else {
        const ImVec2 c = cell(4, 1);
        flight_plots(c);
    }
    // Any further classifier plots (not one of the three known names).
    for (const auto& p : s.classifier.plots) {
        if (p.name == "trajectories_x" || p.name == "center_scale" || p.name == "scores") continue;
        draw_data(p.name.c_str(), &p, p.title, {0, ImGui::GetFontSize() * 12});
    }
    ImGui::End();
}

}  // namespace gs::ui
