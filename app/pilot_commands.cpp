#include "app/pilot_commands.hpp"

namespace gs::app {

namespace {

bool same(const link::Move& a, const link::Move& b) {
    return a.roll == b.roll && a.pitch == b.pitch && a.gaz == b.gaz && a.yaw == b.yaw;
}

}  // namespace

// Manual input wins: while the pilot steers, every change goes out as Move (the link repeats the
// current command every 30 ms); letting go sends one Hover.
std::optional<link::Command> PilotCommands::next(const std::optional<link::Move>& input) {
    if (input) {
        const bool changed = !steering_ || !same(*input, last_);
        steering_ = true;
        last_ = *input;
        if (!changed) return std::nullopt;
        ++moves_;
        return link::Command{*input};
    }
    if (!steering_) return std::nullopt;
    steering_ = false;
    last_ = {};
    ++hovers_;
    return link::Command{link::Hover{}};
}

void PilotCommands::reset() {
    steering_ = false;
    last_ = {};
}

}  // namespace gs::app
