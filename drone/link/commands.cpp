#include "drone/link/commands.hpp"

namespace gs::link {

std::string command_name(const Command& c) {
    struct V {
        std::string operator()(const Takeoff&) const { return "takeoff"; }
        std::string operator()(const Land&) const { return "land"; }
        std::string operator()(const Emergency&) const { return "emergency"; }
        std::string operator()(const Move&) const { return "move"; }
        std::string operator()(const Hover&) const { return "hover"; }
        std::string operator()(const FlatTrim&) const { return "flat trim"; }
        std::string operator()(const Calibrate&) const { return "calibrate"; }
        std::string operator()(const SetConfig& s) const { return "config " + s.key; }
        std::string operator()(const SwitchCamera&) const { return "switch camera"; }
        std::string operator()(const Led&) const { return "led"; }
        std::string operator()(const Anim&) const { return "anim"; }
        std::string operator()(const ReadConfig&) const { return "read configuration"; }
    };
    return std::visit(V{}, c);
}

const char* to_string(ResultCode c) {
    switch (c) {
        case ResultCode::Sent:
            return "sent";
        case ResultCode::NotConnected:
            return "not connected";
        case ResultCode::Rejected:
            return "rejected";
        case ResultCode::Timeout:
            return "timeout";
    }
    return "?";
}

}  // namespace gs::link
