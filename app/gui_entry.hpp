#pragma once
// The window entry: `ardrone-gs` with no subcommand opens the ground-station window (or renders
// it offscreen with --offscreen). Options are registered on the root app by app/cmd_gui.cpp.

namespace gs::app {

// Runs the window with the root options parsed; returns the process exit code.
int run_gui();

}  // namespace gs::app
