#pragma once
// What the GuiAdapter's files (app/gui_*.cpp) share: small conversions and the pure functions
// that turn the session's values into the window's view structs. GUI build only.
#ifdef GS_HAVE_GUI

#include "app/session.hpp"
#include "ui/snapshot.hpp"

#include <array>
#include <vector>

namespace gs::app {

// Milliseconds since `last` (unknown when nothing came yet).
inline double age_ms(TimeNs now, TimeNs last) {
    return last > 0 ? ns_to_ms(now - last) : kUnknown;
}

// The three regions as the window names them.
inline constexpr std::array<const char*, 3> kRegionNames = {"left", "center", "right"};

// app/gui_telemetry.cpp: every field of every navdata option present, grouped by option, in wire
// order, names with units (reuses `out`).
void navdata_fields(const protocol::navdata::Navdata& nd, std::vector<ui::TelemetryField>& out);

// app/gui_plots.cpp: the classifier's series as the Plots window draws them (region scores with
// their thresholds, the centre scale and its threshold slope, trajectories, any other series).
void plot_series(const vision::FrameResult& r, double fit_window, std::vector<ui::PlotData>& plots);

// app/gui_video.cpp: the decisions and the overlay of one classified frame, and its plots.
void classifier_output(const PipelineOutput& o, ui::ClassifierOutput& c, double fit_window);
// The odometry's sample and path as the window shows them (reusing the view's vectors).
void odometry_view(const OdometryOutput& o, ui::OdometryView& v);
// Overlay primitives (raw, distorted pixels) moved onto the undistorted image.
void undistort_overlay(ui::Overlay& ov, const CameraCalibration& cal);

}  // namespace gs::app

#endif  // GS_HAVE_GUI
