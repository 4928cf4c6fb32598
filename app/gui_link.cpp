#ifdef GS_HAVE_GUI

// Link view: connection state, per-stream health and byte rates (the window's sliding window
// over the bytes the link counts: unknown until a quarter second is measured), and what the
// session is doing now in words.

#include "app/gui_adapter.hpp"
#include "app/gui_views.hpp"

#include <algorithm>

namespace gs::app {

namespace {

ui::LinkState to_ui(link::ConnectionState s) {
    switch (s) {
        case link::ConnectionState::Disconnected:
            return ui::LinkState::Disconnected;
        case link::ConnectionState::Bootstrapping:
        case link::ConnectionState::Configuring:
            return ui::LinkState::Connecting;
        case link::ConnectionState::Connected:
            return ui::LinkState::Connected;
        case link::ConnectionState::LinkLost:
            return ui::LinkState::Lost;
    }
    return ui::LinkState::Disconnected;
}

}  // namespace

double SlidingRate::update(std::uint64_t count, TimeNs now) {
    constexpr TimeNs kWindow = ms_to_ns(1000);
    if (size > 0) {
        const auto& newest = ring[(head + kSamples - 1) % kSamples];
        if (count < newest.second || now < newest.first) reset();  // a new stream or source
    }
    ring[head] = {now, count};
    head = (head + 1) % kSamples;
    size = std::min(size + 1, kSamples);
    // The oldest sample inside the window (or the oldest kept, if the window is not full yet).
    std::size_t oldest = (head + kSamples - size) % kSamples;
    for (std::size_t k = 0; k + 1 < size; ++k) {
        const std::size_t i = (head + kSamples - size + k) % kSamples;
        const std::size_t next = (i + 1) % kSamples;
        if (now - ring[next].first >= kWindow)
            oldest = next;
        else
            break;
    }
    const TimeNs span = now - ring[oldest].first;
    if (span < ms_to_ns(250)) return hz;  // too short to say yet: keep the last value
    hz = static_cast<double>(count - ring[oldest].second) * 1e9 / static_cast<double>(span);
    return hz;
}

void GuiAdapter::fill_link(ui::GuiSnapshot& s, TimeNs now) {
    const link::LinkStatus st = source_.link->status();
    s.connection.state = to_ui(st.state);
    s.connection.reason = st.reason;
    link_connected_ = st.state == link::ConnectionState::Connected;

    ui::StreamHealth& n = s.link.navdata;
    n = ui::StreamHealth{};
    n.active = source_.link->running();
    n.rate_hz = nav_rate_.update(st.navdata.accepted, now);
    n.age_ms = age_ms(st.now_ns, st.navdata.last_ns);
    s.link.expected_navdata_hz = kUnknown;
    if (nav_valid_ && nav_.state.drone_state)
        s.link.expected_navdata_hz = (*nav_.state.drone_state & (1u << 10)) ? 15.0 : 200.0;
    n.packets = st.navdata.accepted;
    n.gaps = st.machine.sequence_gaps;
    n.drops = st.machine.out_of_order + st.navdata.foreign_dropped + st.navdata.oversize;
    n.checksum_failures = st.navdata.checksum_failures;
    n.decode_errors = st.navdata.parse_errors;
    // Bytes counted by the link, as a rate over the same sliding window as the packets (the
    // link's own per-second figure reads 0 until its first full second).
    n.bytes_per_s = nav_bytes_rate_.update(st.navdata.bytes, now);

    ui::StreamHealth& v = s.link.video;
    v = ui::StreamHealth{};
    v.active = st.video.connected;
    v.rate_hz = video_rate_.update(st.video.decoded, now);
    v.age_ms = age_ms(st.now_ns, st.video.last_frame_ns);
    last_video_frame_ns_ = st.video.last_frame_ns;
    video_connected_ = st.video.connected;
    v.bytes_per_s = video_bytes_rate_.update(st.video.bytes, now);
    v.packets = st.video.decoded;
    v.gaps = st.video.frame_gaps;
    v.drops = out_ ? out_->frames_dropped : 0;  // frames the classifier could not keep up with
    // Frames in a codec other than H.264 cannot be decoded either (the reason is in last_error).
    v.decode_errors = st.video.decode_errors + st.video.unsupported_codec_frames;
    v.idr_waits = st.video.idr_waits;

    ui::StreamHealth& a = s.link.at;
    a = ui::StreamHealth{};
    a.active = source_.link->running();
    a.rate_hz = at_rate_.update(st.at.counters.datagrams, now);
    // Since the last command went out (not the last period, which a stalled sender keeps).
    a.age_ms = age_ms(st.now_ns, st.at.last_cycle_ns);
    a.packets = st.at.counters.datagrams;
    a.bytes_per_s = at_bytes_rate_.update(st.at.bytes_sent, now);
    a.drops = st.at.counters.stale_moves_dropped;
    a.decode_errors = st.at.send_errors + st.at.counters.encode_errors;
}

// What the session is doing now, in words, as it happens: starting the virtual drone, connecting,
// configuring, waiting for video.
void GuiAdapter::fill_activity(ui::GuiSnapshot& s, const OpeningInfo& op, bool pending) {
    ui::ConnectionInfo& c = s.connection;
    c.opening = pending;
    c.activity.clear();
    if (pending) {
        switch (op.kind) {
            case SessionSource::Sim:
                c.source = ui::SourceKind::Sim;
                c.scenario = op.what;
                c.activity = "Starting virtual drone '" + op.what + "'...";
                break;
            case SessionSource::Drone:
                c.source = ui::SourceKind::Drone;
                c.address = op.what;
                c.activity = "Connecting to " + op.what + "...";
                break;
            case SessionSource::Replay:
                c.source = ui::SourceKind::Replay;
                c.activity = "Opening replay " + op.what + "...";
                break;
            case SessionSource::None:
                break;
        }
        // Whatever was shown before is going: say what comes, not what was.
        if (op.kind == SessionSource::Sim || op.kind == SessionSource::Drone)
            c.state = ui::LinkState::Connecting;
        c.reason = c.activity;
        return;
    }
    if (source_.kind != SessionSource::Drone && source_.kind != SessionSource::Sim) return;
    const std::string who = source_.kind == SessionSource::Sim
                                ? "the virtual drone"
                                : (source_.address.empty() ? "the drone" : source_.address);
    switch (c.state) {
        case ui::LinkState::Connecting:
            c.activity = c.reason.rfind("writing", 0) == 0 || c.reason.rfind("configured", 0) == 0
                             ? "Configuring " + who + "..."
                             : "Connecting to " + who + "...";
            break;
        case ui::LinkState::Lost:
            c.activity = "Link lost: waiting for " + who + "...";
            break;
        case ui::LinkState::Connected:
            if (source_.link && source_.link->config_used().video && !out_)
                c.activity = "Waiting for video...";
            break;
        default:
            break;
    }
}

}  // namespace gs::app

#endif  // GS_HAVE_GUI
