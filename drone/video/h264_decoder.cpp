#include "drone/video/h264_decoder.hpp"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavutil/error.h>
#include <libavutil/frame.h>
#include <libavutil/log.h>
#include <libswscale/swscale.h>
}

#include <algorithm>
#include <climits>
#include <cstring>
#include <mutex>
#include <vector>

namespace gs::video {

std::string to_string(DecodeError e) {
    switch (e) {
        case DecodeError::CodecUnavailable:
            return "H.264 decoder unavailable in libavcodec";
        case DecodeError::InvalidInput:
            return "empty or oversized access unit";
        case DecodeError::DecodeFailed:
            return "libavcodec could not decode the access unit";
    }
    return "unknown decode error";
}

bool contains_idr(std::span<const std::uint8_t> annexb) {
    // A NAL starts after 00 00 01 (a 4-byte start code ends with the same three bytes).
    const std::size_t n = annexb.size();
    for (std::size_t i = 0; i + 3 < n; ++i) {
        if (annexb[i] == 0 && annexb[i + 1] == 0 && annexb[i + 2] == 1) {
            if ((annexb[i + 3] & 0x1F) == 5) return true;
            i += 2;
        }
    }
    return false;
}

std::size_t access_unit_size(std::span<const std::uint8_t> annexb) {
    const std::size_t n = annexb.size();
    bool seen_slice = false;
    for (std::size_t i = 0; i + 3 < n; ++i) {
        if (annexb[i] != 0 || annexb[i + 1] != 0 || annexb[i + 2] != 1) continue;
        const std::size_t start = (i > 0 && annexb[i - 1] == 0) ? i - 1 : i;  // 4-byte code
        const int type = annexb[i + 3] & 0x1F;
        const bool slice = type == 1 || type == 5;
        // first_mb_in_slice is ue(v): 0 is the single bit 1 right after the NAL header byte.
        const bool first_slice = slice && i + 4 < n && (annexb[i + 4] & 0x80) != 0;
        const bool non_vcl_start =
            type == 6 || (type >= 7 && type <= 9) || (type >= 14 && type <= 18);
        if (seen_slice && start > 0 && (first_slice || non_vcl_start)) return start;
        seen_slice = seen_slice || slice;
        i += 2;
    }
    return n;
}

// Same size in and out, so only the colour conversion runs (swscale's unscaled YUV->BGR fast
// path, BT.601). About 48 dB against an exact conversion; the exact flags
// (SWS_ACCURATE_RND | SWS_FULL_CHR_H_INT | SWS_FULL_CHR_H_INP) take ~10x longer per frame.
constexpr int kSwsFlags = SWS_BILINEAR;

struct H264Decoder::Impl {
    const AVCodec* codec = nullptr;
    AVCodecContext* ctx = nullptr;
    AVPacket* pkt = nullptr;
    AVFrame* frame = nullptr;
    SwsContext* sws = nullptr;
    cv::Mat conv;                      // the converter's padded output rows (see convert)
    std::vector<std::uint8_t> padded;  // input copy with the zero padding libavcodec requires

    bool waiting_idr = true;
    std::optional<std::uint32_t> last_frame_number;
    std::optional<std::uint16_t> stream_id;
    int hint_w = 0, hint_h = 0;  // last PaVE display size
    // Geometry of the last emitted picture; 0 = none since the last (re)initialisation.
    int src_w = 0, src_h = 0, src_fmt = -1;
    H264DecoderStats stats;
    // The last picture emitted carries concealed damage: its own, or predicted from a concealed
    // one (P-frames copy the damage on until an intra picture replaces it).
    bool damage_shown = false;

    Impl() {
        // libavcodec logs concealment details on stderr; the counters report them instead.
        static std::once_flag quiet;
        std::call_once(quiet, [] { av_log_set_level(AV_LOG_QUIET); });
        codec = avcodec_find_decoder(AV_CODEC_ID_H264);
        pkt = av_packet_alloc();
        frame = av_frame_alloc();
        open();
    }
    ~Impl() {
        close();
        sws_freeContext(sws);
        av_frame_free(&frame);
        av_packet_free(&pkt);
    }

    bool open() {
        if (codec == nullptr || pkt == nullptr || frame == nullptr) return false;
        ctx = avcodec_alloc_context3(codec);
        if (ctx == nullptr) return false;
        // Baseline has no B-frames: one picture out per access unit, no reordering delay.
        ctx->flags |= AV_CODEC_FLAG_LOW_DELAY;
        ctx->thread_count = 1;
        // Every size read from the wire is bounded: a corrupt or hostile SPS may declare pictures
        // up to 8192x8192 (256 MB of buffers per reference). The AR.Drone 2 sends at most
        // 1280x720; 1080p admits any H.264 a dataset from another tool may hold. libavcodec
        // refuses larger pictures with an error, counted as a failed decode.
        ctx->max_pixels = kMaxPictureWidth * kMaxPictureHeight;
        if (avcodec_open2(ctx, codec, nullptr) < 0) {
            avcodec_free_context(&ctx);
            return false;
        }
        return true;
    }
    void close() { avcodec_free_context(&ctx); }

    void forget_stream() {
        waiting_idr = true;
        damage_shown = false;  // what follows is a new stream, not a repair of the old one
        last_frame_number.reset();
        src_w = src_h = 0;
        src_fmt = -1;
    }

    void reinit() {
        close();
        open();
        forget_stream();
        ++stats.reinits;
    }

    // Converts the decoded picture into `out` (BGR8), cropped to the display size.
    void convert(cv::Mat& out) {
        int w = frame->width;
        int h = frame->height;
        if (hint_w > 0 && hint_h > 0) {
            w = std::min(w, hint_w);
            h = std::min(h, hint_h);
        }
        if (src_w != 0 && (w != src_w || h != src_h || frame->format != src_fmt)) {
            ++stats.reinits;  // the SPS changed size mid-stream: new swscale geometry
        }
        src_w = w;
        src_h = h;
        src_fmt = frame->format;
        sws = sws_getCachedContext(sws, w, h, static_cast<AVPixelFormat>(frame->format), w, h,
                                   AV_PIX_FMT_BGR24, kSwsFlags, nullptr, nullptr, nullptr);
        out.create(h, w, CV_8UC3);
        if (sws == nullptr) {
            out.setTo(cv::Scalar::all(0));
            return;
        }
        // swscale's SIMD converters store whole vector words: a 24-bit row is written up to a
        // few bytes past its last pixel, and past the end of a buffer that holds exactly h rows
        // of 3w bytes (found by the h264 fuzzer: the heap header after the picture overwritten
        // with converted grey). Convert into rows padded to 64 bytes plus a spare row, kept
        // between frames, then copy the picture out.
        const int stride = (w * 3 + 63) / 64 * 64 + 64;
        conv.create(h + 1, stride, CV_8U);
        std::uint8_t* dst[4] = {conv.data, nullptr, nullptr, nullptr};
        int dst_stride[4] = {stride, 0, 0, 0};
        sws_scale(sws, frame->data, frame->linesize, 0, h, dst, dst_stride);
        const std::size_t row = static_cast<std::size_t>(w) * 3;
        for (int y = 0; y < h; ++y) std::memcpy(out.ptr(y), conv.ptr(y), row);
    }
};

H264Decoder::H264Decoder() : impl_(std::make_unique<Impl>()) {}
H264Decoder::~H264Decoder() = default;

const H264DecoderStats& H264Decoder::stats() const {
    return impl_->stats;
}

void H264Decoder::reset() {
    Impl& d = *impl_;
    if (d.ctx != nullptr) avcodec_flush_buffers(d.ctx);
    d.forget_stream();
}

Expected<DecodeStatus, DecodeError> H264Decoder::decode(const AccessUnit& au, cv::Mat& out) {
    Impl& d = *impl_;
    ++d.stats.access_units;
    if (d.ctx == nullptr && !d.open()) return Unexpected{DecodeError::CodecUnavailable};
    if (au.data.empty() || au.data.size() > static_cast<std::size_t>(INT_MAX / 2)) {
        ++d.stats.decode_errors;
        return Unexpected{DecodeError::InvalidInput};
    }

    // A new encoder run (codec/camera switch) or a new display size: start from scratch.
    const bool stream_changed = au.stream_id && d.stream_id && *au.stream_id != *d.stream_id;
    const bool has_hint = au.display_width > 0 && au.display_height > 0;
    const bool size_changed =
        has_hint && d.hint_w > 0 && (au.display_width != d.hint_w || au.display_height != d.hint_h);
    if (stream_changed || size_changed) {
        d.reinit();
        if (d.ctx == nullptr) return Unexpected{DecodeError::CodecUnavailable};
    }
    if (au.stream_id) d.stream_id = au.stream_id;
    if (has_hint) {
        d.hint_w = au.display_width;
        d.hint_h = au.display_height;
    }

    if (au.frame_number) {
        if (d.last_frame_number && *au.frame_number != *d.last_frame_number + 1) {
            // A lost frame breaks the reference chain: P-frames would decode into garbage.
            ++d.stats.frame_gaps;
            if (!d.waiting_idr) {
                d.waiting_idr = true;
                avcodec_flush_buffers(d.ctx);
            }
        }
        d.last_frame_number = au.frame_number;
    }
    if (d.waiting_idr) {
        if (!contains_idr(au.data)) {
            ++d.stats.skipped_waiting_idr;
            return DecodeStatus::NoFrame;
        }
        d.waiting_idr = false;
    }

    const std::size_t n = au.data.size();
    d.padded.resize(n + AV_INPUT_BUFFER_PADDING_SIZE);
    std::memcpy(d.padded.data(), au.data.data(), n);
    std::memset(d.padded.data() + n, 0, AV_INPUT_BUFFER_PADDING_SIZE);
    d.pkt->data = d.padded.data();
    d.pkt->size = static_cast<int>(n);

    int ret = avcodec_send_packet(d.ctx, d.pkt);
    d.pkt->data = nullptr;
    d.pkt->size = 0;
    if (ret < 0 && ret != AVERROR(EAGAIN)) {
        ++d.stats.decode_errors;
        return Unexpected{DecodeError::DecodeFailed};
    }
    bool got = false;
    bool failed = false;
    for (;;) {
        ret = avcodec_receive_frame(d.ctx, d.frame);
        if (ret == AVERROR(EAGAIN) || ret == AVERROR_EOF) break;
        if (ret < 0) {
            failed = true;
            break;
        }
        if (d.frame->width > 0 && d.frame->height > 0) {
            if (d.frame->decode_error_flags != 0 || (d.frame->flags & AV_FRAME_FLAG_CORRUPT) != 0) {
                ++d.stats.concealed;
                d.damage_shown = true;
            } else if (d.damage_shown && d.frame->pict_type == AV_PICTURE_TYPE_I) {
                ++d.stats.repaired;
                d.damage_shown = false;
            }
            d.convert(out);
            got = true;
        }
        av_frame_unref(d.frame);
    }
    if (failed) {
        ++d.stats.decode_errors;
        if (!got) return Unexpected{DecodeError::DecodeFailed};
    }
    if (!got) return DecodeStatus::NoFrame;
    ++d.stats.decoded;
    return DecodeStatus::Frame;
}

}  // namespace gs::video
