#include "ui/key_latch.hpp"

#include <GLFW/glfw3.h>

namespace gs::ui {

void KeyLatch::on_key(int key, Event e) {
    if (key < 0 || key >= static_cast<int>(down_.size())) return;  // GLFW_KEY_UNKNOWN (-1) ...
    const auto k = static_cast<std::size_t>(key);
    switch (e) {
        case Event::Press:
            down_.set(k);
            pressed_.set(k);
            if (down_.test(GLFW_KEY_LEFT_CONTROL) || down_.test(GLFW_KEY_RIGHT_CONTROL))
                pressed_with_ctrl_.set(k);
            ++presses_;
            break;
        case Event::Release:
            down_.reset(k);
            break;
        case Event::Repeat:  // auto-repeat of a held key: not a new press
            break;
    }
}

void KeyLatch::take(InputState& in) {
    in.keys |= down_;
    in.pressed |= pressed_;
    in.pressed_with_ctrl |= pressed_with_ctrl_;
    pressed_.reset();
    pressed_with_ctrl_.reset();
}

}  // namespace gs::ui
