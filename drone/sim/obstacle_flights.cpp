#include "drone/sim/obstacle_flights.hpp"
#include "drone/core/unknown.hpp"

#include "drone/dataset/csv.hpp"
#include "drone/dataset/video_dataset_writer.hpp"
#include "drone/dataset/writer.hpp"
#include "drone/sim/drone_core.hpp"
#include "drone/sim/realism.hpp"
#include "drone/sim/renderer.hpp"
#include "drone/sim/rng.hpp"
#include "drone/video/h264_encoder.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <optional>

namespace gs::sim {
namespace fs = std::filesystem;

nlohmann::json ObstacleFlightInfo::extra_labels() const {
    nlohmann::json j;
    j["scenario"] = scenario;
    j["source"] = "ardrone-gs virtual drone, rendered offline (ground truth)";
    j["scene"] = scene.name;
    if (!scene.target_id.empty()) j["target"] = scene.target_id;
    if (!group.empty()) j["group"] = group;
    if (!split.empty()) j["split"] = split;
    j["speed_mps"] = params.speed_mps;
    j["height_m"] = params.height_m;
    j["roll_wobble_deg"] = params.flight.roll_wobble_deg;
    j["wind_right_mps"] = params.flight.wind_right_mps;
    j["yaw_drift_deg_s"] = params.flight.yaw_drift_deg_s;
    j["yaw_wobble_deg"] = params.yaw_wobble_deg;
    j["yaw_wobble_hz"] = params.yaw_wobble_hz;
    if (!std::isnan(params.end_lateral_m)) j["end_lateral_m"] = params.end_lateral_m;
    if (!std::isnan(params.clear_path_m)) {
        j["clear_path_m"] = params.clear_path_m;
        j["clear_ahead_s"] = params.clear_ahead_s;
    }
    j["seed"] = params.seed;
    return j;
}

namespace {

double since_ms(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// One recorded frame of a flight: the drone's state and pose, and where the target is.
struct FlightFrame {
    std::int64_t index;
    TimeNs t_ns;  // from the start of the recording
    const FlightState& state;
    Pose pose;
    double distance_m, lateral_m;  // target (NaN without one)
};

struct FlightEnd {
    std::int64_t frames = 0;
    double duration_s = 0;
    double lateral_m = kUnknown;  // target's lateral offset at the last frame
};

// Flies the protocol with the virtual drone's brain and flight model: take off (to ~1 m), climb
// or sink to the flight height, hover facing the obstacle, then fly forward until the scenario's
// end; calls on_frame for every recorded frame (frames at p.fps). Deterministic.
template <class OnFrame>
Expected<FlightEnd, std::string> fly_protocol(const ObstacleFlightInfo& fl, const Scene& scene,
                                              std::optional<std::size_t> target,
                                              OnFrame&& on_frame) {
    const ObstacleFlightParams& p = fl.params;
    DroneCoreOptions co;
    co.flight = p.flight;
    co.start = scene.start;
    co.start.z_m = 0;
    co.seed = p.seed;
    const double climb_rate = 0.5;
    const double dz = p.height_m - co.flight.takeoff_height_m;
    const double climb_s = std::abs(dz) / climb_rate;
    co.autopilot.push_back({"takeoff", 0, 0, 0, 0, 0});
    if (climb_s > 0.05)
        co.autopilot.push_back({"move", climb_s, 0, 0, dz > 0 ? climb_rate : -climb_rate, 0});
    co.autopilot.push_back({"hover", p.settle_s, 0, 0, 0, 0});
    if (p.yaw_wobble_deg > 0 && p.yaw_wobble_hz > 0) {
        // The approach in 0.1 s steps whose yaw rates follow d/dt of A sin(2 pi f t).
        const double step_s = 0.1, w = 2 * std::numbers::pi * p.yaw_wobble_hz;
        for (double ts = 0; ts < p.max_record_s + 5; ts += step_s) {
            const double rate =
                p.yaw_wobble_deg * (std::sin(w * (ts + step_s)) - std::sin(w * ts)) / step_s;
            co.autopilot.push_back({"move", step_s, p.speed_mps, 0, 0, rate});
        }
    }
    co.autopilot.push_back({"move", p.max_record_s + 60, p.speed_mps, 0, 0, 0});
    co.autopilot_enabled = true;
    DroneCore core(co);

    std::vector<OutDatagram> sink;
    const TimeNs frame_ns = static_cast<TimeNs>(std::llround(1e9 / p.fps));
    const TimeNs limit_ns = static_cast<TimeNs>((p.max_record_s + 60 + climb_s + p.settle_s) * 1e9);
    std::optional<TimeNs> airborne_ns, record_ns;
    double start_x = 0, start_y = 0;
    FlightEnd end;
    for (TimeNs t = 0; t < limit_ns; t += frame_ns) {
        sink.clear();
        core.advance(t, sink);
        const FlightState& s = core.flight();
        if (!airborne_ns && (s.major == CtrlMajor::Hovering || s.major == CtrlMajor::Flying))
            airborne_ns = t;
        if (!airborne_ns) continue;
        if (!record_ns) {
            if (t < *airborne_ns + static_cast<TimeNs>((climb_s + p.settle_s) * 1e9)) continue;
            record_ns = t;
            start_x = s.x_m;
            start_y = s.y_m;
        }
        const Pose pose = core.pose();
        const double travelled = std::hypot(s.x_m - start_x, s.y_m - start_y);
        double distance = kUnknown, lateral = kUnknown;
        if (target) {
            const ObstacleHit h =
                obstacle_relative(scene, *target, pose.x_m, pose.y_m, pose.yaw_deg);
            distance = h.distance_m;
            lateral = h.lateral_m;
        }
        const double rec_s = static_cast<double>(t - *record_ns) * 1e-9;
        bool stop = rec_s > p.max_record_s;
        if (fl.scenario == "center")
            stop = stop || distance <= p.stop_before_m;
        else if (fl.scenario == "left" || fl.scenario == "right")
            stop = stop || distance < -p.pass_by_m;
        else
            stop = stop || travelled >= p.open_path_m;
        if (stop) break;
        if (auto e = on_frame(FlightFrame{end.frames, t - *record_ns, s, pose, distance, lateral}))
            return Unexpected(*e);
        end.duration_s = rec_s;
        end.lateral_m = lateral;
        ++end.frames;
    }
    if (end.frames == 0)
        return Unexpected(std::string("the flight never reached its recording phase"));
    return end;
}

}  // namespace

Expected<FlownScene, std::string> flown_scene(const ObstacleFlightInfo& fl) {
    const ObstacleFlightParams& p = fl.params;
    FlownScene out;
    out.scene = fl.scene;
    Scene& scene = out.scene;
    std::optional<std::size_t>& target = out.target;
    if (fl.scenario != "none") {
        target = find_obstacle(scene, scene.target_id);
        if (!target)
            return Unexpected("scene " + scene.name + " has no target obstacle '" +
                              scene.target_id + "'");
    }
    const bool correct_drift = target && !std::isnan(p.end_lateral_m);
    if (!correct_drift && !(p.clear_path_m > 0)) return out;
    // A dry run (no pixels) of the same flight: the flight model does not depend on where it
    // starts, so what it gives holds, shifted, for the real one.
    std::vector<cv::Point2d>& path = out.path;
    auto dry = fly_protocol(fl, scene, target, [&](const FlightFrame& f) {
        path.emplace_back(f.pose.x_m, f.pose.y_m);
        return std::optional<std::string>();
    });
    if (!dry) return Unexpected(dry.error());
    const double yaw = scene.start.yaw_deg * std::numbers::pi / 180;
    if (correct_drift) {
        // Drift (wind) carries the drone sideways during the approach: move the start across
        // the heading so that the target ends at end_lateral_m.
        const double shift = dry->lateral_m - p.end_lateral_m;  // start moves right by this
        const cv::Point2d d(-shift * std::sin(yaw), shift * std::cos(yaw));
        scene.start.x_m += d.x;
        scene.start.y_m += d.y;
        for (cv::Point2d& q : path) q += d;
        const Room& r = scene.room;
        if (!(scene.start.x_m > r.x_min_m + 0.3 && scene.start.x_m < r.x_max_m - 0.3 &&
              scene.start.y_m > r.y_min_m + 0.3 && scene.start.y_m < r.y_max_m - 0.3))
            return Unexpected("the drift correction moves the start of " + fl.name +
                              " out of the room");
    }
    if (p.clear_path_m > 0) {
        // The flight line ahead of the last position, along the start heading.
        if (!path.empty() && p.clear_ahead_s > 0) {
            const cv::Point2d heading(std::cos(yaw), std::sin(yaw));
            const cv::Point2d end = path.back();
            const double ahead_m = p.speed_mps * p.clear_ahead_s;
            for (double s_m = 0.1; s_m <= ahead_m; s_m += 0.1) path.push_back(end + s_m * heading);
        }
        const std::string target_id = target ? scene.obstacles[*target].id : std::string();
        std::erase_if(scene.obstacles, [&](const Obstacle& o) {
            if (!o.clutter || (!target_id.empty() && o.id == target_id)) return false;
            for (const cv::Point2d& q : path)
                if (footprint_distance(o, q.x, q.y) < p.clear_path_m) return true;
            return false;
        });
        if (target) target = find_obstacle(scene, scene.target_id);
    }
    return out;
}

Expected<ObstacleFlightSummary, std::string> write_obstacle_flight(const fs::path& dir,
                                                                   const ObstacleFlightInfo& fl) {
    const ObstacleFlightParams& p = fl.params;
    if (!(p.fps > 0 && p.fps <= 120)) return Unexpected(std::string("fps out of range"));
    if (!(p.speed_mps > 0 && p.speed_mps <= 5))
        return Unexpected(std::string("speed out of range"));
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_empty(dir, ec))
        return Unexpected(dir.string() + " exists and is not empty");

    GS_TRY_ASSIGN(FlownScene prepared, flown_scene(fl));
    Scene scene = std::move(prepared.scene);
    std::optional<std::size_t> target = prepared.target;
    if (auto e = p.realism.check()) return Unexpected(*e);
    // The realism layer's scene effects (plain walls ...): what the camera sees, not the flight.
    const SceneEffects scene_fx = apply_scene_effects(scene, p.realism, mix_seed(p.seed, 0x5ce4e));
    const CameraCalibration calib = rendered_front_camera(p.realism);
    auto renderer = Renderer::create(scene, calib, CameraKind::Front, render_options(p.realism));
    if (!renderer) return Unexpected("renderer: " + to_string(renderer.error()));
    video::H264EncoderConfig ec_cfg;
    ec_cfg.width = calib.width;
    ec_cfg.height = calib.height;
    ec_cfg.fps = static_cast<int>(std::lround(p.fps));
    ec_cfg.gop = 15;
    ec_cfg.bitrate_bps = p.bitrate_bps;
    auto encoder = video::H264Encoder::create(ec_cfg);
    if (!encoder) return Unexpected("H.264 encoder: " + to_string(encoder.error()));

    GS_TRY_ASSIGN(dataset::VideoDatasetWriter out, dataset::VideoDatasetWriter::create(dir));
    std::string labels_csv = "frame,distance_m,lateral_m\n";

    Rng noise(mix_seed(p.seed, 0x0b5));
    CameraEffects camera_fx(calib, p.realism, mix_seed(p.seed, 0xca3e7a));
    StreamDamage damage(p.realism.slice_loss_pct, mix_seed(p.seed, 0x511ce));
    NavdataEffects nav_fx(p.realism, mix_seed(p.seed, 0x4a7da7a));
    std::optional<Pose> last_pose;
    std::vector<PersonTrack> people;  // planned at the first recorded frame
    std::vector<Obstacle> movers;
    std::vector<std::uint8_t> au;
    cv::Mat image;
    ObstacleFlightSummary sum;
    sum.start_distance_m = kUnknown;
    sum.end_distance_m = kUnknown;
    auto flown =
        fly_protocol(fl, scene, target, [&](const FlightFrame& f) -> std::optional<std::string> {
            const FlightState& s = f.state;
            if (p.realism.people_crossing > 0) {
                // People crossing the path ahead: scenery the renderer draws, never the flight's.
                if (f.index == 0)
                    people = plan_people(p.realism, scene.room, f.pose.x_m, f.pose.y_m,
                                         scene.start.yaw_deg, 1.25 * p.speed_mps,
                                         mix_seed(p.seed, 0x9e091e));
                const double t_s = static_cast<double>(f.t_ns) * 1e-9;
                movers.clear();
                for (const PersonTrack& q : people)
                    if (q.present(t_s)) movers.push_back(q.at(t_s));
                renderer->set_movers(movers);
            }
            auto t0 = std::chrono::steady_clock::now();
            renderer->render(f.pose, image);
            sum.render_ms += since_ms(t0);
            const double frame_s = 1 / p.fps;
            if (p.realism.geometric() || p.realism.photometric()) {
                t0 = std::chrono::steady_clock::now();
                const CameraMotion m =
                    last_pose ? camera_motion(*last_pose, f.pose, frame_s, CameraKind::Front)
                              : CameraMotion{};
                camera_fx.apply(image, static_cast<double>(f.t_ns) * 1e-9, m,
                                renderer->inverse_depth());
                sum.realism_ms += since_ms(t0);
            }
            last_pose = f.pose;
            t0 = std::chrono::steady_clock::now();
            bool idr = false;
            auto n = (*encoder)->encode(image, au, idr);
            if (!n) return "H.264 encoder: " + to_string(n.error());
            sum.encode_ms += since_ms(t0);
            damage.apply(au, idr);
            t0 = std::chrono::steady_clock::now();
            dataset::FrameRow row;
            row.nav.t_ns = f.t_ns;
            NavState truth = true_navdata(s, f.t_ns);
            if (p.realism.navdata()) {
                // Late, jittered and drifting, as the drone's estimator reports it.
                nav_fx.push_truth(truth);
                truth = nav_fx.sample(f.t_ns);
            }
            row.nav.roll_deg = truth.roll_deg + gaussian(noise, p.attitude_noise_deg);
            row.nav.pitch_deg = truth.pitch_deg + gaussian(noise, p.attitude_noise_deg);
            row.nav.yaw_deg = truth.yaw_deg + gaussian(noise, p.attitude_noise_deg);
            row.nav.vx_mps = truth.vx_mps + gaussian(noise, p.velocity_noise_mps);
            row.nav.vy_mps = truth.vy_mps + gaussian(noise, p.velocity_noise_mps);
            row.nav.vz_mps = truth.vz_mps + gaussian(noise, p.velocity_noise_mps);
            row.nav.altitude_m = truth.altitude_m;
            row.nav.battery_pct = std::floor(s.battery_pct);
            row.gt = dataset::GroundTruthPose{f.pose.x_m, f.pose.y_m, f.pose.z_m, f.pose.yaw_deg};
            labels_csv += std::to_string(out.frames()) + ',' +
                          dataset::csv::format_number(f.distance_m) + ',' +
                          dataset::csv::format_number(f.lateral_m) + '\n';
            out.add(au, row);
            sum.video_bytes += au.size();
            if (f.index == 0) sum.start_distance_m = f.distance_m;
            sum.end_distance_m = f.distance_m;
            sum.write_ms += since_ms(t0);
            return std::nullopt;
        });
    if (!flown) return Unexpected(flown.error());
    sum.frames = static_cast<int>(flown->frames);
    sum.slices_lost = damage.damaged();
    sum.duration_s = flown->duration_s;

    dataset::DatasetInfo info;
    info.camera = CameraId::Front;
    info.width = calib.width;
    info.height = calib.height;
    info.fps = p.fps;
    info.frames = out.frames();
    info.calibration = calib;
    info.source = "rendered: ardrone-gs virtual drone (" + fl.name + ")";
    std::string flight_json = dataset::flight_json_text(info);
    if (p.realism.any()) {
        // What the realism layer did (docs/dataset.md "realism"), beside the standard keys.
        auto j = nlohmann::ordered_json::parse(flight_json);
        nlohmann::ordered_json r = p.realism.to_json();
        r["video_bitrate_kbps"] = p.bitrate_bps / 1000.0;
        r["seed"] = p.seed;
        r["slices_lost"] = sum.slices_lost;
        if (p.realism.low_texture_walls_pct > 0) r["plain_walls"] = scene_fx.plain_walls;
        if (p.realism.people_crossing > 0) {
            r["people"] = nlohmann::ordered_json::array();
            for (const PersonTrack& q : people)
                r["people"].push_back(nlohmann::ordered_json::parse(q.to_json().dump()));
        }
        j["realism"] = r;
        flight_json = j.dump(2) + "\n";
    }
    if (auto e = out.finish_with(flight_json, {{"labels.csv", labels_csv},
                                               {"labels.json", fl.extra_labels().dump(2) + "\n"}}))
        return Unexpected(*e);
    return sum;
}

ObstacleFlightInfo scenario_flight(const Scene& scene, double speed_mps, std::uint64_t seed) {
    ObstacleFlightInfo f;
    f.name = scene.name;
    f.scenario = scene.scenario;
    f.scene = scene;
    f.params.speed_mps = speed_mps;
    f.params.height_m = scene.start.z_m;
    f.params.seed = seed;
    return f;
}

namespace {

struct Variation {
    double speed_mps, height_m, roll_wobble_deg, wobble_hz, wind_right_mps, yaw_wobble_deg;
    double yaw_wobble_hz;
    double start_distance_m;
};

Variation vary(Rng& r) {
    Variation v;
    v.speed_mps = r.uniform(0.6, 1.5);
    v.height_m = r.uniform(0.8, 1.6);
    v.roll_wobble_deg = r.uniform(0.0, 2.0);
    v.wobble_hz = r.uniform(0.3, 1.2);
    v.wind_right_mps = r.uniform(-0.15, 0.15);
    v.yaw_wobble_deg = r.uniform(0.0, 3.0);
    v.yaw_wobble_hz = r.uniform(0.15, 0.5);
    v.start_distance_m = r.uniform(6.0, 7.5);
    return v;
}

ObstacleFlightParams params_of(const Variation& v, std::uint64_t seed) {
    ObstacleFlightParams p;
    p.speed_mps = v.speed_mps;
    p.height_m = v.height_m;
    p.flight.roll_wobble_deg = v.roll_wobble_deg;
    p.flight.roll_wobble_hz = v.wobble_hz;
    p.flight.wind_right_mps = v.wind_right_mps;
    p.yaw_wobble_deg = v.yaw_wobble_deg;
    p.yaw_wobble_hz = v.yaw_wobble_hz;
    p.seed = seed;
    return p;
}

// Half the target's extent across the flight direction (heading 0: world y).
double half_width_y(const Obstacle& o) {
    if (o.shape == ObstacleShape::Cylinder) return o.radius_m;
    const double c = std::abs(std::cos(o.yaw_deg * std::numbers::pi / 180)),
                 s = std::abs(std::sin(o.yaw_deg * std::numbers::pi / 180));
    return 0.5 * (o.size_y_m * c + o.size_x_m * s);
}
double half_depth_x(const Obstacle& o) {
    if (o.shape == ObstacleShape::Cylinder) return o.radius_m;
    const double c = std::abs(std::cos(o.yaw_deg * std::numbers::pi / 180)),
                 s = std::abs(std::sin(o.yaw_deg * std::numbers::pi / 180));
    return 0.5 * (o.size_x_m * c + o.size_y_m * s);
}

// Moves the drone's start so the target sits `lateral` to the side of the flight line (negative:
// left), its near face `distance` ahead.
void place_start(Scene& s, const Obstacle& t, double lateral, double distance, double height) {
    s.start.y_m = t.y_m - lateral;
    s.start.x_m = t.x_m - half_depth_x(t) - distance;
    s.start.x_m = std::max(s.start.x_m, s.room.x_min_m + 0.6);
    s.start.z_m = height;
    s.start.yaw_deg = 0;
}

ObstacleFlightInfo flight(std::string name, std::string group, std::string scenario, Scene scene,
                          const Variation& v, std::uint64_t seed, int index_in_kind) {
    ObstacleFlightInfo f;
    f.name = std::move(name);
    f.group = std::move(group);
    f.scenario = std::move(scenario);
    f.scene = std::move(scene);
    f.scene.scenario = f.scenario;
    f.scene.name = f.name;
    f.params = params_of(v, seed);
    f.split = index_in_kind % 2 == 0 ? "tune" : "test";
    return f;
}

// Scenery keeps this far from the path flown (edge to the drone's centre line: 0.74 m of air
// beside its hull): only the target is in the way.
constexpr double kClearPathM = 1.0;

// The target's centre across the path where the flight ends. Side flights pass it (thesis §5.2:
// about 0.5 m to the side) with 0.3-0.5 m between its near face and the flight line: outside the
// drone's 0.26 m half-width, so they stay passes however the drone drifted on the way. Centre
// flights end head-on, within 0.1 m.
double pass_lateral(Rng& rng, const std::string& scenario, const Obstacle& t) {
    const double clearance = rng.uniform(0.3, 0.5);
    if (scenario == "left") return -(half_width_y(t) + clearance);
    if (scenario == "right") return half_width_y(t) + clearance;
    return rng.uniform(-0.1, 0.1);
}

char tag(const std::string& scenario) {
    return scenario == "left" ? 'L' : scenario == "right" ? 'R' : scenario == "center" ? 'C' : 'N';
}

}  // namespace

std::vector<ObstacleFlightInfo> thesis_suite(std::uint64_t seed) {
    std::vector<ObstacleFlightInfo> out;
    Rng rng(mix_seed(seed, 0x5417e));
    char name[64];

    // Uncluttered (§5.2.2): one artificial obstacle, black cloth with white tape, in a plain
    // room; 5 left, 5 right, 10 centre.
    {
        GeneratorParams gp;
        gp.scenario = "center";
        gp.clutter_density = 0.0;
        gp.texture_richness = 0.15;
        Scene base = generate_scene(gp, mix_seed(seed, 100));
        Obstacle& t = base.obstacles[*find_obstacle(base, base.target_id)];
        t.texture.kind = TextureKind::Tape;
        t.texture.color_rgb = {25, 25, 28};
        t.texture.scale_m = 1.0;
        t.height_m = base.room.height_m;
        const std::vector<std::pair<std::string, int>> kinds = {
            {"left", 5}, {"right", 5}, {"center", 10}};
        for (const auto& [scenario, count] : kinds) {
            for (int i = 0; i < count; ++i) {
                const Variation v = vary(rng);
                Scene s = base;
                const Obstacle& tt = s.obstacles[*find_obstacle(s, s.target_id)];
                const double lat = pass_lateral(rng, scenario, tt);
                place_start(s, tt, lat, v.start_distance_m, v.height_m);
                std::snprintf(name, sizeof name, "uncluttered_%c%02d", tag(scenario), i + 1);
                out.push_back(flight(name, "uncluttered", scenario, std::move(s), v,
                                     mix_seed(seed, out.size() + 1), i));
                out.back().params.end_lateral_m = lat;
                out.back().params.clear_path_m = kClearPathM;
            }
        }
    }

    // Cluttered (§5.2.2): four pillars with paper sheets in a busy room; per pillar 4 centre
    // flights and 4 past it (pillars 1 and 3 on the right, 2 and 4 on the left).
    for (int pillar = 0; pillar < 4; ++pillar) {
        GeneratorParams gp;
        gp.scenario = "center";
        gp.clutter_density = 0.9;
        gp.texture_richness = 0.8;
        Scene base = generate_scene(gp, mix_seed(seed, 200 + static_cast<std::uint64_t>(pillar)));
        Obstacle& t = base.obstacles[*find_obstacle(base, base.target_id)];
        t.texture.kind = TextureKind::Paper;
        t.texture.scale_m = 1.6;
        t.height_m = base.room.height_m;
        const std::string side = pillar % 2 == 0 ? "right" : "left";
        for (const std::string& scenario : {std::string("center"), side}) {
            for (int i = 0; i < 4; ++i) {
                const Variation v = vary(rng);
                Scene s = base;
                const Obstacle& tt = s.obstacles[*find_obstacle(s, s.target_id)];
                const double lat = pass_lateral(rng, scenario, tt);
                place_start(s, tt, lat, v.start_distance_m, v.height_m);
                std::snprintf(name, sizeof name, "cluttered_p%d_%c%02d", pillar + 1, tag(scenario),
                              i + 1);
                out.push_back(flight(name, "cluttered", scenario, std::move(s), v,
                                     mix_seed(seed, out.size() + 1), pillar * 4 + i));
                out.back().params.end_lateral_m = lat;
                out.back().params.clear_path_m = kClearPathM;
            }
        }
    }

    // Open space (§5.2.2): a large hall, three paths, ten flights each, nothing in the path.
    for (int path = 0; path < 3; ++path) {
        GeneratorParams gp;
        gp.scenario = "none";
        gp.start_distance_m = 12.0;
        gp.clutter_density = 0.35;
        gp.texture_richness = 0.7;
        Scene base = generate_scene(gp, mix_seed(seed, 300 + static_cast<std::uint64_t>(path)));
        // A hall: wide and long, so the far wall stays far (> 6 m) at the end of the path.
        base.room.x_max_m = std::max(base.room.x_max_m, base.start.x_m + 18.0);
        for (int i = 0; i < 10; ++i) {
            const Variation v = vary(rng);
            Scene s = base;
            s.start.z_m = v.height_m;
            s.start.y_m += rng.uniform(-0.3, 0.3);
            std::snprintf(name, sizeof name, "open_path%d_%02d", path + 1, i + 1);
            ObstacleFlightInfo f = flight(name, "open", "none", std::move(s), v,
                                          mix_seed(seed, out.size() + 1), path * 10 + i);
            f.params.open_path_m = 8.0;
            f.params.clear_path_m = kClearPathM;
            out.push_back(std::move(f));
        }
    }
    return out;
}

}  // namespace gs::sim
