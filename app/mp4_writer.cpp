#include "app/mp4_writer.hpp"

#include "drone/video/h264_encoder.hpp"

extern "C" {
#include <libavformat/avformat.h>
#include <libavutil/error.h>
#include <libavutil/mathematics.h>
}

#include <algorithm>
#include <cmath>
#include <vector>

namespace gs {
namespace {

std::string av_error(int code) {
    char b[AV_ERROR_MAX_STRING_SIZE] = {};
    av_strerror(code, b, sizeof b);
    return b;
}

}  // namespace

struct Mp4Writer::Impl {
    Mp4WriterConfig cfg;
    std::filesystem::path path;
    std::unique_ptr<video::H264Encoder> encoder;
    AVFormatContext* fmt = nullptr;
    AVStream* stream = nullptr;
    AVPacket* pkt = nullptr;
    std::vector<std::uint8_t> au;
    std::int64_t frames = 0;
    bool header_written = false;
    bool closed = false;
    int fps_num = 30, fps_den = 1;

    ~Impl() {
        if (fmt != nullptr) {
            if (!(fmt->oformat->flags & AVFMT_NOFILE) && fmt->pb != nullptr) avio_closep(&fmt->pb);
            avformat_free_context(fmt);
        }
        av_packet_free(&pkt);
    }
};

Mp4Writer::Mp4Writer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

Mp4Writer::~Mp4Writer() {
    if (impl_) (void)close();
}

std::int64_t Mp4Writer::frames() const {
    return impl_->frames;
}

Expected<std::unique_ptr<Mp4Writer>, std::string> Mp4Writer::create(
    const std::filesystem::path& path, const Mp4WriterConfig& cfg) {
    if (cfg.width <= 0 || cfg.height <= 0 || cfg.width % 2 || cfg.height % 2)
        return Unexpected("MP4 frames must have an even, positive size (got " +
                          std::to_string(cfg.width) + "x" + std::to_string(cfg.height) + ")");
    if (!(cfg.fps > 0 && cfg.fps <= 1000)) return Unexpected(std::string("MP4 fps out of range"));
    auto m = std::make_unique<Impl>();
    m->cfg = cfg;
    m->path = path;
    // Frame rate as a rational (29.97 and friends included).
    m->fps_den = 1000;
    m->fps_num = static_cast<int>(std::lround(cfg.fps * 1000));
    video::H264EncoderConfig ec;
    ec.width = cfg.width;
    ec.height = cfg.height;
    ec.fps = std::max(1, static_cast<int>(std::lround(cfg.fps)));
    ec.gop = cfg.gop;
    ec.bitrate_bps = cfg.bitrate_bps;
    ec.preset = "veryfast";
    auto enc = video::H264Encoder::create(ec);
    if (!enc) return Unexpected("H.264 encoder: " + to_string(enc.error()));
    m->encoder = std::move(*enc);

    const std::string file = path.string();
    int r = avformat_alloc_output_context2(&m->fmt, nullptr, "mp4", file.c_str());
    if (r < 0 || m->fmt == nullptr) return Unexpected("MP4 muxer: " + av_error(r));
    m->stream = avformat_new_stream(m->fmt, nullptr);
    if (m->stream == nullptr) return Unexpected(std::string("MP4 muxer: cannot add a stream"));
    AVCodecParameters* par = m->stream->codecpar;
    par->codec_type = AVMEDIA_TYPE_VIDEO;
    par->codec_id = AV_CODEC_ID_H264;
    par->width = cfg.width;
    par->height = cfg.height;
    par->format = AV_PIX_FMT_YUV420P;
    m->stream->time_base = AVRational{m->fps_den, m->fps_num};
    m->stream->avg_frame_rate = AVRational{m->fps_num, m->fps_den};
    m->pkt = av_packet_alloc();
    if (m->pkt == nullptr) return Unexpected(std::string("out of memory"));
    r = avio_open(&m->fmt->pb, file.c_str(), AVIO_FLAG_WRITE);
    if (r < 0) return Unexpected("cannot create " + file + ": " + av_error(r));
    return std::unique_ptr<Mp4Writer>(new Mp4Writer(std::move(m)));
}

std::optional<std::string> Mp4Writer::write(const cv::Mat& bgr) {
    Impl& m = *impl_;
    if (m.closed) return std::string("MP4 writer already closed");
    bool idr = false;
    auto n = m.encoder->encode(bgr, m.au, idr);
    if (!n) return "H.264 encoder: " + to_string(n.error());
    if (!m.header_written) {
        // The muxer takes SPS/PPS from the first (IDR) access unit's in-band headers.
        AVCodecParameters* par = m.stream->codecpar;
        par->extradata =
            static_cast<std::uint8_t*>(av_mallocz(m.au.size() + AV_INPUT_BUFFER_PADDING_SIZE));
        if (par->extradata == nullptr) return std::string("out of memory");
        // Extradata = everything before the first slice NAL (SPS, PPS, SEI) in Annex-B form.
        std::size_t end = m.au.size();
        for (std::size_t i = 0; i + 4 < m.au.size(); ++i) {
            const bool sc3 = m.au[i] == 0 && m.au[i + 1] == 0 && m.au[i + 2] == 1;
            if (!sc3) continue;
            const int type = m.au[i + 3] & 0x1f;
            if (type == 1 || type == 5) {
                end = (i > 0 && m.au[i - 1] == 0) ? i - 1 : i;
                break;
            }
        }
        std::copy(m.au.begin(), m.au.begin() + static_cast<long>(end), par->extradata);
        par->extradata_size = static_cast<int>(end);
        const int r = avformat_write_header(m.fmt, nullptr);
        if (r < 0) return "MP4 header: " + av_error(r);
        m.header_written = true;
    }
    av_packet_unref(m.pkt);
    m.pkt->data = m.au.data();
    m.pkt->size = static_cast<int>(m.au.size());
    m.pkt->stream_index = m.stream->index;
    m.pkt->pts = m.pkt->dts =
        av_rescale_q(m.frames, AVRational{m.fps_den, m.fps_num}, m.stream->time_base);
    m.pkt->duration = av_rescale_q(1, AVRational{m.fps_den, m.fps_num}, m.stream->time_base);
    if (idr) m.pkt->flags |= AV_PKT_FLAG_KEY;
    const int r = av_write_frame(m.fmt, m.pkt);
    m.pkt->data = nullptr;
    m.pkt->size = 0;
    if (r < 0) return "MP4 write: " + av_error(r);
    ++m.frames;
    return std::nullopt;
}

std::optional<std::string> Mp4Writer::close() {
    Impl& m = *impl_;
    if (m.closed) return std::nullopt;
    m.closed = true;
    std::optional<std::string> err;
    if (m.header_written) {
        const int r = av_write_trailer(m.fmt);
        if (r < 0) err = "MP4 trailer: " + av_error(r);
    }
    if (m.fmt != nullptr && m.fmt->pb != nullptr) avio_closep(&m.fmt->pb);
    return err;
}

}  // namespace gs
