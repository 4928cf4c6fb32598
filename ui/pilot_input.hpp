#pragma once
// Keyboard and gamepad to pilot commands, as a pure function of input state (no ImGui, no GLFW
// calls), so the flying-safety rules are unit-tested:
//  - dead zone on every stick axis, rescaled so the output is continuous from 0;
//  - a held movement key overrides the gamepad on its axis (keyboard is the deliberate input);
//  - losing window focus gives a hover command, and a key still held when focus returns is ignored
//    until released (no stale command from a missed key-up);
//  - the emergency key/button is honoured even while a text field has the keyboard, a menu or a
//    dialog is open: it is always reachable. It is a key no text field, menu or popup uses
//    (F12 by default; only F2..F25 and Pause may be bound to it), so typing never cuts the motors;
//  - a press is acted on exactly once, even when it is released before the frame that reads it
//    (InputState::pressed, latched from the key callback by KeyLatch).
// The assist: its toggle (B, gamepad right bumper) is an edge; its override (Left Shift, gamepad
// left bumper) acts only while held and is dropped on focus loss like every held key.
// Escape is never a pilot key: it closes menus and dialogs (ui/gui.cpp) and nothing else.
// Key codes are GLFW key codes (the ImGui 1.86 GLFW backend indexes io.KeysDown with them).

#include "ui/actions.hpp"

#include <array>
#include <bitset>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace gs::ui {

enum class PilotKey : int {
    Forward,
    Back,
    Left,
    Right,
    Climb,
    Descend,
    YawLeft,
    YawRight,
    Takeoff,
    Land,
    Emergency,
    FlatTrim,
    SwitchCamera,
    Record,
    CalibrationCapture,  // Calibration window: capture the current view
    AssistToggle,        // the collision-prevention assist on / off
    AssistOverride,      // held: the assist lets the pilot's commands pass unchanged
    Count
};
inline constexpr std::size_t kPilotKeyCount = static_cast<std::size_t>(PilotKey::Count);
const char* to_string(PilotKey k);    // "forward", "emergency" ... (settings key)
const char* description(PilotKey k);  // "Move forward (pitch down)"

inline constexpr int kNoKey = -1;  // an action with no key bound

struct Keymap {
    std::array<int, kPilotKeyCount> keys{};  // GLFW key code per action (kNoKey: unbound)
    float keyboard_gain = 0.5f;              // fraction of max deflection a held key gives
    float yaw_gain = 0.7f;
    float gaz_gain = 0.7f;
    float dead_zone = 0.15f;  // gamepad stick dead zone, fraction of full travel

    static Keymap defaults();
    int key(PilotKey k) const { return keys[static_cast<std::size_t>(k)]; }
    int& key(PilotKey k) { return keys[static_cast<std::size_t>(k)]; }
};

// The default emergency key (F12): on every keyboard, typed into nothing, used by no menu.
int default_emergency_key();
// True for the keys the emergency may be bound to: F3..F25 and Pause (F1, F2: key help, layout). A
// key a text field types or edits with, or one that closes menus (Escape), would either cut the
// motors while typing a path or be pressed by reflex to close a menu.
bool emergency_key_allowed(int glfw_key);
// Keys no pilot action may use: Escape closes menus and dialogs, and only that; F1 toggles the
// key help, F2 the flight / engineering layout.
bool reserved_ui_key(int glfw_key);
inline constexpr int kHelpKey = 290;    // GLFW_KEY_F1
inline constexpr int kLayoutKey = 291;  // GLFW_KEY_F2

// Makes a keymap safe, whatever a settings file said: actions bound to a reserved key (Escape)
// or the emergency on a key that is not allowed go back to their default; an action that then
// shares a key with the emergency is unbound. Returns one line per change, for the user.
std::vector<std::string> sanitize_keymap(Keymap& map);

// "W", "Up", "Escape", "Space" ... for GLFW key codes; empty for unknown codes.
std::string key_name(int glfw_key);
// Inverse of key_name; -1 if unknown.
int key_from_name(std::string_view name);

// GLFW gamepad state in GLFW's layout (GLFW_GAMEPAD_AXIS_*, GLFW_GAMEPAD_BUTTON_*):
// axes in [-1, 1], stick y positive = down.
struct GamepadState {
    bool connected = false;
    std::array<float, 6> axes{};
    std::array<bool, 15> buttons{};
};

struct InputState {
    std::bitset<512> keys;  // held keys, by GLFW key code
    // Keys pressed since the previous frame (KeyLatch: from the key callback), held or already
    // released: a tap shorter than a frame is still one press.
    std::bitset<512> pressed;
    // Of those, the ones pressed while Ctrl was held (Ctrl+Q tapped inside one frame: by the
    // frame, Ctrl may already be released).
    std::bitset<512> pressed_with_ctrl;
    bool window_focused = true;
    bool text_input_active = false;  // a text field owns the keyboard: only emergency passes
    GamepadState gamepad;
};

// Radial-per-axis dead zone: |v| <= dz -> 0, else rescaled to (0, 1] keeping the sign.
float apply_dead_zone(float v, float dead_zone);

// One frame of piloting intent. Edges (takeoff ...) are true only on the frame of the press.
struct PilotFrame {
    PilotInput pilot;
    bool manual = false;  // a movement key is held or a stick is outside the dead zone
    bool takeoff = false, land = false, emergency = false, flat_trim = false, switch_camera = false,
         record_toggle = false, calibration_capture = false;
    bool assist_toggle = false;    // edge: the key or the gamepad's right bumper
    bool assist_override = false;  // level: the key or the gamepad's left bumper held
};

// Stateful only for edges and the focus latch; otherwise a pure map from InputState.
class PilotMapper {
public:
    PilotFrame update(const InputState& in, const Keymap& map);
    void reset() { *this = PilotMapper{}; }

private:
    std::bitset<512> prev_keys_;
    std::bitset<512> latched_;  // keys held across a focus loss: ignored until released
    std::array<bool, 15> prev_buttons_{};
    bool was_focused_ = true;
};

}  // namespace gs::ui
