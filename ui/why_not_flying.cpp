#include "ui/windows.hpp"

#include <cstdio>

namespace gs::ui {

std::vector<Reason> explain_not_flying(const GuiSnapshot& s) {
    std::vector<Reason> out;
    auto add = [&](Severity sev, std::string t, std::string d) {
        out.push_back({sev, std::move(t), std::move(d)});
    };
    switch (s.connection.state) {
        case LinkState::Disconnected:
            add(Severity::Blocker, "Not connected",
                s.connection.reason.empty() ? "Connect to the drone (or the virtual drone) first."
                                            : s.connection.reason);
            return out;
        case LinkState::Connecting:
            add(Severity::Blocker, "Connecting",
                s.connection.reason.empty() ? "Waiting for the first navdata from the drone."
                                            : s.connection.reason);
            return out;
        case LinkState::Lost:
            add(Severity::Blocker, "Link lost",
                (s.connection.reason.empty() ? std::string("No navdata from the drone.")
                                             : s.connection.reason) +
                    " A flying drone hovers, then lands by itself after about 2 s without "
                    "commands.");
            break;
        case LinkState::Replay:
            add(Severity::Info, "Replay", "Showing a recorded flight: there is no drone to fly.");
            return out;
        case LinkState::Connected:
            break;
    }
    if (!s.telemetry.valid || !s.telemetry.state) {
        add(Severity::Blocker, "No drone state yet",
            "Navdata has not reported the drone state bits.");
        return out;
    }
    const DroneStateBits& b = *s.telemetry.state;
    if (b.navdata_bootstrap)
        add(Severity::Warning, "Navdata in bootstrap",
            "The drone sends only its header: the ground station has not configured navdata yet.");
    // A cut-out the pilot commanded is no fault: the drone sets its cut-out bit either way, so
    // only an emergency nobody asked for points at the propellers.
    const bool commanded = b.emergency && s.telemetry.emergency_commanded;
    if (commanded)
        add(Severity::Blocker, "Emergency: motors cut by the pilot",
            "You cut the motors (EMERGENCY). Check the drone, set it level on the ground, then "
            "press EMERGENCY once more to reset the emergency; take off again when ready.");
    else if (b.emergency)
        add(Severity::Blocker, "Emergency: motors cut",
            "The drone cut its motors by itself and will not start. Find the cause below, set it "
            "flat, then press EMERGENCY once to reset the emergency.");
    if (b.user_emergency_landing)
        add(Severity::Blocker, "User emergency landing", "An emergency landing was requested.");
    if (b.battery_low)
        add(Severity::Blocker, "Battery too low (VBAT_LOW)",
            "The drone refuses to take off and lands when flying. Replace or charge the battery.");
    else if (s.telemetry.valid && known(s.telemetry.nav.battery_pct) &&
             s.telemetry.nav.battery_pct < s.telemetry.battery_low_pct) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "Battery at %.0f%%: expect a forced landing soon.",
                      s.telemetry.nav.battery_pct);
        add(Severity::Warning, "Battery low", buf);
    }
    if (b.angles_out_of_range)
        add(Severity::Blocker, "Angles out of range",
            "The drone is tilted too much (crash or flip). Put it flat on the ground, then clear "
            "the emergency.");
    if (b.cutout && !commanded)
        add(Severity::Blocker, "Motor cut-out",
            "A motor was cut (propeller blocked or hit). Check the propellers and the hull.");
    if (b.motors_problem)
        add(Severity::Blocker, "Motor problem", "A motor or its controller reports a fault.");
    if (b.software_fault)
        add(Severity::Blocker, "Software fault",
            "The drone reports a software fault: land as soon as possible and restart it.");
    if (b.com_lost)
        add(Severity::Blocker, "Communication lost (COM_LOST)",
            "The drone lost our commands; it hovers and lands if they do not come back.");
    if (b.com_watchdog && !b.navdata_bootstrap)
        add(Severity::Warning, "Communication watchdog",
            "The drone got no command for more than 50 ms; the link answers with AT*COMWDG.");
    if (b.ultrasound_deaf)
        add(Severity::Warning, "Ultrasound altimeter deaf",
            "Altitude hold is unreliable (soft or reflective floor, or sensor fault).");
    if (b.too_much_wind)
        add(Severity::Warning, "Too much wind", "The drone cannot hold its position.");
    if (b.ctrl_watchdog || b.adc_watchdog)
        add(Severity::Warning, "On-board watchdog",
            b.ctrl_watchdog ? "The control loop ran late (> 5 ms)."
                            : "The nav-board link ran late (> 5 ms).");
    if (b.timer_elapsed) add(Severity::Info, "Timer elapsed", "The drone's flight timer elapsed.");
    if (b.magneto_needs_calib)
        add(Severity::Info, "Magnetometer needs calibration",
            "Heading may drift; calibrate while flying.");

    bool blocked = false;
    for (const auto& r : out) blocked = blocked || r.severity == Severity::Blocker;
    if (!blocked) {
        if (b.flying)
            add(Severity::Ok, "Flying",
                std::string("Control state ") + s.telemetry.ctrl_state + ".");
        else
            add(Severity::Ok, "Ready to take off", "No state bit prevents a take-off.");
    }
    return out;
}

void WhyNotFlyingWindow::draw(const GuiSnapshot& s, ViewState& v) {
    if (ImGui::Begin("Why not flying", &v.open.why_not_flying)) {
        for (const Reason& r : explain_not_flying(s)) {
            std::uint32_t col = colors::kInfo;
            const char* tag = "INFO";
            switch (r.severity) {
                case Severity::Blocker:
                    col = colors::kBad;
                    tag = "BLOCK";
                    break;
                case Severity::Warning:
                    col = colors::kWarn;
                    tag = "WARN";
                    break;
                case Severity::Info:
                    col = colors::kInfo;
                    tag = "INFO";
                    break;
                case Severity::Ok:
                    col = colors::kGood;
                    tag = "OK";
                    break;
            }
            ImGui::TextColored(colors::v4(col), "%-5s", tag);
            ImGui::SameLine(ImGui::GetFontSize() * 4.4f);
            ImGui::TextColored(colors::v4(col), "%s", r.title.c_str());
            if (!r.detail.empty()) {
                ImGui::Indent(ImGui::GetFontSize() * 4.4f - ImGui::GetStyle().WindowPadding.x);
                ImGui::PushTextWrapPos(0);
                ImGui::TextColored(colors::v4(colors::kDim), "%s", r.detail.c_str());
                ImGui::PopTextWrapPos();
                ImGui::Unindent(ImGui::GetFontSize() * 4.4f - ImGui::GetStyle().WindowPadding.x);
            }
        }
    }
    ImGui::End();
}

}  // namespace gs::ui
