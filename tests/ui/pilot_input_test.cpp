// Keyboard/gamepad -> pilot command mapping: the flying-safety rules.
#include "ui/pilot_input.hpp"

#include <GLFW/glfw3.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace gs::ui {
namespace {

InputState keys(std::initializer_list<int> held) {
    InputState in;
    for (int k : held) in.keys.set(static_cast<std::size_t>(k));
    return in;
}

TEST(DeadZone, ZeroInsideRescaledOutside) {
    EXPECT_EQ(apply_dead_zone(0.10f, 0.15f), 0.0f);
    EXPECT_EQ(apply_dead_zone(-0.15f, 0.15f), 0.0f);
    EXPECT_NEAR(apply_dead_zone(0.575f, 0.15f), 0.5f, 1e-6);  // (0.575-0.15)/0.85
    EXPECT_NEAR(apply_dead_zone(-0.575f, 0.15f), -0.5f, 1e-6);
    EXPECT_EQ(apply_dead_zone(1.0f, 0.15f), 1.0f);
    EXPECT_EQ(apply_dead_zone(-3.0f, 0.15f), -1.0f);  // out-of-range axis clamped
    EXPECT_EQ(apply_dead_zone(std::numeric_limits<float>::quiet_NaN(), 0.15f), 0.0f);
}

TEST(PilotMapper, KeysMapToSignedAxesWithGains) {
    PilotMapper m;
    const Keymap km = Keymap::defaults();
    PilotFrame f = m.update(keys({GLFW_KEY_W, GLFW_KEY_D, GLFW_KEY_UP, GLFW_KEY_LEFT}), km);
    EXPECT_FLOAT_EQ(f.pilot.pitch, -km.keyboard_gain);  // forward = nose down
    EXPECT_FLOAT_EQ(f.pilot.roll, km.keyboard_gain);    // right
    EXPECT_FLOAT_EQ(f.pilot.gaz, km.gaz_gain);          // climb
    EXPECT_FLOAT_EQ(f.pilot.yaw, -km.yaw_gain);         // turn left
    EXPECT_TRUE(f.manual);
    f = m.update(keys({GLFW_KEY_S, GLFW_KEY_A, GLFW_KEY_DOWN, GLFW_KEY_RIGHT}), km);
    EXPECT_FLOAT_EQ(f.pilot.pitch, km.keyboard_gain);
    EXPECT_FLOAT_EQ(f.pilot.roll, -km.keyboard_gain);
    EXPECT_FLOAT_EQ(f.pilot.gaz, -km.gaz_gain);
    EXPECT_FLOAT_EQ(f.pilot.yaw, km.yaw_gain);
    f = m.update(keys({GLFW_KEY_W, GLFW_KEY_S}), km);  // opposite keys cancel, still manual
    EXPECT_EQ(f.pilot.pitch, 0.0f);
    EXPECT_TRUE(f.manual);
    f = m.update(keys({}), km);
    EXPECT_FALSE(f.pilot.any());
    EXPECT_FALSE(f.manual);
}

TEST(PilotMapper, EdgesFireOncePerPress) {
    PilotMapper m;
    const Keymap km = Keymap::defaults();
    EXPECT_TRUE(m.update(keys({GLFW_KEY_T}), km).takeoff);
    EXPECT_FALSE(m.update(keys({GLFW_KEY_T}), km).takeoff);
    EXPECT_FALSE(m.update(keys({}), km).takeoff);
    EXPECT_TRUE(m.update(keys({GLFW_KEY_T}), km).takeoff);
    const PilotFrame f = m.update(keys({GLFW_KEY_L, GLFW_KEY_F, GLFW_KEY_C, GLFW_KEY_R}), km);
    EXPECT_TRUE(f.land && f.flat_trim && f.switch_camera && f.record_toggle);
    EXPECT_FALSE(f.emergency || f.takeoff);
}

TEST(PilotMapper, FocusLossHoversAndIgnoresKeysHeldAcrossIt) {
    PilotMapper m;
    const Keymap km = Keymap::defaults();
    EXPECT_LT(m.update(keys({GLFW_KEY_W}), km).pilot.pitch, 0.0f);
    InputState lost = keys({GLFW_KEY_W});
    lost.window_focused = false;
    EXPECT_FALSE(m.update(lost, km).pilot.any());
    // Focus returns, W still "held" (the key-up went to another window): ignored.
    EXPECT_FALSE(m.update(keys({GLFW_KEY_W}), km).pilot.any());
    EXPECT_FALSE(m.update(keys({GLFW_KEY_W, GLFW_KEY_T}), km).pilot.any());
    // ...while a key pressed after focus returned works.
    EXPECT_GT(m.update(keys({GLFW_KEY_W, GLFW_KEY_D}), km).pilot.roll, 0.0f);
    // Once released, W works again.
    m.update(keys({}), km);
    EXPECT_LT(m.update(keys({GLFW_KEY_W}), km).pilot.pitch, 0.0f);
}

TEST(PilotMapper, TextFieldKeepsKeysButNotEmergency) {
    PilotMapper m;
    const Keymap km = Keymap::defaults();
    InputState typing = keys({GLFW_KEY_W, GLFW_KEY_T, GLFW_KEY_F12});
    typing.text_input_active = true;
    const PilotFrame f = m.update(typing, km);
    EXPECT_FALSE(f.pilot.any());
    EXPECT_FALSE(f.takeoff);
    EXPECT_TRUE(f.emergency);
}

TEST(PilotMapper, HeldKeyOverridesStickOnItsAxisOnly) {
    PilotMapper m;
    const Keymap km = Keymap::defaults();
    InputState in = keys({GLFW_KEY_A});
    in.gamepad.connected = true;
    in.gamepad.axes[GLFW_GAMEPAD_AXIS_RIGHT_X] = 1.0f;    // stick: full right
    in.gamepad.axes[GLFW_GAMEPAD_AXIS_RIGHT_Y] = -1.0f;   // stick up: forward
    in.gamepad.axes[GLFW_GAMEPAD_AXIS_LEFT_Y] = -0.575f;  // stick up: climb
    in.gamepad.axes[GLFW_GAMEPAD_AXIS_LEFT_X] = 0.1f;     // inside dead zone
    const PilotFrame f = m.update(in, km);
    EXPECT_FLOAT_EQ(f.pilot.roll, -km.keyboard_gain);  // key wins over the stick
    EXPECT_FLOAT_EQ(f.pilot.pitch, -1.0f);
    EXPECT_NEAR(f.pilot.gaz, 0.5f, 1e-6);
    EXPECT_EQ(f.pilot.yaw, 0.0f);
    EXPECT_TRUE(f.manual);
}

TEST(PilotMapper, GamepadButtonsAreEdges) {
    PilotMapper m;
    const Keymap km = Keymap::defaults();
    InputState in;
    in.gamepad.connected = true;
    in.gamepad.buttons[GLFW_GAMEPAD_BUTTON_BACK] = true;
    in.gamepad.buttons[GLFW_GAMEPAD_BUTTON_A] = true;
    PilotFrame f = m.update(in, km);
    EXPECT_TRUE(f.emergency);
    EXPECT_TRUE(f.takeoff);
    f = m.update(in, km);
    EXPECT_FALSE(f.emergency || f.takeoff);
    // Stick inside the dead zone: hover, not manual.
    in.gamepad.axes[GLFW_GAMEPAD_AXIS_RIGHT_X] = 0.12f;
    EXPECT_FALSE(m.update(in, km).manual);
}

TEST(PilotMapper, RemappedKeysAreUsed) {
    PilotMapper m;
    Keymap km = Keymap::defaults();
    km.key(PilotKey::Emergency) = GLFW_KEY_PAUSE;
    km.key(PilotKey::Forward) = GLFW_KEY_I;
    EXPECT_FALSE(m.update(keys({GLFW_KEY_F12, GLFW_KEY_W}), km).emergency);
    const PilotFrame f = m.update(keys({GLFW_KEY_PAUSE, GLFW_KEY_I}), km);
    EXPECT_TRUE(f.emergency);
    EXPECT_LT(f.pilot.pitch, 0.0f);
}

TEST(KeyNames, RoundTrip) {
    for (int k :
         {GLFW_KEY_W, GLFW_KEY_0, GLFW_KEY_F12, GLFW_KEY_ESCAPE, GLFW_KEY_SPACE, GLFW_KEY_UP})
        EXPECT_EQ(key_from_name(key_name(k)), k) << key_name(k);
    EXPECT_EQ(key_name(GLFW_KEY_ESCAPE), "Escape");
    EXPECT_EQ(key_from_name("w"), GLFW_KEY_W);
    EXPECT_EQ(key_from_name("NoSuchKey"), -1);
    EXPECT_EQ(key_from_name("F99"), -1);
}

}  // namespace
}  // namespace gs::ui
