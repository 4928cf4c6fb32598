#include "drone/dataset/annexb.hpp"
#include "drone/dataset/raw_replay.hpp"
#include "drone/protocol/navdata.hpp"
#include "drone/protocol/pave.hpp"
#include "drone/video/h264_decoder.hpp"

#include <memory>

namespace gs::dataset {

std::optional<NavState> navdata_state(std::span<const std::uint8_t> datagram) {
    auto nd = protocol::navdata::parse_navdata(datagram);
    if (!nd) return std::nullopt;
    return protocol::navdata::to_nav_state(*nd, 0);
}

RawReplayDecoders make_protocol_replay_decoders() {
    // The same framer and decoder the link's video thread runs, fed the same bytes.
    struct Video {
        protocol::PaveFramer framer;
        video::H264Decoder decoder;
        cv::Mat image;
        bool seen_idr = false;  // the writer skips frames before the first IDR
    };
    auto v = std::make_shared<Video>();
    RawReplayDecoders d;
    d.navdata = [](std::span<const std::uint8_t> b) { return navdata_state(b); };
    d.video = [v](std::span<const std::uint8_t> chunk, TimeNs recv_ns, std::vector<TimeNs>& out) {
        v->framer.push(chunk);
        while (auto ev = v->framer.next()) {
            const auto* frame = std::get_if<protocol::PaveFrame>(&*ev);
            if (frame == nullptr || frame->header.video_codec != protocol::PaveCodec::H264)
                continue;
            video::AccessUnit au;
            au.data = frame->payload;
            au.frame_number = frame->header.frame_number;
            au.display_width = frame->header.display_width;
            au.display_height = frame->header.display_height;
            au.stream_id = frame->header.stream_id;
            auto res = v->decoder.decode(au, v->image);
            if (!res || *res != video::DecodeStatus::Frame) continue;
            if (!v->seen_idr) {
                if (!annexb_has_idr(frame->payload)) continue;
                v->seen_idr = true;
            }
            out.push_back(recv_ns);
        }
    };
    return d;
}

}  // namespace gs::dataset
