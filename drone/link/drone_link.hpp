#pragma once
// The live link to an AR.Drone 2 (or the virtual one): one object owns the sockets and threads.
//   AT sender      UDP 5556, the current command set every 30 ms (at_scheduler)
//   navdata        UDP 5554, wake-up, parsing, the connection state machine (link_state)
//   video          TCP 5555, PaVE framer → H.264 decoder → frames
//   control        TCP 5559, configuration dumps for read-back
// Threads share data only through latest-value slots and bounded queues. Every stream publishes
// a snapshot and counters; commands are typed values with typed results.

#include "drone/core/clock.hpp"
#include "drone/core/sample.hpp"
#include "drone/core/sync.hpp"
#include "drone/link/at_scheduler.hpp"
#include "drone/link/commands.hpp"
#include "drone/link/link_state.hpp"
#include "drone/protocol/config.hpp"
#include "drone/protocol/navdata.hpp"
#include "drone/protocol/pave.hpp"
#include "drone/protocol/ports.hpp"
#include "drone/video/receiver.hpp"

#include <array>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace gs::link {

struct LinkConfig {
    std::string drone_address = "192.168.1.1";
    std::uint16_t at_port = protocol::DronePorts{}.at;
    std::uint16_t navdata_port = protocol::DronePorts{}.navdata;
    std::uint16_t video_port = protocol::DronePorts{}.video;
    std::uint16_t control_port = protocol::DronePorts{}.control;
    std::string bind_address = "0.0.0.0";  // local address for the UDP sockets
    LinkSetup setup;                       // navdata mode, ids, timing of the state machine
    TimeNs at_period_ns = ms_to_ns(30);
    double min_takeoff_battery_pct = 20.0;
    bool video = true;    // connect the video port
    bool control = true;  // connect the control port (config read-back)
    TimeNs video_silence_reconnect_ns = ms_to_ns(1000);
    TimeNs reconnect_delay_ns = ms_to_ns(300);
};

// One accepted navdata packet.
struct NavSample {
    TimeNs recv_ns = 0;  // monotonic receive time
    std::uint32_t seq = 0;
    double drone_time_s = kUnknown;   // from the time option, when sent
    NavState state;                   // units of docs/dataset.md, t_ns from the link's start
    protocol::navdata::Navdata data;  // every decoded option
};

// Raw bytes as they crossed the wire, for recording (docs/dataset.md raw/). VideoConnect (no bytes)
// marks where a new video TCP connection begins: the Video bytes after it are the new one's.
struct RawEvent {
    enum class Kind : std::uint8_t { Navdata, Video, At, VideoConnect };
    Kind kind = Kind::Navdata;
    TimeNs t_ns = 0;  // monotonic receive / send time
    std::vector<std::uint8_t> bytes;
    std::uint64_t stream_offset = 0;  // Video: the offset of bytes[0] in the video receiver's
                                      // stream (AccessUnitEvent::stream_offset counts the same)
    // Navdata: the sample the link accepted from this datagram (its state, t_ns from the link's
    // start); nullopt when it was refused (bad checksum, malformed, duplicate, late). One event
    // carries both, so a recording's raw/ and navdata.csv come from the same datagrams.
    std::optional<NavState> accepted;
    // Navdata accepted: how many samples the link had accepted, this one included (1-based), so a
    // recorder can prove it took every accepted sample between its first and its last.
    std::uint64_t accepted_ordinal = 0;

    static RawEvent of(Kind kind, TimeNs t_ns, std::span<const std::uint8_t> bytes = {},
                       std::uint64_t stream_offset = 0) {
        RawEvent e;
        e.kind = kind;
        e.t_ns = t_ns;
        e.bytes.assign(bytes.begin(), bytes.end());
        e.stream_offset = stream_offset;
        return e;
    }
};

// Every access unit the video receiver cut from the stream (the PaVE payload, Annex-B), with what
// became of it, for a recorder: the units that produced a picture are what video.h264 stores and
// what replaying raw/ reproduces; the others are drops with their reason. Only built when someone
// subscribed.
struct AccessUnitEvent {
    std::int64_t index = -1;       // the decoded frame's FrameSample::index; -1 without a picture
    std::int64_t unit = 0;         // 0-based over every unit received
    std::uint32_t connection = 0;  // the video connection it came on (0-based)
    std::uint64_t stream_offset = 0;  // where its PaVE header began (RawEvent::stream_offset)
    std::uint64_t stream_end = 0;     // one past its last byte
    TimeNs recv_ns = 0;               // monotonic receive time of the chunk that completed it
    TimeNs capture_ns = 0;            // monotonic capture time (the drone's timestamp, mapped)
    TimeNs t_ns = 0;                  // capture_ns from the link's start (FrameSample::t_ns)
    std::uint32_t frame_number = 0;   // PaVE frame_number
    std::optional<std::uint32_t> pave_timestamp_ms;  // PaVE timestamp (drone clock, ms)
    bool is_idr = false;                             // contains an IDR slice
    video::UnitFate fate = video::UnitFate::NoPicture;
    std::vector<std::uint8_t> bytes;
    cv::Mat image;  // the decoded frame (a pooled buffer: drop it soon)
};

// Events per second over the last second (packet and frame rates).
class RateMeter {
public:
    void tick(TimeNs now, std::uint64_t count = 1);
    double rate_hz(TimeNs now) const;

private:
    TimeNs window_start_ = 0;
    std::uint64_t count_ = 0;
    double last_rate_ = 0;
};

struct NavdataStats {
    std::uint64_t datagrams = 0;  // received from the drone's address
    std::uint64_t accepted = 0;
    std::uint64_t parse_errors = 0;  // malformed (bad magic, truncated, sizes)
    std::uint64_t checksum_failures = 0;
    std::uint64_t foreign_dropped = 0;  // from any other address or port
    std::uint64_t oversize = 0;         // datagrams larger than the 4096-byte maximum
    // Bytes of the datagrams from the drone's address. Counted only: a rate is the reader's
    // (the window's sliding window over this total, app/gui_link.cpp), unknown until measured.
    std::uint64_t bytes = 0;
    double rate_hz = 0;
    TimeNs last_ns = 0;
    std::string last_error;
};

struct VideoStats {
    bool connected = false;
    std::uint64_t bytes = 0;  // received on the video connection (counted only, as navdata's)
    std::uint64_t pave_frames = 0;
    std::uint64_t decoded = 0;
    std::uint64_t decode_errors = 0;
    std::uint64_t idr_waits = 0;  // access units skipped waiting for an IDR
    std::uint64_t frame_gaps = 0;
    std::uint64_t resyncs = 0;  // PaVE resynchronisations
    std::uint64_t bytes_skipped = 0;
    std::uint64_t connects = 0;
    std::uint64_t disconnects = 0;               // resets, silences, errors
    std::uint64_t pool_exhausted = 0;            // every pooled frame still in use: one allocated
    std::uint64_t unsupported_codec_frames = 0;  // PaVE frames not H.264: skipped (last_error)
    std::uint64_t concealed = 0;                 // frames shown with damage the decoder concealed
    std::uint64_t repaired = 0;      // intra frames that replaced concealed damage (they jump)
    std::uint64_t no_picture = 0;    // access units that gave no picture (damaged beyond repair)
    std::uint64_t cut_by_reset = 0;  // frames a connection ended inside (never joined to the next)
    std::uint64_t clock_frozen = 0;  // frames timed by their arrival: the drone's clock stood still
    std::uint64_t nav_interpolated = 0;  // frames whose attitude lies between two samples
    std::uint64_t nav_nearest = 0;       // frames captured past the newest sample (or before the
                                         // oldest): the nearest one is used
    std::uint64_t nav_missing = 0;       // frames with no sample within kFrameNavMaxGapNs: unknown
    double fps = 0;
    double decode_ms_last = 0;
    TimeNs last_frame_ns = 0;
    std::string last_error;
};

struct AtStats {
    AtCounters counters;
    std::uint64_t send_errors = 0;
    std::uint64_t bytes_sent = 0;  // AT datagram bytes handed to the socket (counted only)
    double period_ms_last = 0;
    double period_ms_max = 0;  // worst gap between two cycles since start
    TimeNs last_cycle_ns = 0;  // when the last cycle sent (0: none yet); its age says a stall
    // Every gap between two cycles since start: bin i counts gaps in [i, i + 1) ms, the last bin
    // everything longer. The AR.Drone wants a command at least every 30 ms or so; a pilot's
    // input waits for the next beat.
    static constexpr std::size_t kPeriodBins = 100;
    std::array<std::uint32_t, kPeriodBins> period_hist{};
    std::uint64_t periods = 0;
    std::uint64_t periods_off_by_3ms = 0;  // gaps outside the period +- 3 ms
    // The drone never writes to the AT socket: whatever arrives there (a stray or hostile peer)
    // is read every cycle, counted and dropped, so it cannot fill the kernel buffer.
    std::uint64_t foreign_datagrams = 0;
    std::uint64_t foreign_bytes = 0;
    bool realtime = false;                  // the sender thread got a real-time priority
    FlyIntent intent = FlyIntent::Unknown;  // the take-off intent REF carries (at_scheduler.hpp)
    // The gap (ms, bin resolution) below which a share q of the gaps fell; NaN before any.
    double period_ms_quantile(double q) const;
};

struct LinkStatus {
    ConnectionState state = ConnectionState::Disconnected;
    std::string reason;
    LinkCounters machine;
    NavdataStats navdata;
    VideoStats video;
    AtStats at;
    bool control_connected = false;
    std::uint64_t config_dumps = 0;
    TimeNs now_ns = 0;  // when this status was assembled (age = now_ns - navdata.last_ns)
};

// Why DroneLink::start() failed; `message` is the sentence shown to the user.
struct StartError {
    enum class Code { BadDroneAddress, BadBindAddress, Socket };
    Code code;
    std::string message;
};

class DroneLink {
public:
    explicit DroneLink(LinkConfig config, Clock& clock = SteadyClock::instance());
    ~DroneLink();
    DroneLink(const DroneLink&) = delete;
    DroneLink& operator=(const DroneLink&) = delete;

    // Opens the sockets and starts the threads (nothing when already running). Fails when a
    // socket cannot be opened (the drone need not be reachable yet).
    [[nodiscard]] Expected<void, StartError> start();
    void stop();
    bool running() const { return running_.load(); }

    // Non-blocking: the result arrives through the future (at once for most commands; after the
    // drone acknowledged and the read-back for configuration writes).
    std::future<CommandResult> submit(Command c);
    // Blocking helper for the command line.
    CommandResult execute(Command c, std::chrono::milliseconds timeout);

    const LatestValue<NavSample>& navdata() const { return nav_slot_; }
    const LatestValue<FrameSample>& video() const { return frame_slot_; }
    const LatestValue<protocol::ConfigMap>& config() const { return config_slot_; }
    LinkStatus status() const;
    ConnectionState state() const;

    // Every decoded frame, for a consumer that must not miss frames or wants to wait on them
    // (the pipeline, the recorder). Bounded; overflow drops the oldest and is counted there.
    std::shared_ptr<BoundedQueue<FrameSample>> subscribe_frames(std::size_t capacity);
    std::shared_ptr<BoundedQueue<NavSample>> subscribe_navdata(std::size_t capacity);
    // Raw bytes of every stream (navdata datagrams, video TCP chunks, AT datagrams) for raw/.
    // Overflow of the two recording queues rejects the new item (counted by the queue): the link
    // never waits for a consumer.
    std::shared_ptr<BoundedQueue<RawEvent>> subscribe_raw(std::size_t capacity);
    // The access unit of every decoded frame (see AccessUnitEvent).
    std::shared_ptr<BoundedQueue<AccessUnitEvent>> subscribe_access_units(std::size_t capacity);
    // Stops feeding the queue returned by any subscribe_*(). Returns once every link thread has
    // moved on to the new list (within one of its cycles, tens of ms): nothing is pushed into
    // the queue after that, so a recorder that drains it then has everything.
    void unsubscribe(const void* queue);
    // The clock every *_ns of the link is on (a recorder must use the same one).
    const Clock& clock() const { return clock_; }

    const LinkConfig& config_used() const { return config_; }
    // The local port navdata arrives on (after start; 0 before).
    std::uint16_t navdata_local_port() const;
    // The local port AT commands are sent from (after start; 0 before).
    std::uint16_t at_local_port() const;
    TimeNs start_ns() const { return start_ns_; }

private:
    struct NavRequest {
        SetConfig write;
        bool read_dump = false;
        std::promise<CommandResult> done;
    };
    struct AtRequest {
        enum class Kind {
            Fly,
            Move,
            Hover,
            Emergency,
            OneShot,
            LinkLost,
            LinkRestored,
            Connected,
            DroneRestarted
        };
        Kind kind = Kind::Hover;
        bool fly = false;
        Move move;
        bool drone_emergency = false;
        std::uint32_t drone_state = 0;  // Connected: the drone's state then
        OneShot oneshot;
    };

    void navdata_loop();
    void at_loop();
    void video_loop();
    void control_loop();
    void push_at(AtRequest r);

    LinkConfig config_;
    Clock& clock_;
    std::atomic<bool> running_{false};
    TimeNs start_ns_ = 0;

    struct Sockets;
    std::unique_ptr<Sockets> sockets_;
    std::vector<std::thread> threads_;

    BoundedQueue<AtRequest> at_queue_{256};
    BoundedQueue<NavRequest> nav_queue_{64};
    BoundedQueue<protocol::ConfigMap> dump_queue_{4};
    // Accepted navdata for the video thread, which times each frame's attitude at its capture
    // (the newest samples win when it falls behind).
    BoundedQueue<NavState> nav_to_video_{512, QueueFull::DropOldest};

    LatestValue<NavSample> nav_slot_;
    LatestValue<FrameSample> frame_slot_;
    LatestValue<protocol::ConfigMap> config_slot_;
    LatestValue<NavdataStats> nav_stats_slot_;
    LatestValue<VideoStats> video_stats_slot_;
    LatestValue<AtStats> at_stats_slot_;
    struct MachineSnapshot {
        ConnectionState state = ConnectionState::Disconnected;
        std::string reason = "not started";
        LinkCounters counters;
        std::uint64_t config_dumps = 0;
    };
    LatestValue<bool> control_connected_slot_;
    LatestValue<MachineSnapshot> machine_slot_;

    struct Subscribers {
        std::vector<std::shared_ptr<BoundedQueue<FrameSample>>> frames;
        std::vector<std::shared_ptr<BoundedQueue<NavSample>>> navdata;
        std::vector<std::shared_ptr<BoundedQueue<RawEvent>>> raw;
        std::vector<std::shared_ptr<BoundedQueue<AccessUnitEvent>>> access_units;
    };
    LatestValue<Subscribers> subscribers_;
    // The subscriber list generation each thread (navdata, AT, video) works with, for
    // unsubscribe() to wait on; a thread sets it after reading the list at the top of its cycle.
    std::array<std::atomic<std::uint64_t>, 3> subs_seen_{};
};

}  // namespace gs::link
