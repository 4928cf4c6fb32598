#include "drone/video/receiver.hpp"

namespace gs::video {

const char* to_string(UnitFate f) {
    switch (f) {
        case UnitFate::Decoded:
            return "decoded";
        case UnitFate::Concealed:
            return "decoded with concealed damage";
        case UnitFate::WaitingIdr:
            return "skipped: reference lost, waiting for an IDR";
        case UnitFate::NoPicture:
            return "no picture";
        case UnitFate::NotH264:
            return "not H.264";
        case UnitFate::NotDecoded:
            return "not decoded";
    }
    return "unknown";
}

VideoReceiver::VideoReceiver(ReceiverOptions options)
    : options_(options), pool_(FramePool::create(options.pool_slots)) {}

void VideoReceiver::begin_connection(TimeNs now_ns) {
    recv_ns_ = now_ns;
    if (!any_connection_) {
        any_connection_ = true;
        stats_.connections = 1;
        return;
    }
    // Whatever is still buffered belongs to a frame the old connection ended inside: it is never
    // joined to the new connection's bytes.
    const protocol::PavePending p = framer_.pending();
    if (p.buffered_bytes > 0) ++stats_.cut_by_reset;
    framer_.reset();
    decoder_.reset();
    ++connection_;
    ++stats_.connections;
}

void VideoReceiver::push(std::span<const std::uint8_t> bytes, TimeNs recv_ns) {
    if (!any_connection_) begin_connection(recv_ns);
    recv_ns_ = recv_ns;
    stats_.bytes += bytes.size();
    framer_.push(bytes);
}

std::optional<ReceivedUnit> VideoReceiver::next() {
    while (auto ev = framer_.next()) {
        const auto* frame = std::get_if<protocol::PaveFrame>(&*ev);
        if (frame == nullptr) {  // a resync: counted by the framer
            if (resyncs_.size() < 1024) resyncs_.push_back(std::get<protocol::PaveResync>(*ev));
            stats_.resyncs = framer_.stats().resyncs;
            stats_.bytes_skipped = framer_.stats().bytes_skipped;
            continue;
        }
        const protocol::PaveHeader& h = frame->header;
        ReceivedUnit u;
        u.unit = next_unit_++;
        u.connection = connection_;
        u.frame_number = h.frame_number;
        u.pave_timestamp_ms = h.timestamp;
        u.stream_id = h.stream_id;
        u.stream_offset = frame->stream_offset;
        u.header = h;
        u.codec = h.video_codec;
        u.recv_ns = recv_ns_;
        u.capture_ns = clock_.map(h.timestamp, recv_ns_);
        u.idr = contains_idr(frame->payload);
        u.bytes = frame->payload;
        ++stats_.units;
        stats_.clock_anchors = clock_.anchors();
        stats_.clock_frozen = clock_.frozen_frames();
        if (h.video_codec != protocol::PaveCodec::H264) {
            u.fate = UnitFate::NotH264;
            ++stats_.not_h264;
            stats_.last_error = "PaVE frame " + std::to_string(h.frame_number) + " has codec " +
                                to_string(h.video_codec) +
                                ": only H.264 is decoded (set video:video_codec to an H.264 mode)";
            return u;
        }
        if (!options_.decode) {
            u.fate = UnitFate::NotDecoded;
            return u;
        }
        AccessUnit au;
        au.data = frame->payload;
        au.frame_number = h.frame_number;
        au.display_width = h.display_width;
        au.display_height = h.display_height;
        au.stream_id = h.stream_id;
        const H264DecoderStats before = decoder_.stats();
        cv::Mat image = pool_->acquire();
        auto res = decoder_.decode(au, image);
        const H264DecoderStats& after = decoder_.stats();
        stats_.pool_exhausted = pool_->exhausted();
        if (res && *res == DecodeStatus::Frame) {
            const bool concealed = after.concealed > before.concealed;
            u.fate = concealed ? UnitFate::Concealed : UnitFate::Decoded;
            u.repaired = after.repaired > before.repaired;
            u.image = std::move(image);
            u.frame_index = next_frame_++;
            ++stats_.pictures;
            if (concealed) ++stats_.concealed;
            if (u.repaired) ++stats_.repaired;
        } else if (after.skipped_waiting_idr > before.skipped_waiting_idr) {
            u.fate = UnitFate::WaitingIdr;
            ++stats_.waiting_idr;
        } else {
            u.fate = UnitFate::NoPicture;
            ++stats_.no_picture;
            stats_.last_error =
                "PaVE frame " + std::to_string(h.frame_number) + ": " +
                (res ? std::string("the decoder gave no picture") : to_string(res.error()));
        }
        return u;
    }
    stats_.resyncs = framer_.stats().resyncs;
    stats_.bytes_skipped = framer_.stats().bytes_skipped;
    return std::nullopt;
}

}  // namespace gs::video
