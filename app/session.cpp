#include "app/session.hpp"

#include "app/replay_run.hpp"

#include "drone/dataset/video_frames.hpp"
#include "drone/sim/scenarios.hpp"
#include "drone/video/frame_pool.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>

namespace gs::app {

const char* to_string(SessionSource s) {
    switch (s) {
        case SessionSource::None:
            return "none";
        case SessionSource::Drone:
            return "drone";
        case SessionSource::Sim:
            return "virtual drone";
        case SessionSource::Replay:
            return "replay";
    }
    return "?";
}

namespace {

constexpr TimeNs kIdleWaitNs = ms_to_ns(20);
constexpr std::size_t kImagePool = 6;
constexpr std::size_t kOutputPool = 3;  // the slot's, the window's copy, one being filled

CameraCalibration front_calibration() {
    auto c = default_calibration(CameraId::Front, assets_dir());
    // The same numbers compiled in if the asset is missing (docs/protocol.md §6.2).
    return c ? *c : builtin_calibration(CameraId::Front);
}

// The bottom camera's default (assets/calibration/ardrone2_bottom.json, else the same numbers
// compiled in).
CameraCalibration bottom_calibration() {
    auto c = default_calibration(CameraId::Bottom, assets_dir());
    return c ? *c : builtin_calibration(CameraId::Bottom);
}

// Frames already queued or on the wire when a camera switch is seen may still be of the other
// camera: this many are shown but given to neither the classifier nor the odometry.
constexpr int kCameraSettleFrames = 3;

}  // namespace

std::filesystem::path default_record_root() {
    const char* home = std::getenv("HOME");
    if (home && *home) return std::filesystem::path(home) / "ardrone-gs" / "flights";
    return "flights";
}

// Everything about the open source; lives on the session thread.
struct Session::Current {
    SessionSource kind = SessionSource::None;
    std::uint64_t id = 0;
    std::string address, scenario, path;
    std::shared_ptr<sim::VirtualDrone> drone;
    std::shared_ptr<link::DroneLink> link;
    std::shared_ptr<BoundedQueue<FrameSample>> frames;
    std::unique_ptr<dataset::DatasetSource> replay;
    ReplayInfo rinfo;
    // A replayed image is copied into a buffer the pipeline owns, because the dataset reader
    // reuses its own for the next frame while the window may still be drawing the previous one:
    // the video receiver's pool (explicit acquire and release, no reference count read).
    std::shared_ptr<video::FramePool> pool = video::FramePool::create(kImagePool);
    // The video's camera: the dataset's (replay) or the drone's configuration (live).
    CameraId camera = CameraId::Front;
    std::uint64_t config_gen = 0;
    int settle = 0;  // frames still to skip after a camera switch
    // Pipeline rate.
    TimeNs rate_t0 = 0;
    std::uint64_t rate_n = 0;
    double fps = kUnknown;
};

Session::Session(SessionOptions options, Clock& clock)
    : opts_(std::move(options)),
      clock_(clock),
      cur_(std::make_unique<Current>()),
      pipeline_(opts_.classifier, front_calibration()),
      odometry_(bottom_calibration()) {
    if (!pipeline_.ok()) (void)pipeline_.select(std::string(vision::kDefaultClassifier));
    use_calibration(front_calibration(), "assets default (front)");
    publish_source();
    publish_replay();
    publish_classifier();
    thread_ = std::thread([this] { run(); });
}

Session::~Session() {
    running_ = false;
    requests_.close();
    if (thread_.joinable()) thread_.join();
    close_current();
    calibrator_.reset();  // joins the worker (its apply() only posts to the closed queue)
}

bool Session::request(SessionRequest r) {
    // An open request is announced before it is queued, so no reader sees the old source as the
    // current one after asking for another (the session thread's answer comes later).
    const bool opens = std::holds_alternative<ConnectDrone>(r) ||
                       std::holds_alternative<StartSim>(r) || std::holds_alternative<OpenReplay>(r);
    if (!opens) return requests_.push(std::move(r));
    std::lock_guard lock(opening_mutex_);
    OpeningInfo o;
    o.count = opening_last_.count + 1;
    if (const auto* d = std::get_if<ConnectDrone>(&r)) {
        o.kind = SessionSource::Drone;
        o.what = d->address.empty() ? "192.168.1.1" : d->address;
    } else if (const auto* sim = std::get_if<StartSim>(&r)) {
        o.kind = SessionSource::Sim;
        o.what = sim->scenario.empty() ? "warehouse" : sim->scenario;
    } else if (const auto* rp = std::get_if<OpenReplay>(&r)) {
        o.kind = SessionSource::Replay;
        o.what = rp->path;
    }
    const OpeningInfo before = opening_last_;
    opening_last_ = o;
    opening_.publish(o);
    if (requests_.push(std::move(r))) return true;
    opening_last_ = before;  // never queued: nothing is being opened
    opening_.publish(before);
    return false;
}

void Session::message(std::string m) {
    messages_.push(std::move(m));
}

void Session::publish_source(std::string error) {
    SourceInfo s;
    s.kind = cur_->kind;
    s.id = cur_->id;
    s.address = cur_->address;
    s.scenario = cur_->scenario;
    s.path = cur_->path;
    s.error = std::move(error);
    s.link = cur_->link;
    s.virtual_drone = cur_->drone;
    s.opens_handled = opens_handled_;
    source_.publish(std::move(s));
}

void Session::publish_replay() {
    replay_.publish(cur_->rinfo);
}

void Session::publish_classifier(std::string error) {
    ClassifierInfo c;
    c.active = pipeline_.classifier_name();
    for (auto n : vision::classifier_names()) c.available.emplace_back(n);
    if (pipeline_.ok()) {
        // Defaults from a fresh instance: what "reset to default" goes back to.
        const auto fresh = vision::make_classifier(c.active, CameraCalibration{});
        std::vector<vision::ParamInfo> defaults;
        if (fresh) defaults = fresh->params();
        for (auto& p : pipeline_.classifier().params()) {
            ParamState ps;
            ps.default_value = p.value;
            for (const auto& d : defaults)
                if (d.name == p.name) ps.default_value = d.value;
            ps.info = std::move(p);
            c.params.push_back(std::move(ps));
        }
    }
    c.error = std::move(error);
    classifier_.publish(std::move(c));
}

void Session::use_calibration(const CameraCalibration& c, std::string origin) {
    calib_in_use_ = c;
    calib_origin_ = std::move(origin);
    pipeline_.set_calibration(c);
    publish_calibration();
}

void Session::publish_calibration() {
    CalibrationInUse u;
    u.which = cur_->camera;
    if (cur_->camera == CameraId::Bottom) {
        u.camera = odometry_.calibration();
        u.origin =
            cur_->kind == SessionSource::Replay ? calib_origin_ : "assets default (bottom camera)";
    } else {
        u.camera = calib_in_use_;
        u.origin = calib_origin_;
    }
    u.source_id = cur_->id;
    calibration_.publish(std::move(u));
}

// Both vision stages forget their history (new source, seek, new calibration, camera switch).
void Session::reset_vision() {
    pipeline_.reset();
    odometry_.restart();
}

void Session::set_camera(CameraId camera, const char* why) {
    Current& c = *cur_;
    if (camera == c.camera) return;
    c.camera = camera;
    c.settle = kCameraSettleFrames;
    reset_vision();
    publish_calibration();
    message(std::string("video: ") + to_string(camera) + " camera (" + why + ")" +
            (camera == CameraId::Bottom
                 ? ": visual odometry runs; the obstacle classifier waits for the front camera"
                 : ": the obstacle classifier runs"));
    if (recorder_ && recorder_->recording())
        message(
            "the recording in progress keeps the camera it started with in flight.json: "
            "stop and record again for a dataset of one camera");
}

// Live: the camera the drone's configuration reports (read back after every switch).
void Session::update_camera() {
    Current& c = *cur_;
    if (!c.link || c.link->config().generation() == c.config_gen) return;
    protocol::ConfigMap cfg;
    if (!c.link->config().read_if_newer(c.config_gen, cfg)) return;
    const auto v = cfg.get("video:video_channel");
    const auto ch = v ? protocol::config_int(*v) : std::nullopt;
    if (!ch) return;
    set_camera(*ch == 1 ? CameraId::Bottom : CameraId::Front, "drone configuration");
}

// A real drone: the calibration the calibration mode saved, when there is one.
CameraCalibration Session::drone_calibration(std::string& origin) const {
    std::error_code ec;
    if (!opts_.calibration_file.empty() && std::filesystem::exists(opts_.calibration_file, ec)) {
        auto c = load_calibration_file(opts_.calibration_file);
        if (c && c->valid()) {
            origin = opts_.calibration_file.string();
            return *c;
        }
    }
    origin = "assets default (front)";
    return front_calibration();
}

vision::CalibrationMode& Session::calibration_worker() {
    if (!calibrator_) {
        vision::CalibrationModeOptions mo;
        mo.save_path = opts_.calibration_file.string();
        mo.interval_ms = opts_.calibration_interval_ms;
        mo.auto_interval_ms = opts_.calibration_auto_interval_ms;
        calibrator_ = std::make_unique<vision::CalibrationMode>(
            std::move(mo),
            [this](const vision::CalibrationModeState& st) { calibration_mode_.publish(st); },
            // Saved on the worker thread: applied by the session thread, in request order.
            [this](const CameraCalibration& cam, const std::string& source,
                   const std::string& path) {
                CameraCalibration applied = cam;
                applied.source = source;
                (void)requests_.push(ApplyCalibration{std::move(applied), path});
            });
    }
    return *calibrator_;
}

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
    sim::VirtualDroneOptions vo;
    vo.bind_address = "127.0.0.1";
    vo.at_port = vo.navdata_port = vo.video_port = vo.control_port = 0;  // ephemeral
    vo.scene = std::move(*scene);
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
    link::LinkConfig lc;
    lc.drone_address = "127.0.0.1";
    lc.bind_address = "127.0.0.1";
    lc.at_port = drone->at_port();
    lc.navdata_port = drone->navdata_port();
    lc.video_port = drone->video_port();
    lc.control_port = drone->control_port();
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
    use_calibration(front_calibration(), "virtual drone camera (assets default)");
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

void Session::handle(SessionRequest& r) {
    Current& c = *cur_;
    std::visit(
        [&](auto& q) {
            using T = std::decay_t<decltype(q)>;
            if constexpr (std::is_same_v<T, ConnectDrone>) {
                ++opens_handled_;  // counted first: every publish from here says it is done
                open_drone(q.address);
            } else if constexpr (std::is_same_v<T, StartSim>) {
                ++opens_handled_;
                open_sim(q);
            } else if constexpr (std::is_same_v<T, OpenReplay>) {
                ++opens_handled_;
                open_replay(q.path);
            } else if constexpr (std::is_same_v<T, CloseSource>) {
                const bool had = c.kind != SessionSource::None;
                close_current();
                publish_source();
                publish_replay();
                if (had) message("disconnected");
            } else if constexpr (std::is_same_v<T, RecordStart>) {
                record_start(q.dir);
            } else if constexpr (std::is_same_v<T, RecordStop>) {
                record_stop();
            } else if constexpr (std::is_same_v<T, ApplyCalibration>) {
                if (!q.camera.valid()) {
                    message("calibration from " + q.origin + " is not valid; not applied");
                    return;
                }
                use_calibration(q.camera, q.origin);
                reset_vision();  // the tracks were undistorted with the old model
                char b[160];
                std::snprintf(b, sizeof b, "calibration applied: fx %.1f fy %.1f cx %.1f cy %.1f",
                              q.camera.fx, q.camera.fy, q.camera.cx, q.camera.cy);
                message(std::string(b) + " (" + q.origin + ")");
            } else if constexpr (std::is_same_v<T, CalibrationStart>) {
                vision::CalibrationMode& w = calibration_worker();
                w.start(q.board);
                // A paused replay sends no new frame: give the mode the one on screen.
                if (auto o = output_.latest(); o && *o && (*o)->source_id == c.id)
                    w.offer((*o)->frame.image, (*o)->frame.index, c.id, /*even_inactive=*/true);
            } else if constexpr (std::is_same_v<T, CalibrationStop>) {
                if (calibrator_) calibrator_->stop();
            } else if constexpr (std::is_same_v<T, CalibrationCapture>) {
                calibration_worker().capture();
            } else if constexpr (std::is_same_v<T, CalibrationUndo>) {
                calibration_worker().undo();
            } else if constexpr (std::is_same_v<T, CalibrationReset>) {
                calibration_worker().reset();
            } else if constexpr (std::is_same_v<T, CalibrationAutoCapture>) {
                calibration_worker().set_auto_capture(q.on);
            } else if constexpr (std::is_same_v<T, CalibrationSave>) {
                calibration_worker().save();
            } else if constexpr (std::is_same_v<T, SelectClassifier>) {
                if (pipeline_.select(q.name)) {
                    publish_classifier();
                    message("classifier: " + q.name);
                } else {
                    publish_classifier("unknown classifier '" + q.name + "'");
                }
            } else if constexpr (std::is_same_v<T, SetClassifierParam>) {
                if (!pipeline_.ok()) return;
                const auto st = pipeline_.classifier().set_param(q.name, q.value);
                if (st == vision::ParamStatus::Ok)
                    publish_classifier();
                else
                    publish_classifier(q.name + ": " + vision::to_string(st));
            } else {
                // Replay controls: ignored (and said so) without a replay.
                if (!c.replay) {
                    message("no replay open");
                    return;
                }
                if constexpr (std::is_same_v<T, ReplayPlay>) {
                    if (q.play && c.rinfo.ended) {
                        (void)c.replay->seek(0);
                        reset_vision();
                        c.rinfo.ended = false;
                    }
                    c.replay->set_paused(!q.play);
                    c.rinfo.playing = q.play;
                } else if constexpr (std::is_same_v<T, ReplayStep>) {
                    c.replay->set_paused(true);
                    c.rinfo.playing = false;
                    (void)replay_step(q.delta);
                } else if constexpr (std::is_same_v<T, ReplaySeek>) {
                    const auto f = std::clamp<std::int64_t>(q.frame, 0, c.rinfo.frame_count - 1);
                    if (c.replay->seek(f)) {
                        reset_vision();  // the classifier's history is of other frames
                        c.rinfo.ended = false;
                        if (!c.rinfo.playing) (void)replay_step(0);
                    }
                } else if constexpr (std::is_same_v<T, ReplaySpeed>) {
                    const double s = std::clamp(q.speed, Pacing::kMinSpeed, Pacing::kMaxSpeed);
                    if (!opts_.replay_lockstep) c.replay->set_pacing(Pacing::realtime(s));
                    c.rinfo.speed = s;
                } else if constexpr (std::is_same_v<T, ReplayLoop>) {
                    c.rinfo.loop = q.loop;
                }
                publish_replay();
            }
        },
        r);
}

// Shows one frame while paused: delta +1 the next, -1 the previous, 0 the one at the position.
bool Session::replay_step(int delta) {
    Current& c = *cur_;
    dataset::DatasetSource& src = *c.replay;
    std::int64_t target = src.position();
    if (delta < 0) {
        target = c.rinfo.frame - 1;
        if (target < 0) return false;
    }
    if (delta <= 0 && target != src.position()) {
        if (!src.seek(target)) return false;
        reset_vision();
    }
    FrameSample f;
    const SourceStatus st = src.step(f);
    if (st == SourceStatus::End) {
        c.rinfo.ended = true;
        return false;
    }
    if (st != SourceStatus::Sample) {
        c.rinfo.error = src.last_error();
        return false;
    }
    replay_nav_.publish(f.nav);
    process(f, f.recv_ns);
    return true;
}

// Pulls what is due from a playing replay. Returns true when a frame was processed; `wait_ns`
// says how long nothing will be due.
bool Session::replay_tick(TimeNs& wait_ns) {
    Current& c = *cur_;
    dataset::DatasetSource& src = *c.replay;
    NavState nav;
    bool have_nav = false;
    while (src.next_nav(nav) == SourceStatus::Sample) have_nav = true;
    if (have_nav) replay_nav_.publish(nav);
    FrameSample f;
    const SourceStatus st = src.next(f);
    switch (st) {
        case SourceStatus::Sample:
            process(f, f.recv_ns);
            return true;
        case SourceStatus::NotYet:
            wait_ns = std::clamp<TimeNs>(src.wait_hint_ns(), 0, kIdleWaitNs);
            return false;
        case SourceStatus::End:
            if (c.rinfo.loop && c.rinfo.frame_count > 0) {
                (void)src.seek(0);
                reset_vision();
                return false;
            }
            if (!c.rinfo.ended) {
                c.rinfo.ended = true;
                c.rinfo.playing = false;
                src.set_paused(true);
                publish_replay();
                message("replay: end of the flight");
            }
            wait_ns = kIdleWaitNs;
            return false;
        case SourceStatus::Error:
            c.rinfo.error = src.last_error();
            c.rinfo.playing = false;
            src.set_paused(true);
            publish_replay();
            message("replay: " + c.rinfo.error);
            wait_ns = kIdleWaitNs;
            return false;
        case SourceStatus::Paused:
            wait_ns = kIdleWaitNs;
            return false;
    }
    return false;
}

void Session::process(FrameSample& f, TimeNs recv_ns) {
    Current& c = *cur_;
    update_camera();
    if (c.kind == SessionSource::Replay && !f.image.empty()) {
        cv::Mat buf = c.pool->acquire();
        f.image.copyTo(buf);
        f.image = std::move(buf);
    }
    // Outputs are recycled once nobody holds them any more (the slot keeps the latest, the window
    // a copy of it while drawing): assigning into one reuses its vectors, so a frame allocates
    // nothing here once the pool is warm.
    std::shared_ptr<PipelineOutput> out;
    for (const auto& o : out_pool_)
        if (o.use_count() == 1) {
            out = o;
            break;
        }
    if (!out) {
        out = std::make_shared<PipelineOutput>();
        if (out_pool_.size() < kOutputPool) out_pool_.push_back(out);
    }
    out->source_id = c.id;
    out->classifier = pipeline_.classifier_name();
    out->camera = c.camera;
    out->stale = false;
    out->result = {};
    if (c.kind != SessionSource::Replay) {
        last_live_frame_ns_ = recv_ns > 0 ? recv_ns : clock_.now_ns();
        stale_published_ = false;
    }
    // A drone streaming another size than the calibration's (720p, set in Drone -> Settings):
    // the same lens, its intrinsics scaled to the frames.
    if (c.camera == CameraId::Front && !f.image.empty() && calib_in_use_.width > 0 &&
        (f.image.cols != calib_in_use_.width || f.image.rows != calib_in_use_.height)) {
        const CameraCalibration scaled = calib_in_use_.scaled_to(f.image.cols, f.image.rows);
        use_calibration(scaled, calib_origin_ + " (scaled to " + std::to_string(f.image.cols) +
                                    "x" + std::to_string(f.image.rows) + ")");
        reset_vision();
        message("video " + std::to_string(f.image.cols) + "x" + std::to_string(f.image.rows) +
                ": calibration scaled to it");
    }
    out->odometry.active = false;
    if (c.settle > 0) {
        --c.settle;  // may still be of the camera before the switch
    } else if (c.camera == CameraId::Bottom) {
        // The obstacle classifier is for the front camera: the floor seen from above is for
        // the odometry.
        odometry_.process(f, out->odometry);
    } else if (pipeline_.ok() && !f.image.empty()) {
        out->result = pipeline_.process(f);
    }
    const TimeNs now = clock_.now_ns();
    out->latency_ms = recv_ns > 0 ? ns_to_ms(now - recv_ns) : kUnknown;
    if (c.rate_n == 0) c.rate_t0 = now;
    ++c.rate_n;
    if (now - c.rate_t0 >= ms_to_ns(1000)) {
        c.fps = static_cast<double>(c.rate_n - 1) * 1e9 / static_cast<double>(now - c.rate_t0);
        c.rate_t0 = now;
        c.rate_n = 1;
    }
    out->fps = c.fps;
    out->frames_dropped = c.frames ? c.frames->dropped() : 0;
    out->frame = std::move(f);
    // The calibration mode gets the frame too (a header; its worker detects on its own thread).
    if (calibrator_ && calibrator_->active())
        calibrator_->offer(out->frame.image, out->frame.index, c.id);
    if (c.kind == SessionSource::Replay) {
        c.rinfo.frame = out->frame.index;
        publish_replay();
    }
    output_.publish(std::move(out));
    ++processed_;
}

// Live video that stopped: the decision on screen is of a frozen picture. Its regions are
// republished unknown (StaleVideo), so that nothing downstream (the window, an assist) takes the
// last "clear" for a current one.
void Session::check_stale(TimeNs now) {
    if (stale_published_ || last_live_frame_ns_ == 0 || now - last_live_frame_ns_ <= kGapNs) return;
    const auto latest = output_.latest();
    if (!latest || !*latest || (*latest)->source_id != cur_->id) return;
    auto stale = std::make_shared<PipelineOutput>(**latest);  // once per stall: not per frame
    mark_unknown(stale->result, vision::UnknownReason::StaleVideo);
    stale->stale = true;
    output_.publish(std::move(stale));
    stale_published_ = true;
    message("video stale: no frame for " + std::to_string((now - last_live_frame_ns_) / 1'000'000) +
            " ms; regions unknown until it is back");
}

void Session::record_start(const std::string& dir) {
    Current& c = *cur_;
    if (!c.link) {
        message("recording needs a drone or the virtual drone (a replay is already recorded)");
        return;
    }
    if (recorder_ && recorder_->recording()) {
        message("already recording to " + last_record_path_);
        return;
    }
    std::filesystem::path path = dir;
    if (path.empty()) {
        const std::time_t t = std::time(nullptr);
        std::tm tm{};
        localtime_r(&t, &tm);
        char name[64];
        std::strftime(name, sizeof name, "%Y-%m-%d_%H%M%S", &tm);
        path = (opts_.record_root.empty() ? default_record_root() : opts_.record_root) / name;
    }
    std::error_code ec;
    std::filesystem::create_directories(path.parent_path(), ec);
    recorder_ = std::make_unique<record::Recorder>(*c.link, c.drone.get());
    record::RecorderOptions ro;
    // The camera the video comes from now, with its calibration: a bottom-camera flight replays
    // through the odometry (`ardrone-gs odometry`, the window).
    update_camera();
    ro.camera = c.camera;
    ro.writer.calibration = c.camera == CameraId::Bottom ? odometry_.calibration() : calib_in_use_;
    ro.writer.source = c.kind == SessionSource::Sim ? "simulated (virtual drone)" : "recorded";
    if (auto st = recorder_->start(path, ro); !st) {
        message("recording failed: " + st.error().message);
        recorder_.reset();
        RecordingInfo ri;
        ri.status.error = st.error().message;
        ri.last_path = last_record_path_;
        recording_.publish(std::move(ri));
        return;
    }
    last_record_path_ = path.string();
    last_space_check_ = 0;
    message("recording to " + last_record_path_ + " (" + to_string(c.camera) + " camera)");
    publish_recording(clock_.now_ns());
}

void Session::record_stop() {
    if (!recorder_) return;
    const record::RecorderStatus st = recorder_->stop();
    recorder_.reset();
    RecordingInfo ri;
    ri.status = st;
    ri.status.recording = false;
    ri.disk_free_bytes = disk_free_bytes_;
    ri.last_path = last_record_path_;
    recording_.publish(std::move(ri));
    message("recording stopped: " + std::to_string(st.frames) + " frames, " +
            std::to_string(st.navdata) + " navdata in " + last_record_path_ +
            (st.drops ? ", " + std::to_string(st.drops) + " dropped" : ""));
}

void Session::publish_recording(TimeNs now) {
    if (!recorder_) return;
    if (now - last_space_check_ > ms_to_ns(2000)) {  // statvfs is a syscall: every 2 s is enough
        std::error_code ec;
        const auto sp = std::filesystem::space(last_record_path_, ec);
        disk_free_bytes_ = ec ? kUnknown : static_cast<double>(sp.available);
        last_space_check_ = now;
    }
    RecordingInfo ri;
    ri.status = recorder_->status();
    ri.disk_free_bytes = disk_free_bytes_;
    ri.last_path = last_record_path_;
    recording_.publish(std::move(ri));
    last_record_publish_ = now;
}

void Session::run() {
    while (running_) {
        // Requests first: connecting, switching classifier, replay controls.
        while (auto r = requests_.try_pop()) handle(*r);
        if (recorder_) {
            const TimeNs now = clock_.now_ns();
            if (now - last_record_publish_ >= ms_to_ns(100)) publish_recording(now);
        }
        Current& c = *cur_;
        if (c.frames) {
            auto f = c.frames->pop_for(std::chrono::nanoseconds(kIdleWaitNs));
            if (f)
                process(*f, f->recv_ns);
            else
                check_stale(clock_.now_ns());
            continue;
        }
        TimeNs wait = kIdleWaitNs;
        if (c.replay && !opts_.replay_lockstep && replay_tick(wait)) continue;
        if (auto r = requests_.pop_for(std::chrono::nanoseconds(std::max<TimeNs>(wait, 1'000'000))))
            handle(*r);
    }
}

}  // namespace gs::app
