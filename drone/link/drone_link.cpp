#include "drone/link/drone_link.hpp"
#include "drone/core/unknown.hpp"

#include "drone/core/nav_timeline.hpp"
#include "drone/protocol/pave.hpp"
#include "drone/transport/net.hpp"
#include "drone/video/h264_decoder.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/prctl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace gs::link {
namespace {
constexpr std::size_t kNavdataMax = 4096;  // NAVDATA_MAX_SIZE (docs/protocol.md §1.4)
constexpr std::array<std::uint8_t, 4> kWakeUp = {1, 0, 0, 0};
constexpr std::size_t kFramePool = 6;
constexpr int kMaxFlightAnim = 19;  // FLIP_RIGHT (docs/protocol.md §2.9)

std::future<CommandResult> ready(ResultCode code, std::string reason = {}) {
    std::promise<CommandResult> p;
    p.set_value({code, std::move(reason)});
    return p.get_future();
}

// Copies for all but the last subscriber, which gets the value itself.
template <class T>
void fan_out(const std::vector<std::shared_ptr<BoundedQueue<T>>>& subs, T v) {
    for (std::size_t i = 0; i + 1 < subs.size(); ++i) subs[i]->push(v);
    if (!subs.empty()) subs.back()->push(std::move(v));
}

template <class T>
void erase_queue(std::vector<std::shared_ptr<BoundedQueue<T>>>& subs, const void* q) {
    std::erase_if(subs, [q](const auto& s) { return static_cast<const void*>(s.get()) == q; });
}
}  // namespace

void RateMeter::tick(TimeNs now, std::uint64_t count) {
    if (window_start_ == 0) window_start_ = now;
    count_ += count;
    const TimeNs span = now - window_start_;
    if (span >= ms_to_ns(1000)) {
        last_rate_ = static_cast<double>(count_) * 1e9 / static_cast<double>(span);
        count_ = 0;
        window_start_ = now;
    }
}

double RateMeter::rate_hz(TimeNs now) const {
    // A stream that stopped reads 0 after two seconds instead of its last rate.
    return window_start_ != 0 && now - window_start_ > ms_to_ns(2000) ? 0.0 : last_rate_;
}

struct DroneLink::Sockets {
    transport::UdpSocket at;
    transport::UdpSocket navdata;
    transport::Endpoint at_to, navdata_to, video_to, control_to;
};

DroneLink::DroneLink(LinkConfig config, Clock& clock) : config_(std::move(config)), clock_(clock) {}

DroneLink::~DroneLink() {
    stop();
}

Expected<void, StartError> DroneLink::start() {
    using enum StartError::Code;
    if (running_) return {};
    auto drone = transport::Endpoint::parse(config_.drone_address + ":0");
    if (!drone)
        return Unexpected(
            StartError{BadDroneAddress, "bad drone address '" + config_.drone_address + "'"});
    auto local = transport::Endpoint::parse(config_.bind_address + ":0");
    if (!local)
        return Unexpected(
            StartError{BadBindAddress, "bad bind address '" + config_.bind_address + "'"});
    auto s = std::make_unique<Sockets>();
    auto with_port = [&](std::uint16_t port) {
        transport::Endpoint e = *drone;
        e.port = port;
        return e;
    };
    s->at_to = with_port(config_.at_port);
    s->navdata_to = with_port(config_.navdata_port);
    s->video_to = with_port(config_.video_port);
    s->control_to = with_port(config_.control_port);
    auto at = transport::UdpSocket::bind(*local);
    if (!at) return Unexpected(StartError{Socket, "AT socket: " + at.error().message()});
    (void)at->set_send_buffer(4096);
    auto nav = transport::UdpSocket::bind(*local);
    if (!nav) return Unexpected(StartError{Socket, "navdata socket: " + nav.error().message()});
    s->at = std::move(*at);
    s->navdata = std::move(*nav);
    sockets_ = std::move(s);

    start_ns_ = clock_.now_ns();
    at_queue_.reopen();
    nav_queue_.reopen();
    dump_queue_.reopen();
    {
        // A started link is bootstrapping from this moment: without this, status() read before
        // the AT thread's first snapshot said "Disconnected" (the window showed NO SOURCE for a
        // frame while connecting). The AT thread's state machine says the same when it starts.
        MachineSnapshot m;
        m.state = ConnectionState::Bootstrapping;
        m.reason = std::string(kBootstrappingReason);
        if (auto prev = machine_slot_.latest()) m.counters = prev->counters;
        machine_slot_.publish(std::move(m));
    }
    running_ = true;
    threads_.emplace_back([this] { navdata_loop(); });
    threads_.emplace_back([this] { at_loop(); });
    if (config_.video) threads_.emplace_back([this] { video_loop(); });
    if (config_.control) threads_.emplace_back([this] { control_loop(); });
    return {};
}

void DroneLink::stop() {
    if (!running_.exchange(false)) return;
    at_queue_.close();
    nav_queue_.close();
    dump_queue_.close();
    for (auto& t : threads_) t.join();
    threads_.clear();
    // Requests still queued get an answer.
    while (auto r = nav_queue_.try_pop())
        r->done.set_value({ResultCode::NotConnected, "link stopped"});
    sockets_.reset();
    MachineSnapshot m;
    m.state = ConnectionState::Disconnected;
    m.reason = "stopped";
    if (auto prev = machine_slot_.latest()) m.counters = prev->counters;
    machine_slot_.publish(std::move(m));
}

std::uint16_t DroneLink::navdata_local_port() const {
    if (!sockets_) return 0;
    auto e = sockets_->navdata.local_endpoint();
    return e ? e->port : 0;
}

std::uint16_t DroneLink::at_local_port() const {
    if (!sockets_) return 0;
    auto e = sockets_->at.local_endpoint();
    return e ? e->port : 0;
}

ConnectionState DroneLink::state() const {
    auto m = machine_slot_.latest();
    return m ? m->state : ConnectionState::Disconnected;
}

LinkStatus DroneLink::status() const {
    LinkStatus st;
    if (auto m = machine_slot_.latest()) {
        st.state = m->state;
        st.reason = m->reason;
        st.machine = m->counters;
        st.config_dumps = m->config_dumps;
    } else {
        st.reason = "not started";
    }
    st.control_connected = control_connected_slot_.latest().value_or(false);
    if (auto n = nav_stats_slot_.latest()) st.navdata = *n;
    if (auto v = video_stats_slot_.latest()) st.video = *v;
    if (auto a = at_stats_slot_.latest()) st.at = *a;
    st.now_ns = clock_.now_ns();
    return st;
}

std::shared_ptr<BoundedQueue<FrameSample>> DroneLink::subscribe_frames(std::size_t capacity) {
    auto q = std::make_shared<BoundedQueue<FrameSample>>(capacity, QueueFull::DropOldest);
    subscribers_.update([&](Subscribers& s) { s.frames.push_back(q); });
    return q;
}
std::shared_ptr<BoundedQueue<NavSample>> DroneLink::subscribe_navdata(std::size_t capacity) {
    auto q = std::make_shared<BoundedQueue<NavSample>>(capacity, QueueFull::DropOldest);
    subscribers_.update([&](Subscribers& s) { s.navdata.push_back(q); });
    return q;
}
std::shared_ptr<BoundedQueue<RawEvent>> DroneLink::subscribe_raw(std::size_t capacity) {
    auto q = std::make_shared<BoundedQueue<RawEvent>>(capacity, QueueFull::RejectNew);
    subscribers_.update([&](Subscribers& s) { s.raw.push_back(q); });
    return q;
}

std::shared_ptr<BoundedQueue<AccessUnitEvent>> DroneLink::subscribe_access_units(
    std::size_t capacity) {
    auto q = std::make_shared<BoundedQueue<AccessUnitEvent>>(capacity, QueueFull::RejectNew);
    subscribers_.update([&](Subscribers& s) { s.access_units.push_back(q); });
    return q;
}

void DroneLink::unsubscribe(const void* queue) {
    subscribers_.update([&](Subscribers& s) {
        erase_queue(s.frames, queue);
        erase_queue(s.navdata, queue);
        erase_queue(s.raw, queue);
        erase_queue(s.access_units, queue);
    });
    const std::uint64_t gen = subscribers_.generation();
    const bool active[3] = {true, true, config_.video};
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
    for (int i = 0; i < 3; ++i) {
        while (running_ && active[i] && subs_seen_[static_cast<std::size_t>(i)].load() < gen &&
               std::chrono::steady_clock::now() < deadline)
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
}

void DroneLink::push_at(AtRequest r) {
    if (!at_queue_.push(std::move(r))) {
        // The sender drains its queue every 30 ms; a full queue means a flood of commands.
        // Dropping one is counted by the queue and is safe: the next Move or Fly supersedes it.
    }
}

// ---- Commands ----------------------------------------------------------------------------

std::future<CommandResult> DroneLink::submit(Command c) {
    if (!running_) return ready(ResultCode::NotConnected, "link not started");
    const ConnectionState st = state();
    const bool connected = st == ConnectionState::Connected;
    auto nav = nav_slot_.latest();
    const std::uint32_t bits =
        nav && nav->data.header.drone_state.raw ? nav->data.header.drone_state.raw : 0;
    const double battery = nav ? nav->state.battery_pct : kUnknown;
    const std::string not_connected = std::string("link is ") + to_string(st);

    struct V {
        DroneLink& link;
        bool connected;
        protocol::navdata::DroneState state;
        double battery;
        const std::string& nc;

        std::future<CommandResult> operator()(const Takeoff&) {
            if (!connected) return ready(ResultCode::NotConnected, nc);
            if (state.emergency()) {
                return ready(
                    ResultCode::Rejected,
                    "the drone reports an emergency (motors cut): send Emergency to reset it");
            }
            if (known(battery) && battery < link.config_.min_takeoff_battery_pct) {
                return ready(
                    ResultCode::Rejected,
                    "battery " + std::to_string(static_cast<int>(battery)) + " % is below the " +
                        std::to_string(static_cast<int>(link.config_.min_takeoff_battery_pct)) +
                        " % take-off minimum");
            }
            if (state.vbat_low())
                return ready(ResultCode::Rejected, "the drone reports a low battery");
            if (state.angles_out_of_range()) {
                return ready(
                    ResultCode::Rejected,
                    "the drone reports its angles out of range: put it level on the ground");
            }
            AtRequest r;
            r.kind = AtRequest::Kind::Fly;
            r.fly = true;
            link.push_at(std::move(r));
            return ready(ResultCode::Sent);
        }
        std::future<CommandResult> operator()(const Land&) {
            AtRequest r;  // landing is always taken into the intent
            r.kind = AtRequest::Kind::Fly;
            r.fly = false;
            link.push_at(std::move(r));
            return connected ? ready(ResultCode::Sent) : ready(ResultCode::NotConnected, nc);
        }
        std::future<CommandResult> operator()(const Emergency&) {
            AtRequest r;
            r.kind = AtRequest::Kind::Emergency;
            r.drone_emergency = state.emergency();
            link.push_at(std::move(r));
            return connected ? ready(ResultCode::Sent) : ready(ResultCode::NotConnected, nc);
        }
        std::future<CommandResult> operator()(const Move& m) {
            if (!connected) return ready(ResultCode::NotConnected, nc);
            AtRequest r;
            r.kind = AtRequest::Kind::Move;
            r.move = m;
            link.push_at(std::move(r));
            return ready(ResultCode::Sent);
        }
        std::future<CommandResult> operator()(const Hover&) {
            AtRequest r;
            r.kind = AtRequest::Kind::Hover;
            link.push_at(std::move(r));
            return connected ? ready(ResultCode::Sent) : ready(ResultCode::NotConnected, nc);
        }
        std::future<CommandResult> operator()(const FlatTrim&) {
            if (!connected) return ready(ResultCode::NotConnected, nc);
            if (state.fly()) return ready(ResultCode::Rejected, "flat trim needs the drone landed");
            return oneshot(OneShot::Kind::Ftrim);
        }
        std::future<CommandResult> operator()(const Calibrate&) {
            if (!connected) return ready(ResultCode::NotConnected, nc);
            if (!state.fly()) {
                return ready(ResultCode::Rejected,
                             "magnetometer calibration needs the drone flying");
            }
            return oneshot(OneShot::Kind::Calib);
        }
        std::future<CommandResult> operator()(const SetConfig& s) {
            if (!protocol::config_text_ok(s.key) || !protocol::config_text_ok(s.value) ||
                s.key.empty()) {
                return ready(
                    ResultCode::Rejected,
                    "configuration key and value may not contain quotes or control characters");
            }
            if (!connected) return ready(ResultCode::NotConnected, nc);
            NavRequest r;
            r.write = s;
            auto f = r.done.get_future();
            if (!link.nav_queue_.push(std::move(r))) {
                return ready(ResultCode::Rejected, "too many configuration writes pending");
            }
            return f;
        }
        std::future<CommandResult> operator()(const SwitchCamera& s) {
            if (s.channel != 0 && s.channel != 1) {
                return ready(ResultCode::Rejected,
                             "camera channel must be 0 (front) or 1 (bottom)");
            }
            return (*this)(SetConfig{"video:video_channel", std::to_string(s.channel), true});
        }
        std::future<CommandResult> operator()(const Led& l) {
            if (!connected) return ready(ResultCode::NotConnected, nc);
            OneShot o;
            o.kind = OneShot::Kind::Led;
            o.a = l.anim_id;
            o.f = l.freq_hz;
            o.b = l.duration_s;
            return push(std::move(o));
        }
        // Firmware 2 takes flight animations as CONFIG control:flight_anim (docs/protocol.md §2.4,
        // §2.9: SDK 2.0 no longer sends AT*ANIM); the result comes with the drone's ACK.
        std::future<CommandResult> operator()(const Anim& a) {
            if (a.anim_id < 0 || a.anim_id > kMaxFlightAnim) {
                return ready(ResultCode::Rejected,
                             "flight animation id must be 0.." + std::to_string(kMaxFlightAnim));
            }
            if (a.duration_ms <= 0) {
                return ready(ResultCode::Rejected, "flight animation duration must be positive");
            }
            return (*this)(SetConfig{"control:flight_anim",
                                     protocol::at::flight_anim_value(a.anim_id, a.duration_ms),
                                     false});
        }
        std::future<CommandResult> operator()(const ReadConfig&) {
            if (!connected) return ready(ResultCode::NotConnected, nc);
            NavRequest r;
            r.read_dump = true;
            auto f = r.done.get_future();
            if (!link.nav_queue_.push(std::move(r)))
                return ready(ResultCode::Rejected, "too many configuration requests pending");
            return f;
        }
        std::future<CommandResult> oneshot(OneShot::Kind k) {
            OneShot o;
            o.kind = k;
            return push(std::move(o));
        }
        std::future<CommandResult> push(OneShot o) {
            AtRequest r;
            r.kind = AtRequest::Kind::OneShot;
            r.oneshot = std::move(o);
            link.push_at(std::move(r));
            return ready(ResultCode::Sent);
        }
    };
    return std::visit(V{*this, connected, {bits}, battery, not_connected}, c);
}

CommandResult DroneLink::execute(Command c, std::chrono::milliseconds timeout) {
    auto f = submit(std::move(c));
    if (f.wait_for(timeout) != std::future_status::ready) {
        return {ResultCode::Timeout, "no answer within " + std::to_string(timeout.count()) + " ms"};
    }
    return f.get();
}

// ---- Threads -----------------------------------------------------------------------------

void DroneLink::navdata_loop() {
    LinkStateMachine sm(config_.setup);
    LinkActions actions;
    NavdataStats stats;
    RateMeter rate;
    std::vector<std::pair<std::uint64_t, NavRequest>> pending;  // awaiting the machine's verdict
    std::array<std::uint8_t, kNavdataMax + 1> buf{};
    std::uint64_t dumps = 0;
    std::uint64_t subs_gen = 0;
    Subscribers subs;
    TimeNs last_publish = 0;

    auto publish_machine = [&] {
        MachineSnapshot m;
        m.state = sm.state();
        m.reason = sm.state_reason();
        m.counters = sm.counters();
        m.config_dumps = dumps;
        machine_slot_.publish(std::move(m));
    };
    auto apply = [&](TimeNs now) {
        if (actions.send_trigger) {
            (void)sockets_->navdata.send_to(std::span<const std::uint8_t>(kWakeUp),
                                            sockets_->navdata_to);
        }
        auto oneshot = [&](OneShot o) {
            AtRequest r;
            r.kind = AtRequest::Kind::OneShot;
            r.oneshot = std::move(o);
            push_at(std::move(r));
        };
        for (auto& [k, v] : actions.configs) {
            OneShot o;
            o.kind = OneShot::Kind::Config;
            o.key = k;
            o.value = v;
            oneshot(std::move(o));
        }
        if (actions.send_ctrl_ack) oneshot({OneShot::Kind::Ctrl, {}, {}, 5, 0, 0});
        if (actions.send_ctrl_get_config) oneshot({OneShot::Kind::Ctrl, {}, {}, 4, 0, 0});
        // Edges for the AT sender's take-off intent, in the order they happened.
        auto edge = [&](AtRequest::Kind k, std::uint32_t drone_state = 0) {
            AtRequest r;
            r.kind = k;
            r.drone_state = drone_state;
            push_at(std::move(r));
        };
        if (actions.link_lost) edge(AtRequest::Kind::LinkLost);
        if (actions.drone_restarted) edge(AtRequest::Kind::DroneRestarted);
        if (actions.link_restored) edge(AtRequest::Kind::LinkRestored);
        if (actions.connected) edge(AtRequest::Kind::Connected, *actions.connected);
        for (auto& d : actions.done) {
            auto it = std::find_if(pending.begin(), pending.end(),
                                   [&](auto& p) { return p.first == d.id; });
            if (it == pending.end()) continue;
            CommandResult res;
            switch (d.outcome) {
                case ConfigOutcome::Acked:
                case ConfigOutcome::Verified:
                    res = {ResultCode::Sent, d.detail};
                    break;
                case ConfigOutcome::Ignored:
                    res = {ResultCode::Rejected, d.detail};
                    break;
                case ConfigOutcome::Timeout:
                    res = {ResultCode::Timeout, d.detail};
                    break;
                case ConfigOutcome::Cancelled:
                    res = {ResultCode::NotConnected, d.detail};
                    break;
            }
            it->second.done.set_value(std::move(res));
            pending.erase(it);
        }
        (void)now;
        actions.clear();
    };

    TimeNs now = clock_.now_ns();
    sm.start(now, actions);
    apply(now);
    publish_machine();

    while (running_) {
        subscribers_.read_if_newer(subs_gen, subs);
        subs_seen_[0] = subs_gen;
        while (auto r = nav_queue_.try_pop()) {
            if (r->read_dump) {
                sm.request_config_dump();
                r->done.set_value({ResultCode::Sent, {}});
                continue;
            }
            const auto id = sm.write_config(r->write.key, r->write.value, r->write.verify);
            pending.emplace_back(id, std::move(*r));
        }
        while (auto d = dump_queue_.try_pop()) {
            ++dumps;
            sm.on_config_dump(*d, clock_.now_ns(), actions);
        }

        auto got = sockets_->navdata.recv_from(std::span<std::uint8_t>(buf), transport::Millis{5});
        now = clock_.now_ns();
        if (got) {
            const std::span<const std::uint8_t> bytes(buf.data(), got->size);
            if (got->from != sockets_->navdata_to) {
                ++stats.foreign_dropped;
            } else if (got->truncated || got->size > kNavdataMax) {
                ++stats.datagrams;
                ++stats.oversize;
                stats.last_error = "datagram larger than 4096 bytes";
            } else {
                ++stats.datagrams;
                stats.bytes += got->size;
                // Handed to recorders with the link's verdict, below (one event per datagram).
                RawEvent raw_event = RawEvent::of(RawEvent::Kind::Navdata, now);
                if (!subs.raw.empty()) raw_event.bytes.assign(bytes.begin(), bytes.end());
                auto nd = protocol::navdata::parse_navdata(bytes);
                if (!nd) {
                    if (nd.error().code == protocol::navdata::NavdataErrc::BadChecksum)
                        ++stats.checksum_failures;
                    else
                        ++stats.parse_errors;
                    stats.last_error = protocol::navdata::to_string(nd.error());
                } else if (sm.on_navdata({nd->header.drone_state.raw, nd->header.sequence}, now,
                                         actions)) {
                    ++stats.accepted;
                    rate.tick(now);
                    stats.last_ns = now;
                    NavSample s;
                    s.recv_ns = now;
                    s.seq = nd->header.sequence;
                    if (nd->time) {
                        s.drone_time_s =
                            nd->time->time.seconds() + nd->time->time.microseconds() * 1e-6;
                    }
                    s.state = protocol::navdata::to_nav_state(*nd, now - start_ns_);
                    if (config_.video) nav_to_video_.push(s.state);
                    raw_event.accepted = s.state;
                    raw_event.accepted_ordinal = stats.accepted;
                    s.data = std::move(*nd);
                    if (!subs.navdata.empty()) fan_out(subs.navdata, s);
                    nav_slot_.publish(std::move(s));
                }
                if (!subs.raw.empty()) fan_out(subs.raw, std::move(raw_event));
            }
        } else if (got.error().code != transport::NetErrc::Timeout) {
            stats.last_error = got.error().message();
        }
        sm.tick(now, actions);
        apply(now);
        if (now - last_publish >= ms_to_ns(20)) {
            stats.rate_hz = rate.rate_hz(now);
            nav_stats_slot_.publish(stats);
            publish_machine();
            last_publish = now;
        }
    }
    LinkActions final_actions;
    sm.stop(final_actions);
    for (auto& [id, r] : pending) r.done.set_value({ResultCode::NotConnected, "link stopped"});
}

double AtStats::period_ms_quantile(double q) const {
    if (periods == 0) return kUnknown;
    const double want = q * static_cast<double>(periods);
    double seen = 0;
    for (std::size_t i = 0; i < kPeriodBins; ++i) {
        seen += period_hist[i];
        if (seen >= want) return static_cast<double>(i + 1);
    }
    return static_cast<double>(kPeriodBins);
}

void DroneLink::at_loop() {
    AtScheduler sched(config_.setup.ids);
    AtStats stats;
    // The beat the drone expects must survive a busy machine (video decoding, the classifier,
    // the window, a virtual drone rendering on the same cores): ask for a real-time slot for
    // this thread, which sleeps all but microseconds per cycle, and a tight timer. Without the
    // privilege it runs as an ordinary thread (AtStats::realtime says which).
    sched_param sp{};
    sp.sched_priority = 10;
    stats.realtime = pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp) == 0;
    prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
    std::vector<std::string> datagrams;
    std::array<std::uint8_t, 2048> drain{};
    std::uint64_t subs_gen = 0;
    Subscribers subs;
    TimeNs next = clock_.now_ns();
    TimeNs last_cycle = 0;
    while (running_) {
        // Sleep until the next cycle, waking for queued commands only at the cycle (commands are
        // sent on the 30 ms beat, as the drone expects). On a stepped clock (a lock-stepped run)
        // the beat follows the steps.
        if (!sleep_until(clock_, next, running_)) break;
        next += config_.at_period_ns;
        TimeNs now = clock_.now_ns();
        if (next < now) next = now + config_.at_period_ns;  // fell far behind: do not burst

        while (auto r = at_queue_.try_pop()) {
            switch (r->kind) {
                case AtRequest::Kind::Fly:
                    sched.set_fly(r->fly);
                    break;
                case AtRequest::Kind::Move:
                    sched.set_move(r->move);
                    break;
                case AtRequest::Kind::Hover:
                    sched.hover();
                    break;
                case AtRequest::Kind::Emergency:
                    sched.request_emergency(r->drone_emergency, now);
                    break;
                case AtRequest::Kind::OneShot:
                    sched.queue(std::move(r->oneshot));
                    break;
                case AtRequest::Kind::LinkLost:
                    sched.on_link_lost();
                    break;
                case AtRequest::Kind::LinkRestored:
                    sched.on_link_restored();
                    break;
                case AtRequest::Kind::Connected:
                    sched.on_connected(r->drone_state);
                    break;
                case AtRequest::Kind::DroneRestarted:
                    sched.on_drone_restart();
                    break;
            }
        }
        std::optional<std::uint32_t> drone_state;
        if (auto n = nav_slot_.latest()) drone_state = n->data.header.drone_state.raw;
        sched.build(now, drone_state, datagrams);
        subscribers_.read_if_newer(subs_gen, subs);
        subs_seen_[1] = subs_gen;
        for (const auto& d : datagrams) {
            auto sent = sockets_->at.send_to(d, sockets_->at_to, transport::Millis{5});
            if (!sent) {
                ++stats.send_errors;
            } else {
                stats.bytes_sent += d.size();
            }
            if (!subs.raw.empty()) {
                const auto* p = reinterpret_cast<const std::uint8_t*>(d.data());
                fan_out(subs.raw, RawEvent::of(RawEvent::Kind::At, now, std::span(p, d.size())));
            }
        }
        // Drain the AT socket: nothing legitimate arrives there (bounded per cycle).
        for (int i = 0; i < 64; ++i) {
            auto got = sockets_->at.recv_from(std::span<std::uint8_t>(drain), transport::Millis{0});
            if (!got) break;
            ++stats.foreign_datagrams;
            stats.foreign_bytes += got->size;
        }
        if (last_cycle != 0) {
            const double gap = ns_to_ms(now - last_cycle);
            stats.period_ms_last = gap;
            stats.period_ms_max = std::max(stats.period_ms_max, gap);
            const auto bin = static_cast<std::size_t>(
                std::clamp(gap, 0.0, static_cast<double>(AtStats::kPeriodBins - 1)));
            ++stats.period_hist[bin];
            ++stats.periods;
            if (std::abs(gap - ns_to_ms(config_.at_period_ns)) > 3.0) ++stats.periods_off_by_3ms;
        }
        last_cycle = now;
        stats.last_cycle_ns = now;
        stats.counters = sched.counters();
        stats.intent = sched.intent();
        at_stats_slot_.publish(stats);
    }
}

void DroneLink::video_loop() {
    VideoStats stats;
    RateMeter rate;
    // The one receive pipeline (drone/video/receiver.hpp): framing, decoding into pooled
    // buffers, capture times; connections are announced to it so no frame spans two.
    video::ReceiverOptions ro;
    ro.pool_slots = kFramePool;
    video::VideoReceiver rx(ro);
    NavTimeline navs(1024);  // accepted navdata, for each frame's attitude at its capture
    std::vector<std::uint8_t> buf(64 * 1024);
    std::int64_t index = 0;
    std::uint64_t subs_gen = 0;
    Subscribers subs;
    TimeNs last_publish = 0;

    auto publish = [&](TimeNs now) {
        const video::ReceiverStats& r = rx.stats();
        const video::H264DecoderStats& d = rx.decoder_stats();
        stats.pave_frames = r.units;
        stats.decoded = r.pictures;
        stats.concealed = r.concealed;
        stats.repaired = r.repaired;
        stats.no_picture = r.no_picture;
        stats.cut_by_reset = r.cut_by_reset;
        stats.clock_frozen = r.clock_frozen;
        stats.decode_errors = d.decode_errors;
        stats.idr_waits = r.waiting_idr;
        stats.frame_gaps = d.frame_gaps;
        stats.resyncs = r.resyncs;
        stats.bytes_skipped = r.bytes_skipped;
        stats.pool_exhausted = r.pool_exhausted;
        stats.unsupported_codec_frames = r.not_h264;
        stats.fps = rate.rate_hz(now);
        video_stats_slot_.publish(stats);
        last_publish = now;
    };

    while (running_) {
        subscribers_.read_if_newer(subs_gen, subs);  // nothing is pushed while disconnected
        subs_seen_[2] = subs_gen;
        auto stream = transport::TcpStream::connect(sockets_->video_to, transport::Millis{500});
        if (!stream) {
            stats.last_error = stream.error().message();
            video_stats_slot_.publish(stats);
            std::this_thread::sleep_for(std::chrono::nanoseconds(config_.reconnect_delay_ns));
            continue;
        }
        ++stats.connects;
        stats.connected = true;
        const TimeNs opened = clock_.now_ns();
        rx.begin_connection(opened);
        subscribers_.read_if_newer(subs_gen, subs);
        subs_seen_[2] = subs_gen;
        if (!subs.raw.empty())
            fan_out(subs.raw, RawEvent::of(RawEvent::Kind::VideoConnect, opened));
        TimeNs last_data = opened;
        while (running_) {
            auto got = stream->read_some(std::span<std::uint8_t>(buf), transport::Millis{20});
            const TimeNs now = clock_.now_ns();
            subscribers_.read_if_newer(subs_gen, subs);
            subs_seen_[2] = subs_gen;
            if (!got) {
                if (got.error().code == transport::NetErrc::Timeout) {
                    if (now - last_data > config_.video_silence_reconnect_ns) {
                        stats.last_error =
                            "no video for " + std::to_string((now - last_data) / 1'000'000) + " ms";
                        break;
                    }
                    if (now - last_publish >= ms_to_ns(50)) publish(now);  // counts, fps
                    continue;
                }
                stats.last_error = got.error().message();
                break;
            }
            last_data = now;
            stats.bytes += *got;
            const std::span<const std::uint8_t> chunk(buf.data(), *got);
            if (!subs.raw.empty())
                fan_out(subs.raw,
                        RawEvent::of(RawEvent::Kind::Video, now, chunk, rx.bytes_pushed()));
            while (auto n = nav_to_video_.try_pop()) navs.push(*n);
            rx.push(chunk, now);
            rx.clear_resyncs();  // counted in its stats; the link lists none
            while (true) {
                const TimeNs t0 = clock_.now_ns();
                auto u = rx.next();
                if (!u) break;
                if (u->fate == video::UnitFate::NotH264 || u->fate == video::UnitFate::NoPicture)
                    stats.last_error = rx.stats().last_error;
                const bool picture = video::has_picture(u->fate);
                if (picture) stats.decode_ms_last = ns_to_ms(clock_.now_ns() - t0);
                // Capture time (docs/dataset.md's t_ms): the drone's frame clock mapped onto ours,
                // free of the network's and this thread's jitter (drone/capture_clock.hpp).
                const TimeNs t_ns = u->capture_ns - start_ns_;
                if (!subs.access_units.empty()) {
                    AccessUnitEvent e;
                    e.index = picture ? index : -1;
                    e.unit = u->unit;
                    e.connection = u->connection;
                    e.stream_offset = u->stream_offset;
                    e.stream_end = u->stream_offset + u->header.header_size + u->bytes.size();
                    e.recv_ns = u->recv_ns;
                    e.capture_ns = u->capture_ns;
                    e.t_ns = t_ns;
                    e.frame_number = u->frame_number;
                    e.pave_timestamp_ms = u->pave_timestamp_ms;
                    e.is_idr = u->idr;
                    e.fate = u->fate;
                    e.bytes.assign(u->bytes.begin(), u->bytes.end());
                    e.image = u->image;
                    fan_out(subs.access_units, std::move(e));
                }
                if (!picture) continue;
                FrameSample fs;
                fs.index = index++;
                fs.recv_ns = u->recv_ns;
                fs.capture_ns = u->capture_ns;
                fs.t_ns = t_ns;
                fs.frame_number = u->frame_number;
                fs.pave_timestamp_ms = u->pave_timestamp_ms;
                fs.concealed = u->fate == video::UnitFate::Concealed;
                fs.repaired = u->repaired;
                fs.image = std::move(u->image);  // a pooled buffer, free again when dropped
                // The attitude at the capture time, interpolated as a recording does
                // (drone/core/nav_timeline.hpp), not the newest sample relabelled; unknown when
                // no sample is within kFrameNavMaxGapNs of it (a navdata blackout).
                fs.nav = navs.state_at(t_ns, kFrameNavMaxGapNs);
                if (std::isnan(fs.nav.roll_deg))  // every navdata sample has its attitude
                    ++stats.nav_missing;
                else if (navs.newest_t() >= t_ns)
                    ++stats.nav_interpolated;
                else
                    ++stats.nav_nearest;
                rate.tick(now);
                stats.last_frame_ns = now;
                if (!subs.frames.empty()) fan_out(subs.frames, fs);
                frame_slot_.publish(std::move(fs));
            }
            if (now - last_publish >= ms_to_ns(50)) publish(now);
        }
        stats.connected = false;
        ++stats.disconnects;
        publish(clock_.now_ns());
    }
}

void DroneLink::control_loop() {
    std::vector<std::uint8_t> buf(8192);
    auto set_connected = [&](bool on) { control_connected_slot_.publish(on); };
    while (running_) {
        auto stream = transport::TcpStream::connect(sockets_->control_to, transport::Millis{500});
        if (!stream) {
            std::this_thread::sleep_for(std::chrono::nanoseconds(config_.reconnect_delay_ns));
            continue;
        }
        set_connected(true);
        protocol::ConfigDumpReader reader;
        while (running_) {
            auto got = stream->read_some(std::span<std::uint8_t>(buf), transport::Millis{50});
            if (!got) {
                if (got.error().code == transport::NetErrc::Timeout) continue;
                break;
            }
            if (auto dump = reader.push(std::span<const std::uint8_t>(buf.data(), *got))) {
                if (*dump) {
                    config_slot_.publish(**dump);
                    dump_queue_.push(std::move(**dump));
                }
            }
        }
        set_connected(false);
    }
}

}  // namespace gs::link
