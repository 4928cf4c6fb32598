#pragma once
// KeyLatch: every key press the window receives, kept until the next UI frame reads it.
//
// Dear ImGui 1.86 keeps only the current key state (io.KeysDown); a key pressed and released
// between two frames, or while one slow frame is drawn, never shows there. The GLFW key callback
// (app_window.cpp) feeds this latch instead, event by event, and each frame takes the presses
// seen since the last one: a tap shorter than a frame is acted on once, never lost, never twice.
// No GLFW calls here (tests drive it directly); key codes are GLFW's.

#include "ui/pilot_input.hpp"

#include <bitset>
#include <cstdint>

namespace gs::ui {

class KeyLatch {
public:
    enum class Event { Press, Release, Repeat };

    // One key event, in the order the window system delivered them (on the UI thread). A press
    // while a Ctrl key is down is also latched as a Ctrl chord.
    void on_key(int key, Event e);
    // Adds the keys held now and the presses since the last call to `in`, and forgets the
    // presses (each is handed out once).
    void take(InputState& in);

    std::uint64_t presses() const { return presses_; }  // every press seen (diagnostics, tests)

private:
    std::bitset<512> down_, pressed_, pressed_with_ctrl_;
    std::uint64_t presses_ = 0;
};

}  // namespace gs::ui
