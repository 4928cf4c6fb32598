#pragma once
// The link's connection state machine, as pure logic: navdata headers and time go in, the
// actions the link must perform come out (docs/protocol.md §1.3, §5.1, §9). No sockets, threads or
// clocks inside: the link's navdata thread drives it; tests drive it with made-up packets.
//
//   Disconnected → Bootstrapping (wake-up to 5554, re-sent on silence)
//                → Configuring   (CONFIG_IDS + CONFIG, wait ACK bit, AT*CTRL=…,5,0, wait clear)
//                → Connected     → LinkLost (no navdata for 500 ms) → Connected / Configuring

#include "drone/core/clock.hpp"
#include "drone/protocol/config.hpp"

#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace gs::link {

enum class ConnectionState { Disconnected, Bootstrapping, Configuring, Connected, LinkLost };
const char* to_string(ConnectionState s);

struct LinkTiming {
    TimeNs link_lost_after_ns = ms_to_ns(500);  // no navdata this long → LinkLost
    TimeNs trigger_resend_ns = ms_to_ns(100);   // wake-up re-sent after this much silence
    TimeNs ack_timeout_ns = ms_to_ns(500);      // CONFIG not acknowledged → retry
    TimeNs ctrl_ack_resend_ns = ms_to_ns(50);   // AT*CTRL=…,5,0 repeated while ACK is set
    TimeNs config_dump_timeout_ns = ms_to_ns(1500);
    TimeNs settle_ns = ms_to_ns(1000);  // configured but navdata unchanged this long → act
    int config_attempts = 3;            // CONFIG sends before giving up (Timeout)
};

struct NavdataIds {  // multi-configuration ids (docs/protocol.md §2.8), 8 hex digits each
    std::string session = "00000000", profile = "00000000", application = "00000000";
    bool is_default() const {
        return session == "00000000" && profile == "00000000" && application == "00000000";
    }
};

// The navdata options the ground station reads (docs/protocol.md §3.4): demo (attitude, velocities,
// altitude, battery: what the classifier and the odometry use) and time (the drone's clock).
inline constexpr std::uint32_t kNavdataOptionsUsed = (1u << 0) | (1u << 1);

struct LinkSetup {
    // Full navdata (200 Hz) by default: the attitude of a frame is interpolated between samples
    // 5 ms apart instead of 65 ms. A drone that stays in demo mode (15 Hz) is used as it is
    // (link_state: "navdata demo although full was configured").
    bool navdata_demo = false;
    // Full mode: general:navdata_options mask (0 = the drone's default, every option).
    std::uint32_t navdata_options = kNavdataOptionsUsed;
    NavdataIds ids;
    LinkTiming timing;
};

enum class ConfigOutcome {
    Acked,      // the drone raised and cleared the ACK bit
    Verified,   // acked and read back over 5559 with the value written
    Ignored,    // acked, but the read-back shows another value or no such key
    Timeout,    // never acknowledged after every attempt
    Cancelled,  // the link went down or was stopped before it completed
};
const char* to_string(ConfigOutcome o);

struct ConfigDone {
    std::uint64_t id = 0;
    ConfigOutcome outcome = ConfigOutcome::Timeout;
    std::string key, value, detail;  // detail: what the read-back found, or why it failed
};

// What the link must do now, filled by on_navdata()/tick(). Vectors are reused between calls.
struct LinkActions {
    bool send_trigger = false;          // wake-up datagram to navdata port
    bool send_ctrl_ack = false;         // AT*CTRL=…,5,0
    bool send_ctrl_get_config = false;  // AT*CTRL=…,4,0 (the dump arrives on 5559)
    std::vector<std::pair<std::string, std::string>> configs;  // each as CONFIG_IDS + CONFIG
    std::vector<ConfigDone> done;
    bool link_lost = false;        // edge: entered LinkLost this call (drop any Move intent)
    bool link_restored = false;    // edge: navdata flows again after LinkLost
    bool drone_restarted = false;  // edge: the drone rebooted (its take-off state is gone)
    // Edge: entered Connected (first time, after a loss or a restart), with the drone's state
    // then: the AT sender adopts its flying state.
    std::optional<std::uint32_t> connected;
    void clear();
};

struct LinkCounters {
    std::uint64_t packets_accepted = 0;
    std::uint64_t sequence_gaps = 0;    // packets missing between accepted ones
    std::uint64_t out_of_order = 0;     // dropped: sequence not greater than the last accepted
    std::uint64_t sequence_resets = 0;  // a new sequence began (reboot, watchdog, after a loss)
    std::uint64_t link_losses = 0;
    std::uint64_t triggers_sent = 0;
    std::uint64_t configs_sent = 0;
    std::uint64_t config_timeouts = 0;
    std::uint64_t com_watchdog_events = 0;  // COM_WATCHDOG rising edges (AT answers it)
    std::uint64_t drone_restarts = 0;       // bootstrap seen again after being configured
};

// Navdata header facts the machine needs.
struct NavdataHeaderInfo {
    std::uint32_t drone_state = 0;
    std::uint32_t sequence = 0;
};

// Why a started link is in Bootstrapping: the state machine's reason on start(), which the link
// also publishes the moment it starts, before its threads run the machine.
inline constexpr std::string_view kBootstrappingReason =
    "waking navdata up; waiting for the first packet";

class LinkStateMachine {
public:
    explicit LinkStateMachine(LinkSetup setup = {});

    void start(TimeNs now, LinkActions& out);  // Disconnected → Bootstrapping
    void stop(LinkActions& out);               // → Disconnected, cancels pending writes

    // A checksum-valid navdata packet arrived. Returns false when it must be dropped (out of
    // order or duplicate); its header still feeds the ACK logic only when accepted.
    bool on_navdata(const NavdataHeaderInfo& nav, TimeNs now, LinkActions& out);
    // A configuration dump arrived on 5559 (requested by send_ctrl_get_config).
    void on_config_dump(const protocol::ConfigMap& dump, TimeNs now, LinkActions& out);
    // Time passes (call every few ms, and after on_navdata).
    void tick(TimeNs now, LinkActions& out);

    // Queue a configuration write; `verify` reads it back over 5559 afterwards.
    std::uint64_t write_config(std::string key, std::string value, bool verify);
    // Queue a read of the whole configuration (result through on_config_dump + latest_dump()).
    void request_config_dump();

    ConnectionState state() const { return state_; }
    const std::string& state_reason() const { return reason_; }
    const LinkCounters& counters() const { return counters_; }
    std::optional<std::uint32_t> last_drone_state() const { return last_state_; }
    TimeNs last_navdata_ns() const { return last_navdata_ns_; }
    std::size_t pending_jobs() const { return jobs_.size(); }
    const LinkSetup& setup() const { return setup_; }

private:
    enum class JobKind { Write, ReadDump };
    enum class Phase { ClearBefore, Send, WaitAck, ClearAfter, WaitDump };
    struct Job {
        JobKind kind = JobKind::Write;
        std::uint64_t id = 0;
        std::string key, value;
        bool verify = false;
        bool internal = false;  // part of the configuration sequence
        Phase phase = Phase::ClearBefore;
        int attempts = 0;
        TimeNs phase_start = 0;
        TimeNs last_ctrl = 0;
        bool acked = false;
        bool started = false;
    };

    void enter(ConnectionState s, std::string reason);
    void enter_connected(std::string reason, LinkActions& out);
    void begin_configuration();
    void run_jobs(TimeNs now, LinkActions& out);
    void finish_job(ConfigOutcome o, std::string detail, TimeNs now, LinkActions& out);
    void cancel_jobs(LinkActions& out);
    bool ack_bit() const;

    LinkSetup setup_;
    ConnectionState state_ = ConnectionState::Disconnected;
    std::string reason_ = "not started";
    LinkCounters counters_;
    std::optional<std::uint32_t> last_state_;
    std::optional<std::uint32_t> last_seq_;
    bool restart_allowed_ = false;  // after a link loss the next packet may begin a new sequence
    TimeNs last_navdata_ns_ = 0;
    TimeNs last_trigger_ns_ = 0;
    TimeNs started_ns_ = 0;
    bool configured_ = false;  // the configuration sequence completed since the last (re)start
    TimeNs configured_at_ns_ = 0;
    bool prev_comwdg_ = false;
    std::deque<Job> jobs_;
    std::uint64_t next_id_ = 1;
    std::optional<protocol::ConfigMap> pending_dump_;
};

}  // namespace gs::link
