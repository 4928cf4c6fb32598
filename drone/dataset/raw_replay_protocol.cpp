#include "drone/dataset/raw_replay.hpp"
#include "drone/protocol/navdata.hpp"
#include "drone/video/receiver.hpp"

#include <algorithm>
#include <deque>
#include <memory>

namespace gs::dataset {

std::optional<NavState> navdata_state(std::span<const std::uint8_t> datagram) {
    auto nd = protocol::navdata::parse_navdata(datagram);
    if (!nd) return std::nullopt;
    return protocol::navdata::to_nav_state(*nd, 0);
}

RawReplayDecoders make_protocol_replay_decoders() {
    // The link's own video receiver, fed the same bytes and told the same connection boundaries.
    struct State {
        video::VideoReceiver rx{video::ReceiverOptions{4, true}};
        bool seen_idr = false;  // the writer skips frames before the first IDR
        std::deque<RecordedCapture> captures;
        bool have_captures = false;
        std::optional<std::uint32_t> last_seq;  // the link's acceptance rule for navdata
        TimeNs last_ns = 0;
        bool comwdg = false;
    };
    auto st = std::make_shared<State>();
    RawReplayDecoders d;
    d.navdata = [st](std::span<const std::uint8_t> b, TimeNs recv) -> std::optional<NavState> {
        auto s = navdata_state(b);
        if (!s || !s->seq) return s;
        // The link's rules (drone/link/link_state.cpp): duplicates and late packets (sequence
        // not above the last accepted) are dropped, except when the drone restarted its count
        // (bootstrap mode after a reboot); the expectation is forgotten after 500 ms of silence
        // (the link is lost) and on a communication watchdog event.
        constexpr TimeNs link_lost_after = 500'000'000;
        if (st->last_seq && recv - st->last_ns > link_lost_after) st->last_seq.reset();
        st->last_ns = recv;
        const protocol::navdata::DroneState state{s->drone_state.value_or(0)};
        const bool restart = state.navdata_bootstrap();
        if (st->last_seq && *s->seq <= *st->last_seq && !restart) return std::nullopt;
        st->last_seq = *s->seq;
        const bool comwdg = state.com_watchdog() && !restart;
        if (comwdg && !st->comwdg) st->last_seq.reset();
        st->comwdg = comwdg;
        return s;
    };
    d.begin_connection = [st](TimeNs opened) { st->rx.begin_connection(opened); };
    d.capture_times = [st](std::vector<RecordedCapture> c) {
        st->captures.assign(c.begin(), c.end());
        st->have_captures = true;
    };
    d.video = [st](std::span<const std::uint8_t> chunk, TimeNs recv_ns, std::vector<TimeNs>& out) {
        st->rx.push(chunk, recv_ns);
        st->rx.clear_resyncs();
        while (auto u = st->rx.next()) {
            TimeNs capture = u->capture_ns;
            if (st->have_captures) {
                // The recording's times, matched in order (units it had but replay cannot
                // rebuild, such as one begun before the recording, are passed over).
                constexpr std::size_t kLookAhead = 16;
                for (std::size_t k = 0; k < std::min(kLookAhead, st->captures.size()); ++k) {
                    const RecordedCapture& c = st->captures[k];
                    if (c.frame_number != u->frame_number ||
                        c.pave_timestamp_ms != u->pave_timestamp_ms)
                        continue;
                    capture = c.t_ns;
                    st->captures.erase(st->captures.begin(),
                                       st->captures.begin() + static_cast<std::ptrdiff_t>(k + 1));
                    break;
                }
            }
            if (!video::has_picture(u->fate)) continue;
            if (!st->seen_idr) {
                if (!u->idr) continue;
                st->seen_idr = true;
            }
            out.push_back(capture);
        }
    };
    return d;
}

}  // namespace gs::dataset
