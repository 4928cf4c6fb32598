#include "drone/dataset/video_import.hpp"

#include "drone/dataset/video_dataset_writer.hpp"
#include "drone/video/h264_decoder.hpp"
#include "drone/video/h264_encoder.hpp"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavcodec/bsf.h>
#include <libavformat/avformat.h>
#include <libavutil/error.h>
#include <libavutil/frame.h>
#include <libswscale/swscale.h>
}

#include <opencv2/core.hpp>

#include <cmath>
#include <limits>
#include <vector>

namespace gs::dataset {
namespace {
namespace fs = std::filesystem;
using video::AccessUnit;
using video::contains_idr;
using video::DecodeStatus;
using video::H264Decoder;
using video::H264Encoder;
using video::H264EncoderConfig;

std::string av_error_text(int code) {
    char b[AV_ERROR_MAX_STRING_SIZE] = {};
    av_strerror(code, b, sizeof b);
    return b;
}

// Owners of the libav objects, so every return path frees them.
struct InputFile {
    AVFormatContext* fmt = nullptr;
    ~InputFile() { avformat_close_input(&fmt); }
};
struct Packet {
    AVPacket* p = av_packet_alloc();
    ~Packet() { av_packet_free(&p); }
};
struct Frame {
    AVFrame* f = av_frame_alloc();
    ~Frame() { av_frame_free(&f); }
};
struct Bsf {
    AVBSFContext* c = nullptr;
    ~Bsf() { av_bsf_free(&c); }
};
struct Decoder {
    AVCodecContext* c = nullptr;
    SwsContext* sws = nullptr;
    ~Decoder() {
        avcodec_free_context(&c);
        sws_freeContext(sws);
    }
};

// Frame times: the container's presentation times, made strictly increasing (a frame with none,
// or one not after its predecessor, is placed one nominal interval after it and counted), or
// n / fps when the caller gave a rate.
class FrameClock {
public:
    FrameClock(AVRational time_base, double given_fps, double stream_fps)
        : tb_(time_base), given_fps_(given_fps) {
        const double fps = given_fps > 0 ? given_fps : stream_fps > 0 ? stream_fps : 25.0;
        step_ns_ = static_cast<std::int64_t>(std::llround(1e9 / fps));
    }
    std::int64_t next(std::int64_t pts) {
        std::int64_t t = 0;
        if (given_fps_ > 0) {
            t = static_cast<std::int64_t>(std::llround(static_cast<double>(n_) * 1e9 / given_fps_));
        } else if (pts == AV_NOPTS_VALUE) {
            // A raw elementary stream has no times at all: frames at the nominal rate. One
            // frame without a time among timed ones is placed one interval on, and counted.
            t = n_ == 0 ? 0 : last_ + step_ns_;
            if (first_) ++repairs_;
        } else {
            if (!first_) first_ = pts;
            t = av_rescale_q(pts - *first_, tb_, AVRational{1, 1'000'000'000});
            if (n_ > 0 && t <= last_) {
                t = last_ + step_ns_;
                ++repairs_;
            }
        }
        last_ = t;
        ++n_;
        return t;
    }
    std::int64_t repairs() const { return repairs_; }
    bool untimed() const { return given_fps_ <= 0 && !first_; }
    std::int64_t last_ns() const { return last_; }

private:
    AVRational tb_;
    double given_fps_;
    std::int64_t step_ns_ = 40'000'000;
    std::optional<std::int64_t> first_;
    std::int64_t last_ = 0, n_ = 0, repairs_ = 0;
};

double stream_rate(const AVStream* st) {
    for (AVRational r : {st->avg_frame_rate, st->r_frame_rate})
        if (r.num > 0 && r.den > 0) {
            const double v = av_q2d(r);
            if (v > 0 && v <= 1000) return v;
        }
    return 0;
}

bool limit_reached(const VideoImportOptions& o, std::int64_t frames) {
    return o.max_frames >= 0 && frames >= o.max_frames;
}

}  // namespace

Expected<VideoImportSummary, std::string> import_video(const fs::path& input,
                                                       const fs::path& out_dir,
                                                       const VideoImportOptions& o) {
    const std::string in_name = input.string();
    if (!(o.fps >= 0 && o.fps <= 1000)) return Unexpected(std::string("--fps out of range"));
    std::error_code ec;
    if (fs::exists(out_dir, ec) && !fs::is_empty(out_dir, ec))
        return Unexpected(out_dir.string() + " exists and is not empty");

    InputFile in;
    if (int e = avformat_open_input(&in.fmt, in_name.c_str(), nullptr, nullptr); e < 0)
        return Unexpected(in_name + ": cannot open: " + av_error_text(e));
    if (int e = avformat_find_stream_info(in.fmt, nullptr); e < 0)
        return Unexpected(in_name + ": cannot read the streams: " + av_error_text(e));
    const int si = av_find_best_stream(in.fmt, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
    if (si < 0) return Unexpected(in_name + ": no video stream");
    AVStream* st = in.fmt->streams[si];
    const AVCodecParameters* par = st->codecpar;

    VideoImportSummary sum;
    sum.codec = avcodec_get_name(par->codec_id);
    const bool h264 = par->codec_id == AV_CODEC_ID_H264;
    const bool reorders = par->video_delay > 0;
    if (o.mode == VideoImportMode::Copy && (!h264 || reorders))
        return Unexpected(in_name + ": cannot copy a " + sum.codec +
                          (reorders ? " stream with reordered (B-) frames" : " stream") +
                          " into video.h264; import it with encoding");
    sum.copied =
        o.mode == VideoImportMode::Copy || (o.mode == VideoImportMode::Auto && h264 && !reorders);

    GS_TRY_ASSIGN(VideoDatasetWriter out, VideoDatasetWriter::create(out_dir));
    // Imported footage has a time per frame and nothing else: attitude, velocity and altitude
    // are unknown (empty cells).
    auto add = [&out](std::span<const std::uint8_t> au, std::int64_t t_ns) {
        FrameRow row;
        row.nav.t_ns = t_ns;
        out.add(au, row);
    };

    const double rate = stream_rate(st);
    FrameClock clock(st->time_base, o.fps, rate);
    Packet pkt, fpkt;
    if (!pkt.p || !fpkt.p) return Unexpected(std::string("out of memory"));

    if (sum.copied) {
        // MP4/MKV carry length-prefixed NAL units with the parameter sets in the header: the
        // bitstream filter rewrites them as Annex-B with SPS/PPS before each IDR (Annex-B input
        // passes through unchanged).
        Bsf bsf;
        const AVBitStreamFilter* f = av_bsf_get_by_name("h264_mp4toannexb");
        if (!f || av_bsf_alloc(f, &bsf.c) < 0 || avcodec_parameters_copy(bsf.c->par_in, par) < 0 ||
            (bsf.c->time_base_in = st->time_base, av_bsf_init(bsf.c) < 0))
            return Unexpected(std::string("libavcodec: h264_mp4toannexb unavailable"));
        // Decoded with the decoder the dataset reader uses: the size and what it can show.
        H264Decoder check;
        cv::Mat image;
        bool started = false;
        auto drain = [&]() -> std::optional<std::string> {
            for (;;) {
                const int r = av_bsf_receive_packet(bsf.c, fpkt.p);
                if (r == AVERROR(EAGAIN) || r == AVERROR_EOF) return std::nullopt;
                if (r < 0) return in_name + ": " + av_error_text(r);
                const std::span<const std::uint8_t> au(fpkt.p->data,
                                                       static_cast<std::size_t>(fpkt.p->size));
                const std::int64_t pts = fpkt.p->pts != AV_NOPTS_VALUE ? fpkt.p->pts : fpkt.p->dts;
                if (!started && !contains_idr(au)) {
                    ++sum.skipped_before_keyframe;
                    av_packet_unref(fpkt.p);
                    continue;
                }
                started = true;
                if (!limit_reached(o, out.frames())) {
                    AccessUnit unit;
                    unit.data = au;
                    auto d = check.decode(unit, image);
                    if (d && *d == DecodeStatus::Frame && sum.width == 0) {
                        sum.width = image.cols;
                        sum.height = image.rows;
                    }
                    add(au, clock.next(pts));
                    if (o.progress) o.progress(out.frames());
                }
                av_packet_unref(fpkt.p);
            }
        };
        while (av_read_frame(in.fmt, pkt.p) >= 0 && !limit_reached(o, out.frames())) {
            if (pkt.p->stream_index == si) {
                if (int e = av_bsf_send_packet(bsf.c, pkt.p); e < 0) {
                    av_packet_unref(pkt.p);
                    return Unexpected(in_name + ": " + av_error_text(e));
                }
                if (auto e = drain()) return Unexpected(*e);
            }
            av_packet_unref(pkt.p);
        }
        if (av_bsf_send_packet(bsf.c, nullptr) >= 0)
            if (auto e = drain()) return Unexpected(*e);
        sum.decode_errors = static_cast<std::int64_t>(check.stats().decode_errors);
    } else {
        const AVCodec* codec = avcodec_find_decoder(par->codec_id);
        if (!codec) return Unexpected(in_name + ": no decoder for " + sum.codec);
        Decoder dec;
        dec.c = avcodec_alloc_context3(codec);
        if (!dec.c || avcodec_parameters_to_context(dec.c, par) < 0)
            return Unexpected(std::string("libavcodec: cannot set up the decoder"));
        dec.c->pkt_timebase = st->time_base;
        if (int e = avcodec_open2(dec.c, codec, nullptr); e < 0)
            return Unexpected(in_name + ": cannot open the " + sum.codec +
                              " decoder: " + av_error_text(e));
        Frame frame;
        std::unique_ptr<H264Encoder> enc;
        cv::Mat bgr;
        std::vector<std::uint8_t> au;
        auto encode_frame = [&](const AVFrame* fr) -> std::optional<std::string> {
            // x264 wants an even size: an odd last row or column is cropped.
            const int w = fr->width & ~1, h = fr->height & ~1;
            if (w < 16 || h < 16) return in_name + ": frames too small to import";
            if (!enc) {
                H264EncoderConfig cfg;
                cfg.width = w;
                cfg.height = h;
                cfg.fps = std::max(1, static_cast<int>(std::lround(o.fps > 0  ? o.fps
                                                                   : rate > 0 ? rate
                                                                              : 25)));
                cfg.gop = 15;
                cfg.bitrate_bps = o.bitrate_bps;
                auto e = H264Encoder::create(cfg);
                if (!e) return "H.264 encoder: " + to_string(e.error());
                enc = std::move(*e);
                sum.width = w;
                sum.height = h;
            }
            if (w != sum.width || h != sum.height)
                return in_name + ": the frame size changes mid-stream (" + std::to_string(w) + "x" +
                       std::to_string(h) + " after " + std::to_string(sum.width) + "x" +
                       std::to_string(sum.height) + ")";
            bgr.create(h, w, CV_8UC3);
            dec.sws =
                sws_getCachedContext(dec.sws, w, h, static_cast<AVPixelFormat>(fr->format), w, h,
                                     AV_PIX_FMT_BGR24, SWS_BILINEAR, nullptr, nullptr, nullptr);
            if (!dec.sws) return std::string("libswscale: unsupported pixel format");
            std::uint8_t* dst[1] = {bgr.data};
            const int dst_stride[1] = {static_cast<int>(bgr.step)};
            sws_scale(dec.sws, fr->data, fr->linesize, 0, h, dst, dst_stride);
            bool idr = false;
            auto n = enc->encode(bgr, au, idr);
            if (!n) return "H.264 encoder: " + to_string(n.error());
            add(au, clock.next(fr->best_effort_timestamp));
            if (o.progress) o.progress(out.frames());
            return std::nullopt;
        };
        auto receive = [&]() -> std::optional<std::string> {
            for (;;) {
                const int r = avcodec_receive_frame(dec.c, frame.f);
                if (r == AVERROR(EAGAIN) || r == AVERROR_EOF) return std::nullopt;
                if (r < 0) {
                    ++sum.decode_errors;
                    return std::nullopt;
                }
                std::optional<std::string> e;
                if (!limit_reached(o, out.frames())) e = encode_frame(frame.f);
                av_frame_unref(frame.f);
                if (e) return e;
            }
        };
        while (av_read_frame(in.fmt, pkt.p) >= 0 && !limit_reached(o, out.frames())) {
            if (pkt.p->stream_index == si) {
                if (avcodec_send_packet(dec.c, pkt.p) < 0) ++sum.decode_errors;
                if (auto e = receive()) {
                    av_packet_unref(pkt.p);
                    return Unexpected(*e);
                }
            }
            av_packet_unref(pkt.p);
        }
        if (avcodec_send_packet(dec.c, nullptr) >= 0)
            if (auto e = receive()) return Unexpected(*e);
    }

    sum.frames = out.frames();
    if (sum.frames == 0) return Unexpected(in_name + ": no frame could be imported");
    if (sum.width == 0) return Unexpected(in_name + ": no frame could be decoded");
    sum.timestamp_repairs = clock.repairs();
    sum.untimed = clock.untimed();
    sum.fps = o.fps > 0 ? o.fps : rate;
    if (!(sum.fps > 0))  // no rate in the container: the mean over the frames' times
        sum.fps =
            sum.frames > 1 && clock.last_ns() > 0
                ? static_cast<double>(sum.frames - 1) * 1e9 / static_cast<double>(clock.last_ns())
                : 25.0;

    DatasetInfo info;
    info.camera = o.camera;
    info.width = sum.width;
    info.height = sum.height;
    info.fps = sum.fps;
    info.frames = sum.frames;
    if (o.calibration) info.calibration = *o.calibration;
    info.source = "imported: " + input.filename().string() + " (" + sum.codec + ", " +
                  (sum.copied ? "access units copied" : "encoded again as H.264") + "; no navdata)";
    if (auto e = out.finish(info)) return Unexpected(*e);
    return sum;
}

}  // namespace gs::dataset
