#pragma once
// Which flight controls can act now, and why not, as pure functions of the snapshot: the status
// bar disables a button with the reason as its tooltip, and a key for a control that cannot act
// is not sent (the message log says why). Land and the emergency are never held back while a
// link exists: landing a landed drone is harmless, and the emergency must always reach it.

#include "ui/snapshot.hpp"

#include <cstdint>
#include <string>

namespace gs::ui {

enum class Control { Takeoff, Land, Emergency, FlatTrim, Calibrate, SwitchCamera, Record };
const char* to_string(Control c);  // "take-off", "land" ...

struct ControlState {
    bool enabled = true;
    std::string why;  // when disabled: why, in a pilot's words
};
ControlState control_state(const GuiSnapshot& s, Control c);

// The flight state in one word or two, as the status bar shows it, with its colour.
struct FlightStateView {
    std::string text;  // "LANDED", "TAKING OFF", "FLYING", "HOVERING", "LANDING", "EMERGENCY" ...
    std::uint32_t color = 0;
    bool flying = false;
};
FlightStateView flight_state(const GuiSnapshot& s);

// The source as a badge: "LIVE DRONE", "VIRTUAL DRONE", "REPLAY", "DEMO", "NO SOURCE".
struct SourceBadge {
    std::string text;
    std::uint32_t background = 0;
};
SourceBadge source_badge(const GuiSnapshot& s);

// Navdata link quality 0..4 from its measured rate against the expected one and its age.
int link_quality(const GuiSnapshot& s);

}  // namespace gs::ui
