#pragma once
// The pilot's stick input turned into flight commands for the link's AT sender. The path, in
// order (PilotPath, app/pilot_path.hpp, walks it once per window frame for GuiAdapter::send_pilot):
//   1. the input: ui::Actions::manual / pilot, as a link::Move while the pilot steers;
//   2. the collision-prevention assist (app/pilot_path.hpp): it sees the input every window frame
//      (also when it did not change, so it can react to a new obstacle) and returns the command
//      to send instead;
//   3. PilotCommands::next(): a Move when what is to be sent changed, one Hover on release;
//   4. DroneLink::submit (never blocks; the AT sender repeats the current command every 30 ms).
// No GUI types: the session or a test can drive it the same way.

#include "drone/link/commands.hpp"

#include <cstdint>
#include <optional>

namespace gs::app {

class PilotCommands {
public:
    // `input`: what the pilot (after any filter) asks for this frame; nullopt: not steering.
    // Returns the command to submit now, if any.
    std::optional<link::Command> next(const std::optional<link::Move>& input);
    // A new source: nothing was sent to it yet.
    void reset();

    std::uint64_t moves() const { return moves_; }
    std::uint64_t hovers() const { return hovers_; }

private:
    bool steering_ = false;
    link::Move last_;
    std::uint64_t moves_ = 0, hovers_ = 0;
};

}  // namespace gs::app
