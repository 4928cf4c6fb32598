#include "drone/video/h264_encoder.hpp"

#include <opencv2/imgproc.hpp>

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavutil/frame.h>
#include <libavutil/log.h>
#include <libavutil/opt.h>
}

#include <cstring>

namespace gs::video {

std::string to_string(H264EncodeError e) {
    switch (e) {
        case H264EncodeError::CodecUnavailable:
            return "libx264 encoder not available in libavcodec";
        case H264EncodeError::OpenFailed:
            return "could not open the H.264 encoder";
        case H264EncodeError::BadInput:
            return "input is not a BGR image of the configured size";
        case H264EncodeError::EncodeFailed:
            return "H.264 encoding failed";
        case H264EncodeError::NoOutput:
            return "encoder produced no access unit for the frame";
    }
    return "unknown";
}

struct H264Encoder::Impl {
    H264EncoderConfig cfg;
    AVCodecContext* ctx = nullptr;
    AVFrame* frame = nullptr;
    AVPacket* pkt = nullptr;
    cv::Mat i420;  // reused colour conversion buffer
    std::int64_t pts = 0;

    ~Impl() {
        av_packet_free(&pkt);
        av_frame_free(&frame);
        avcodec_free_context(&ctx);
    }
};

H264Encoder::H264Encoder(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
H264Encoder::~H264Encoder() = default;

Expected<std::unique_ptr<H264Encoder>, H264EncodeError> H264Encoder::create(
    const H264EncoderConfig& cfg) {
    if (cfg.width <= 0 || cfg.height <= 0 || cfg.width % 2 || cfg.height % 2 || cfg.fps <= 0 ||
        cfg.gop <= 0 || cfg.bitrate_bps <= 0)
        return Unexpected{H264EncodeError::OpenFailed};
    // libx264 prints its banner (cpu capabilities, profile) at info level: errors only.
    if (av_log_get_level() > AV_LOG_ERROR) av_log_set_level(AV_LOG_ERROR);
    const AVCodec* codec = avcodec_find_encoder_by_name("libx264");
    if (!codec) return Unexpected{H264EncodeError::CodecUnavailable};
    auto m = std::make_unique<Impl>();
    m->cfg = cfg;
    m->ctx = avcodec_alloc_context3(codec);
    m->frame = av_frame_alloc();
    m->pkt = av_packet_alloc();
    if (!m->ctx || !m->frame || !m->pkt) return Unexpected{H264EncodeError::OpenFailed};
    AVCodecContext* c = m->ctx;
    c->width = cfg.width;
    c->height = cfg.height;
    c->pix_fmt = AV_PIX_FMT_YUV420P;
    c->time_base = AVRational{1, cfg.fps};
    c->framerate = AVRational{cfg.fps, 1};
    c->gop_size = cfg.gop;
    c->keyint_min = cfg.gop;
    c->max_b_frames = 0;
    c->bit_rate = cfg.bitrate_bps;
    c->rc_max_rate = cfg.bitrate_bps;
    c->rc_buffer_size = cfg.bitrate_bps;
    c->thread_count = 1;  // deterministic output, and no frame-thread delay
    c->profile = FF_PROFILE_H264_BASELINE;
    av_opt_set(c->priv_data, "profile", "baseline", 0);
    av_opt_set(c->priv_data, "preset", cfg.preset.c_str(), 0);
    av_opt_set(c->priv_data, "tune", "zerolatency", 0);
    av_opt_set(c->priv_data, "forced-idr", "1", 0);
    // repeat-headers: SPS/PPS in-band before every IDR; scenecut=0: IDRs only on the 15 grid.
    av_opt_set(c->priv_data, "x264-params", "repeat-headers=1:scenecut=0:open-gop=0:aud=0", 0);
    if (avcodec_open2(c, codec, nullptr) < 0) return Unexpected{H264EncodeError::OpenFailed};
    m->frame->format = AV_PIX_FMT_YUV420P;
    m->frame->width = cfg.width;
    m->frame->height = cfg.height;
    if (av_frame_get_buffer(m->frame, 32) < 0) return Unexpected{H264EncodeError::OpenFailed};
    return std::unique_ptr<H264Encoder>(new H264Encoder(std::move(m)));
}

Expected<std::size_t, H264EncodeError> H264Encoder::encode(const cv::Mat& bgr,
                                                           std::vector<std::uint8_t>& out,
                                                           bool& is_idr) {
    Impl& m = *impl_;
    if (bgr.type() != CV_8UC3 || bgr.cols != m.cfg.width || bgr.rows != m.cfg.height)
        return Unexpected{H264EncodeError::BadInput};
    cv::cvtColor(bgr, m.i420, cv::COLOR_BGR2YUV_I420);
    if (av_frame_make_writable(m.frame) < 0) return Unexpected{H264EncodeError::EncodeFailed};
    const int W = m.cfg.width, H = m.cfg.height;
    const std::uint8_t* src = m.i420.ptr<std::uint8_t>(0);
    for (int y = 0; y < H; ++y)
        std::memcpy(m.frame->data[0] + std::ptrdiff_t(y) * m.frame->linesize[0],
                    src + std::ptrdiff_t(y) * W, std::size_t(W));
    const std::uint8_t* u = src + std::ptrdiff_t(W) * H;
    const std::uint8_t* v = u + std::ptrdiff_t(W / 2) * (H / 2);
    for (int y = 0; y < H / 2; ++y) {
        std::memcpy(m.frame->data[1] + std::ptrdiff_t(y) * m.frame->linesize[1],
                    u + std::ptrdiff_t(y) * (W / 2), std::size_t(W / 2));
        std::memcpy(m.frame->data[2] + std::ptrdiff_t(y) * m.frame->linesize[2],
                    v + std::ptrdiff_t(y) * (W / 2), std::size_t(W / 2));
    }
    const bool force_idr = m.pts % m.cfg.gop == 0;
    m.frame->pict_type = force_idr ? AV_PICTURE_TYPE_I : AV_PICTURE_TYPE_NONE;
    m.frame->pts = m.pts++;
    if (avcodec_send_frame(m.ctx, m.frame) < 0) return Unexpected{H264EncodeError::EncodeFailed};
    const int r = avcodec_receive_packet(m.ctx, m.pkt);
    if (r == AVERROR(EAGAIN)) return Unexpected{H264EncodeError::NoOutput};
    if (r < 0) return Unexpected{H264EncodeError::EncodeFailed};
    out.assign(m.pkt->data, m.pkt->data + m.pkt->size);
    is_idr = (m.pkt->flags & AV_PKT_FLAG_KEY) != 0;
    const std::size_t n = out.size();
    av_packet_unref(m.pkt);
    return n;
}

const H264EncoderConfig& H264Encoder::config() const {
    return impl_->cfg;
}
std::int64_t H264Encoder::frames_encoded() const {
    return impl_->pts;
}

}  // namespace gs::video
