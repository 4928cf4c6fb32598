// Window flows against the virtual drone through the real wiring (Gui -> GuiAdapter -> Session ->
// DroneLink -> loopback -> VirtualDrone): the telemetry snapshot lists every navdata field
// grouped by option and the link-health counters of the three streams are filled and drawn; and
// closing the window while flying asks first, "Land, then quit" lands the drone and the window
// closes only once the drone reports it has landed. Waits are bounded polls.
#include "app/gui_adapter.hpp"
#include "app/session.hpp"
#include "session_fixture.hpp"
#include "support/wait.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <set>
#include <thread>

namespace gs::ui::test {
namespace {

using namespace std::chrono_literals;

using WindowFlows = SessionFixture;

TEST_F(WindowFlows, TelemetryListsNavdataFieldsGroupedAndLinkHealthCountersAppear) {
    start({}, "warehouse");
    // The configured stream (after the bootstrap) with video flowing and rates measured.
    ASSERT_TRUE(run_until(
        [&] {
            return snap.connection.state == LinkState::Connected && snap.telemetry.valid &&
                   !snap.telemetry.fields.empty() && !std::isnan(snap.telemetry.nav.battery_pct) &&
                   snap.link.video.packets > 5 && snap.link.navdata.rate_hz > 5.0 &&
                   snap.link.video.rate_hz > 0.0 && snap.link.at.rate_hz > 0.0;
        },
        15s))
        << snap.connection.reason;

    // Every field of every option, grouped by option: each group one contiguous run.
    const auto& fields = snap.telemetry.fields;
    std::vector<std::string> order;
    for (const auto& f : fields) {
        EXPECT_FALSE(f.group.empty());
        EXPECT_FALSE(f.name.empty());
        EXPECT_FALSE(f.value.empty()) << f.group << "." << f.name;
        if (order.empty() || order.back() != f.group) order.push_back(f.group);
    }
    const std::set<std::string> distinct(order.begin(), order.end());
    EXPECT_EQ(distinct.size(), order.size()) << "a navdata option's fields are split";
    std::string groups;
    for (const auto& g : order) groups += g + " ";
    std::printf("navdata groups: %s(%zu fields)\n", groups.c_str(), fields.size());
    ASSERT_TRUE(distinct.count("demo")) << groups;
    auto field = [&](const std::string& group, const std::string& prefix) -> const TelemetryField* {
        for (const auto& f : fields)
            if (f.group == group && f.name.rfind(prefix, 0) == 0) return &f;
        return nullptr;
    };
    // Names carry units; values agree with the decoded state.
    const TelemetryField* bat = field("demo", "vbat_flying_percentage");
    ASSERT_NE(bat, nullptr);
    EXPECT_DOUBLE_EQ(std::stod(bat->value), snap.telemetry.nav.battery_pct);
    const TelemetryField* alt = field("demo", "altitude");
    ASSERT_NE(alt, nullptr);
    EXPECT_NE(alt->name.find('['), std::string::npos) << alt->name << ": unit missing";
    ASSERT_NE(field("demo", "ctrl_state"), nullptr);
    ASSERT_TRUE(snap.telemetry.state.has_value());
    EXPECT_FALSE(snap.telemetry.ctrl_state.empty());

    // Link health: the three streams active, counting, with rates and ages.
    const LinkHealth& h = snap.link;
    for (const StreamHealth* s : {&h.navdata, &h.video, &h.at}) {
        EXPECT_TRUE(s->active);
        EXPECT_GT(s->packets, 0u);
        EXPECT_GT(s->rate_hz, 0.0);
    }
    EXPECT_GT(h.navdata.rate_hz, 5.0);  // demo navdata ~15 Hz, full ~200 Hz
    EXPECT_LT(h.navdata.age_ms, 1000.0);
    EXPECT_LT(h.video.age_ms, 1000.0);
    EXPECT_GT(h.video.bytes_per_s, 0.0);
    EXPECT_GT(h.at.rate_hz, 10.0);  // the AT loop repeats every 30 ms
    // A clean loopback link: no checksum failures or decode errors.
    EXPECT_EQ(h.navdata.checksum_failures, 0u);
    EXPECT_EQ(h.navdata.decode_errors, 0u);
    EXPECT_EQ(h.video.decode_errors, 0u);

    // The Telemetry and Link windows draw them (one header per group, the counter table).
    step();
    EXPECT_GT(last_vertices, 3000);
    bool have_windows = false;
    for (const auto& [name, r] : gui.view().layout.windows) have_windows |= name == "Video";
    EXPECT_TRUE(have_windows);
}

TEST_F(WindowFlows, ClosingWhileFlyingLandThenQuitLandsTheVirtualDroneThenCloses) {
    app::SessionOptions so;
    so.sim_video = false;
    start(so, "thesis_pillar_center");
    ASSERT_TRUE(run_until([&] { return snap.connection.state == LinkState::Connected; }, 8s))
        << snap.connection.reason;
    auto drone = session->source().latest()->virtual_drone;
    ASSERT_TRUE(drone);
    step(key(PilotKey::Takeoff));
    ASSERT_TRUE(
        run_until([&] { return drone->status().flight.major == sim::CtrlMajor::Hovering; }, 10s));
    ASSERT_TRUE(
        run_until([&] { return snap.telemetry.state && snap.telemetry.state->flying; }, 3s));

    // The title-bar X: not now, a question first.
    EXPECT_FALSE(gui.request_close(snap));
    ASSERT_TRUE(run_until([&] { return gui.view().layout.button("quit.land") != nullptr; }, 2s));
    step();  // an auto-resized popup settles its size and position over its first frames
    step();
    EXPECT_TRUE(gui.view().quit_dialog_open);
    EXPECT_FALSE(last.quit);
    EXPECT_TRUE(drone->status().flight.motors_on);
    ASSERT_NE(gui.view().layout.button("quit.land"), nullptr);

    // Click "Land, then quit".
    const Rect r = *gui.view().layout.button("quit.land");
    ImGuiIO& io = ImGui::GetIO();
    io.MousePos = {0.5f * (r.x0 + r.x1), 0.5f * (r.y0 + r.y1)};
    step();
    io.MouseDown[0] = true;
    step();
    io.MouseDown[0] = false;
    const Actions clicked = step();
    io.MousePos = {-FLT_MAX, -FLT_MAX};
    EXPECT_TRUE(clicked.land);
    EXPECT_FALSE(clicked.quit) << "still flying: the window must stay";
    EXPECT_TRUE(gui.view().quit_after_landing);

    // The drone lands; the window asks to close only once navdata says it is down.
    bool quit_while_flying = false;
    ASSERT_TRUE(run_until(
        [&] {
            if (last.quit && snap.telemetry.state && snap.telemetry.state->flying)
                quit_while_flying = true;
            return last.quit;
        },
        20s))
        << "never quit; drone " << static_cast<int>(drone->status().flight.major);
    EXPECT_FALSE(quit_while_flying);
    EXPECT_FALSE(snap.telemetry.state->flying);
    // The simulator publishes its status every 20 ms, navdata every 5 ms (full navdata): the
    // window may have seen "landed" before the status caught up with it.
    const auto landed = [&] {
        const auto f = drone->status().flight;
        return (f.major == sim::CtrlMajor::Landed || f.major == sim::CtrlMajor::Default) &&
               !f.motors_on;
    };
    EXPECT_TRUE(gs::test::wait_until(landed, 2s)) << static_cast<int>(drone->status().flight.major)
                                                  << " motors " << drone->status().flight.motors_on;
}

}  // namespace
}  // namespace gs::ui::test
