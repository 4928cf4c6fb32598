// The assist in the product's path, over real sockets (issue 16): the window's pilot input goes
// Gui -> GuiAdapter -> PilotPath (the assist) -> DroneLink -> the virtual drone in the thesis'
// centre-pillar scene, the classifier running in the session on the drone's video. A pilot holding
// "forward" is braked short of the pillar; Escape changes nothing; the override (Left Shift held)
// and the toggle (B) pass the forward command; the emergency key acts at once; the recording made
// meanwhile has the intervention in its assist.csv.
#include "app/gui_adapter.hpp"
#include "app/session.hpp"
#include "drone/sim/at_parser.hpp"
#include "session_fixture.hpp"

#include <GLFW/glfw3.h>
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace gs::ui::test {
namespace {

using namespace std::chrono_literals;

class AssistWiring : public SessionFixture {
protected:
    app::SourceInfo src() const { return session->source().latest().value_or(app::SourceInfo{}); }
};

// The newest PCMD pitches the link sent (progressive ones only), parsed from its AT datagrams.
std::vector<float> sent_forward_pitches(BoundedQueue<link::RawEvent>& raw) {
    std::vector<float> out;
    while (auto e = raw.try_pop()) {
        if (e->kind != link::RawEvent::Kind::At) continue;
        auto p = sim::at::parse_datagram(std::span<const std::uint8_t>(e->bytes));
        if (!p) continue;
        for (const auto& c : p->commands)
            if (const auto* pc = std::get_if<sim::at::Pcmd>(&c.body))
                if (pc->flags & 1) out.push_back(pc->pitch);
    }
    return out;
}

bool assist_has_pitch(const std::vector<float>& v, float pitch) {
    for (float p : v)
        if (p == pitch) return true;
    return false;
}

TEST_F(AssistWiring, ForwardAtTheCentrePillarIsBrakedOverrideAndToggleOffPassEmergencyActs) {
    namespace fs = std::filesystem;
    const fs::path rec =
        fs::temp_directory_path() / ("gs_assist_rec_" + std::to_string(::getpid()));
    fs::remove_all(rec);
    app::SessionOptions so;
    start(so, "thesis_pillar_center");
    ASSERT_TRUE(run_until([&] { return !snap.video.bgr.empty(); }, 15s)) << snap.connection.reason;
    EXPECT_TRUE(snap.assist.available);
    EXPECT_TRUE(snap.assist.enabled) << "on by default";
    const auto s = src();
    ASSERT_TRUE(s.link && s.virtual_drone);
    auto drone = s.virtual_drone;
    auto raw = s.link->subscribe_raw(8192);
    ASSERT_TRUE(session->request(app::RecordStart{rec.string()}));

    // A pilot holding forward (0.3, ~1.1 m/s) at the pillar 7 m ahead: braked, stopped short.
    adapter->set_hold_forward(0.3f);
    // (Braking when the drone is already moving, holding forward at zero when the centre is
    // flagged before it got going: both stop the pilot's forward.)
    bool limited = false;
    ASSERT_TRUE(run_until(
        [&] {
            limited = limited || snap.assist.action == "BRAKING" || snap.assist.action == "HOLDING";
            return limited && snap.assist.action == "HOLDING" && snap.telemetry.valid &&
                   std::abs(snap.telemetry.nav.vx_mps) < 0.2;
        },
        45s))
        << "assist: " << snap.assist.line << "; limited " << limited << ", vx "
        << snap.telemetry.nav.vx_mps << "; collisions " << drone->status().collisions.size();
    EXPECT_TRUE(drone->status().collisions.empty()) << "hit the pillar with the assist on";
    EXPECT_FALSE(protocol::navdata::DroneState{drone->status().drone_state}.emergency());
    EXPECT_GE(snap.assist.interventions, 1u);
    bool logged = false;
    for (const auto& m : snap.messages)
        logged = logged || m.text.rfind("assist BRAKING", 0) == 0 ||
                 m.text.rfind("assist HOLDING", 0) == 0;
    EXPECT_TRUE(logged) << "the intervention is in the message log";
    ASSERT_TRUE(session->request(app::RecordStop{}));
    ASSERT_TRUE(
        run_until([&] { return !snap.recording.active && fs::exists(rec / "assist.csv"); }, 10s));
    // frames.csv's capture time of each frame (frame,t_ms,...).
    std::map<std::string, double> capture_ms;
    {
        std::ifstream in(rec / "frames.csv");
        std::string line;
        ASSERT_TRUE(std::getline(in, line));
        while (std::getline(in, line)) {
            const auto a = line.find(','), b = line.find(',', a + 1);
            if (a == std::string::npos || b == std::string::npos) continue;
            capture_ms[line.substr(0, a)] = std::stod(line.substr(a + 1, b - a - 1));
        }
    }
    {
        std::ifstream in(rec / "assist.csv");
        std::string header, row;
        ASSERT_TRUE(std::getline(in, header));
        EXPECT_EQ(header.rfind("t_ms,frame,pave_frame,decision_ms,action,region,reason", 0), 0u);
        // Every row: the pilot's forward (-0.3) replaced by no forward or a nose-up brake, with
        // the dataset frame the decision was made on.
        int rows = 0;
        while (std::getline(in, row)) {
            ++rows;
            const bool brake =
                row.find(",BRAKING,centre,BRAKING: obstacle ahead") != std::string::npos;
            const bool hold = row.find(",HOLDING,centre,HOLDING: ") != std::string::npos;
            EXPECT_TRUE(brake || hold) << row;
            EXPECT_NE(row.find(",1,0.000,-0.300,0.000,0.000,"), std::string::npos) << row;
            EXPECT_NE(row.substr(row.find(',') + 1, 1), ",") << "frame column empty: " << row;
            // The decision's age runs from its frame's capture (frames.csv's t_ms of that
            // frame), not from when the frame arrived: t_ms, frame, pave_frame, decision_ms.
            std::vector<std::string> cells;
            for (std::size_t at = 0, k = 0; k < 4; ++k) {
                const std::size_t end = row.find(',', at);
                cells.push_back(row.substr(at, end - at));
                at = end + 1;
            }
            const auto frame = capture_ms.find(cells[1]);
            ASSERT_NE(frame, capture_ms.end()) << "frame " << cells[1] << " not in frames.csv";
            EXPECT_NEAR(std::stod(cells[3]), frame->second, 0.002) << row;
            EXPECT_LE(std::stod(cells[3]), std::stod(cells[0])) << row;
        }
        EXPECT_GE(rows, 1) << "no intervention recorded";
    }

    // Escape (a desktop reflex) does not switch the assist off nor end what it does after the
    // brake: it still remembers the pillar (holding, or letting the pilot approach while the
    // remembered obstacle is farther than the gap plus the stopping distance, or probing).
    (void)sent_forward_pitches(*raw);
    InputState esc;
    esc.keys.set(GLFW_KEY_ESCAPE);
    step(esc);
    for (int i = 0; i < 10; ++i) {
        step();
        EXPECT_TRUE(snap.assist.enabled) << "Escape switched the assist off";
        const std::string& a = snap.assist.action;
        EXPECT_TRUE(a == "BRAKING" || a == "HOLDING" || a == "APPROACHING" || a == "PROBING")
            << "Escape ended the hold: " << snap.assist.line;
    }

    // Override held: the forward command passes while the key is down. (While approaching, the
    // assist passes the pilot's forward too, so only datagrams sent after the window shows the
    // override count: the queue is drained once it does.)
    const InputState shift = key(PilotKey::AssistOverride);
    ASSERT_TRUE(run_until([&] { return snap.assist.action == "OVERRIDE"; }, 10s, shift))
        << snap.assist.line;
    (void)sent_forward_pitches(*raw);
    ASSERT_TRUE(run_until(
        [&] {
            EXPECT_EQ(snap.assist.action, "OVERRIDE") << "the override ended while held";
            return assist_has_pitch(sent_forward_pitches(*raw), -0.3f);
        },
        10s, shift));
    EXPECT_EQ(snap.assist.line, "OVERRIDE: assist bypassed while held");

    // Released: held again. Then B switches the assist off and forward passes.
    ASSERT_TRUE(run_until([&] { return snap.assist.acting; }, 10s));
    const Actions b = step(key(PilotKey::AssistToggle));
    EXPECT_TRUE(b.assist_toggle);
    step();
    EXPECT_FALSE(snap.assist.enabled);
    EXPECT_EQ(snap.assist.line, "ASSIST OFF");
    (void)sent_forward_pitches(*raw);
    ASSERT_TRUE(
        run_until([&] { return assist_has_pitch(sent_forward_pitches(*raw), -0.3f); }, 10s));

    // The emergency key while forward is being sent: the motors are cut at once.
    const Actions ea = step(key(PilotKey::Emergency));
    EXPECT_TRUE(ea.emergency);
    ASSERT_TRUE(run_until(
        [&] { return protocol::navdata::DroneState{drone->status().drone_state}.emergency(); },
        10s));
    EXPECT_FALSE(drone->status().flight.motors_on);
    fs::remove_all(rec);
}

}  // namespace
}  // namespace gs::ui::test
