// Single widgets drawn on a bare ImGui context (no renderer): the plot widget's layout (legend
// outside the data area, equal scales on a map, padded autoscale), number formatting for scores,
// and the replay window's numeric speed field driven by synthetic clicks and typing.
#include "imgui_fixture.hpp"
#include "ui/plot.hpp"
#include "ui/windows.hpp"

#include <GLFW/glfw3.h>
#include <imgui_internal.h>

#include <cmath>
#include <string>
#include <vector>

namespace gs::ui::test {
namespace {

class Widgets : public ImGuiFixture {
protected:
    // One frame with `draw` inside a fixed window at (0, 0), size `size`.
    template <class F>
    void window_frame(ImVec2 size, F&& draw) {
        ImGui::NewFrame();
        ImGui::SetNextWindowPos({0, 0});
        ImGui::SetNextWindowSize(size);
        ImGui::Begin("test", nullptr, ImGuiWindowFlags_NoDecoration);
        draw();
        ImGui::End();
        ImGui::Render();
    }
};

TEST(FormatSig, SmallScoresKeepTheirSignificantDigits) {
    EXPECT_EQ(format_sig(1e-4), "0.0001");
    EXPECT_EQ(format_sig(0.00012345), "0.000123");
    EXPECT_EQ(format_sig(0.5234), "0.523");
    EXPECT_EQ(format_sig(12.345), "12.3");
    EXPECT_EQ(format_sig(12345.6), "12346");
    EXPECT_EQ(format_sig(-0.0021), "-0.0021");
    EXPECT_EQ(format_sig(std::nan("")), "-");
}

TEST(PlotScale, AFixedLimitKeepsThePadOnTheFreeSide) {
    // Altitude from 0 (fixed) up to 1.0 m: the top is padded, not on the border.
    const Range r = axis_range(0.2, 1.0, 0.0, std::nullopt, 0.08);
    EXPECT_EQ(r.lo, 0.0);
    EXPECT_NEAR(r.hi, 1.08, 1e-9);
    // Both free: symmetric pad; both fixed: as given.
    const Range f = axis_range(1.0, 3.0, std::nullopt, std::nullopt, 0.1);
    EXPECT_NEAR(f.lo, 0.8, 1e-9);
    EXPECT_NEAR(f.hi, 3.2, 1e-9);
    const Range b = axis_range(10.0, 20.0, 0.0, 100.0, 0.1);
    EXPECT_EQ(b.lo, 0.0);
    EXPECT_EQ(b.hi, 100.0);
}

TEST_F(Widgets, LegendStaysOutsideTheDataAreaWhateverTheWidth) {
    std::vector<double> ys(50);
    for (std::size_t i = 0; i < ys.size(); ++i) ys[i] = std::sin(0.2 * static_cast<double>(i));
    const std::vector<std::string> names = {"left score",   "left threshold",
                                            "centre score", "centre threshold",
                                            "right score",  "right threshold"};
    for (float width : {1200.0f, 420.0f, 200.0f}) {
        PlotSpec spec;
        spec.title = "Region scores";
        spec.y_label = "score";
        for (const auto& n : names) {
            PlotSeriesView s;
            s.name = n;
            s.y = ys;
            spec.series.push_back(s);
        }
        PlotResult r;
        window_frame({width + 20, 300}, [&] { r = draw_plot("scores", spec, {width, 260}); });
        ASSERT_GT(r.legend_max.x, r.legend_min.x) << "legend drawn at width " << width;
        // Entirely above the data area and within the widget.
        EXPECT_LE(r.legend_max.y, r.area_min.y) << width;
        EXPECT_GE(r.legend_min.y, r.frame_min.y) << width;
        EXPECT_GE(r.legend_min.x, r.frame_min.x) << width;
        EXPECT_LE(r.legend_max.x, r.frame_max.x) << width;
        // The data area keeps most of the widget's height.
        EXPECT_GT(r.area_max.y - r.area_min.y, 0.5f * 260) << width;
    }
}

TEST_F(Widgets, EqualAspectMapHasTheSameScaleOnBothAxesAndShowsAllPoints) {
    // A path 10 m right and 1 m forward in a tall widget, then in a wide one.
    const std::vector<double> x = {0, 2, 5, 10}, y = {0, 1, 0.5, 1};
    for (ImVec2 size : {ImVec2{300, 500}, ImVec2{700, 200}}) {
        PlotSpec spec;
        spec.title = "Flight path";
        spec.equal_aspect = true;
        PlotSeriesView s;
        s.name = "navdata";
        s.x = x;
        s.y = y;
        spec.series.push_back(s);
        PlotResult r;
        window_frame({size.x + 20, size.y + 20}, [&] { r = draw_plot("map", spec, size); });
        const double xpp = (r.x_hi - r.x_lo) / static_cast<double>(r.area_max.x - r.area_min.x);
        const double ypp = (r.y_hi - r.y_lo) / static_cast<double>(r.area_max.y - r.area_min.y);
        EXPECT_NEAR(ypp / xpp, 1.0, 1e-6) << size.x << "x" << size.y;
        for (std::size_t i = 0; i < x.size(); ++i) {
            EXPECT_GE(x[i], r.x_lo);
            EXPECT_LE(x[i], r.x_hi);
            EXPECT_GE(y[i], r.y_lo);
            EXPECT_LE(y[i], r.y_hi);
        }
    }
}

TEST_F(Widgets, HoverOverTheDataAreaOpensTheReadOut) {
    const std::vector<double> ys = {0, 1, 2, 3, 4};
    PlotSpec spec;
    spec.title = "t";
    PlotSeriesView s;
    s.name = "altitude";
    s.y = ys;
    spec.series.push_back(s);
    PlotResult r;
    window_frame({420, 320}, [&] { r = draw_plot("p", spec, {400, 300}); });
    ImGuiIO& io = ImGui::GetIO();
    io.MousePos = {0.5f * (r.area_min.x + r.area_max.x), 0.5f * (r.area_min.y + r.area_max.y)};
    for (int i = 0; i < 2; ++i)
        window_frame({420, 320}, [&] { r = draw_plot("p", spec, {400, 300}); });
    EXPECT_TRUE(r.hovered);
    // The read-out is a tooltip window.
    ImGuiWindow* tip = ImGui::FindWindowByName("##Tooltip_00");
    ASSERT_NE(tip, nullptr);
    EXPECT_TRUE(tip->Active || tip->WasActive);
    io.MousePos = {-FLT_MAX, -FLT_MAX};
}

class ReplaySpeedField : public Widgets {
protected:
    // Draws the replay window with a dataset open at `speed`; returns its actions.
    Actions draw(double speed) {
        GuiSnapshot s;
        s.replay.open = true;
        s.replay.frame_count = 100;
        s.replay.fps = 30;
        s.replay.speed = speed;
        Actions a;
        view.layout = LayoutReport{};
        ImGui::NewFrame();
        ImGui::SetNextWindowPos({0, 0});
        ImGui::SetNextWindowSize({700, 300});
        win.draw(s, view, a);
        ImGui::Render();
        return a;
    }
    // Clicks the field, types `text` and presses Enter; the actions of the Enter frame.
    Actions type_speed(const std::string& text, double speed) {
        ImGuiIO& io = ImGui::GetIO();
        io.KeyMap[ImGuiKey_Enter] = GLFW_KEY_ENTER;
        (void)draw(speed);
        const Rect* f = view.layout.button("replay_speed_value");
        EXPECT_NE(f, nullptr);
        if (!f) return {};
        io.MousePos = {0.5f * (f->x0 + f->x1), 0.5f * (f->y0 + f->y1)};
        (void)draw(speed);
        io.MouseDown[0] = true;
        (void)draw(speed);
        io.MouseDown[0] = false;
        (void)draw(speed);
        // Select what is there and replace it.
        io.KeyCtrl = true;
        io.KeyMap[ImGuiKey_A] = GLFW_KEY_A;
        io.KeysDown[GLFW_KEY_A] = true;
        (void)draw(speed);
        io.KeysDown[GLFW_KEY_A] = false;
        io.KeyCtrl = false;
        for (char c : text) io.AddInputCharacter(static_cast<unsigned>(c));
        (void)draw(speed);
        io.KeysDown[GLFW_KEY_ENTER] = true;
        const Actions a = draw(speed);
        io.KeysDown[GLFW_KEY_ENTER] = false;
        (void)draw(speed);
        io.MousePos = {-FLT_MAX, -FLT_MAX};
        return a;
    }
    ReplayWindow win;
    ViewState view;
};

TEST_F(ReplaySpeedField, ATypedSpeedIsSentAndClampedToTheRange) {
    Actions a = type_speed("3", 1.0);
    ASSERT_TRUE(a.replay_speed.has_value());
    EXPECT_DOUBLE_EQ(*a.replay_speed, 3.0);
    a = type_speed("1.5", 3.0);
    ASSERT_TRUE(a.replay_speed.has_value());
    EXPECT_DOUBLE_EQ(*a.replay_speed, 1.5);
    a = type_speed("20", 1.0);
    ASSERT_TRUE(a.replay_speed.has_value());
    EXPECT_DOUBLE_EQ(*a.replay_speed, kReplayMaxSpeed);
    a = type_speed("0.1", 1.0);
    ASSERT_TRUE(a.replay_speed.has_value());
    EXPECT_DOUBLE_EQ(*a.replay_speed, kReplayMinSpeed);
    // Nothing typed, nothing sent.
    EXPECT_FALSE(draw(2.0).replay_speed.has_value());
}

}  // namespace
}  // namespace gs::ui::test
