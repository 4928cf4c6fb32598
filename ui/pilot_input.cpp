#include "ui/pilot_input.hpp"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <utility>

namespace gs::ui {

const char* to_string(PilotKey k) {
    switch (k) {
        case PilotKey::Forward:
            return "forward";
        case PilotKey::Back:
            return "back";
        case PilotKey::Left:
            return "left";
        case PilotKey::Right:
            return "right";
        case PilotKey::Climb:
            return "climb";
        case PilotKey::Descend:
            return "descend";
        case PilotKey::YawLeft:
            return "yaw_left";
        case PilotKey::YawRight:
            return "yaw_right";
        case PilotKey::Takeoff:
            return "takeoff";
        case PilotKey::Land:
            return "land";
        case PilotKey::Emergency:
            return "emergency";
        case PilotKey::FlatTrim:
            return "flat_trim";
        case PilotKey::SwitchCamera:
            return "switch_camera";
        case PilotKey::Record:
            return "record";
        case PilotKey::CalibrationCapture:
            return "calibration_capture";
        case PilotKey::AssistToggle:
            return "assist_toggle";
        case PilotKey::AssistOverride:
            return "assist_override";
        case PilotKey::Count:
            break;
    }
    return "?";
}

const char* description(PilotKey k) {
    switch (k) {
        case PilotKey::Forward:
            return "Move forward (pitch down)";
        case PilotKey::Back:
            return "Move backward (pitch up)";
        case PilotKey::Left:
            return "Move left (roll left)";
        case PilotKey::Right:
            return "Move right (roll right)";
        case PilotKey::Climb:
            return "Climb";
        case PilotKey::Descend:
            return "Descend";
        case PilotKey::YawLeft:
            return "Turn left (yaw)";
        case PilotKey::YawRight:
            return "Turn right (yaw)";
        case PilotKey::Takeoff:
            return "Take off";
        case PilotKey::Land:
            return "Land";
        case PilotKey::Emergency:
            return "EMERGENCY: cut motors / clear emergency";
        case PilotKey::FlatTrim:
            return "Flat trim (landed, on level ground)";
        case PilotKey::SwitchCamera:
            return "Switch camera (front / bottom)";
        case PilotKey::Record:
            return "Start / stop recording";
        case PilotKey::CalibrationCapture:
            return "Calibration window: capture the view (board found, adds coverage)";
        case PilotKey::AssistToggle:
            return "Collision assist on / off";
        case PilotKey::AssistOverride:
            return "Hold: collision assist bypassed (commands pass unchanged)";
        case PilotKey::Count:
            break;
    }
    return "?";
}

Keymap Keymap::defaults() {
    Keymap m;
    m.key(PilotKey::Forward) = GLFW_KEY_W;
    m.key(PilotKey::Back) = GLFW_KEY_S;
    m.key(PilotKey::Left) = GLFW_KEY_A;
    m.key(PilotKey::Right) = GLFW_KEY_D;
    m.key(PilotKey::Climb) = GLFW_KEY_UP;
    m.key(PilotKey::Descend) = GLFW_KEY_DOWN;
    m.key(PilotKey::YawLeft) = GLFW_KEY_LEFT;
    m.key(PilotKey::YawRight) = GLFW_KEY_RIGHT;
    m.key(PilotKey::Takeoff) = GLFW_KEY_T;
    m.key(PilotKey::Land) = GLFW_KEY_L;
    // Typed into no text field, used by no menu or popup, at the end of the function-key row.
    m.key(PilotKey::Emergency) = GLFW_KEY_F12;
    m.key(PilotKey::FlatTrim) = GLFW_KEY_F;
    m.key(PilotKey::SwitchCamera) = GLFW_KEY_C;
    m.key(PilotKey::Record) = GLFW_KEY_R;
    m.key(PilotKey::CalibrationCapture) = GLFW_KEY_K;
    m.key(PilotKey::AssistToggle) = GLFW_KEY_B;
    m.key(PilotKey::AssistOverride) = GLFW_KEY_LEFT_SHIFT;
    return m;
}

int default_emergency_key() {
    return GLFW_KEY_F12;
}

bool emergency_key_allowed(int k) {
    return (k >= GLFW_KEY_F3 && k <= GLFW_KEY_F25) || k == GLFW_KEY_PAUSE;
}

bool reserved_ui_key(int k) {
    return k == GLFW_KEY_ESCAPE || k == GLFW_KEY_F1 || k == GLFW_KEY_F2;
}

std::vector<std::string> sanitize_keymap(Keymap& map) {
    std::vector<std::string> notes;
    const Keymap def = Keymap::defaults();
    auto name = [](int k) { return k == kNoKey ? std::string("no key") : key_name(k); };
    for (std::size_t i = 0; i < kPilotKeyCount; ++i) {
        const auto a = static_cast<PilotKey>(i);
        int& k = map.key(a);
        const bool bad_emergency = a == PilotKey::Emergency && !emergency_key_allowed(k);
        if (!reserved_ui_key(k) && !bad_emergency) continue;
        std::string why = k == GLFW_KEY_ESCAPE ? "Escape only closes menus and dialogs now"
                          : reserved_ui_key(k) ? "F1 and F2 are the key help and the layout"
                                               : "the emergency key must be one no text field "
                                                 "or menu uses";
        notes.push_back(std::string(description(a)) + ": " + name(k) + " -> " + name(def.key(a)) +
                        " (" + why + ")");
        k = def.key(a);
    }
    // Nothing else may share the emergency key: one press must never do two things.
    const int e = map.key(PilotKey::Emergency);
    for (std::size_t i = 0; i < kPilotKeyCount; ++i) {
        const auto a = static_cast<PilotKey>(i);
        if (a == PilotKey::Emergency || map.key(a) != e) continue;
        notes.push_back(std::string(description(a)) + ": " + name(e) +
                        " -> no key (it is the emergency key)");
        map.key(a) = kNoKey;
    }
    return notes;
}

namespace {
const std::vector<std::pair<int, const char*>>& named_keys() {
    static const std::vector<std::pair<int, const char*>> t = {
        {GLFW_KEY_SPACE, "Space"},
        {GLFW_KEY_ESCAPE, "Escape"},
        {GLFW_KEY_ENTER, "Enter"},
        {GLFW_KEY_TAB, "Tab"},
        {GLFW_KEY_BACKSPACE, "Backspace"},
        {GLFW_KEY_INSERT, "Insert"},
        {GLFW_KEY_DELETE, "Delete"},
        {GLFW_KEY_RIGHT, "Right"},
        {GLFW_KEY_LEFT, "Left"},
        {GLFW_KEY_DOWN, "Down"},
        {GLFW_KEY_UP, "Up"},
        {GLFW_KEY_PAGE_UP, "PageUp"},
        {GLFW_KEY_PAGE_DOWN, "PageDown"},
        {GLFW_KEY_HOME, "Home"},
        {GLFW_KEY_END, "End"},
        {GLFW_KEY_PAUSE, "Pause"},
        {GLFW_KEY_SCROLL_LOCK, "ScrollLock"},
        {GLFW_KEY_LEFT_SHIFT, "LeftShift"},
        {GLFW_KEY_RIGHT_SHIFT, "RightShift"},
        {GLFW_KEY_LEFT_CONTROL, "LeftCtrl"},
        {GLFW_KEY_RIGHT_CONTROL, "RightCtrl"},
        {GLFW_KEY_KP_ENTER, "KeypadEnter"},
        {GLFW_KEY_KP_0, "Keypad0"},
        {GLFW_KEY_KP_2, "Keypad2"},
        {GLFW_KEY_KP_4, "Keypad4"},
        {GLFW_KEY_KP_5, "Keypad5"},
        {GLFW_KEY_KP_6, "Keypad6"},
        {GLFW_KEY_KP_8, "Keypad8"},
        {GLFW_KEY_KP_ADD, "KeypadPlus"},
        {GLFW_KEY_KP_SUBTRACT, "KeypadMinus"},
        {GLFW_KEY_COMMA, "Comma"},
        {GLFW_KEY_PERIOD, "Period"},
        {GLFW_KEY_SLASH, "Slash"},
    };
    return t;
}
}  // namespace

std::string key_name(int k) {
    if (k >= GLFW_KEY_A && k <= GLFW_KEY_Z)
        return std::string(1, static_cast<char>('A' + (k - GLFW_KEY_A)));
    if (k >= GLFW_KEY_0 && k <= GLFW_KEY_9)
        return std::string(1, static_cast<char>('0' + (k - GLFW_KEY_0)));
    if (k >= GLFW_KEY_F1 && k <= GLFW_KEY_F25) {
        char buf[8];
        std::snprintf(buf, sizeof buf, "F%d", k - GLFW_KEY_F1 + 1);
        return buf;
    }
    for (const auto& [code, name] : named_keys())
        if (code == k) return name;
    return {};
}

int key_from_name(std::string_view name) {
    if (name.size() == 1) {
        const char c = static_cast<char>(std::toupper(static_cast<unsigned char>(name[0])));
        if (c >= 'A' && c <= 'Z') return GLFW_KEY_A + (c - 'A');
        if (c >= '0' && c <= '9') return GLFW_KEY_0 + (c - '0');
    }
    if (name.size() >= 2 && name[0] == 'F') {
        int n = 0;
        for (char c : name.substr(1)) {
            if (c < '0' || c > '9') {
                n = -1;
                break;
            }
            n = n * 10 + (c - '0');
        }
        if (n >= 1 && n <= 25) return GLFW_KEY_F1 + n - 1;
    }
    for (const auto& [code, kname] : named_keys())
        if (name == kname) return code;
    return -1;
}

float apply_dead_zone(float v, float dead_zone) {
    if (!std::isfinite(v)) return 0.0f;
    v = std::clamp(v, -1.0f, 1.0f);
    const float dz = std::clamp(dead_zone, 0.0f, 0.95f);
    const float a = std::fabs(v);
    if (a <= dz) return 0.0f;
    return std::copysign((a - dz) / (1.0f - dz), v);
}

PilotFrame PilotMapper::update(const InputState& in, const Keymap& map) {
    PilotFrame out;
    auto valid = [](int k) { return k >= 0 && k < 512; };

    // Focus latch: whatever is held while unfocused (or at the moment focus returns) was pressed
    // outside our sight; its key-up may never arrive. Ignore it until we see it released, unless
    // we saw it pressed again (a press event is a new press).
    if (!in.window_focused) {
        latched_ |= in.keys;
    } else {
        if (!was_focused_) latched_ |= in.keys;
        latched_ &= ~in.pressed;  // pressed again in our window: a fresh press
    }
    latched_ &= in.keys;  // released keys are free again

    const std::bitset<512> none;
    const std::bitset<512> held_now = in.window_focused ? (in.keys & ~latched_) : none;
    // A press is a latched press event or a key seen held now and not in the last frame; a key
    // pressed and released between two frames is held for this one frame (a short tap moves).
    const std::bitset<512> presses =
        in.window_focused ? ((in.pressed & ~latched_) | (held_now & ~prev_keys_)) : none;
    const std::bitset<512> usable = held_now | presses;
    auto held = [&](PilotKey k) {
        const int c = map.key(k);
        return valid(c) && usable.test(static_cast<std::size_t>(c));
    };
    auto pressed = [&](PilotKey k) {
        const int c = map.key(k);
        return valid(c) && presses.test(static_cast<std::size_t>(c));
    };

    // Emergency first and unconditionally: text fields, menus and dialogs do not swallow it (its
    // key types nothing; a keymap putting it on a typing key is refused, see sanitize_keymap).
    out.emergency = pressed(PilotKey::Emergency) &&
                    (!in.text_input_active || emergency_key_allowed(map.key(PilotKey::Emergency)));

    float k_roll = 0, k_pitch = 0, k_gaz = 0, k_yaw = 0;
    bool k_roll_set = false, k_pitch_set = false, k_gaz_set = false, k_yaw_set = false;
    if (!in.text_input_active) {
        auto axis = [&](PilotKey neg, PilotKey pos, float gain, float& v, bool& set) {
            const bool n = held(neg), p = held(pos);
            set = n || p;
            v = (static_cast<float>(p) - static_cast<float>(n)) * gain;
        };
        axis(PilotKey::Left, PilotKey::Right, map.keyboard_gain, k_roll, k_roll_set);
        axis(PilotKey::Forward, PilotKey::Back, map.keyboard_gain, k_pitch, k_pitch_set);
        axis(PilotKey::Descend, PilotKey::Climb, map.gaz_gain, k_gaz, k_gaz_set);
        axis(PilotKey::YawLeft, PilotKey::YawRight, map.yaw_gain, k_yaw, k_yaw_set);
        out.takeoff = pressed(PilotKey::Takeoff);
        out.land = pressed(PilotKey::Land);
        out.flat_trim = pressed(PilotKey::FlatTrim);
        out.switch_camera = pressed(PilotKey::SwitchCamera);
        out.record_toggle = pressed(PilotKey::Record);
        out.calibration_capture = pressed(PilotKey::CalibrationCapture);
        out.assist_toggle = pressed(PilotKey::AssistToggle);
    }
    // The override is a held key: a text field having the keyboard does not stop it (it types
    // nothing and moves nothing by itself).
    out.assist_override = held(PilotKey::AssistOverride);

    // Gamepad (mode 2: left stick yaw/climb, right stick roll/pitch). Polled state, so it has no
    // stale-key problem and keeps working without window focus.
    float g_roll = 0, g_pitch = 0, g_gaz = 0, g_yaw = 0;
    const GamepadState& gp = in.gamepad;
    if (gp.connected) {
        g_yaw = apply_dead_zone(gp.axes[GLFW_GAMEPAD_AXIS_LEFT_X], map.dead_zone);
        g_gaz = -apply_dead_zone(gp.axes[GLFW_GAMEPAD_AXIS_LEFT_Y], map.dead_zone);
        g_roll = apply_dead_zone(gp.axes[GLFW_GAMEPAD_AXIS_RIGHT_X], map.dead_zone);
        g_pitch = apply_dead_zone(gp.axes[GLFW_GAMEPAD_AXIS_RIGHT_Y], map.dead_zone);
        auto bpress = [&](int b) {
            return gp.buttons[static_cast<std::size_t>(b)] &&
                   !prev_buttons_[static_cast<std::size_t>(b)];
        };
        out.emergency = out.emergency || bpress(GLFW_GAMEPAD_BUTTON_BACK);
        out.takeoff = out.takeoff || bpress(GLFW_GAMEPAD_BUTTON_A);
        out.land = out.land || bpress(GLFW_GAMEPAD_BUTTON_B);
        out.flat_trim = out.flat_trim || bpress(GLFW_GAMEPAD_BUTTON_X);
        out.switch_camera = out.switch_camera || bpress(GLFW_GAMEPAD_BUTTON_Y);
        out.record_toggle = out.record_toggle || bpress(GLFW_GAMEPAD_BUTTON_START);
        out.assist_toggle = out.assist_toggle || bpress(GLFW_GAMEPAD_BUTTON_RIGHT_BUMPER);
        out.assist_override = out.assist_override || gp.buttons[GLFW_GAMEPAD_BUTTON_LEFT_BUMPER];
        prev_buttons_ = gp.buttons;
    } else {
        prev_buttons_ = {};
    }

    // A held key overrides the stick on its axis.
    out.pilot.roll = std::clamp(k_roll_set ? k_roll : g_roll, -1.0f, 1.0f);
    out.pilot.pitch = std::clamp(k_pitch_set ? k_pitch : g_pitch, -1.0f, 1.0f);
    out.pilot.gaz = std::clamp(k_gaz_set ? k_gaz : g_gaz, -1.0f, 1.0f);
    out.pilot.yaw = std::clamp(k_yaw_set ? k_yaw : g_yaw, -1.0f, 1.0f);
    out.manual = k_roll_set || k_pitch_set || k_gaz_set || k_yaw_set || out.pilot.any();

    prev_keys_ = held_now;
    was_focused_ = in.window_focused;
    return out;
}

}  // namespace gs::ui
