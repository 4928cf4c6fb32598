// Leaving a flying drone asks first. Quitting, disconnecting, opening a replay or connecting to
// another source all stop commanding the drone; while it flies, each waits behind one question:
// "Land, then <do it>" (the drone lands, and it is done once navdata says it is down) or
// "Cancel" (or Escape). With the link lost the drone cannot be told to land: a third button does
// it now.
#include "ui/gui.hpp"

#include <cstdio>

namespace gs::ui {

const char* leave_verb(LeaveKind k) {
    switch (k) {
        case LeaveKind::None:
            return "";
        case LeaveKind::Quit:
            return "quit";
        case LeaveKind::Disconnect:
            return "disconnect";
        case LeaveKind::OpenReplay:
            return "open the replay";
        case LeaveKind::Connect:
            return "connect";
    }
    return "?";
}

namespace {

constexpr const char* kLeavePopup = "The drone is flying";

// What happens to the drone if the request is carried out now.
std::string consequence(const LeaveRequest& r) {
    switch (r.kind) {
        case LeaveKind::Quit:
            return "Closing the ground station now would leave the drone without commands.";
        case LeaveKind::Disconnect:
            return "Disconnecting now would leave the drone without commands.";
        case LeaveKind::OpenReplay:
            return "Opening the replay " + r.replay_path +
                   " closes the link: the drone would be left without commands.";
        case LeaveKind::Connect:
            return std::string("Connecting to ") +
                   (r.connect.sim ? "the virtual drone" : r.connect.address) +
                   " closes the link to this drone: it would be left without commands.";
        case LeaveKind::None:
            break;
    }
    return {};
}

void apply(const LeaveRequest& r, Actions& a) {
    switch (r.kind) {
        case LeaveKind::Quit:
            a.quit = true;
            break;
        case LeaveKind::Disconnect:
            a.disconnect = true;
            break;
        case LeaveKind::OpenReplay:
            a.replay_open = r.replay_path;
            break;
        case LeaveKind::Connect:
            a.connect = r.connect;
            break;
        case LeaveKind::None:
            break;
    }
}

}  // namespace

bool Gui::commanding_flying_drone(const GuiSnapshot& s) {
    const LinkState st = s.connection.state;
    const bool live = st == LinkState::Connected || st == LinkState::Lost;
    return live && s.telemetry.state && s.telemetry.state->flying;
}

bool Gui::request_close(const GuiSnapshot& s) {
    if (!commanding_flying_drone(s)) return true;
    view_.leave_asked = LeaveRequest{LeaveKind::Quit, {}, {}};
    view_.leave_popup_requested = true;
    return false;
}

void Gui::guard_leaving(const GuiSnapshot& s, Actions& a) {
    LeaveRequest r;
    if (a.disconnect)
        r.kind = LeaveKind::Disconnect;
    else if (a.replay_open)
        r = LeaveRequest{LeaveKind::OpenReplay, *a.replay_open, {}};
    else if (a.connect)
        r = LeaveRequest{LeaveKind::Connect, {}, *a.connect};
    if (!r.pending() || !commanding_flying_drone(s)) return;
    a.disconnect = false;
    a.replay_open.reset();
    a.connect.reset();
    view_.leave_asked = std::move(r);
    view_.leave_popup_requested = true;
}

// A window, not a modal popup: the status bar's Land and EMERGENCY stay clickable while it is
// up. Escape or Cancel closes it; nothing happens to the drone until a button says so.
void Gui::draw_leave_dialog(const GuiSnapshot& s, Actions& a) {
    view_.quit_dialog_open = false;
    const bool appearing = view_.leave_popup_requested;
    view_.leave_popup_requested = false;
    if (!view_.leave_asked.pending()) return;
    const ImVec2 c{ImGui::GetIO().DisplaySize.x * 0.5f, ImGui::GetIO().DisplaySize.y * 0.5f};
    ImGui::SetNextWindowPos(c, appearing ? ImGuiCond_Always : ImGuiCond_Appearing, {0.5f, 0.5f});
    if (appearing) ImGui::SetNextWindowFocus();
    const bool visible =
        ImGui::Begin(kLeavePopup, nullptr,
                     ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse |
                         ImGuiWindowFlags_NoSavedSettings);
    {
        const ImVec2 wp = ImGui::GetWindowPos(), ws = ImGui::GetWindowSize();
        view_.layout.windows.push_back({kLeavePopup, {wp.x, wp.y, wp.x + ws.x, wp.y + ws.y}});
    }
    if (!visible) {
        ImGui::End();
        return;
    }
    view_.quit_dialog_open = true;
    const LeaveRequest r = view_.leave_asked;
    const bool lost = s.connection.state == LinkState::Lost;
    ImGui::TextUnformatted(consequence(r).c_str());
    if (lost)
        ImGui::TextColored(colors::v4(colors::kWarn),
                           "The link is lost: the drone cannot be told to land until it is back.");
    ImGui::Text("Land first? This is done once the drone reports it has landed.");
    ImGui::Spacing();
    const std::string verb = leave_verb(r.kind);
    const bool quit = r.kind == LeaveKind::Quit;
    const std::string land_label = "Land, then " + verb;
    const float fs = ImGui::GetFontSize();
    const bool land = ImGui::Button(land_label.c_str(), {fs * 13.0f, 0});
    record_button(view_, "leave.land");
    if (quit) record_button(view_, "quit.land");
    ImGui::SameLine();
    const bool cancel = ImGui::Button("Cancel", {fs * 8.0f, 0});
    record_button(view_, "leave.cancel");
    if (quit) record_button(view_, "quit.cancel");
    bool now = false;
    if (lost) {
        ImGui::SameLine();
        const std::string now_label = std::string("Link lost: ") + verb + " now";
        now = ImGui::Button(now_label.c_str());
        record_button(view_, "leave.now");
    }
    ImGui::End();
    if (land) {
        a.land = true;
        view_.leave_after_landing = r;
        view_.quit_after_landing = quit;
        a.notes.push_back("landing, then " + verb);
    }
    if (now) apply(r, a);
    if (land || cancel || now) view_.leave_asked = {};
}

void Gui::finish_leaving(const GuiSnapshot& s, Actions& a) {
    LeaveRequest& r = view_.leave_after_landing;
    if (!r.pending()) return;
    // Taking off again (or cutting the motors) cancels what waited for the landing.
    if (a.takeoff || a.emergency) {
        a.notes.push_back(std::string("cancelled: ") + leave_verb(r.kind) + " after landing");
        r = {};
        view_.quit_after_landing = false;
        return;
    }
    if (commanding_flying_drone(s)) return;
    apply(r, a);
    r = {};
    view_.quit_after_landing = false;
}

}  // namespace gs::ui
