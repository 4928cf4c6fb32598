#pragma once
// Canned snapshots for exercising the window before (and without) a link: a plausible flight
// with a synthetic camera image, classifier overlay and plots (left region flagged), plus the
// "no link" and "no video" edge cases. Deterministic in the frame number.

#include "ui/snapshot.hpp"

namespace gs::ui {

struct DemoOptions {
    double battery_pct = 67.0;
    bool flag_left = true, flag_center = false, flag_right = false;
    int width = 640, height = 360;
    double fps = 30.0;
};

// Fills `out` for `frame` (reuses out.video.bgr's buffer when the size matches).
void make_demo_snapshot(GuiSnapshot& out, int frame, const DemoOptions& opt = {});
// Disconnected: no telemetry, no video, no classifier output.
GuiSnapshot demo_no_link();
// Connected and flying, telemetry flowing, but no video frame yet.
GuiSnapshot demo_no_video();

}  // namespace gs::ui
