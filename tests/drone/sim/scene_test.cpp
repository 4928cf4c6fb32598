// Scene files, JSON error reporting, ground-truth queries and the seeded generator.

#include "drone/sim/scene.hpp"
#include "support/dataset_fixtures.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace gs::sim {
namespace {

const std::string kScenes = std::string(GS_ASSETS_DIR) + "/scenes/";

// In one directory of this process's own, removed at exit.
std::string write_temp(const std::string& name, const std::string& text) {
    static const gs::test::TempDir dir;
    const auto path = (dir / name).string();
    std::ofstream(path) << text;
    return path;
}

std::string minimal(const std::string& extra) {
    return R"({"room": {"x_m": [-1, 10], "y_m": [-3, 3], "height_m": 3},
  "start": {"x_m": 0, "y_m": 0, "z_m": 1})" +
           extra + "}";
}

TEST(SimScene, ShippedScenesLoad) {
    for (const char* f : {"thesis_pillar_left.json", "thesis_pillar_right.json",
                          "thesis_pillar_center.json", "thesis_open_hall.json", "warehouse.json"}) {
        auto s = load_scene(kScenes + f);
        ASSERT_TRUE(s.has_value()) << f << ": " << to_string(s.error());
        EXPECT_FALSE(s->autopilot.empty()) << f;
    }
}

// Thesis 5.2: start at least 6 m before the obstacle, ~0.5 m to the side for left/right (the
// pillar's centre 0.6 m from the flight line: the 0.52 m hull passes 9 cm from its face).
TEST(SimScene, ThesisSetupsMatchChapter5) {
    for (const auto& [file, lateral] :
         {std::pair{"thesis_pillar_left.json", -0.6}, std::pair{"thesis_pillar_right.json", 0.6},
          std::pair{"thesis_pillar_center.json", 0.0}}) {
        auto s = load_scene(kScenes + file);
        ASSERT_TRUE(s.has_value());
        auto t = find_obstacle(*s, s->target_id);
        ASSERT_TRUE(t.has_value());
        const ObstacleHit h =
            obstacle_relative(*s, *t, s->start.x_m, s->start.y_m, s->start.yaw_deg);
        EXPECT_NEAR(h.distance_m, 7.0, 1e-9) << file;  // pillar 0.5 m deep, centre at x = 7.25
        EXPECT_NEAR(h.lateral_m, lateral, 1e-9) << file;
        EXPECT_GE(h.distance_m, 6.0);
    }
    auto hall = load_scene(kScenes + "thesis_open_hall.json");
    ASSERT_TRUE(hall.has_value());
    EXPECT_EQ(hall->scenario, "none");
    EXPECT_FALSE(obstacle_ahead(*hall, 0, 0, 0, 1.0, 20.0).has_value());
}

TEST(SimScene, GroundTruthQueries) {
    auto s = load_scene(kScenes + "thesis_pillar_center.json");
    ASSERT_TRUE(s.has_value());
    // Straight ahead: the near face at 7 m from x = 0, 2 m after flying 5 m, passed beyond 7.5 m.
    auto h = obstacle_ahead(*s, 0, 0, 0, 0.3);
    ASSERT_TRUE(h.has_value());
    EXPECT_NEAR(h->distance_m, 7.0, 1e-9);
    EXPECT_NEAR(obstacle_relative(*s, h->index, 5.0, 0, 0).distance_m, 2.0, 1e-9);
    EXPECT_NEAR(obstacle_relative(*s, h->index, 8.0, 0, 0).distance_m, -1.0, 1e-9);
    // Heading 90 deg (facing right, +y): the pillar is now 7.25 m to the left of that line.
    EXPECT_NEAR(obstacle_relative(*s, h->index, 0, 0, 90).lateral_m, -7.25, 1e-9);
    // Rays: forward hits the pillar's face, up hits the ceiling (3 m room, eye at 1 m), back the
    // wall.
    EXPECT_NEAR(ray_distance(*s, 0, 0, 1, 1, 0, 0).value(), 7.0, 1e-9);
    EXPECT_NEAR(ray_distance(*s, 0, 0, 1, 0, 0, 1).value(), 2.0, 1e-9);
    EXPECT_NEAR(ray_distance(*s, 0, 0, 1, -1, 0, 0).value(), 3.0, 1e-9);
    // Left scene: the pillar spans lateral -0.85..-0.35, so a 0.3 m corridor misses it.
    auto l = load_scene(kScenes + "thesis_pillar_left.json");
    ASSERT_TRUE(l.has_value());
    EXPECT_FALSE(obstacle_ahead(*l, 0, 0, 0, 0.3).has_value());
    ASSERT_TRUE(obstacle_ahead(*l, 0, 0, 0, 0.4).has_value());
}

TEST(SimScene, JsonErrorsNameFileAndKey) {
    auto missing = load_scene("/nonexistent/scene.json");
    ASSERT_FALSE(missing.has_value());
    EXPECT_EQ(missing.error().kind, AssetErrorKind::FileNotFound);
    EXPECT_NE(to_string(missing.error()).find("/nonexistent/scene.json"), std::string::npos);

    const auto bad_json = write_temp("bad.json", "{ \"room\": ");
    EXPECT_EQ(load_scene(bad_json).error().kind, AssetErrorKind::ParseError);

    const auto no_room = write_temp("noroom.json", R"({"start": {"x_m": 0, "y_m": 0}})");
    auto e1 = load_scene(no_room);
    ASSERT_FALSE(e1.has_value());
    EXPECT_EQ(e1.error().kind, AssetErrorKind::MissingKey);
    EXPECT_EQ(e1.error().key, "room");
    EXPECT_EQ(to_string(e1.error()), no_room + ": room: required");

    const auto bad_tex =
        write_temp("badtex.json", minimal(R"(, "obstacles": [{"type": "box", "center_m": [5, 0],
        "size_m": [0.5, 0.5]}, {"type": "box", "center_m": [5, 1], "size_m": [0.5, 0.5],
        "texture": {"kind": "marble"}}])"));
    auto e2 = load_scene(bad_tex);
    ASSERT_FALSE(e2.has_value());
    EXPECT_EQ(e2.error().key, "obstacles[1].texture.kind");
    EXPECT_NE(e2.error().detail.find("marble"), std::string::npos);

    const auto bad_size =
        write_temp("badsize.json", minimal(R"(, "obstacles": [{"type": "box", "center_m": [5, 0],
        "size_m": [0.5]}])"));
    EXPECT_EQ(load_scene(bad_size).error().key, "obstacles[0].size_m");

    const auto bad_type = write_temp(
        "badtype.json", minimal(R"(, "obstacles": [{"type": "cone", "center_m": [5, 0]}])"));
    EXPECT_EQ(load_scene(bad_type).error().key, "obstacles[0].type");

    const auto no_target =
        write_temp("notarget.json", minimal(R"(, "scenario": "left", "target": "pillar")"));
    auto e3 = load_scene(no_target);
    ASSERT_FALSE(e3.has_value());
    EXPECT_EQ(e3.error().key, "target");

    const auto outside =
        write_temp("outside.json", R"({"room": {"x_m": [-1, 10], "y_m": [-3, 3], "height_m": 3},
        "start": {"x_m": 0, "y_m": 5}})");
    EXPECT_EQ(load_scene(outside).error().key, "start");

    const auto bad_number =
        write_temp("badnum.json", R"({"room": {"x_m": [-1, 10], "y_m": [-3, 3], "height_m": "3"},
        "start": {"x_m": 0, "y_m": 0}})");
    EXPECT_EQ(load_scene(bad_number).error().key, "room.height_m");
}

TEST(SimScene, GeneratorIsDeterministicAndKeepsThePathClear) {
    for (const char* scenario : {"left", "right", "center", "none"}) {
        GeneratorParams p;
        p.scenario = scenario;
        p.start_distance_m = 6.5;
        p.clutter_density = 1.0;
        for (std::uint64_t seed = 1; seed <= 15; ++seed) {
            const Scene a = generate_scene(p, seed), b = generate_scene(p, seed);
            ASSERT_EQ(a.obstacles.size(), b.obstacles.size());
            for (std::size_t i = 0; i < a.obstacles.size(); ++i) {
                EXPECT_EQ(a.obstacles[i].x_m, b.obstacles[i].x_m);
                EXPECT_EQ(a.obstacles[i].texture, b.obstacles[i].texture);
            }
            // Nothing but the target within 0.9 m of the flight line before the front wall.
            auto ahead = obstacle_ahead(a, a.start.x_m, a.start.y_m, 0, 0.9);
            if (std::string(scenario) == "none") {
                EXPECT_FALSE(ahead.has_value()) << "seed " << seed;
                continue;
            }
            auto t = find_obstacle(a, a.target_id);
            ASSERT_TRUE(t.has_value());
            ASSERT_TRUE(ahead.has_value());
            EXPECT_EQ(ahead->index, *t) << scenario << " seed " << seed;
            const ObstacleHit h = obstacle_relative(a, *t, a.start.x_m, a.start.y_m, 0);
            EXPECT_NEAR(h.distance_m, 6.5, 1e-9);
            const double want = std::string(scenario) == "left"    ? -0.5
                                : std::string(scenario) == "right" ? 0.5
                                                                   : 0.0;
            EXPECT_NEAR(h.lateral_m, want, 0.081);
        }
    }
    GeneratorParams p;
    EXPECT_NE(generate_scene(p, 1).room.x_max_m, generate_scene(p, 2).room.x_max_m);
}

}  // namespace
}  // namespace gs::sim
