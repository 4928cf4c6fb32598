#pragma once
// The virtual AR.Drone's brain, as pure logic: AT datagrams and navdata wake-ups go in with their
// time and sender, navdata datagrams come out, and the drone behaves as docs/protocol.md describes
// a real one: bootstrap navdata until configured; demo (15 Hz) or full (200 Hz) navdata with valid
// checksums; every drone_state bit maintained; navdata sent to the address and port the wake-up
// came from; AT sequence rules; a configuration store with the ACK bit; the communication
// watchdog; emergency cut-off. Faults for tests (loss, reordering, duplication, corrupt checksums,
// blackout, reboot) are applied here from a seeded generator, so a run is reproducible.
// The sockets and the video live in virtual_drone.hpp.

#include "drone/core/clock.hpp"
#include "drone/protocol/config.hpp"
#include "drone/protocol/navdata.hpp"
#include "drone/sim/at_parser.hpp"
#include "drone/sim/collision.hpp"
#include "drone/sim/flight_model.hpp"
#include "drone/sim/scene.hpp"
#include "drone/transport/endpoint.hpp"

#include <cstdint>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace gs::sim {

struct NavdataFaults {
    double loss = 0;              // probability a datagram is not sent
    double reorder = 0;           // probability a datagram is held back and sent after the next one
    double duplicate = 0;         // probability a datagram is sent twice
    double corrupt_checksum = 0;  // probability its checksum is off by one
};

struct DroneCoreOptions {
    FlightParams flight;
    Pose start;  // where the drone sits at boot (z = 0: on the ground)
    // Flown from boot when enabled and non-empty. The pilot always wins: the autopilot yields
    // for good as soon as the client asks for something it is not doing (a PCMD with the
    // progressive flag, REF's take-off bit going from set to clear while flying, an emergency,
    // a flight animation (AT*ANIM or CONFIG control:flight_anim), a calibration).
    std::vector<AutopilotStep> autopilot;
    bool autopilot_enabled = false;
    NavdataFaults faults;
    std::uint64_t seed = 1;
    TimeNs watchdog_after_ns = ms_to_ns(50);    // no AT this long → COM_WATCHDOG bit
    TimeNs bootstrap_period_ns = ms_to_ns(65);  // bootstrap and demo navdata ≈ 15 Hz
    TimeNs full_period_ns = ms_to_ns(5);        // full navdata 200 Hz
    double battery_pct = 100.0;
    int video_bitrate_kbps = 1000;  // what video:bitrate reports at boot (the encoder's rate)
    // The scene's geometry the body is tested against each physics step; none: it flies through
    // everything (a drone in an empty infinite space).
    std::optional<Collider> collider;
};

struct OutDatagram {
    transport::Endpoint to;
    std::vector<std::uint8_t> bytes;
};

struct DroneCoreCounters {
    std::uint64_t at_datagrams = 0;
    std::uint64_t at_commands = 0;
    std::uint64_t at_skipped = 0;       // malformed commands (ignored, as the drone does)
    std::uint64_t at_rejected_seq = 0;  // older sequence numbers
    std::uint64_t at_too_long = 0;      // datagrams over 1024 bytes
    std::uint64_t configs = 0;
    std::uint64_t configs_unknown = 0;  // acknowledged but not stored
    std::uint64_t comwdg = 0;
    std::uint64_t watchdog_events = 0;
    std::uint64_t navdata_sent = 0;
    std::uint64_t navdata_dropped = 0;  // by the loss fault
    std::uint64_t navdata_reordered = 0, navdata_duplicated = 0, navdata_corrupted = 0;
    std::uint64_t reboots = 0;
    std::uint64_t at_while_booting = 0;  // AT datagrams that arrived before the boot finished
    std::uint64_t ftrims = 0, calibrations = 0, leds = 0, anims = 0;  // AT*LED/ANIM or CONFIG
    // Configuration writes kept but changed to what the firmware allows (clamped to its range)
    // or refused (a value it does not support): the read-back shows the drone's value.
    std::uint64_t configs_clamped = 0, configs_refused = 0;
    std::uint64_t configs_without_ids = 0;  // AT*CONFIG not right after an AT*CONFIG_IDS
    std::uint64_t autopilot_yields = 0;     // 1 once the pilot took over
    std::uint64_t collisions = 0;  // crashes: contacts at or above the crash speed (motors cut)
    std::uint64_t bumps = 0;       // gentle contacts
};

class DroneCore {
public:
    explicit DroneCore(DroneCoreOptions options = {});

    // Any datagram on the navdata port wakes navdata up towards its sender.
    void on_navdata_trigger(const transport::Endpoint& from, TimeNs now);
    void on_at(std::span<const std::uint8_t> datagram, const transport::Endpoint& from, TimeNs now);
    // Runs the drone up to `now` (fixed 5 ms physics steps) and appends the navdata due.
    void advance(TimeNs now, std::vector<OutDatagram>& out);

    // A configuration dump requested with AT*CTRL=…,4,0, to be written on the control port.
    std::optional<std::string> take_config_dump();

    // Faults.
    void set_faults(const NavdataFaults& f) { options_.faults = f; }
    void blackout(TimeNs from, TimeNs until);  // no navdata at all in [from, until)
    // Sequences, configuration, client and autopilot forgotten; back on the ground. For
    // `boot_ns` the drone is down (a real one takes seconds): it neither hears AT commands or
    // wake-ups nor sends navdata.
    void reboot(TimeNs now, TimeNs boot_ns = 0);

    const FlightState& flight() const { return model_.state(); }
    Pose pose() const;  // the drone body pose in the world (docs/dataset.md frame)
    std::uint32_t drone_state() const { return state_bits_; }
    bool navdata_demo() const { return demo_; }
    bool bootstrap() const { return bootstrap_; }
    int video_channel() const;
    // The video stream the configuration asks for: video:video_codec (129 H.264 360p, 131 H.264
    // 720p) and video:bitrate (kbit/s).
    int video_codec() const { return video_codec_; }
    int video_bitrate_kbps() const { return video_bitrate_kbps_; }
    std::uint32_t video_frame_number() const { return video_frame_number_; }
    void set_video_frame(std::uint32_t number, std::uint32_t size_bytes) {
        video_frame_number_ = number;
        video_frame_size_ = size_bytes;
    }
    const protocol::ConfigMap& config() const { return config_; }
    const DroneCoreCounters& counters() const { return counters_; }
    // Crashes and bumps, oldest first (the newest kMaxCollisionEvents; counters() has the totals).
    const std::vector<CollisionEvent>& collisions() const { return collisions_; }
    static constexpr std::size_t kMaxCollisionEvents = 256;
    std::optional<transport::Endpoint> navdata_client() const { return navdata_client_; }
    std::uint32_t navdata_sequence() const { return seq_; }
    TimeNs now() const { return now_; }
    bool autopilot_done() const;
    bool autopilot_active() const { return ap_active_; }  // false once the pilot took over
    const std::string& autopilot_yield_reason() const { return ap_yield_reason_; }

private:
    void apply_command(const at::Command& c, TimeNs now);
    void apply_config(const std::string& key, const std::string& value);
    void reset_config();  // the factory configuration, with this drone's own video bitrate
    void update_bits();
    void emit_navdata(std::vector<OutDatagram>& out);
    void send(std::vector<std::uint8_t> bytes, std::vector<OutDatagram>& out);
    FlightInput autopilot_input();
    void collide();  // after each physics step
    void autopilot_yield(const char* reason);
    bool booting(TimeNs now) const { return now < booted_at_ns_; }

    DroneCoreOptions options_;
    FlightModel model_;
    protocol::ConfigMap config_;
    at::SeqFilter seq_filter_;
    std::optional<transport::Endpoint> navdata_client_;
    std::optional<std::string> pending_dump_;
    std::mt19937_64 rng_;
    std::optional<OutDatagram> held_;  // reorder fault: sent after the next datagram

    TimeNs now_ = 0;
    TimeNs boot_ns_ = 0;
    TimeNs sim_ns_ = 0;  // physics time reached
    TimeNs last_at_ns_ = 0;
    TimeNs last_nav_ns_ = 0;
    TimeNs blackout_from_ = 0, blackout_until_ = 0;
    TimeNs booted_at_ns_ = 0;  // down until then after a reboot
    bool started_ = false;     // advance() has run once
    std::uint32_t seq_ = 0;
    std::uint32_t state_bits_ = 0;
    bool bootstrap_ = true;
    bool demo_ = false;
    std::uint32_t navdata_options_ = 0;
    bool ack_ = false;
    bool com_watchdog_ = false;
    bool com_lost_ = false;
    FlightInput input_;  // from REF and PCMD
    int video_codec_ = 129;
    int video_bitrate_kbps_ = 1000;
    bool ids_pending_ = false;  // an AT*CONFIG_IDS came and its AT*CONFIG not yet
    std::uint32_t video_frame_number_ = 0;
    std::uint32_t video_frame_size_ = 0;
    double calibration_yaw_left_deg_ = 0;
    // Autopilot
    std::size_t ap_step_ = 0;
    double ap_step_time_s_ = 0;
    bool ap_active_ = false;
    std::string ap_yield_reason_;
    DroneCoreCounters counters_;
    std::vector<CollisionEvent> collisions_;
    bool in_contact_ = false;         // a contact lasting several steps is one event
    protocol::navdata::Navdata nav_;  // reused packet contents
};

// The configuration a factory-fresh AR.Drone 2 reports (docs/protocol.md §5.4 defaults).
protocol::ConfigMap default_drone_config();

}  // namespace gs::sim
