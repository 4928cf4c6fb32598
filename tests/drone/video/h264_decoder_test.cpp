// H.264 decoding of the real AR.Drone 2 captures: frame counts, IDR gating, gaps, corruption,
// and pixel agreement with an independent decoder (OpenH264, tests/data/pave_reference/).
#include "drone/video/h264_decoder.hpp"
#include "drone/video/h264_encoder.hpp"

#include "drone/protocol/pave.hpp"
#include "support/video_fixtures.hpp"

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace gs {
namespace {

using namespace video;

using test::OwnedFrame;
using test::read_fixture;
using test::run_framer;

struct Decoded {
    std::vector<cv::Mat> images;
    std::vector<std::uint32_t> frame_numbers;  // of the PaVE frames that produced them
    std::vector<DecodeError> errors;
};

AccessUnit access_unit(const OwnedFrame& f) {
    AccessUnit au;
    au.data = f.payload;
    au.frame_number = f.header.frame_number;
    au.display_width = f.header.display_width;
    au.display_height = f.header.display_height;
    au.stream_id = f.header.stream_id;
    return au;
}

void decode_frames(H264Decoder& dec, const std::vector<OwnedFrame>& frames, Decoded& out) {
    cv::Mat img;
    for (const auto& f : frames) {
        auto r = dec.decode(access_unit(f), img);
        if (!r) {
            out.errors.push_back(r.error());
        } else if (*r == DecodeStatus::Frame) {
            out.images.push_back(img.clone());
            out.frame_numbers.push_back(f.header.frame_number);
        }
    }
}

Decoded decode_capture(H264Decoder& dec, const std::string& name) {
    Decoded out;
    decode_frames(dec, run_framer(read_fixture(name), 0).frames, out);
    return out;
}

using test::split_annexb;

TEST(H264Decoder, NodeCaptureMatchesIndependentDecoderFromFirstIdr) {
    H264Decoder dec;
    const Decoded d = decode_capture(dec, "node-ar-drone_pave.bin");
    ASSERT_TRUE(d.errors.empty());
    ASSERT_EQ(d.images.size(), 17u);  // frames 3..19
    EXPECT_EQ(d.frame_numbers.front(), 17565u);
    EXPECT_EQ(d.frame_numbers.back(), 17581u);
    const auto& s = dec.stats();
    EXPECT_EQ(s.access_units, 20u);
    EXPECT_EQ(s.decoded, 17u);
    EXPECT_EQ(s.skipped_waiting_idr, 3u);
    EXPECT_EQ(s.frame_gaps, 1u);  // 17368 -> 17563 inside the wait
    EXPECT_EQ(s.decode_errors, 0u);
    EXPECT_EQ(s.concealed, 0u);
    EXPECT_EQ(s.reinits, 0u);

    std::vector<cv::Mat> refs;
    for (std::size_t i = 0; i < d.images.size(); ++i) {
        char name[64];
        std::snprintf(name, sizeof name, "/pave_reference/%06zu.png", i);
        const cv::Mat i420 = cv::imread(GS_TEST_DATA_DIR + std::string(name), cv::IMREAD_GRAYSCALE);
        ASSERT_EQ(i420.size(), cv::Size(640, 540)) << name;
        cv::cvtColor(i420, refs.emplace_back(), cv::COLOR_YUV2BGR_I420);
    }
    double worst = 1e9;
    double min_margin = 1e9;
    for (std::size_t i = 0; i < d.images.size(); ++i) {
        const cv::Mat& img = d.images[i];
        ASSERT_EQ(img.cols, 640);
        ASSERT_EQ(img.rows, 360);
        ASSERT_EQ(img.type(), CV_8UC3);
        const double psnr = cv::PSNR(img, refs[i]);
        EXPECT_GT(psnr, 40.0) << "frame " << i;
        worst = std::min(worst, psnr);
        // The scene is nearly static (neighbouring frames reach ~44 dB against each other), so
        // also require that frame i matches reference i better than any other reference.
        double wrong = 0;
        for (std::size_t j = 0; j < refs.size(); ++j) {
            if (j != i) wrong = std::max(wrong, cv::PSNR(img, refs[j]));
        }
        EXPECT_GT(psnr, wrong + 1.0) << "frame " << i;
        min_margin = std::min(min_margin, psnr - wrong);
    }
    RecordProperty("min_margin_over_other_frames_db", std::to_string(min_margin));
    RecordProperty("worst_psnr_db", std::to_string(worst));
}

TEST(H264Decoder, Capture68YieldsFiveFrames) {
    H264Decoder dec;
    const Decoded d = decode_capture(dec, "node-ar-drone_pave-68.bin");
    EXPECT_TRUE(d.errors.empty());
    ASSERT_EQ(d.images.size(), 5u);
    for (const auto& img : d.images) EXPECT_EQ(img.size(), cv::Size(640, 360));
    EXPECT_EQ(dec.stats().skipped_waiting_idr, 0u);
}

TEST(H264Decoder, UavDumpDecodesEveryCompleteFrameFromIdr17081) {
    H264Decoder dec;
    const Decoded d = decode_capture(dec, "uav-pilot_ardrone_video_stream_dump.bin");
    EXPECT_TRUE(d.errors.empty());
    ASSERT_EQ(d.images.size(), 24u);
    EXPECT_EQ(d.frame_numbers.front(), 17081u);
    EXPECT_EQ(d.frame_numbers.back(), 17104u);
    for (const auto& img : d.images) EXPECT_EQ(img.size(), cv::Size(640, 360));
    EXPECT_EQ(dec.stats().frame_gaps, 0u);
    EXPECT_EQ(dec.stats().concealed, 0u);
}

TEST(H264Decoder, BadDumpLosesFrame17082AndWaitsForTheNextIdr) {
    H264Decoder dec;
    const Decoded d = decode_capture(dec, "uav-pilot_ardrone_video_stream_dump_bad_pave.bin");
    // 17081 (with 30 stray bytes after it), then the gap 17081 -> 17083 drops P-frames
    // 17083..17095 until the IDR 17096, which decodes on with 17097..17104.
    ASSERT_EQ(d.images.size(), 10u);
    EXPECT_EQ(d.frame_numbers[0], 17081u);
    EXPECT_EQ(d.frame_numbers[1], 17096u);
    EXPECT_EQ(dec.stats().frame_gaps, 1u);
    EXPECT_EQ(dec.stats().skipped_waiting_idr, 13u);
}

TEST(H264Decoder, FrameNumberGapForcesIdrWait) {
    auto frames = run_framer(read_fixture("uav-pilot_ardrone_video_stream_dump.bin"), 0).frames;
    frames.erase(frames.begin() + 4);  // lose frame 17085
    H264Decoder dec;
    Decoded d;
    decode_frames(dec, frames, d);
    EXPECT_EQ(dec.stats().frame_gaps, 1u);
    EXPECT_EQ(dec.stats().skipped_waiting_idr, 10u);  // 17086..17095
    ASSERT_EQ(d.images.size(), 4u + 9u);
    EXPECT_EQ(d.frame_numbers[3], 17084u);
    EXPECT_EQ(d.frame_numbers[4], 17096u);
}

TEST(H264Decoder, ResetWaitsForTheNextIdr) {
    const auto frames =
        run_framer(read_fixture("uav-pilot_ardrone_video_stream_dump.bin"), 0).frames;
    H264Decoder dec;
    cv::Mat img;
    ASSERT_EQ(*dec.decode(access_unit(frames[0]), img), DecodeStatus::Frame);
    dec.reset();
    EXPECT_EQ(*dec.decode(access_unit(frames[1]), img), DecodeStatus::NoFrame);
    EXPECT_EQ(dec.stats().skipped_waiting_idr, 1u);
    EXPECT_EQ(dec.stats().frame_gaps, 0u);  // reset forgot the previous frame number
    EXPECT_EQ(*dec.decode(access_unit(frames[15]), img), DecodeStatus::Frame);  // IDR 17096
}

TEST(H264Decoder, RealAnnexBClipDecodesAll82Frames) {
    const auto clip = test::read_bytes(std::string(GS_FIXTURES_DIR) +
                                       "/real/video/ardrone2_front_office_person.h264");
    ASSERT_EQ(clip.size(), 350831u);
    const auto aus = split_annexb(clip);
    ASSERT_EQ(aus.size(), 82u);
    EXPECT_TRUE(contains_idr(aus[0]));
    H264Decoder dec;
    cv::Mat img;
    int frames = 0;
    for (const auto& au : aus) {
        auto r = dec.decode(AccessUnit{au, std::nullopt, 0, 0, std::nullopt}, img);
        ASSERT_TRUE(r.has_value()) << to_string(r.error());
        if (*r == DecodeStatus::Frame) {
            ++frames;
            EXPECT_EQ(img.size(), cv::Size(640, 360));  // SPS cropping, no PaVE hint
        }
    }
    EXPECT_EQ(frames, 82);
    EXPECT_EQ(dec.stats().decode_errors, 0u);
    EXPECT_EQ(dec.stats().concealed, 0u);
}

// Damage lives on in the P-frames predicted from a concealed picture until an intra picture
// replaces it: that picture is whole again but jumps where the damage was, and the decoder says
// so (`repaired`). The real clip has an intra picture every 15 frames (0, 15, 30, ...: ffprobe);
// a slice of frame 20 is damaged, so frame 20 is concealed and frame 30 repairs it, once.
TEST(H264Decoder, TheIntraPictureAfterConcealedDamageIsCountedAsARepair) {
    const auto clip = test::office_clip_damaged_at(20);
    const auto aus = split_annexb(clip);
    ASSERT_EQ(aus.size(), 82u);
    H264Decoder dec;
    cv::Mat img;
    std::vector<int> concealed, repaired;
    for (std::size_t i = 0; i < aus.size(); ++i) {
        const H264DecoderStats before = dec.stats();
        auto r = dec.decode(AccessUnit{aus[i], std::nullopt, 0, 0, std::nullopt}, img);
        ASSERT_TRUE(r.has_value()) << i << ": " << to_string(r.error());
        ASSERT_EQ(*r, DecodeStatus::Frame) << i;
        if (dec.stats().concealed > before.concealed) concealed.push_back(static_cast<int>(i));
        if (dec.stats().repaired > before.repaired) repaired.push_back(static_cast<int>(i));
    }
    EXPECT_EQ(concealed, std::vector<int>{20});
    EXPECT_EQ(repaired, std::vector<int>{30});
    EXPECT_EQ(dec.stats().repaired, 1u);

    // After a reset (a dataset's random access, a new connection) the next picture starts a new
    // stream: it repairs nothing, though the last one shown before the reset was damaged.
    H264Decoder seek;
    for (std::size_t i = 0; i <= 25; ++i)
        (void)seek.decode(AccessUnit{aus[i], std::nullopt, 0, 0, std::nullopt}, img);
    ASSERT_EQ(seek.stats().concealed, 1u);
    seek.reset();
    for (std::size_t i = 0; i <= 25; ++i)
        (void)seek.decode(AccessUnit{aus[i], std::nullopt, 0, 0, std::nullopt}, img);
    EXPECT_EQ(seek.stats().repaired, 0u);
}

TEST(H264Decoder, CodedSizeChangeReinitialises) {
    H264Decoder dec;
    const Decoded first = decode_capture(dec, "node-ar-drone_pave-68.bin");
    ASSERT_EQ(first.images.size(), 5u);
    ASSERT_EQ(dec.stats().reinits, 0u);
    // A 320x240 Baseline stream (tests/data/h264/README.md) straight after, without PaVE hints.
    const auto small =
        test::read_bytes(GS_TEST_DATA_DIR + std::string("/h264/testsrc_320x240_baseline.h264"));
    const auto aus = split_annexb(small);
    ASSERT_EQ(aus.size(), 6u);
    cv::Mat img;
    int frames = 0;
    for (const auto& au : aus) {
        auto r = dec.decode(AccessUnit{au, std::nullopt, 0, 0, std::nullopt}, img);
        ASSERT_TRUE(r.has_value());
        if (*r == DecodeStatus::Frame) {
            ++frames;
            EXPECT_EQ(img.size(), cv::Size(320, 240));
        }
    }
    EXPECT_EQ(frames, 6);
    EXPECT_EQ(dec.stats().reinits, 1u);
}

// The picture is written within its own w x h x 3 bytes and not a byte after: swscale's SIMD
// converters store whole vector words, past the last pixel of a 24-bit row (the h264 fuzzer found
// the heap header after an exactly-sized picture overwritten with converted grey). The caller's
// buffer is followed by canary bytes; display sizes that are not multiples of 8 or 16 too.
TEST(H264Decoder, ThePictureIsWrittenWithinItsBufferAndNotAByteAfter) {
    const auto small =
        test::read_bytes(GS_TEST_DATA_DIR + std::string("/h264/testsrc_320x240_baseline.h264"));
    const auto aus = split_annexb(small);
    ASSERT_FALSE(aus.empty());
    for (const cv::Size size : {cv::Size(320, 240), cv::Size(317, 237), cv::Size(318, 239),
                                cv::Size(300, 200), cv::Size(301, 7)}) {
        const std::size_t bytes = static_cast<std::size_t>(size.area()) * 3;
        std::vector<std::uint8_t> backing(bytes + 256, 0xA5);
        cv::Mat img(size, CV_8UC3, backing.data());  // create() keeps a buffer of the same size
        H264Decoder dec;
        int frames = 0;
        for (const auto& au : aus) {
            auto r = dec.decode(AccessUnit{au, std::nullopt, size.width, size.height, std::nullopt},
                                img);
            ASSERT_TRUE(r.has_value()) << size;
            if (*r != DecodeStatus::Frame) continue;
            ++frames;
            ASSERT_EQ(img.size(), size);
            ASSERT_EQ(img.data, backing.data()) << size;
            std::size_t spoiled = 0;
            for (std::size_t i = bytes; i < backing.size(); ++i) spoiled += backing[i] != 0xA5;
            ASSERT_EQ(spoiled, 0u) << size << ": bytes written past the picture";
        }
        EXPECT_EQ(frames, static_cast<int>(aus.size())) << size;
    }
}

TEST(H264Decoder, StreamIdOrDisplaySizeChangeReinitialisesAndWaitsForIdr) {
    const auto frames =
        run_framer(read_fixture("uav-pilot_ardrone_video_stream_dump.bin"), 0).frames;
    H264Decoder dec;
    cv::Mat img;
    ASSERT_EQ(*dec.decode(access_unit(frames[0]), img), DecodeStatus::Frame);
    AccessUnit au = access_unit(frames[1]);
    au.stream_id = 2;  // a new encoder run: P-frames of the old one are useless
    EXPECT_EQ(*dec.decode(au, img), DecodeStatus::NoFrame);
    EXPECT_EQ(dec.stats().reinits, 1u);
    EXPECT_EQ(dec.stats().skipped_waiting_idr, 1u);

    au = access_unit(frames[15]);  // IDR 17096
    au.stream_id = 2;
    au.display_width = 320;  // smaller display size: re-initialised, output cropped to it
    au.display_height = 200;
    ASSERT_EQ(*dec.decode(au, img), DecodeStatus::Frame);
    EXPECT_EQ(dec.stats().reinits, 2u);
    EXPECT_EQ(img.size(), cv::Size(320, 200));
}

TEST(H264Decoder, RandomBitFlipsNeverCrashAndAreCounted) {
    const auto frames =
        run_framer(read_fixture("uav-pilot_ardrone_video_stream_dump.bin"), 0).frames;
    std::mt19937 rng(2024);
    H264DecoderStats total;
    for (int iter = 0; iter < 12; ++iter) {
        H264Decoder dec;
        cv::Mat img;
        for (const auto& f : frames) {
            std::vector<std::uint8_t> payload = f.payload;
            const int flips = 1 + static_cast<int>(rng() % 8);
            for (int k = 0; k < flips; ++k) {
                const std::size_t at = rng() % payload.size();
                payload[at] ^= static_cast<std::uint8_t>(1u << (rng() % 8));
            }
            if (rng() % 4 == 0) payload.resize(rng() % payload.size() + 1);  // truncated too
            AccessUnit au = access_unit(f);
            au.data = payload;
            auto r = dec.decode(au, img);
            if (r && *r == DecodeStatus::Frame) {
                ASSERT_FALSE(img.empty());
                ASSERT_EQ(img.type(), CV_8UC3);
            }
        }
        const auto& s = dec.stats();
        EXPECT_EQ(s.access_units, frames.size());
        total.decode_errors += s.decode_errors;
        total.concealed += s.concealed;
        total.decoded += s.decoded;
        total.skipped_waiting_idr += s.skipped_waiting_idr;
    }
    // Damage is reported, not silently passed on as clean frames.
    EXPECT_GT(total.decode_errors + total.concealed, 12u);
    EXPECT_GT(total.decoded, 0u);
}

TEST(H264Decoder, EmptyAccessUnitIsAnError) {
    H264Decoder dec;
    cv::Mat img;
    auto r = dec.decode(AccessUnit{}, img);
    ASSERT_FALSE(r.has_value());
    EXPECT_EQ(r.error(), DecodeError::InvalidInput);
    EXPECT_EQ(dec.stats().decode_errors, 1u);
}

// A picture larger than the decoder's bound (a corrupt or hostile SPS can declare 8192x8192) is
// refused and counted, not allocated; the same decoder then takes a normal stream.
TEST(H264Decoder, PictureAboveTheSizeBoundIsRefusedAndCounted) {
    H264EncoderConfig cfg;
    cfg.width = kMaxPictureWidth + 128;
    cfg.height = kMaxPictureHeight + 64;
    auto enc = H264Encoder::create(cfg);
    ASSERT_TRUE(enc.has_value());
    const cv::Mat big(cfg.height, cfg.width, CV_8UC3, cv::Scalar(40, 90, 160));
    H264Decoder dec;
    cv::Mat img;
    int frames = 0;
    std::vector<std::uint8_t> au;
    for (int i = 0; i < 3; ++i) {
        bool idr = false;
        ASSERT_TRUE((*enc)->encode(big, au, idr).has_value());
        auto r = dec.decode(AccessUnit{au, std::nullopt, 0, 0, std::nullopt}, img);
        if (r && *r == DecodeStatus::Frame) ++frames;
    }
    EXPECT_EQ(frames, 0);
    EXPECT_GE(dec.stats().decode_errors, 1u);
    EXPECT_EQ(dec.stats().decoded, 0u);

    dec.reset();
    const Decoded after = decode_capture(dec, "node-ar-drone_pave-68.bin");
    EXPECT_EQ(after.images.size(), 5u);
}

TEST(H264Annexb, ContainsIdrMatchesPaveFrameType) {
    const auto frames = run_framer(read_fixture("node-ar-drone_pave.bin"), 0).frames;
    for (const auto& f : frames) {
        EXPECT_EQ(contains_idr(f.payload), f.header.frame_type == protocol::PaveFrameType::Idr)
            << f.header.frame_number;
    }
    const std::vector<std::uint8_t> three_byte = {0, 0, 1, 0x65, 0x88};
    EXPECT_TRUE(contains_idr(three_byte));
    const std::vector<std::uint8_t> cut = {0, 0, 0, 1};  // start code, no NAL header
    EXPECT_FALSE(contains_idr(cut));
    EXPECT_FALSE(contains_idr({}));
}

TEST(H264Annexb, AccessUnitSizeSplitsIdrWithItsParameterSets) {
    const auto frames = run_framer(read_fixture("node-ar-drone_pave.bin"), 0).frames;
    // Two PaVE payloads back to back split back into exactly those two access units.
    std::vector<std::uint8_t> both = frames[3].payload;  // SPS + PPS + IDR
    both.insert(both.end(), frames[4].payload.begin(), frames[4].payload.end());
    EXPECT_EQ(access_unit_size(both), frames[3].payload.size());
    EXPECT_EQ(access_unit_size(frames[4].payload), frames[4].payload.size());
    EXPECT_EQ(access_unit_size({}), 0u);
}

}  // namespace
}  // namespace gs
