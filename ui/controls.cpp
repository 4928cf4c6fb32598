#include "ui/controls.hpp"

#include "ui/windows.hpp"

#include <cmath>
#include <cstdio>

namespace gs::ui {

const char* to_string(Control c) {
    switch (c) {
        case Control::Takeoff:
            return "take-off";
        case Control::Land:
            return "land";
        case Control::Emergency:
            return "emergency";
        case Control::FlatTrim:
            return "flat trim";
        case Control::Calibrate:
            return "magnetometer calibration";
        case Control::SwitchCamera:
            return "camera switch";
        case Control::Record:
            return "recording";
    }
    return "?";
}

namespace {

bool link_exists(const GuiSnapshot& s) {
    const LinkState st = s.connection.state;
    return st == LinkState::Connecting || st == LinkState::Connected || st == LinkState::Lost;
}

std::string no_drone_reason(const GuiSnapshot& s) {
    if (s.connection.state == LinkState::Replay)
        return "this is a replay of a recorded flight: there is no drone to command";
    if (s.connection.opening) return s.connection.activity;
    return "not connected to a drone";
}

}  // namespace

ControlState control_state(const GuiSnapshot& s, Control c) {
    if (s.connection.source == SourceKind::Demo) return {};
    if (c == Control::Record && s.recording.active) return {};  // stopping is always possible
    const bool link = link_exists(s);
    const bool connected = s.connection.state == LinkState::Connected;
    const std::optional<DroneStateBits>& b = s.telemetry.state;
    const bool known = s.telemetry.valid && b.has_value();
    const bool flying = known && b->flying;
    const bool emergency = known && b->emergency;
    if (!link) return {false, no_drone_reason(s)};
    switch (c) {
        case Control::Emergency:
            return {};
        case Control::Land:
            if (connected && known && !flying && !emergency)
                return {false, "the drone is on the ground"};
            return {};
        case Control::Takeoff: {
            if (!connected)
                return {false, s.connection.state == LinkState::Lost
                                   ? "the link is lost: the drone's state is unknown"
                                   : "still connecting"};
            if (!known) return {false, "no navdata from the drone yet"};
            if (emergency) return {false, "the drone is in emergency: clear it first"};
            if (flying) return {false, "already flying"};
            const double bat = s.telemetry.nav.battery_pct;
            if ((std::isfinite(bat) && bat < s.telemetry.battery_low_pct) || b->battery_low) {
                char buf[96];
                std::snprintf(buf, sizeof buf, "battery %.0f %% is below the %.0f %% minimum", bat,
                              s.telemetry.battery_low_pct);
                return {false, std::isfinite(bat) ? buf : "the drone reports a low battery"};
            }
            if (b->angles_out_of_range) return {false, "the drone is not level"};
            return {};
        }
        case Control::FlatTrim:
            if (!connected || !known) return {false, "needs the drone connected and landed"};
            if (flying) return {false, "only on the ground, on a level surface"};
            return {};
        case Control::Calibrate:
            if (!connected || !known) return {false, "needs the drone connected and flying"};
            if (!flying) return {false, "only in flight: the drone turns a full circle"};
            return {};
        case Control::SwitchCamera:
            if (!connected) return {false, "needs the drone connected"};
            return {};
        case Control::Record:
            return {};  // any link records (from its first byte); stopping is always possible
    }
    return {};
}

FlightStateView flight_state(const GuiSnapshot& s) {
    FlightStateView v;
    const Telemetry& t = s.telemetry;
    if (!t.valid) {
        v.text = s.connection.state == LinkState::Replay ? "NO NAVDATA" : "NO DATA";
        v.color = colors::kDim;
        return v;
    }
    if (!t.state) {  // attitude and speeds, but no state bits (a dataset that has none)
        v.text = "STATE UNKNOWN";
        v.color = colors::kDim;
        return v;
    }
    v.flying = t.state->flying;
    if (t.state->emergency) {
        v.text = "EMERGENCY";
        v.color = colors::kBad;
        return v;
    }
    const std::uint32_t major = t.nav.ctrl_state ? (*t.nav.ctrl_state >> 16) : 0xFFFFu;
    switch (major) {
        case 0:
        case 1:
            v.text = "INIT";
            v.color = colors::kDim;
            break;
        case 2:
            v.text = "LANDED";
            v.color = colors::kText;
            break;
        case 3:
            v.text = "FLYING";
            v.color = colors::kInfo;
            break;
        case 4:
            v.text = "HOVERING";
            v.color = colors::kInfo;
            break;
        case 6:
            v.text = "TAKING OFF";
            v.color = colors::kWarn;
            break;
        case 7:
            v.text = "GOING TO FIX";
            v.color = colors::kInfo;
            break;
        case 8:
            v.text = "LANDING";
            v.color = colors::kWarn;
            break;
        case 9:
            v.text = "LOOPING";
            v.color = colors::kWarn;
            break;
        default:
            v.text = v.flying ? "FLYING" : "LANDED";
            v.color = v.flying ? colors::kInfo : colors::kText;
            break;
    }
    if (s.connection.state == LinkState::Replay) v.text += " (recorded)";
    if (t.stale) {
        char buf[48];
        std::snprintf(buf, sizeof buf, " - stale %.1f s", t.age_ms / 1000.0);
        v.text += buf;
        v.color = colors::kWarn;
    }
    return v;
}

SourceBadge source_badge(const GuiSnapshot& s) {
    switch (s.connection.state) {
        case LinkState::Replay:
            return {"REPLAY", IM_COL32(230, 120, 20, 255)};
        case LinkState::Disconnected:
            if (!s.connection.opening) return {"NO SOURCE", IM_COL32(70, 74, 82, 255)};
            break;
        default:
            break;
    }
    switch (s.connection.source) {
        case SourceKind::Drone:
            return {"LIVE DRONE", IM_COL32(30, 140, 70, 255)};
        case SourceKind::Sim:
            return {"VIRTUAL DRONE", IM_COL32(70, 90, 200, 255)};
        case SourceKind::Replay:
            return {"REPLAY", IM_COL32(230, 120, 20, 255)};
        case SourceKind::Demo:
            return {"DEMO", IM_COL32(120, 80, 150, 255)};
    }
    return {"?", IM_COL32(70, 74, 82, 255)};
}

int link_quality(const GuiSnapshot& s) {
    if (s.connection.state != LinkState::Connected && s.connection.state != LinkState::Lost)
        return 0;
    const StreamHealth& n = s.link.navdata;
    if (!std::isfinite(n.age_ms) || n.age_ms > kStaleAfterMs) return 0;
    const double expected =
        std::isfinite(s.link.expected_navdata_hz) ? s.link.expected_navdata_hz : 15.0;
    const double r = std::isfinite(n.rate_hz) ? n.rate_hz / expected : 0.0;
    int q = r >= 0.9 ? 4 : r >= 0.7 ? 3 : r >= 0.4 ? 2 : 1;
    if (n.age_ms > 200 && q > 2) q = 2;
    return q;
}

}  // namespace gs::ui
