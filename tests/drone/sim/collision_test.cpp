// The virtual drone's body against the scene: contact geometry (boxes, cylinders, walls, ceiling),
// the crash / bump rule in DroneCore (motors cut, emergency with the cut-out cause in
// drone_state, the drone on the floor) and the shipped scenes' scripted flights staying clear.

#include "drone/sim/collision.hpp"
#include "drone/protocol/at.hpp"
#include "drone/protocol/navdata.hpp"
#include "drone/sim/drone_core.hpp"
#include "drone/sim/scene.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace gs::sim {
namespace {

const std::string kCollisionScenes = std::string(GS_ASSETS_DIR) + "/scenes/";

Scene room_with(std::vector<Obstacle> obstacles) {
    Scene s;
    s.room.x_min_m = -2;
    s.room.x_max_m = 20;
    s.room.y_min_m = -5;
    s.room.y_max_m = 5;
    s.room.height_m = 3;
    s.obstacles = std::move(obstacles);
    return s;
}

Obstacle pillar(double x, double y, double radius = 0.25) {
    Obstacle o;
    o.id = "pillar";
    o.shape = ObstacleShape::Cylinder;
    o.x_m = x;
    o.y_m = y;
    o.radius_m = radius;
    o.height_m = 3;
    return o;
}

Obstacle box(double x, double y, double sx, double sy, double yaw_deg = 0, double z = 0,
             double h = 3) {
    Obstacle o;
    o.id = "box";
    o.x_m = x;
    o.y_m = y;
    o.size_x_m = sx;
    o.size_y_m = sy;
    o.yaw_deg = yaw_deg;
    o.z_m = z;
    o.height_m = h;
    return o;
}

TEST(SimCollision, CylinderAheadTouchesTheHullNotTheCentre) {
    const Collider c(room_with({pillar(5.0, 0.0)}));
    // Hull 0.52 m long: its nose is 0.26 m ahead of the centre; pillar face at x = 4.75.
    EXPECT_FALSE(c.contact(4.48, 0, 1, 0).has_value());
    auto hit = c.contact(4.50, 0, 1, 0);
    ASSERT_TRUE(hit.has_value());
    EXPECT_EQ(hit->kind, ContactKind::Obstacle);
    EXPECT_EQ(hit->what, "pillar");
    EXPECT_NEAR(hit->depth_m, 0.01, 1e-9);
    EXPECT_NEAR(hit->nx, -1, 1e-9);  // out of the pillar, back towards the drone
    EXPECT_NEAR(c.clearance(4.40, 0, 1, 0), 0.09, 1e-9);
    // Beside it: the hull's side 0.26 m from the centre line.
    EXPECT_FALSE(c.contact(5.0, -0.52, 1, 0).has_value());
    EXPECT_TRUE(c.contact(5.0, -0.50, 1, 0).has_value());
    // Turned 45 degrees the hull's corner reaches further: 0.26 * sqrt(2) = 0.368 m.
    EXPECT_TRUE(c.contact(4.40, 0, 1, 45).has_value());
    EXPECT_FALSE(c.contact(4.40, 0, 1, 0).has_value());
}

TEST(SimCollision, BoxesYawedAndHeightMatters) {
    const Collider c(room_with({box(5.0, 0.0, 1.0, 1.0, 45.0, 0.0, 0.8)}));
    // A 1 m box turned 45 degrees: its corner points back at x = 5 - 0.707.
    EXPECT_FALSE(c.contact(5.0 - 0.707 - 0.27, 0, 0.5, 0).has_value());
    EXPECT_TRUE(c.contact(5.0 - 0.707 - 0.25, 0, 0.5, 0).has_value());
    // Above it (box top at 0.8 m): clear; touching its top from above.
    EXPECT_FALSE(c.contact(5.0, 0, 0.85, 0).has_value());
    auto top = c.contact(5.0, 0, 0.79, 0);
    ASSERT_TRUE(top.has_value());
    EXPECT_NEAR(top->nz, 1, 1e-9);
    EXPECT_NEAR(top->depth_m, 0.01, 1e-9);
}

TEST(SimCollision, WallsCeilingAndFloor) {
    const Collider c(room_with({}));
    EXPECT_FALSE(c.contact(0, 0, 1, 0).has_value());
    auto front = c.contact(19.8, 0, 1, 0);
    ASSERT_TRUE(front.has_value());
    EXPECT_EQ(front->kind, ContactKind::Wall);
    EXPECT_EQ(front->what, "front wall");
    EXPECT_NEAR(front->depth_m, 0.06, 1e-9);
    EXPECT_EQ(c.contact(0, 4.8, 1, 0)->what, "right wall");
    EXPECT_EQ(c.contact(0, -4.8, 1, 0)->what, "left wall");
    EXPECT_EQ(c.contact(-1.8, 0, 1, 0)->what, "back wall");
    auto ceiling = c.contact(0, 0, 2.9, 0);
    ASSERT_TRUE(ceiling.has_value());
    EXPECT_EQ(ceiling->kind, ContactKind::Ceiling);
    EXPECT_NEAR(ceiling->nz, -1, 1e-9);
    EXPECT_EQ(c.contact(0, 0, -0.01, 0)->kind, ContactKind::Floor);
    EXPECT_NEAR(c.clearance(0, 0, 1, 0), 2 - 0.26, 1e-9);  // the back wall at x = -2
    EXPECT_TRUE(std::isinf(c.clearance(0, 0, 1, 0, false)));  // no obstacle at all
}

// A ground station flying the core: REF + PCMD every 30 ms.
struct Pilot {
    DroneCore core;
    TimeNs now = ms_to_ns(1000);
    protocol::at::SeqCounter seq;
    bool fly = false;
    float pitch = 0, roll = 0;
    std::vector<OutDatagram> out;
    protocol::navdata::DroneState last_state;

    explicit Pilot(DroneCoreOptions o) : core(std::move(o)) {
        core.on_navdata_trigger(*transport::Endpoint::parse("127.0.0.1:40000"), now);
        core.advance(now, out);
    }
    void run(double seconds) {
        const auto from = *transport::Endpoint::parse("127.0.0.1:40000");
        for (int t = 0; t < static_cast<int>(seconds * 1000); t += 5) {
            now += ms_to_ns(5);
            if (t % 30 == 0) {
                std::string d = protocol::at::ref(seq.next(), protocol::at::ref_input(fly, false));
                const bool move = pitch != 0 || roll != 0;
                d += move ? protocol::at::pcmd(seq.next(), protocol::at::kPcmdProgressive, roll,
                                               pitch, 0, 0)
                          : protocol::at::hover(seq.next());
                core.on_at({reinterpret_cast<const std::uint8_t*>(d.data()), d.size()}, from, now);
            }
            out.clear();
            core.advance(now, out);
            for (auto& o : out)
                if (auto nd = protocol::navdata::parse_navdata(o.bytes))
                    last_state = nd->header.drone_state;
        }
    }
};

DroneCoreOptions options_with(const Scene& scene) {
    DroneCoreOptions o;
    o.start = scene.start;
    o.start.z_m = 0;
    o.collider.emplace(scene);
    return o;
}

TEST(SimCollision, FlyingIntoAPillarCutsTheMotors) {
    Scene s = room_with({pillar(4.0, 0.0)});
    Pilot p(options_with(s));
    p.fly = true;
    p.run(5.0);  // take off and settle
    ASSERT_TRUE(p.core.flight().flying());
    p.pitch = -0.5f;  // forward, about 1.5 m/s after a few seconds
    for (int i = 0; i < 100 && p.core.counters().collisions == 0; ++i) p.run(0.1);
    ASSERT_EQ(p.core.counters().collisions, 1u);
    const CollisionEvent& e = p.core.collisions().back();
    EXPECT_TRUE(e.crash);
    EXPECT_EQ(e.what, "pillar");
    EXPECT_GT(e.approach_mps, 0.3);
    EXPECT_NEAR(e.x_m, 4.0 - 0.25 - 0.26, 0.05);  // the hull's nose at the pillar's face
    p.run(2.0);
    const FlightState& f = p.core.flight();
    EXPECT_TRUE(f.emergency);
    EXPECT_FALSE(f.motors_on);
    EXPECT_EQ(f.z_m, 0.0);                       // fell to the floor
    EXPECT_LT(f.x_m, 4.0 - 0.25 - 0.26 + 1e-6);  // not through the pillar
    EXPECT_TRUE(p.last_state.emergency());
    EXPECT_TRUE(p.last_state.cutout());
    EXPECT_TRUE(p.last_state.motors());
    EXPECT_FALSE(p.last_state.user_el());
    EXPECT_FALSE(p.last_state.fly());
    EXPECT_EQ(p.core.counters().collisions, 1u);  // the fall along its face is not another
}

TEST(SimCollision, DriftingGentlyIntoAWallIsABump) {
    Scene s = room_with({});
    s.start.x_m = 18.9;  // nose 0.84 m from the front wall
    Pilot p(options_with(s));
    p.fly = true;
    p.run(5.0);
    p.pitch = -0.04f;  // creeping forward, ~0.2 m/s at most
    p.run(8.0);
    EXPECT_EQ(p.core.counters().collisions, 0u);
    EXPECT_EQ(p.core.counters().bumps, 1u);
    EXPECT_TRUE(p.core.flight().flying());
    EXPECT_LE(p.core.flight().x_m + 0.26, 20.0 + 1e-9);  // held against it, not through it
    EXPECT_FALSE(p.last_state.emergency());
}

TEST(SimCollision, WithoutAColliderItFliesThrough) {
    Scene s = room_with({pillar(4.0, 0.0)});
    DroneCoreOptions o = options_with(s);
    o.collider.reset();
    Pilot p(o);
    p.fly = true;
    p.run(5.0);
    p.pitch = -0.5f;
    p.run(6.0);
    EXPECT_GT(p.core.flight().x_m, 4.5);
    EXPECT_EQ(p.core.counters().collisions + p.core.counters().bumps, 0u);
}

// Every shipped scene's scripted flight keeps clear of its geometry.
TEST(SimCollision, ShippedScriptedFlightsTouchNothing) {
    for (const char* f : {"thesis_pillar_left.json", "thesis_pillar_right.json",
                          "thesis_pillar_center.json", "thesis_open_hall.json", "warehouse.json"}) {
        auto s = load_scene(kCollisionScenes + f);
        ASSERT_TRUE(s.has_value()) << f;
        DroneCoreOptions o;
        o.start = s->start;
        o.autopilot = s->autopilot;
        o.autopilot_enabled = true;
        o.collider.emplace(*s);
        DroneCore core(o);
        std::vector<OutDatagram> out;
        TimeNs now = ms_to_ns(1000);
        core.advance(now, out);
        double min_clearance = 1e9;
        for (int i = 0; i < 60 * 200 && !core.autopilot_done(); ++i) {
            now += ms_to_ns(5);
            core.advance(now, out);
            const FlightState& st = core.flight();
            if (st.z_m > 0.05)
                min_clearance = std::min(min_clearance,
                                         o.collider->clearance(st.x_m, st.y_m, st.z_m, st.yaw_deg));
        }
        EXPECT_TRUE(core.autopilot_done()) << f;
        EXPECT_EQ(core.counters().collisions, 0u) << f;
        EXPECT_EQ(core.counters().bumps, 0u) << f;
        EXPECT_GT(min_clearance, 0.05) << f;
    }
}

}  // namespace
}  // namespace gs::sim
