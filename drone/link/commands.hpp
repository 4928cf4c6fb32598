#pragma once
// What a pilot, the GUI or a script asks of the drone: typed commands with typed results
// (docs/style.md rule 11). The link turns them into AT commands; nothing here touches a socket.

#include <cstdint>
#include <string>
#include <variant>

namespace gs::link {

struct Takeoff {};
struct Land {};
// Cuts the motors when flying; when the drone reports an emergency, resets it.
struct Emergency {};
// Progressive motion, fractions of the configured maxima, each in [-1, 1] (clamped):
// roll > 0 bank right, pitch > 0 nose up (backwards), gaz > 0 climb, yaw > 0 clockwise.
struct Move {
    float roll = 0, pitch = 0, gaz = 0, yaw = 0;
};
struct Hover {};
struct FlatTrim {};   // only when landed on flat ground
struct Calibrate {};  // magnetometer; only when flying
struct SetConfig {
    std::string key, value;
    bool verify = true;  // read it back over the control port
};
// Reads the drone's whole configuration back over the control port (the dump arrives on
// DroneLink::config()).
struct ReadConfig {};
struct SwitchCamera {
    int channel = 0;  // 0 front, 1 bottom
};
struct Led {
    int anim_id = 0;
    float freq_hz = 1;
    int duration_s = 1;
};
struct Anim {
    int anim_id = 0;
    int duration_ms = 1000;
};

using Command = std::variant<Takeoff, Land, Emergency, Move, Hover, FlatTrim, Calibrate, SetConfig,
                             SwitchCamera, Led, Anim, ReadConfig>;
std::string command_name(const Command& c);

enum class ResultCode { Sent, NotConnected, Rejected, Timeout };

struct CommandResult {
    ResultCode code = ResultCode::Sent;
    std::string reason;  // why it was rejected / timed out; what a read-back found
    bool ok() const { return code == ResultCode::Sent; }
};
const char* to_string(ResultCode c);

}  // namespace gs::link
