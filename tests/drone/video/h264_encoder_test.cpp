// The encoder against libavcodec's own decoder: quality, the IDR grid with SPS/PPS in front of each
// IDR, one access unit per frame, and a decoder joining mid-stream.

#include "drone/video/h264_encoder.hpp"
#include "drone/core/camera_calibration.hpp"
#include "drone/sim/renderer.hpp"
#include "drone/sim/scene.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

extern "C" {
#include <libavcodec/avcodec.h>
}

#include <memory>
#include <string>
#include <vector>

namespace gs {
namespace {

using namespace video;

// NAL unit types of an Annex-B buffer, in order.
std::vector<int> nal_types(const std::vector<std::uint8_t>& b) {
    std::vector<int> out;
    for (std::size_t i = 0; i + 3 < b.size(); ++i)
        if (b[i] == 0 && b[i + 1] == 0 && b[i + 2] == 1) {
            out.push_back(b[i + 3] & 0x1f);
            i += 3;
        }
    return out;
}

// Minimal libavcodec H.264 decoder to BGR (the project's H264Decoder lives elsewhere).
struct TestDecoder {
    AVCodecContext* ctx = nullptr;
    AVPacket* pkt = av_packet_alloc();
    AVFrame* frame = av_frame_alloc();
    TestDecoder() {
        const AVCodec* c = avcodec_find_decoder(AV_CODEC_ID_H264);
        ctx = avcodec_alloc_context3(c);
        ctx->thread_count = 1;
        avcodec_open2(ctx, c, nullptr);
    }
    ~TestDecoder() {
        av_frame_free(&frame);
        av_packet_free(&pkt);
        avcodec_free_context(&ctx);
    }
    bool decode(std::vector<std::uint8_t>& au, cv::Mat& bgr) {
        pkt->data = au.data();
        pkt->size = int(au.size());
        if (avcodec_send_packet(ctx, pkt) < 0) return false;
        if (avcodec_receive_frame(ctx, frame) < 0) return false;
        const int w = frame->width, h = frame->height;
        cv::Mat i420(h * 3 / 2, w, CV_8UC1);
        for (int y = 0; y < h; ++y)
            std::memcpy(i420.ptr(y), frame->data[0] + y * frame->linesize[0], std::size_t(w));
        auto* u = i420.ptr(h);
        for (int y = 0; y < h / 2; ++y) {
            std::memcpy(u + y * (w / 2), frame->data[1] + y * frame->linesize[1],
                        std::size_t(w / 2));
            std::memcpy(u + (h / 2) * (w / 2) + y * (w / 2),
                        frame->data[2] + y * frame->linesize[2], std::size_t(w / 2));
        }
        cv::cvtColor(i420, bgr, cv::COLOR_YUV2BGR_I420);
        av_frame_unref(frame);
        return true;
    }
};

TEST(H264Encoder, DecodesWithHighPsnrAndIdrEvery15WithHeaders) {
    auto scene = sim::load_scene(std::string(GS_ASSETS_DIR) + "/scenes/thesis_pillar_center.json");
    ASSERT_TRUE(scene.has_value());
    auto renderer =
        sim::Renderer::create(*scene, builtin_calibration(CameraId::Front), sim::CameraKind::Front);
    ASSERT_TRUE(renderer.has_value());
    auto enc = H264Encoder::create({});
    ASSERT_TRUE(enc.has_value()) << to_string(enc.error());
    TestDecoder full, late;  // `late` joins at frame 20: must decode from the IDR at 30
    cv::Mat img, dec;
    std::vector<std::uint8_t> au;
    double min_psnr = 1e9;
    int late_first = -1;
    for (int i = 0; i < 46; ++i) {
        sim::Pose p = scene->start;
        p.x_m += i / 30.0;
        p.roll_deg = 2.0 * std::sin(i * 0.2);
        renderer->render(p, img);
        bool idr = false;
        auto n = (*enc)->encode(img, au, idr);
        ASSERT_TRUE(n.has_value()) << to_string(n.error());
        ASSERT_EQ(*n, au.size());
        ASSERT_GT(au.size(), 0u);
        const auto types = nal_types(au);
        EXPECT_EQ(idr, i % 15 == 0) << "frame " << i;
        if (i % 15 == 0) {
            ASSERT_GE(types.size(), 3u);
            EXPECT_EQ(types[0], 7) << "SPS first, frame " << i;
            EXPECT_EQ(types[1], 8) << "PPS second, frame " << i;
            EXPECT_EQ(types.back(), 5);
        } else {
            for (int t : types)
                EXPECT_TRUE(t != 5 && t != 7 && t != 8) << "frame " << i << " type " << t;
        }
        ASSERT_TRUE(full.decode(au, dec))
            << "no picture for frame " << i << " (one AU in, one frame out)";
        ASSERT_EQ(dec.size(), img.size());
        min_psnr = std::min(min_psnr, cv::PSNR(img, dec));
        if (i >= 20 && late_first < 0) {
            cv::Mat d2;
            if (late.decode(au, d2) && cv::PSNR(img, d2) > 30) late_first = i;
        }
    }
    EXPECT_GT(min_psnr, 30.0);
    EXPECT_EQ(late_first, 30);
    EXPECT_EQ((*enc)->frames_encoded(), 46);
}

TEST(H264Encoder, RejectsWrongInput) {
    auto enc = H264Encoder::create({});
    ASSERT_TRUE(enc.has_value());
    std::vector<std::uint8_t> au;
    bool idr = false;
    cv::Mat small(100, 100, CV_8UC3, cv::Scalar::all(0));
    EXPECT_EQ((*enc)->encode(small, au, idr).error(), H264EncodeError::BadInput);
    cv::Mat grey(360, 640, CV_8UC1, cv::Scalar::all(0));
    EXPECT_EQ((*enc)->encode(grey, au, idr).error(), H264EncodeError::BadInput);
    H264EncoderConfig odd;
    odd.width = 641;
    EXPECT_FALSE(H264Encoder::create(odd).has_value());
}

}  // namespace
}  // namespace gs
