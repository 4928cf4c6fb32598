// Issue 15 item 3: the one video receiver (bytes + time in, access units and frames out, with
// connection boundaries and IDR flags) and its frame pool with explicit acquire / release.
#include "drone/video/receiver.hpp"
#include "drone/video/frame_pool.hpp"
#include "drone/video/h264_decoder.hpp"
#include "support/video_fixtures.hpp"

#include <gtest/gtest.h>

#include <random>
#include <set>

namespace gs::video_receiver_test {  // named: the drone tests are one unity build
namespace {
using test::fixture_path;
using test::read_bytes;
using namespace gs::protocol;
using namespace gs::video;

struct Unit {
    std::int64_t unit;
    std::uint32_t connection, frame_number;
    video::UnitFate fate;
    bool idr;
    std::vector<std::uint8_t> bytes;
    double image_sum;
};

std::vector<Unit> receive(const std::vector<std::uint8_t>& bytes, std::size_t chunk,
                          video::VideoReceiver& rx, bool random = false) {
    std::vector<Unit> out;
    std::mt19937 rng(7);
    for (std::size_t pos = 0; pos < bytes.size();) {
        std::size_t n = std::min(chunk, bytes.size() - pos);
        if (random) n = std::min<std::size_t>(bytes.size() - pos, 1 + rng() % chunk);
        rx.push(std::span(bytes).subspan(pos, n), static_cast<TimeNs>(pos) * 1000);
        pos += n;
        while (auto u = rx.next())
            out.push_back({u->unit, u->connection, u->frame_number, u->fate, u->idr,
                           std::vector<std::uint8_t>(u->bytes.begin(), u->bytes.end()),
                           u->image.empty() ? -1.0 : cv::sum(u->image)[0]});
    }
    return out;
}

TEST(VideoReceiver, AnyChunkingGivesTheSameUnitsAndPicturesAsTheFramerAndDecoder) {
    const auto bytes = read_bytes(fixture_path("node-ar-drone_pave.bin"));
    ASSERT_FALSE(bytes.empty());
    // The independent path: the framer and the decoder by hand.
    const test::FramerRun framed = test::run_framer(bytes, 0);
    H264Decoder decoder;
    cv::Mat img;
    int pictures = 0;
    for (const auto& f : framed.frames) {
        AccessUnit au{f.payload, f.header.frame_number, f.header.display_width,
                      f.header.display_height, f.header.stream_id};
        auto r = decoder.decode(au, img);
        pictures += r && *r == DecodeStatus::Frame;
    }
    ASSERT_GT(pictures, 10);
    std::vector<Unit> reference;
    for (std::size_t chunk : {std::size_t{1460}, std::size_t{1}, std::size_t{100000}}) {
        video::VideoReceiver rx;
        const auto units = receive(bytes, chunk, rx, chunk == 1460);
        ASSERT_EQ(units.size(), framed.frames.size()) << chunk;
        int got = 0;
        for (std::size_t i = 0; i < units.size(); ++i) {
            EXPECT_EQ(units[i].bytes, framed.frames[i].payload);
            EXPECT_EQ(units[i].idr, contains_idr(framed.frames[i].payload));
            got += video::has_picture(units[i].fate);
        }
        EXPECT_EQ(got, pictures) << chunk;
        EXPECT_EQ(rx.stats().pictures, static_cast<std::uint64_t>(pictures));
        if (reference.empty()) {
            reference = units;
        } else {
            for (std::size_t i = 0; i < units.size(); ++i) {
                EXPECT_EQ(units[i].fate, reference[i].fate) << i;
                EXPECT_EQ(units[i].image_sum, reference[i].image_sum) << i;
            }
        }
    }
}

TEST(VideoReceiver, AConnectionEndingInsideAFrameNeverJoinsTheNextConnectionsBytes) {
    // Issue 14 point 1: the cut frame's declared size used to swallow the start of the next
    // connection, its IDR included.
    const auto bytes = read_bytes(fixture_path("node-ar-drone_pave.bin"));
    const test::FramerRun framed = test::run_framer(bytes, 0);
    // The second IDR frame: cut the first connection in its middle.
    std::size_t idr = 0;
    for (std::size_t i = 1; i < framed.frames.size() && idr == 0; ++i)
        if (framed.frames[i].header.frame_type == PaveFrameType::Idr) idr = i;
    ASSERT_GT(idr, 0u);
    const auto& cut = framed.frames[idr];
    const std::size_t cut_at = cut.stream_offset + cut.header.header_size + cut.payload.size() / 2;
    // The second connection starts 3 frames later (P-frames: their reference is lost), so the
    // decoder must wait for the next IDR.
    const std::size_t resume = framed.frames[idr + 3].stream_offset;
    video::VideoReceiver rx;
    std::vector<std::uint8_t> first(bytes.begin(), bytes.begin() + static_cast<long>(cut_at));
    std::vector<std::uint8_t> second(bytes.begin() + static_cast<long>(resume), bytes.end());
    auto units = receive(first, 1460, rx);
    rx.begin_connection(1'000'000);
    auto more = receive(second, 1460, rx);
    EXPECT_EQ(rx.stats().connections, 2u);
    EXPECT_EQ(rx.stats().cut_by_reset, 1u);
    ASSERT_EQ(units.size(), idr);  // everything before the cut frame, nothing of it
    for (const auto& u : more) {
        EXPECT_EQ(u.connection, 1u);
        // Every unit is one whole frame of the original stream.
        bool found = false;
        for (const auto& f : framed.frames) found = found || f.payload == u.bytes;
        EXPECT_TRUE(found) << "unit " << u.unit << " joins bytes of two frames";
    }
    ASSERT_FALSE(more.empty());
    EXPECT_EQ(more.front().fate, video::UnitFate::WaitingIdr);  // its reference was cut off
    bool resumed = false;
    for (const auto& u : more) {
        if (u.idr) resumed = true;
        if (!resumed) {
            EXPECT_EQ(u.fate, video::UnitFate::WaitingIdr);
        } else {
            EXPECT_TRUE(video::has_picture(u.fate)) << u.unit;
        }
    }
    EXPECT_TRUE(resumed);
}

TEST(VideoReceiver, OtherCodecsAreUnitsWithoutAPictureAndAReason) {
    std::vector<std::uint8_t> stream;
    for (std::uint32_t n = 1; n <= 3; ++n) {
        PaveHeader h;
        h.video_codec = PaveCodec::Mpeg4Visual;
        h.payload_size = 50;
        h.frame_number = n;
        h.timestamp = 33 * n;
        const std::size_t at = stream.size();
        stream.resize(at + h.header_size + h.payload_size, 0x55);
        ASSERT_TRUE(write_pave_header(h, std::span<std::uint8_t>(stream).subspan(at)));
    }
    video::VideoReceiver rx;
    const auto units = receive(stream, 4096, rx);
    ASSERT_EQ(units.size(), 3u);
    for (const auto& u : units) EXPECT_EQ(u.fate, video::UnitFate::NotH264);
    EXPECT_EQ(rx.stats().not_h264, 3u);
    EXPECT_NE(rx.stats().last_error.find("frame 3"), std::string::npos) << rx.stats().last_error;
}

// The live path's view of damaged video: the real clip (an intra picture every 15 frames) in PaVE
// frames as the drone sends it, with 24 bytes of frame 20 flipped. Frame 20 comes out concealed,
// frame 30 (the next intra picture, which puts the concealed parts back) as the one repair.
TEST(VideoReceiver, TheIntraPictureAfterConcealedDamageIsMarkedRepaired) {
    const auto clip = test::office_clip_damaged_at(20);
    const auto aus = test::split_annexb(clip);
    ASSERT_EQ(aus.size(), 82u);
    std::vector<std::uint8_t> stream;
    for (std::size_t i = 0; i < aus.size(); ++i) {
        PaveHeader h;
        h.payload_size = static_cast<std::uint32_t>(aus[i].size());
        h.encoded_stream_width = 640;
        h.encoded_stream_height = 368;
        h.display_width = 640;
        h.display_height = 360;
        h.frame_number = static_cast<std::uint32_t>(i + 1);
        h.timestamp = static_cast<std::uint32_t>(i * 33);
        h.frame_type =
            i % 15 == 0 ? (i == 0 ? PaveFrameType::Idr : PaveFrameType::I) : PaveFrameType::P;
        const std::size_t off = stream.size();
        stream.resize(off + h.header_size + h.payload_size);
        ASSERT_TRUE(write_pave_header(h, std::span<std::uint8_t>(stream).subspan(off)));
        std::copy(aus[i].begin(), aus[i].end(),
                  stream.begin() + static_cast<std::ptrdiff_t>(off + h.header_size));
    }
    video::VideoReceiver rx;
    std::vector<std::int64_t> concealed, repaired;
    rx.push(stream, 0);
    int units = 0;
    while (auto u = rx.next()) {
        ++units;
        ASSERT_TRUE(video::has_picture(u->fate)) << u->unit << ": " << video::to_string(u->fate);
        if (u->fate == video::UnitFate::Concealed) concealed.push_back(u->unit);
        if (u->repaired) repaired.push_back(u->unit);
    }
    EXPECT_EQ(units, 82);
    EXPECT_EQ(concealed, std::vector<std::int64_t>{20});
    EXPECT_EQ(repaired, std::vector<std::int64_t>{30});
    EXPECT_EQ(rx.stats().concealed, 1u);
    EXPECT_EQ(rx.stats().repaired, 1u);
}

TEST(FramePool, BuffersAreReusedOnlyOnceTheirLastHolderLetsGo) {
    auto pool = video::FramePool::create(2);
    cv::Mat a = pool->acquire();
    a.create(36, 64, CV_8UC3);
    const uchar* pa = a.data;
    EXPECT_EQ(pool->in_use(), 1u);
    cv::Mat held = a;  // a consumer keeps a header: the buffer stays taken
    a.release();
    EXPECT_EQ(pool->in_use(), 1u);
    cv::Mat b = pool->acquire();
    b.create(36, 64, CV_8UC3);
    EXPECT_NE(b.data, pa);
    EXPECT_EQ(pool->in_use(), 2u);
    // Every buffer out: the next frame gets heap memory, counted.
    cv::Mat c = pool->acquire();
    c.create(36, 64, CV_8UC3);
    EXPECT_EQ(pool->exhausted(), 1u);
    EXPECT_NE(c.data, pa);
    EXPECT_NE(c.data, b.data);
    held.release();  // the last holder lets go: that buffer is free again
    EXPECT_EQ(pool->in_use(), 1u);
    cv::Mat d = pool->acquire();
    d.create(36, 64, CV_8UC3);
    EXPECT_EQ(d.data, pa);  // reused, no allocation
    // The pool outlives its owner while frames are out (ASan checks the memory).
    pool.reset();
    d.setTo(cv::Scalar(1, 2, 3));
    EXPECT_EQ(d.at<cv::Vec3b>(5, 5)[2], 3);
}

TEST(FramePool, TheReceiverKeepsAFrameAConsumerStillHolds) {
    const auto bytes = read_bytes(fixture_path("node-ar-drone_pave.bin"));
    video::ReceiverOptions o;
    o.pool_slots = 2;
    video::VideoReceiver rx(o);
    rx.push(bytes, 0);
    cv::Mat kept, copy;
    int later = 0;
    while (auto u = rx.next()) {
        if (!video::has_picture(u->fate)) continue;
        if (kept.empty()) {
            kept = u->image;  // held: never overwritten by later frames
            copy = kept.clone();
            continue;
        }
        ++later;
    }
    ASSERT_GT(later, 5);
    EXPECT_EQ(cv::norm(kept, copy, cv::NORM_INF), 0.0);
    EXPECT_EQ(rx.frames_in_use(), 1u);
}

}  // namespace
}  // namespace gs::video_receiver_test
