// Source lifecycle: a real drone through a DroneLink, the virtual drone on loopback with a link to
// it, a recorded dataset replayed; closing whichever is open.
#include "app/session_current.hpp"

#include "app/replay_run.hpp"
#include "drone/dataset/video_frames.hpp"
#include "drone/sim/loopback.hpp"
#include "drone/sim/scenarios.hpp"

namespace gs::app {

void Session::close_current() {
    record_stop();  // the recorder holds a reference to the link
    Current& c = *cur_;
    if (c.frames) c.frames->close();
    if (c.link) c.link->stop();
    if (c.drone) c.drone->stop();
    const bool had = c.kind != SessionSource::None;
    c.frames.reset();
    c.link.reset();
    c.drone.reset();
    c.replay.reset();
    c.kind = SessionSource::None;
    c.address.clear();
    c.scenario.clear();
    c.path.clear();
    c.rinfo = ReplayInfo{};
    c.fps = kUnknown;
    c.rate_n = 0;
    c.camera = CameraId::Front;
    c.config_gen = 0;
    c.settle = 0;
    last_live_frame_ns_ = 0;
    stale_published_ = false;
    if (had) {
        c.id = next_id_++;
        reset_vision();
    }
}

void Session::open_drone(const std::string& address) {
    close_current();
    link::LinkConfig lc;
    lc.drone_address = address.empty() ? "192.168.1.1" : address;
    auto l = std::make_shared<link::DroneLink>(lc, clock_);
    if (auto st = l->start(); !st) {
        publish_source("cannot connect to " + lc.drone_address + ": " + st.error().message);
        message("connect failed: " + st.error().message);
        return;
    }
    Current& c = *cur_;
    c.kind = SessionSource::Drone;
    c.id = next_id_++;
    c.address = lc.drone_address;
    c.link = std::move(l);
    c.frames = c.link->subscribe_frames(opts_.frame_queue);
    std::string origin;
    const CameraCalibration cal = drone_calibration(origin);
    odometry_.set_calibration(bottom_calibration());
    use_calibration(cal, origin);
    reset_vision();
    publish_source();
    publish_replay();
    message("connecting to the drone at " + c.address + " (calibration: " + origin + ")");
}

void Session::open_sim(const StartSim& s) {
    close_current();
    const std::string name = s.scenario.empty() ? "warehouse" : s.scenario;
    auto scene = sim::resolve_scene(name);
    if (!scene) {
        publish_source("scenario '" + name + "': " + sim::to_string(scene.error()));
        message("virtual drone: " + sim::to_string(scene.error()));
        return;
    }
    sim::VirtualDroneOptions vo = sim::loopback_options(std::move(*scene));
    vo.autopilot = s.autopilot;
    vo.video = opts_.sim_video;
    vo.core.battery_pct = opts_.sim_battery_pct;
    vo.clock = &clock_;  // a stepped session clock lock-steps the drone (offscreen runs)
    auto drone = std::make_shared<sim::VirtualDrone>(std::move(vo));
    if (auto st = drone->start(); !st) {
        publish_source("cannot start the virtual drone: " + st.error().message);
        message("virtual drone: " + st.error().message);
        return;
    }
    link::LinkConfig lc = sim::link_config(*drone);
    lc.video = opts_.sim_video;
    auto l = std::make_shared<link::DroneLink>(lc, clock_);
    if (auto st = l->start(); !st) {
        drone->stop();
        publish_source("cannot open the link to the virtual drone: " + st.error().message);
        message("virtual drone link: " + st.error().message);
        return;
    }
    Current& c = *cur_;
    c.kind = SessionSource::Sim;
    c.id = next_id_++;
    c.scenario = drone->scene().name.empty() ? name : drone->scene().name;
    c.address = "127.0.0.1:" + std::to_string(drone->navdata_port());
    c.drone = std::move(drone);
    c.link = std::move(l);
    c.frames = c.link->subscribe_frames(opts_.frame_queue);
    odometry_.set_calibration(bottom_calibration());
    // The virtual drone renders with a global shutter: nothing to unroll (track.readout_ms).
    CameraCalibration front = front_calibration();
    front.readout_ms = 0;
    use_calibration(front, "virtual drone camera (assets default, global shutter)");
    reset_vision();
    publish_source();
    publish_replay();
    message("virtual drone '" + c.scenario + "' on " + c.address +
            (s.autopilot ? " (autopilot)" : ""));
}

void Session::open_replay(const std::string& path) {
    close_current();
    auto ds = dataset::Dataset::open(path);
    if (!ds) {
        publish_source("cannot open " + path + ": " + to_string(ds.error()));
        message("replay: cannot open " + path + ": " + to_string(ds.error()));
        return;
    }
    auto frames = dataset::open_frames(*ds);
    if (!frames) {
        publish_source("no frames in " + path + ": " + to_string(frames.error()));
        message("replay: " + to_string(frames.error()));
        return;
    }
    for (const auto& w : ds->warnings()) message("replay: " + w);
    std::vector<std::string> missing;
    for (const auto& m : missing_inputs(*ds, pipeline_.classifier_name())) {
        missing.push_back(to_string(m));
        message("replay: " + missing.back());
    }
    const CameraCalibration calib = ds->calibration();
    const CameraId camera = ds->info().camera;
    const double fps = ds->info().fps;
    const std::int64_t n = ds->frame_count();
    Current& c = *cur_;
    c.replay = std::make_unique<dataset::DatasetSource>(
        std::move(*ds), std::move(*frames), clock_,
        opts_.replay_lockstep ? Pacing::fastest() : Pacing::realtime());
    const bool play = opts_.replay_autoplay && !opts_.replay_lockstep;
    c.replay->set_paused(!play);
    c.kind = SessionSource::Replay;
    c.id = next_id_++;
    c.path = path;
    c.rinfo = ReplayInfo{};
    c.rinfo.open = true;
    c.rinfo.path = path;
    c.rinfo.frame_count = n;
    c.rinfo.fps = fps;
    c.rinfo.missing_inputs = std::move(missing);
    c.rinfo.playing = play;
    c.camera = camera;
    // The dataset's calibration is its camera's: the odometry's for a bottom-camera flight.
    odometry_.set_calibration(camera == CameraId::Bottom ? calib : bottom_calibration());
    use_calibration(calib, "dataset " + path);
    reset_vision();
    publish_source();
    publish_replay();
    message("replay: " + path + " (" + std::to_string(n) + " frames, " + to_string(camera) +
            " camera" +
            (camera == CameraId::Bottom ? ": visual odometry runs, not the obstacle classifier)"
                                        : ")"));
}

}  // namespace gs::app
