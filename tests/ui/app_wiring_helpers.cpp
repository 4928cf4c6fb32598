// The window's wiring (app/session, app/gui_adapter, app/pipeline) is compiled into the program,
// not a library, so ui_tests builds the same source files in here to drive them in-process.
#ifndef GS_HAVE_GUI
#define GS_HAVE_GUI 1
#endif
#include "app/gui_adapter.cpp"
#include "app/pipeline.cpp"
#include "app/session.cpp"
