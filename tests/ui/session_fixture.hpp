// The window wired to a live session (Gui -> GuiAdapter -> Session -> DroneLink -> loopback ->
// VirtualDrone) for tests that press keys and watch what the drone does. Real sockets and
// threads: waits are bounded polls, never fixed sleeps standing in for logic.
#pragma once

#include "app/gui_adapter.hpp"
#include "app/session.hpp"
#include "imgui_fixture.hpp"
#include "support/wait.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <thread>

namespace gs::ui::test {

class SessionFixture : public ImGuiFixture {
protected:
    // A session with `so` and the window's adapter on it.
    void make_session(const app::SessionOptions& so) {
        session = std::make_unique<app::Session>(so);
        adapter = std::make_unique<app::GuiAdapter>(*session);
    }
    // ... flying the virtual drone in `scenario`.
    void start(app::SessionOptions so, const std::string& scenario) {
        make_session(so);
        ASSERT_TRUE(session->request(app::StartSim{scenario, false}));
    }
    void TearDown() override {
        adapter.reset();
        session.reset();
        ImGuiFixture::TearDown();
    }
    // One window frame: snapshot from the session, draw, hand the actions back; `edit` adds to
    // what the window asked for (a test standing in for a click on a control it need not find).
    Actions step(const InputState& in = {}, const std::function<void(Actions&)>& edit = {}) {
        adapter->fill(snap);
        Actions a = frame(gui, snap, in);
        if (edit) edit(a);
        adapter->consume(a);
        last = a;
        return a;
    }
    Actions step(const std::function<void(Actions&)>& edit) { return step({}, edit); }
    // Window frames (one per `frame_period`) until `pred` holds or `timeout` passes.
    bool run_until(const std::function<bool()>& pred, std::chrono::milliseconds timeout,
                   const InputState& in = {}) {
        return gs::test::wait_until(
                   pred, timeout, [&] { step(in); }, frame_period)
            .has_value();
    }
    static InputState key(PilotKey k) {
        InputState in;
        in.keys.set(static_cast<std::size_t>(Keymap::defaults().key(k)));
        return in;
    }

    std::unique_ptr<app::Session> session;
    std::unique_ptr<app::GuiAdapter> adapter;
    Gui gui;
    GuiSnapshot snap;
    Actions last;  // what the last frame asked for
    std::chrono::milliseconds frame_period{10};
};

}  // namespace gs::ui::test
