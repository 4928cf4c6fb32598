#pragma once
// The virtual AR.Drone 2 on sockets: AT on UDP 5556, navdata on UDP 5554 (sent from that port to
// whoever woke it up), PaVE-framed H.264 of the rendered camera on TCP 5555, configuration dumps
// on TCP 5559. Runs standalone (`ardrone-gs sim`) or inside the GUI and the tests, on loopback.
// Threads: one owns the DroneCore (UDP I/O + physics), one renders/encodes/serves video, one
// serves the control port; they share data only through latest-value slots and bounded queues.

#include "drone/core/sync.hpp"
#include "drone/protocol/ports.hpp"
#include "drone/record/ground_truth.hpp"
#include "drone/sim/drone_core.hpp"
#include "drone/sim/renderer.hpp"
#include "drone/sim/scene.hpp"
#include "drone/transport/net.hpp"

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>
#include <variant>
#include <vector>

namespace gs::sim {

struct VirtualDroneOptions {
    std::string bind_address = "127.0.0.1";
    std::uint16_t at_port = protocol::DronePorts{}.at;
    std::uint16_t navdata_port = protocol::DronePorts{}.navdata;
    std::uint16_t video_port = protocol::DronePorts{}.video;
    std::uint16_t control_port = protocol::DronePorts{}.control;
    Scene scene;             // the world (its start pose and autopilot are used)
    bool autopilot = false;  // fly the scene's script after boot
    // The drone is a body of its real size in the scene and can crash (drone/sim/collision.hpp).
    // Off: it flies through everything, as the virtual drone did before it had a body.
    bool collisions = true;
    CollisionParams collision;
    DroneCoreOptions core;  // start/autopilot are taken from the scene
    bool video = true;
    int fps = 30;
    int gop = 15;
    int bitrate_bps = 1'500'000;  // until a client writes video:bitrate
    // The clock the drone lives on; null: the steady clock (free-running, real time). A clock its
    // owner steps (a FakeClock) makes the drone lock-stepped: physics, navdata and video frames
    // follow that clock and nothing else, so a run is the same however fast the machine is. The
    // owner advances the clock, then wait_reached() until the drone has caught up.
    const Clock* clock = nullptr;
};

// Faults injected while running (tests and the GUI's fault panel).
struct FaultNavdata {
    NavdataFaults faults;
};
struct FaultBlackout {
    int ms = 1000;  // no navdata at all for this long, from now
};
struct FaultVideoStall {
    int ms = 1000;  // no video bytes for this long
};
// Reset the video TCP connection in the middle of a frame; with `during_idr`, of the next IDR
// frame, so the new connection starts with P-frames the decoder must skip until the next IDR.
struct FaultVideoReset {
    bool during_idr = false;
};
// The drone restarts: sequences, configuration and client reset, back on the ground. It is down
// (deaf and silent) for `boot_ms`, as a real one is for seconds: the video and configuration
// connections are cut at once and connecting to those ports is refused until it is back up.
struct FaultReboot {
    int boot_ms = 1000;
};
using Fault =
    std::variant<FaultNavdata, FaultBlackout, FaultVideoStall, FaultVideoReset, FaultReboot>;

struct VirtualDroneStatus {
    FlightState flight;
    std::uint32_t drone_state = 0;
    DroneCoreCounters counters;
    std::uint64_t video_frames_sent = 0;
    std::uint64_t video_clients = 0;
    std::uint64_t video_resets = 0;
    std::uint64_t reboot_closes = 0;  // video/control connections cut by a reboot
    bool booting = false;             // down after a reboot: ports closed, nothing sent
    double render_ms_last = 0, encode_ms_last = 0;
    bool autopilot_done = false;
    bool autopilot_active = false;           // flying its script (false once a pilot took over)
    std::vector<CollisionEvent> collisions;  // crashes and bumps, oldest first (counters: totals)
    std::string last_error;
};

// Ground truth at one instant, for labels and tests.
struct GroundTruth {
    TimeNs t_ns = 0;  // monotonic
    Pose pose;
    std::uint32_t frame_number = 0;  // last video frame rendered
};

// Why VirtualDrone::start() failed; `message` is the sentence shown to the user.
struct StartError {
    enum class Code { BadBindAddress, Socket, Renderer };
    Code code;
    std::string message;
};

// Also the recorder's ground truth: the scene's scenario, the drone's pose, the target obstacle.
class VirtualDrone final : public record::GroundTruthSource {
public:
    explicit VirtualDrone(VirtualDroneOptions options);
    ~VirtualDrone();
    VirtualDrone(const VirtualDrone&) = delete;
    VirtualDrone& operator=(const VirtualDrone&) = delete;

    // Binds every port (0 = ephemeral; see the bound ports below) and starts the threads.
    [[nodiscard]] Expected<void, StartError> start();
    void stop();

    std::uint16_t at_port() const { return ports_[0]; }
    std::uint16_t navdata_port() const { return ports_[1]; }
    std::uint16_t video_port() const { return ports_[2]; }
    std::uint16_t control_port() const { return ports_[3]; }

    void inject(Fault f) { faults_.push(std::move(f)); }

    // Lock-step: true once the drone has run everything due up to `t` on its clock: physics and
    // navdata, and with a video client every frame due at or before `t` rendered and sent. False
    // when `timeout` of real time passed first.
    [[nodiscard]] bool wait_reached(TimeNs t, std::chrono::milliseconds timeout) const;
    // Counters the lock-stepped owner waits on (any thread).
    std::uint64_t video_frames_sent() const { return frames_sent_.load(); }
    std::uint32_t last_frame_number() const { return last_frame_number_.load(); }
    std::uint32_t navdata_sequence() const { return navdata_seq_.load(); }
    bool video_client_connected() const { return video_client_.load(); }
    const Clock& clock() const;
    VirtualDroneStatus status() const { return status_.latest().value_or(VirtualDroneStatus{}); }
    GroundTruth ground_truth() const { return truth_.latest().value_or(GroundTruth{}); }
    const Scene& scene() const { return options_.scene; }

    // record::GroundTruthSource
    record::TruthScene truth_scene() const override;
    record::TruthSample truth_sample() const override;
    std::optional<record::TargetOffset> target_offset(const record::TruthPose& p) const override;
    std::vector<record::TruthCollision> truth_collisions() const override;

private:
    void core_loop();
    void video_loop();
    void control_loop();

    VirtualDroneOptions options_;
    std::optional<std::size_t> target_;  // the scene's target obstacle (index), if it names one
    std::atomic<bool> running_{false};
    std::uint16_t ports_[4] = {0, 0, 0, 0};
    struct Sockets;
    std::unique_ptr<Sockets> sockets_;
    std::vector<std::thread> threads_;

    BoundedQueue<Fault> faults_{64};
    BoundedQueue<FaultVideoStall> video_stalls_{8};
    BoundedQueue<FaultVideoReset> video_resets_{8};
    BoundedQueue<std::string> dumps_{8};
    struct CameraState {
        Pose pose;
        int channel = 0;
        TimeNs t_ns = 0;
        int codec = 129;  // video:video_codec
        int bitrate_kbps = 1500;
    };
    // Lock-step progress (written by the drone's threads).
    std::atomic<TimeNs> core_time_{-1};       // physics and navdata done up to here
    std::atomic<TimeNs> video_next_due_{-1};  // every frame due before this was sent
    std::atomic<bool> video_client_{false};
    std::atomic<std::uint64_t> frames_sent_{0};
    std::atomic<std::uint32_t> last_frame_number_{0};
    std::atomic<std::uint32_t> navdata_seq_{0};
    LatestValue<CameraState> camera_;
    struct VideoReport {
        std::uint32_t frame_number = 0, size = 0;
        std::uint64_t frames_sent = 0, clients = 0, resets = 0;
        double render_ms = 0, encode_ms = 0;
        std::string error;
    };
    LatestValue<VideoReport> video_report_;
    // A reboot as the core thread saw it, for the video and control threads: a new generation
    // closes their connections and listeners, which listen again once the drone is up.
    struct BootState {
        std::uint64_t generation = 0;
        TimeNs up_at_ns = 0;
    };
    LatestValue<BootState> boot_;
    std::atomic<std::uint64_t> reboot_closes_{0};
    // Closes the listener `which` (2 video, 3 control) until the drone is up again, then listens
    // on the same port. Returns false when stopping.
    bool wait_for_boot(transport::TcpListener& listener, int which, const BootState& boot);
    LatestValue<VirtualDroneStatus> status_;
    LatestValue<GroundTruth> truth_;
};

}  // namespace gs::sim
