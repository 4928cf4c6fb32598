#include "ui/plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace gs::ui {

RingSeries::RingSeries(std::size_t capacity)
    : xs_(capacity == 0 ? 1 : capacity), ys_(capacity == 0 ? 1 : capacity) {}

void RingSeries::push(double x, double y) {
    xs_[head_] = x;
    ys_[head_] = y;
    head_ = (head_ + 1) % xs_.size();
    count_ = std::min(count_ + 1, xs_.size());
}

double nice_step(double range, int max_ticks) {
    if (!(range > 0) || !std::isfinite(range)) return 1.0;
    max_ticks = std::max(max_ticks, 2);
    const double raw = range / static_cast<double>(max_ticks - 1);
    const double mag = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0, 10.0}) {
        const double step = m * mag;
        if (std::floor(range / step) + 1 <= static_cast<double>(max_ticks)) return step;
    }
    return 10.0 * mag;
}

std::vector<double> nice_ticks(double lo, double hi, int max_ticks) {
    std::vector<double> ticks;
    if (!std::isfinite(lo) || !std::isfinite(hi) || hi <= lo) return ticks;
    const double step = nice_step(hi - lo, max_ticks);
    const double first = std::ceil(lo / step - 1e-9) * step;
    for (int i = 0; i < 64; ++i) {
        double t = first + static_cast<double>(i) * step;
        if (t > hi + step * 1e-9) break;
        if (std::fabs(t) < step * 1e-9) t = 0.0;  // no "-0" or 1e-17
        ticks.push_back(t);
    }
    return ticks;
}

Range autoscale(double data_min, double data_max, double pad) {
    if (!std::isfinite(data_min) || !std::isfinite(data_max)) return {0.0, 1.0};
    if (data_max - data_min <= 1e-12 * std::max(1.0, std::fabs(data_max))) {
        const double half = std::max(0.5, std::fabs(data_min) * 0.1);
        return {data_min - half, data_max + half};
    }
    const double p = (data_max - data_min) * pad;
    return {data_min - p, data_max + p};
}

std::uint32_t palette_color(std::size_t i) {
    static const std::uint32_t colors[] = {
        IM_COL32(86, 180, 233, 255),   // sky blue
        IM_COL32(240, 160, 40, 255),   // orange
        IM_COL32(120, 210, 120, 255),  // green
        IM_COL32(230, 110, 170, 255),  // pink
        IM_COL32(240, 228, 66, 255),   // yellow
        IM_COL32(170, 140, 240, 255),  // violet
        IM_COL32(0, 190, 170, 255),    // teal
        IM_COL32(220, 220, 220, 255),  // grey
    };
    return colors[i % std::size(colors)];
}

std::string format_tick(double v, double step) {
    int decimals = 0;
    if (step > 0 && std::isfinite(step))
        decimals = std::clamp(static_cast<int>(-std::floor(std::log10(step) + 1e-9)), 0, 6);
    char buf[48];
    if (std::fabs(v) >= 1e6 || (std::fabs(v) > 0 && std::fabs(v) < 1e-4 && decimals > 5))
        std::snprintf(buf, sizeof buf, "%.3g", v);
    else
        std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    return buf;
}

namespace {

constexpr std::uint32_t kFrameBg = IM_COL32(22, 24, 28, 255);
constexpr std::uint32_t kAreaBg = IM_COL32(14, 15, 18, 255);
constexpr std::uint32_t kGrid = IM_COL32(255, 255, 255, 22);
constexpr std::uint32_t kAxis = IM_COL32(255, 255, 255, 90);
constexpr std::uint32_t kText = IM_COL32(200, 204, 210, 255);
constexpr std::uint32_t kDimText = IM_COL32(150, 154, 160, 255);
constexpr std::uint32_t kThreshold = IM_COL32(255, 190, 40, 230);

void dashed_hline(ImDrawList* dl, float x0, float x1, float y, std::uint32_t col, float thick) {
    const float dash = 6.0f, gap = 4.0f;
    for (float x = x0; x < x1; x += dash + gap)
        dl->AddLine({x, y}, {std::min(x + dash, x1), y}, col, thick);
}

float text_w(float font_size, std::string_view t) {
    return ImGui::GetFont()
        ->CalcTextSizeA(font_size, FLT_MAX, 0.0f, t.data(), t.data() + t.size())
        .x;
}

// `t` shortened with ".." until it is at most `max_w` wide.
std::string fit_text(std::string_view t, float font_size, float max_w) {
    std::string out(t);
    if (text_w(font_size, out) <= max_w) return out;
    while (!out.empty() && text_w(font_size, out + "..") > max_w) out.pop_back();
    return out.empty() ? std::string() : out + "..";
}

// Where the legend goes: on the title row, right-aligned, when it fits there; otherwise in rows
// of its own under the title (at most a third of the plot's height; entries that do not fit are
// summed up as "+N", listed when hovered). Either way outside the data area, in a smaller font.
struct LegendEntry {
    std::size_t series = 0;
    ImVec2 pos;
    float w = 0;
};
struct Legend {
    float height = 0;  // of the rows under the title row (0: on the title row, or no legend)
    float font = 0;
    float swatch = 0, pad = 3.0f;
    std::vector<LegendEntry> entries;
    std::size_t more = 0;  // series left out (the last ones)
    ImVec2 more_pos;
};

Legend layout_legend(const PlotSpec& spec, ImVec2 p0, ImVec2 size, float title_h, float bottom_h) {
    Legend L;
    if (!spec.show_legend || spec.series.empty()) return L;
    const float fh = ImGui::GetFontSize();
    L.font = std::round(fh * 0.86f);
    L.swatch = L.font * 0.8f;
    const float gap = 10.0f;
    std::vector<float> widths;
    float total = 0;
    for (const auto& s : spec.series) {
        widths.push_back(L.swatch + L.pad + text_w(L.font, s.name));
        total += widths.back() + (widths.size() > 1 ? gap : 0.0f);
    }
    const float x_left = p0.x + 6.0f, x_right = p0.x + size.x - 6.0f;
    float title_w = 0;
    if (!spec.title.empty()) {
        title_w = text_w(fh, spec.title);
        if (!spec.y_label.empty()) title_w += 6.0f + text_w(fh, spec.y_label) + 2 * fh * 0.35f;
    }
    if (!spec.title.empty() && x_left + title_w + 16.0f + total <= x_right) {
        float x = x_right - total;
        for (std::size_t i = 0; i < widths.size(); ++i) {
            L.entries.push_back({i, {x, p0.y + 3.0f + (fh - L.font) * 0.5f}, widths[i]});
            x += widths[i] + gap;
        }
        return L;
    }
    const float row_h = L.font + 3.0f;
    const float plot_h = size.y - title_h - bottom_h;
    const int max_rows = std::clamp(static_cast<int>(plot_h / 3.0f / row_h), 1, 3);
    float x = x_left;
    int row = 0;
    for (std::size_t i = 0; i < widths.size(); ++i) {
        if (x > x_left && x + widths[i] > x_right) {
            ++row;
            x = x_left;
        }
        if (row >= max_rows) {
            L.more = widths.size() - i;
            break;
        }
        L.entries.push_back({i, {x, p0.y + title_h + static_cast<float>(row) * row_h}, widths[i]});
        x += widths[i] + gap;
    }
    if (L.more > 0) {
        const float more_w = text_w(L.font, "+99");
        while (!L.entries.empty() &&
               L.entries.back().pos.x + L.entries.back().w + gap + more_w > x_right &&
               L.entries.back().pos.x > x_left) {
            L.entries.pop_back();
            ++L.more;
        }
        const LegendEntry& last = L.entries.back();
        L.more_pos = {last.pos.x + last.w + gap, last.pos.y};
    }
    int rows = 0;
    for (const auto& e : L.entries)
        rows = std::max(rows, static_cast<int>((e.pos.y - p0.y - title_h) / row_h + 0.5f) + 1);
    L.height = static_cast<float>(rows) * row_h + 2.0f;
    return L;
}

}  // namespace

Range axis_range(double data_min, double data_max, std::optional<double> lo,
                 std::optional<double> hi, double pad) {
    Range r = autoscale(data_min, data_max, pad);
    if (lo) r.lo = *lo;
    if (hi) r.hi = *hi;
    // A fixed side: the free one still keeps its pad from the data, measured over the range
    // actually shown (a fixed 0 under data at 1.0 would otherwise leave 1.0 on the border).
    if (std::isfinite(data_min) && std::isfinite(data_max)) {
        if (lo && !hi && data_max > r.lo) r.hi = std::max(r.hi, data_max + pad * (data_max - r.lo));
        if (hi && !lo && data_min < r.hi) r.lo = std::min(r.lo, data_min - pad * (r.hi - data_min));
    }
    if (!(r.hi > r.lo)) r.hi = r.lo + 1;
    return r;
}

PlotResult draw_plot(const char* id, const PlotSpec& spec, ImVec2 size) {
    PlotResult r;
    ImGui::PushID(id);
    const ImVec2 avail = ImGui::GetContentRegionAvail();
    if (size.x <= 0) size.x = std::max(avail.x, 50.0f);
    if (size.y <= 0) size.y = std::max(avail.y, 50.0f);
    const ImVec2 p0 = ImGui::GetCursorScreenPos();
    ImGui::InvisibleButton("##plot", size);
    r.hovered = ImGui::IsItemHovered();
    const ImVec2 p1{p0.x + size.x, p0.y + size.y};
    r.frame_min = p0;
    r.frame_max = p1;

    ImGuiStorage* storage = ImGui::GetStateStorage();
    auto hidden_id = [&](std::string_view name) {
        return ImGui::GetID(name.data(), name.data() + name.size());
    };

    // Ranges over the visible series (and thresholds: a threshold must stay on screen).
    double xmin = std::numeric_limits<double>::infinity(), xmax = -xmin, ymin = xmin, ymax = -xmin;
    for (const auto& s : spec.series) {
        if (storage->GetBool(hidden_id(s.name), false)) continue;
        const std::size_t n = s.size();
        for (std::size_t i = 0; i < n; ++i) {
            const double x = s.px(i), y = s.py(i);
            if (!std::isfinite(x) || !std::isfinite(y)) continue;
            xmin = std::min(xmin, x);
            xmax = std::max(xmax, x);
            ymin = std::min(ymin, y);
            ymax = std::max(ymax, y);
        }
    }
    for (const auto& t : spec.thresholds) {
        if (!std::isfinite(t.y)) continue;
        ymin = std::min(ymin, t.y);
        ymax = std::max(ymax, t.y);
    }
    const Range xr0 = axis_range(xmin, xmax, spec.x_min, spec.x_max, 0.0);
    const Range yr0 = axis_range(ymin, ymax, spec.y_min, spec.y_max, 0.08);
    Range xr = xr0, yr = yr0;

    // Layout: title row (the legend on it when it fits, else in rows of its own below it), y tick
    // labels on the left, x tick labels (+ label) below. The legend never covers the data area.
    const float fh = ImGui::GetFontSize();
    const float title_h = spec.title.empty() ? 4.0f : fh + 6.0f;
    const float bottom_h = fh + 6.0f + (spec.x_label.empty() ? 0.0f : fh + 2.0f);
    ImDrawList* dl = ImGui::GetWindowDrawList();
    const Legend legend = layout_legend(spec, p0, size, title_h, bottom_h);

    // y ticks first: their label width sets the left margin (and, with equal aspect, the area
    // sets the ranges): the area is laid out with a guessed margin, then once more with the
    // labels' width, and the ranges are made from the final area.
    const float top_h = title_h + legend.height;
    const float area_h_guess = std::max(size.y - top_h - bottom_h - 4.0f, 10.0f);
    const int max_yticks = std::clamp(static_cast<int>(area_h_guess / (fh * 2.2f)) + 1, 2, 10);
    float left_w = fh * 3.0f;
    auto compute_area = [&]() {
        r.area_min = {p0.x + left_w + 6.0f, p0.y + top_h};
        r.area_max = {p1.x - 8.0f, p1.y - bottom_h};
        if (r.area_max.x < r.area_min.x + 10) r.area_max.x = r.area_min.x + 10;
        if (r.area_max.y < r.area_min.y + 10) r.area_max.y = r.area_min.y + 10;
    };
    std::vector<double> yticks;
    std::vector<std::string> ylabels;
    double ystep = 1;
    for (int pass = 0; pass < 2; ++pass) {
        compute_area();
        xr = xr0;
        yr = yr0;
        if (spec.equal_aspect) {
            const double w = static_cast<double>(r.area_max.x - r.area_min.x);
            const double h = static_cast<double>(r.area_max.y - r.area_min.y);
            const double upp = std::max((xr.hi - xr.lo) / w, (yr.hi - yr.lo) / h);
            const double xc = 0.5 * (xr.lo + xr.hi), yc = 0.5 * (yr.lo + yr.hi);
            xr = {xc - upp * w * 0.5, xc + upp * w * 0.5};
            yr = {yc - upp * h * 0.5, yc + upp * h * 0.5};
        }
        yticks = nice_ticks(yr.lo, yr.hi, max_yticks);
        ystep = nice_step(yr.hi - yr.lo, max_yticks);
        ylabels.clear();
        float max_label = 0;
        for (double t : yticks) {
            ylabels.push_back(format_tick(t, ystep));
            max_label = std::max(max_label, ImGui::CalcTextSize(ylabels.back().c_str()).x);
        }
        const float want = std::max(max_label, fh * 1.5f);
        if (want == left_w) break;
        left_w = want;  // pass 1 lays out with it (its labels may differ by a digit: kept)
    }
    r.x_lo = xr.lo;
    r.x_hi = xr.hi;
    r.y_lo = yr.lo;
    r.y_hi = yr.hi;

    const ImVec2 a0 = r.area_min, a1 = r.area_max;
    auto to_px = [&](double x, double y) {
        const double fx = (x - xr.lo) / (xr.hi - xr.lo), fy = (y - yr.lo) / (yr.hi - yr.lo);
        return ImVec2{a0.x + static_cast<float>(fx) * (a1.x - a0.x),
                      a1.y - static_cast<float>(fy) * (a1.y - a0.y)};
    };

    dl->AddRectFilled(p0, p1, kFrameBg, 3.0f);
    dl->AddRectFilled(a0, a1, kAreaBg);
    dl->PushClipRect(p0, p1, true);
    if (!spec.title.empty()) {
        const std::string title(spec.title);
        dl->AddText({p0.x + 6.0f, p0.y + 3.0f}, kText, title.c_str());
        if (!spec.y_label.empty()) {
            std::string yl(1, '[');
            yl += spec.y_label;
            yl += ']';
            const float tw = ImGui::CalcTextSize(title.c_str()).x;
            dl->AddText({p0.x + 12.0f + tw, p0.y + 3.0f}, kDimText, yl.c_str());
        }
    }

    // Grid and tick labels.
    for (std::size_t i = 0; i < yticks.size(); ++i) {
        const float y = to_px(xr.lo, yticks[i]).y;
        dl->AddLine({a0.x, y}, {a1.x, y}, kGrid);
        const ImVec2 ts = ImGui::CalcTextSize(ylabels[i].c_str());
        dl->AddText({a0.x - 4.0f - ts.x, y - ts.y * 0.5f}, kDimText, ylabels[i].c_str());
    }
    const float area_w = a1.x - a0.x;
    // As many x ticks as their labels fit (the widest label at a fine step, plus a gap).
    const double fine = nice_step(xr.hi - xr.lo, 12);
    const float xlabel_w = std::max(ImGui::CalcTextSize(format_tick(xr.lo, fine).c_str()).x,
                                    ImGui::CalcTextSize(format_tick(xr.hi, fine).c_str()).x) +
                           fh * 1.2f;
    const int max_xticks = std::clamp(static_cast<int>(area_w / xlabel_w) + 1, 2, 12);
    const double xstep = nice_step(xr.hi - xr.lo, max_xticks);
    for (double t : nice_ticks(xr.lo, xr.hi, max_xticks)) {
        const float x = to_px(t, yr.lo).x;
        dl->AddLine({x, a0.y}, {x, a1.y}, kGrid);
        const std::string lbl = format_tick(t, xstep);
        const ImVec2 ts = ImGui::CalcTextSize(lbl.c_str());
        const float lx = std::clamp(x - ts.x * 0.5f, a0.x - 2.0f, a1.x - ts.x + 2.0f);
        dl->AddText({lx, a1.y + 3.0f}, kDimText, lbl.c_str());
    }
    if (!spec.x_label.empty()) {
        const std::string xl(spec.x_label);
        const ImVec2 ts = ImGui::CalcTextSize(xl.c_str());
        dl->AddText({0.5f * (a0.x + a1.x) - ts.x * 0.5f, a1.y + fh + 5.0f}, kDimText, xl.c_str());
    }
    if (yr.lo < 0 && yr.hi > 0) {
        const float y = to_px(xr.lo, 0.0).y;
        dl->AddLine({a0.x, y}, {a1.x, y}, kAxis);
    }
    dl->AddRect(a0, a1, kAxis);

    // Data, clipped to the area.
    dl->PushClipRect(a0, a1, true);
    for (const auto& t : spec.thresholds) {
        if (!std::isfinite(t.y)) continue;
        const float y = to_px(xr.lo, t.y).y;
        const std::uint32_t col = t.rgba ? t.rgba : kThreshold;
        dashed_hline(dl, a0.x, a1.x, y, col, 1.5f);
        if (!t.name.empty()) {
            // Inside the area: right-aligned above the line, below it when the line is at the
            // top, shortened when the area is narrower than the name.
            const float lfs = std::round(fh * 0.86f);
            const std::string n = fit_text(t.name, lfs, a1.x - a0.x - 8.0f);
            const float tw = text_w(lfs, n);
            float ty = y - lfs - 1.0f;
            if (ty < a0.y + 1.0f) ty = y + 2.0f;
            ty = std::clamp(ty, a0.y + 1.0f, std::max(a0.y + 1.0f, a1.y - lfs - 1.0f));
            dl->AddText(ImGui::GetFont(), lfs, {std::max(a1.x - tw - 4.0f, a0.x + 4.0f), ty}, col,
                        n.c_str());
        }
    }
    std::vector<ImVec2> pts;
    for (std::size_t si = 0; si < spec.series.size(); ++si) {
        const auto& s = spec.series[si];
        if (storage->GetBool(hidden_id(s.name), false)) continue;
        const std::uint32_t col = s.rgba ? s.rgba : palette_color(si);
        const std::size_t n = s.size();
        pts.clear();
        auto flush = [&]() {
            if (pts.size() >= 2)
                dl->AddPolyline(pts.data(), static_cast<int>(pts.size()), col, 0, s.thickness);
            else if (pts.size() == 1)
                dl->AddCircleFilled(pts[0], s.thickness + 1.0f, col);
            pts.clear();
        };
        for (std::size_t i = 0; i < n; ++i) {
            const double x = s.px(i), y = s.py(i);
            if (!std::isfinite(x) || !std::isfinite(y)) {
                flush();
                continue;
            }
            const ImVec2 p = to_px(x, y);
            if (s.markers) dl->AddCircleFilled(p, 2.0f, col);
            // Skip points that land on the same pixel column as the previous one (dense history).
            if (!pts.empty() && std::fabs(p.x - pts.back().x) < 0.5f &&
                std::fabs(p.y - pts.back().y) < 0.5f)
                continue;
            pts.push_back(p);
        }
        flush();
    }
    dl->PopClipRect();

    // Legend (laid out above): click an entry to hide/show its series.
    if (!legend.entries.empty()) {
        r.legend_min = {FLT_MAX, FLT_MAX};
        r.legend_max = {-FLT_MAX, -FLT_MAX};
        for (const LegendEntry& e : legend.entries) {
            r.legend_min = {std::min(r.legend_min.x, e.pos.x), std::min(r.legend_min.y, e.pos.y)};
            r.legend_max = {std::max(r.legend_max.x, e.pos.x + e.w),
                            std::max(r.legend_max.y, e.pos.y + legend.font)};
        }
        const ImVec2 mouse = ImGui::GetIO().MousePos;
        const float lfs = legend.font;
        for (const LegendEntry& e : legend.entries) {
            const auto& s = spec.series[e.series];
            const ImGuiID hid = hidden_id(s.name);
            const bool hidden = storage->GetBool(hid, false);
            const std::uint32_t col = s.rgba ? s.rgba : palette_color(e.series);
            const ImVec2 e1{e.pos.x + e.w, e.pos.y + lfs};
            if (r.hovered && mouse.x >= e.pos.x && mouse.x < e1.x && mouse.y >= e.pos.y &&
                mouse.y < e1.y && ImGui::IsMouseClicked(ImGuiMouseButton_Left))
                storage->SetBool(hid, !hidden);
            const ImVec2 q0{e.pos.x, e.pos.y + lfs * 0.2f},
                q1{e.pos.x + legend.swatch, e.pos.y + lfs * 0.8f};
            if (hidden)
                dl->AddRect(q0, q1, col);
            else
                dl->AddRectFilled(q0, q1, col);
            const std::string name(s.name);
            dl->AddText(ImGui::GetFont(), lfs, {e.pos.x + legend.swatch + legend.pad, e.pos.y},
                        hidden ? kDimText : kText, name.c_str());
        }
        if (legend.more > 0) {
            const std::string more = "+" + std::to_string(legend.more);
            dl->AddText(ImGui::GetFont(), lfs, legend.more_pos, kDimText, more.c_str());
            const ImVec2 mouse1{legend.more_pos.x + text_w(lfs, more), legend.more_pos.y + lfs};
            if (r.hovered && mouse.x >= legend.more_pos.x && mouse.x < mouse1.x &&
                mouse.y >= legend.more_pos.y && mouse.y < mouse1.y) {
                ImGui::BeginTooltip();
                for (std::size_t i = spec.series.size() - legend.more; i < spec.series.size(); ++i)
                    ImGui::TextColored(
                        ImColor(spec.series[i].rgba ? spec.series[i].rgba : palette_color(i)), "%s",
                        std::string(spec.series[i].name).c_str());
                ImGui::EndTooltip();
            }
        }
    }
    dl->PopClipRect();  // the frame's

    // Hover read-out: cursor line and the value of every series at the nearest x.
    const ImVec2 m = ImGui::GetIO().MousePos;
    if (r.hovered && m.x >= a0.x && m.x <= a1.x && m.y >= a0.y && m.y <= a1.y) {
        const double mx =
            xr.lo + static_cast<double>((m.x - a0.x) / (a1.x - a0.x)) * (xr.hi - xr.lo);
        const double my =
            yr.lo + static_cast<double>((a1.y - m.y) / (a1.y - a0.y)) * (yr.hi - yr.lo);
        dl->AddLine({m.x, a0.y}, {m.x, a1.y}, IM_COL32(255, 255, 255, 70));
        ImGui::BeginTooltip();
        ImGui::Text("%s %s   y %s", spec.x_label.empty() ? "x" : std::string(spec.x_label).c_str(),
                    format_tick(mx, xstep / 10).c_str(), format_tick(my, ystep / 10).c_str());
        for (std::size_t si = 0; si < spec.series.size(); ++si) {
            const auto& s = spec.series[si];
            if (storage->GetBool(hidden_id(s.name), false) || s.size() == 0) continue;
            std::size_t best = 0;
            double bd = std::numeric_limits<double>::infinity();
            // Nearest in x (a time series), or nearest on the map (equal aspect: a path).
            for (std::size_t i = 0; i < s.size(); ++i) {
                const double d = spec.equal_aspect ? std::hypot(s.px(i) - mx, s.py(i) - my)
                                                   : std::fabs(s.px(i) - mx);
                if (std::isfinite(d) && d < bd) {
                    bd = d;
                    best = i;
                }
            }
            if (!std::isfinite(bd)) continue;
            const std::uint32_t col = s.rgba ? s.rgba : palette_color(si);
            const ImVec2 hp = to_px(s.px(best), s.py(best));
            if (hp.x >= a0.x && hp.x <= a1.x && hp.y >= a0.y && hp.y <= a1.y)
                dl->AddCircle(hp, 4.0f, col, 0, 1.5f);
            if (spec.equal_aspect)
                ImGui::TextColored(ImColor(col), "%s: (%.4g, %.4g)", std::string(s.name).c_str(),
                                   s.px(best), s.py(best));
            else
                ImGui::TextColored(ImColor(col), "%s: %.4g", std::string(s.name).c_str(),
                                   s.py(best));
        }
        for (const auto& t : spec.thresholds)
            ImGui::TextColored(ImColor(t.rgba ? t.rgba : kThreshold), "%s: %.4g",
                               std::string(t.name).c_str(), t.y);
        ImGui::EndTooltip();
    }
    ImGui::PopID();
    return r;
}

}  // namespace gs::ui
