#pragma once
// Where the windows go. The main menu bar and the status bar (take-off / land / emergency, the
// flight state) are fixed at the top and cannot be scrolled, moved or closed away; every other
// window lies below them. Two layouts: the engineering one (video, plots, connection, classifier,
// telemetry, link ...) and the flight one (the video filling the window above a compact plot
// strip). Windows are kept inside the viewport: a saved layout from a bigger screen, a window
// dragged off or a resize is re-anchored, and View -> Reset layout puts every window back.

#include "ui/view_state.hpp"

#include <imgui.h>

#include <string_view>

namespace gs::ui {

// Heights of the fixed bars at the top (they depend on the font).
float menu_bar_height();
float status_bar_height();
// Top of the area windows may use (below the menu and the status bar).
float content_top();
// Height of the flight layout's plot strip at the bottom.
float plot_strip_height(ImVec2 display);

// Default rectangle of a window in a layout for a display of `size`.
Rect default_window_rect(const char* window, ImVec2 display,
                         LayoutMode mode = LayoutMode::Engineering);
// `r` moved (and shrunk if it must) so that it lies inside [0, top] .. display.
Rect keep_inside(const Rect& r, ImVec2 display, float top);

// Positions the next window: the layout's default the first time (or always after a reset or in
// the flight layout, whose windows are fixed), else where it was, scaled when the viewport
// changed size and pulled back inside the viewport when it lies outside. Call before Begin.
void place_window(const char* window, ImVec2 display, ViewState& v);

// Once per frame after the windows: remembers the layout drawn and counts down a layout reset.
void end_layout_frame(ViewState& v);

}  // namespace gs::ui
