// PaVE header parsing/writing and the streaming framer, against the four real captures
// (docs/protocol.md §7.5, fixtures/ardrone/SOURCES.md) and HEIDI's pave_test.py behaviours.
#include "drone/protocol/pave.hpp"

#include "support/video_fixtures.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <numeric>
#include <string>

namespace gs {
namespace {

using namespace protocol;

using test::FramerRun;
using test::read_fixture;
using test::run_framer;

std::span<const std::uint8_t> as_span(const std::vector<std::uint8_t>& v) {
    return v;
}

std::vector<std::uint8_t> bytes_of(const std::string& s) {
    return {s.begin(), s.end()};
}

std::vector<std::uint8_t> concat(std::initializer_list<std::vector<std::uint8_t>> parts) {
    std::vector<std::uint8_t> out;
    for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
    return out;
}

// A complete frame (header + payload) built with write_pave_header.
std::vector<std::uint8_t> make_frame(std::uint32_t frame_number, std::uint32_t payload_size,
                                     std::uint16_t header_size = 64) {
    PaveHeader h;
    h.header_size = header_size;
    h.payload_size = payload_size;
    h.encoded_stream_width = 640;
    h.encoded_stream_height = 368;
    h.display_width = 640;
    h.display_height = 360;
    h.frame_number = frame_number;
    h.frame_type = PaveFrameType::P;
    h.advertised_size = payload_size;
    std::vector<std::uint8_t> out(header_size + payload_size);
    EXPECT_TRUE(write_pave_header(h, out).has_value());
    for (std::uint32_t i = 0; i < payload_size; ++i) {
        out[header_size + i] = static_cast<std::uint8_t>(frame_number * 31 + i);
    }
    return out;
}

const std::vector<std::uint8_t>& node_pave() {
    static const auto v = read_fixture("node-ar-drone_pave.bin");
    return v;
}
const std::vector<std::uint8_t>& node_pave68() {
    static const auto v = read_fixture("node-ar-drone_pave-68.bin");
    return v;
}
const std::vector<std::uint8_t>& uav_dump() {
    static const auto v = read_fixture("uav-pilot_ardrone_video_stream_dump.bin");
    return v;
}
const std::vector<std::uint8_t>& uav_bad_dump() {
    static const auto v = read_fixture("uav-pilot_ardrone_video_stream_dump_bad_pave.bin");
    return v;
}

// ---- Header ---------------------------------------------------------------------------------

TEST(PaveHeader, ParsesEveryFieldOfNodeFrameZero) {
    ASSERT_EQ(node_pave().size(), 102747u);
    auto h = parse_pave_header(as_span(node_pave()));
    ASSERT_TRUE(h.has_value()) << to_string(h.error());
    EXPECT_EQ(h->signature, kPaveSignature);
    EXPECT_EQ(h->version, 2);
    EXPECT_EQ(h->video_codec, PaveCodec::H264);
    EXPECT_EQ(h->header_size, 64);
    EXPECT_EQ(h->payload_size, 2632u);
    EXPECT_EQ(h->encoded_stream_width, 640);
    EXPECT_EQ(h->encoded_stream_height, 368);
    EXPECT_EQ(h->display_width, 640);
    EXPECT_EQ(h->display_height, 360);
    EXPECT_EQ(h->frame_number, 17368u);
    EXPECT_EQ(h->timestamp, 1792570814u);
    EXPECT_EQ(h->total_chuncks, 1);
    EXPECT_EQ(h->chunck_index, 0);
    EXPECT_EQ(h->frame_type, PaveFrameType::P);
    EXPECT_EQ(h->control, 0);
    EXPECT_EQ(h->stream_byte_position_lw, 72366960u);
    EXPECT_EQ(h->stream_byte_position_uw, 0u);
    EXPECT_EQ(h->stream_byte_position(), 72366960u);
    EXPECT_EQ(h->stream_id, 5);
    EXPECT_EQ(h->total_slices, 1);
    EXPECT_EQ(h->slice_index, 0);
    EXPECT_EQ(h->header1_size, 0);
    EXPECT_EQ(h->header2_size, 0);
    EXPECT_EQ(h->advertised_size, 2632u);
    EXPECT_FALSE(h->is_key_frame());
    EXPECT_EQ(to_string(h->frame_type), "P");
    EXPECT_EQ(to_string(h->video_codec), "H264");
}

TEST(PaveHeader, Parses68ByteHeaderWithExtension) {
    auto h = parse_pave_header(as_span(node_pave68()));
    ASSERT_TRUE(h.has_value());
    EXPECT_EQ(h->header_size, 68);
    EXPECT_EQ(h->payload_size, 10180u);
    EXPECT_EQ(h->frame_number, 245401u);
    EXPECT_EQ(h->timestamp, 8015353u);
    EXPECT_EQ(h->frame_type, PaveFrameType::Idr);
    EXPECT_EQ(h->stream_byte_position_lw, 1009151980u);
    EXPECT_EQ(h->stream_id, 1);
    EXPECT_EQ(h->header1_size, 14);
    EXPECT_EQ(h->header2_size, 10);
    EXPECT_EQ(h->advertised_size, 10180u);
    // docs/protocol.md §4.1: a u32 2 at byte 52, then non-zero words up to byte 67.
    EXPECT_EQ(h->reserved3[0], 2);
    EXPECT_NE(h->extension, (std::array<std::uint8_t, 4>{}));
    EXPECT_TRUE(h->is_key_frame());
}

TEST(PaveHeader, WriteReproducesCaptureBytesExactly) {
    for (const auto* capture : {&node_pave(), &node_pave68(), &uav_dump()}) {
        auto h = parse_pave_header(as_span(*capture));
        ASSERT_TRUE(h.has_value());
        std::vector<std::uint8_t> out(h->header_size + 10, 0xAA);
        auto n = write_pave_header(*h, out);
        ASSERT_TRUE(n.has_value());
        EXPECT_EQ(*n, h->header_size);
        EXPECT_TRUE(std::equal(out.begin(), out.begin() + h->header_size, capture->begin()));
        EXPECT_EQ(out[h->header_size], 0xAA) << "wrote past header_size";
    }
}

TEST(PaveHeader, WriteParseRoundTripKeepsEveryField) {
    for (std::uint16_t hs : {64, 68, 100}) {
        PaveHeader h;
        h.version = 2;
        h.video_codec = PaveCodec::Mpeg4Visual;
        h.header_size = hs;
        h.payload_size = 0x0001F00D;
        h.encoded_stream_width = 1280;
        h.encoded_stream_height = 720;
        h.display_width = 1279;
        h.display_height = 719;
        h.frame_number = 0xDEADBEEF;
        h.timestamp = 0x01020304;
        h.total_chuncks = 3;
        h.chunck_index = 2;
        h.frame_type = PaveFrameType::I;
        h.control = kPaveCtrlLastFrameInStream;
        h.stream_byte_position_lw = 0xFFFFFFF0;
        h.stream_byte_position_uw = 7;
        h.stream_id = 0x1234;
        h.total_slices = 4;
        h.slice_index = 1;
        h.header1_size = 14;
        h.header2_size = 10;
        h.reserved2 = {9, 8};
        h.advertised_size = 77;
        for (std::size_t i = 0; i < h.reserved3.size(); ++i) h.reserved3[i] = std::uint8_t(i + 1);
        if (hs >= 68) h.extension = {0xA1, 0xB2, 0xC3, 0xD4};
        std::vector<std::uint8_t> buf(hs);
        ASSERT_TRUE(write_pave_header(h, buf).has_value());
        auto back = parse_pave_header(as_span(buf));
        ASSERT_TRUE(back.has_value());
        EXPECT_EQ(*back, h) << "header_size " << hs;
        EXPECT_EQ(back->stream_byte_position(), (7ull << 32) | 0xFFFFFFF0u);
    }
}

TEST(PaveHeader, RejectsBadFieldsWithTypedErrors) {
    std::vector<std::uint8_t> good(node_pave().begin(), node_pave().begin() + 64);
    auto with = [&](std::size_t off, std::uint8_t v) {
        auto b = good;
        b[off] = v;
        return parse_pave_header(as_span(b));
    };
    EXPECT_EQ(with(0, 'X').error(), PaveError::BadSignature);
    EXPECT_EQ(with(4, 0).error(), PaveError::BadVersion);
    EXPECT_EQ(with(4, 3).error(), PaveError::BadVersion);
    EXPECT_EQ(with(5, 0).error(), PaveError::BadCodec);
    EXPECT_EQ(with(5, 5).error(), PaveError::BadCodec);
    EXPECT_EQ(with(6, 63).error(), PaveError::BadHeaderSize);
    EXPECT_EQ(with(6, 129).error(), PaveError::BadHeaderSize);
    EXPECT_EQ(with(7, 1).error(), PaveError::BadHeaderSize);     // 64 + 256
    EXPECT_EQ(with(11, 1).error(), PaveError::PayloadTooLarge);  // 2632 + 16 MiB
    // payload 2632: a cap one below rejects it, the exact value passes.
    EXPECT_EQ(parse_pave_header(as_span(good), 2631).error(),
              PaveError::PayloadTooLarge);
    EXPECT_TRUE(parse_pave_header(as_span(good), 2632).has_value());
    // header_size 68 needs 68 bytes even though 64 are a whole SDK struct.
    auto h68 = std::vector<std::uint8_t>(node_pave68().begin(), node_pave68().begin() + 67);
    EXPECT_EQ(parse_pave_header(as_span(h68)).error(), PaveError::TooShort);

    PaveHeader h;
    std::vector<std::uint8_t> small(63);
    EXPECT_EQ(write_pave_header(h, small).error(), PaveError::BufferTooSmall);
    h.header_size = 20;
    std::vector<std::uint8_t> big(200);
    EXPECT_EQ(write_pave_header(h, big).error(), PaveError::BadHeaderSize);
}

TEST(PaveHeader, EveryTruncationIsTooShortNeverARead) {
    for (std::size_t n = 0; n < 68; ++n) {
        // A fresh heap copy of exactly n bytes: ASan flags any read past it.
        std::vector<std::uint8_t> b(node_pave68().begin(), node_pave68().begin() + n);
        auto h = parse_pave_header(as_span(b));
        ASSERT_FALSE(h.has_value());
        EXPECT_EQ(h.error(), PaveError::TooShort) << n;
    }
}

// ---- Framer on the real captures --------------------------------------------------------------

TEST(PaveFramer, NodeCaptureGivesTwentyFramesAndNothingLeft) {
    const FramerRun run = run_framer(node_pave(), 0);
    ASSERT_EQ(run.frames.size(), 20u);
    EXPECT_TRUE(run.resyncs.empty());
    EXPECT_EQ(run.pending.buffered_bytes, 0u);
    EXPECT_FALSE(run.pending.header.has_value());
    EXPECT_EQ(run.stats.bytes_skipped, 0u);
    std::uint64_t total = 0;
    for (std::size_t i = 0; i < run.frames.size(); ++i) {
        const auto& f = run.frames[i];
        EXPECT_EQ(f.index, i);
        EXPECT_EQ(f.stream_offset, total);
        EXPECT_EQ(f.header.header_size, 64);
        EXPECT_EQ(f.header.stream_id, 5);
        EXPECT_EQ(f.payload.size(), f.header.payload_size);
        total += 64 + f.header.payload_size;
        // Frame 0 is 17368, then the capture jumps to 17563 and counts up by one.
        EXPECT_EQ(f.header.frame_number, i == 0 ? 17368u : 17562u + i);
        const bool idr = i == 3 || i == 18;
        EXPECT_EQ(f.header.frame_type,
                  idr ? PaveFrameType::Idr : PaveFrameType::P)
            << i;
        EXPECT_EQ(f.header.header1_size, idr ? 14 : 0);
        EXPECT_EQ(f.header.header2_size, idr ? 10 : 0);
        if (i >= 2) {
            // stream_byte_position advances by the previous payload (docs/protocol.md §4.1), minus the
            // SPS/PPS the firmware prepends to an IDR (seen in this capture: 14 + 10 bytes).
            const auto& prev = run.frames[i - 1].header;
            EXPECT_EQ(f.header.stream_byte_position(), prev.stream_byte_position() +
                                                           prev.payload_size - prev.header1_size -
                                                           prev.header2_size)
                << i;
        }
    }
    EXPECT_EQ(total, node_pave().size());
    EXPECT_EQ(run.frames[3].header.frame_number, 17565u);
    EXPECT_EQ(run.frames[3].header.payload_size, 18800u);
    EXPECT_EQ(run.frames[18].header.frame_number, 17580u);
    EXPECT_EQ(run.frames[18].header.payload_size, 19107u);
    // IDR payload = SPS (14) + PPS (10) + IDR slice, Annex-B start codes included.
    const std::vector<std::uint8_t> sps = {0,    0,    0,    1,    0x67, 0x42, 0x80,
                                           0x1E, 0x8B, 0x68, 0x0A, 0x02, 0xF7, 0x95};
    EXPECT_TRUE(std::equal(sps.begin(), sps.end(), run.frames[3].payload.begin()));
    EXPECT_EQ(run.stats.frames, 20u);
    EXPECT_EQ(run.stats.payload_bytes, node_pave().size() - 20 * 64);
}

TEST(PaveFramer, Node68CaptureGivesFiveFramesWith68ByteHeaders) {
    const FramerRun run = run_framer(node_pave68(), 0);
    ASSERT_EQ(run.frames.size(), 5u);
    EXPECT_TRUE(run.resyncs.empty());
    EXPECT_EQ(run.pending.buffered_bytes, 0u);
    for (std::size_t i = 0; i < 5; ++i) {
        EXPECT_EQ(run.frames[i].header.header_size, 68);
        EXPECT_EQ(run.frames[i].header.frame_number, 245401u + i);
    }
    EXPECT_EQ(run.frames[0].header.payload_size, 10180u);
    EXPECT_EQ(run.frames[0].stream_offset, 0u);
    EXPECT_EQ(run.frames[1].stream_offset, 68u + 10180u);
    // The payload starts right after the 68-byte header with the SPS start code.
    EXPECT_EQ(run.frames[0].payload[4], 0x67);
}

TEST(PaveFramer, UavDumpHoldsTheTruncatedLastFrame) {
    const FramerRun run = run_framer(uav_dump(), 0);
    ASSERT_EQ(run.frames.size(), 24u);
    EXPECT_TRUE(run.resyncs.empty());
    std::uint64_t payload_total = 0;
    for (std::size_t i = 0; i < run.frames.size(); ++i) {
        const auto& h = run.frames[i].header;
        EXPECT_EQ(h.frame_number, 17081u + i);
        EXPECT_EQ(h.header_size, 68);
        EXPECT_EQ(h.stream_id, 1);
        EXPECT_EQ(h.frame_type,
                  (i == 0 || i == 15) ? PaveFrameType::Idr : PaveFrameType::P);
        payload_total += h.payload_size;
        if (i > 0) {
            const auto& prev = run.frames[i - 1].header;
            EXPECT_EQ(h.stream_byte_position(), prev.stream_byte_position() + prev.payload_size -
                                                    prev.header1_size - prev.header2_size)
                << i;
        }
    }
    EXPECT_EQ(payload_total, 100495u);
    EXPECT_EQ(run.stats.payload_bytes, 100495u);
    ASSERT_TRUE(run.pending.header.has_value());
    EXPECT_EQ(run.pending.header->frame_number, 17105u);
    EXPECT_EQ(run.pending.header->payload_size, 2864u);
    EXPECT_EQ(run.pending.buffered_bytes, 68u + 205u);
    EXPECT_EQ(run.pending.header_offset, uav_dump().size() - 273);
    EXPECT_EQ(run.stats.bytes_skipped, 0u);
}

TEST(PaveFramer, BadDumpResyncsAt14991AndKeepsEveryLaterFrame) {
    ASSERT_EQ(uav_bad_dump().size(), uav_dump().size());
    const FramerRun run = run_framer(uav_bad_dump(), 0);
    ASSERT_EQ(run.frames.size(), 23u);
    // Frame 0 claims 12287 bytes (true 12257): trusting it swallows frame 17082's header.
    EXPECT_EQ(run.frames[0].header.payload_size, 12287u);
    EXPECT_EQ(run.frames[0].header.frame_number, 17081u);
    ASSERT_EQ(run.resyncs.size(), 1u);
    EXPECT_EQ(run.resyncs[0].stream_offset, 12355u);
    EXPECT_EQ(run.resyncs[0].stream_offset + run.resyncs[0].bytes_skipped, 14991u);
    EXPECT_EQ(run.resyncs[0].reason, PaveError::BadSignature);
    EXPECT_EQ((run.order), (std::vector<int>{0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
                                             0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0}));
    EXPECT_EQ(run.frames[1].stream_offset, 14991u);
    for (std::size_t i = 1; i < run.frames.size(); ++i) {
        EXPECT_EQ(run.frames[i].header.frame_number, 17082u + i);
    }
    // Every frame after the resync is byte-identical to the clean dump's.
    const FramerRun clean = run_framer(uav_dump(), 0);
    for (std::size_t i = 1; i < run.frames.size(); ++i) {
        EXPECT_EQ(run.frames[i].payload, clean.frames[i + 1].payload);
        EXPECT_EQ(run.frames[i].stream_offset, clean.frames[i + 1].stream_offset);
    }
    ASSERT_TRUE(run.pending.header.has_value());
    EXPECT_EQ(run.pending.header->frame_number, 17105u);
    EXPECT_EQ(run.stats.resyncs, 1u);
    EXPECT_EQ(run.stats.bytes_skipped, 14991u - 12355u);
    EXPECT_EQ(run.stats.oversize_rejections, 0u);
}

TEST(PaveFramer, EveryChunkingGivesIdenticalResults) {
    for (const auto* capture : {&node_pave(), &node_pave68(), &uav_dump(), &uav_bad_dump()}) {
        const FramerRun whole = run_framer(*capture, 0);
        for (int chunk : {1, 7, 64, 4096, -13, -3000}) {
            const FramerRun run = run_framer(*capture, chunk);
            EXPECT_EQ(run.frames, whole.frames) << "chunk " << chunk;
            EXPECT_EQ(run.resyncs, whole.resyncs) << "chunk " << chunk;
            EXPECT_EQ(run.order, whole.order) << "chunk " << chunk;
            EXPECT_EQ(run.stats.frames, whole.stats.frames);
            EXPECT_EQ(run.stats.payload_bytes, whole.stats.payload_bytes);
            EXPECT_EQ(run.stats.bytes_skipped, whole.stats.bytes_skipped);
            EXPECT_EQ(run.stats.resyncs, whole.stats.resyncs);
            EXPECT_EQ(run.stats.bytes_in, capture->size());
            EXPECT_EQ(run.pending.buffered_bytes, whole.pending.buffered_bytes);
            EXPECT_EQ(run.pending.header, whole.pending.header);
        }
    }
}

// ---- HEIDI pave_test.py behaviours (docs/protocol.md §7.5) ------------------------------------------

TEST(PaveFramer, EmptyInputGivesNothing) {
    PaveFramer framer;
    framer.push({});
    EXPECT_FALSE(framer.next().has_value());
    EXPECT_EQ(framer.pending().buffered_bytes, 0u);
}

TEST(PaveFramer, OneFullPacketIsReturnedThenNothing) {
    const auto pkt = make_frame(1, 100);
    PaveFramer framer;
    framer.push(pkt);
    auto ev = framer.next();
    ASSERT_TRUE(ev.has_value());
    const auto* f = std::get_if<PaveFrame>(&*ev);
    ASSERT_NE(f, nullptr);
    EXPECT_EQ(f->header.frame_number, 1u);
    EXPECT_TRUE(std::equal(f->payload.begin(), f->payload.end(), pkt.begin() + 64));
    EXPECT_FALSE(framer.next().has_value());
}

TEST(PaveFramer, PacketSplitAfterFiveBytesWaitsThenReturns) {
    const auto pkt = make_frame(2, 50);
    PaveFramer framer;
    framer.push(std::span(pkt).first(5));
    EXPECT_FALSE(framer.next().has_value());
    EXPECT_EQ(framer.pending().buffered_bytes, 5u);
    framer.push(std::span(pkt).subspan(5));
    auto ev = framer.next();
    ASSERT_TRUE(ev.has_value());
    EXPECT_EQ(std::get<PaveFrame>(*ev).header.frame_number, 2u);
    EXPECT_FALSE(framer.next().has_value());
}

TEST(PaveFramer, GarbageBeforeIsSkippedAndReported) {
    const FramerRun run = run_framer(concat({bytes_of("blabla"), make_frame(3, 20)}), 0);
    ASSERT_EQ(run.frames.size(), 1u);
    EXPECT_EQ(run.frames[0].stream_offset, 6u);
    ASSERT_EQ(run.resyncs.size(), 1u);
    EXPECT_EQ(run.resyncs[0].stream_offset, 0u);
    EXPECT_EQ(run.resyncs[0].bytes_skipped, 6u);
    EXPECT_EQ(run.order, (std::vector<int>{1, 0}));
}

TEST(PaveFramer, TwoPacketsBackToBackGiveBoth) {
    const FramerRun run = run_framer(concat({make_frame(4, 10), make_frame(5, 0, 68)}), 0);
    ASSERT_EQ(run.frames.size(), 2u);
    EXPECT_EQ(run.frames[0].header.frame_number, 4u);
    EXPECT_EQ(run.frames[1].header.frame_number, 5u);
    EXPECT_TRUE(run.frames[1].payload.empty());
    EXPECT_TRUE(run.resyncs.empty());
}

TEST(PaveFramer, BadBytesBetweenPacketsGiveBoth) {
    const auto data = concat({make_frame(6, 30), bytes_of("bad bytes"), make_frame(7, 30)});
    for (int chunk : {0, 1, 5}) {
        const FramerRun run = run_framer(data, chunk);
        ASSERT_EQ(run.frames.size(), 2u);
        EXPECT_EQ(run.frames[1].header.frame_number, 7u);
        ASSERT_EQ(run.resyncs.size(), 1u);
        EXPECT_EQ(run.resyncs[0].stream_offset, 94u);
        EXPECT_EQ(run.resyncs[0].bytes_skipped, 9u);
    }
}

TEST(PaveFramer, FalseSignatureInGarbageIsSkippedWithItsReason) {
    // "PaVE" followed by version 9 is not a header: skipped, the real one after it is found.
    auto junk = bytes_of("xxPaVE");
    junk.push_back(9);
    const auto data = concat({junk, make_frame(8, 12)});
    const FramerRun run = run_framer(data, 1);
    ASSERT_EQ(run.frames.size(), 1u);
    ASSERT_EQ(run.resyncs.size(), 1u);
    EXPECT_EQ(run.resyncs[0].bytes_skipped, junk.size());
    EXPECT_EQ(run.resyncs[0].reason,
              PaveError::BadSignature);  // the first skipped byte was 'x'
    const FramerRun direct = run_framer(concat({bytes_of("PaVE"), {9}, make_frame(8, 12)}), 0);
    ASSERT_EQ(direct.resyncs.size(), 1u);
    EXPECT_EQ(direct.resyncs[0].reason, PaveError::BadVersion);
}

TEST(PaveFramer, PartialSignatureAtTheEndIsKept) {
    const auto pkt = make_frame(9, 8);
    PaveFramer framer;
    const auto garbage = bytes_of("zzzzPaV");
    framer.push(garbage);
    EXPECT_FALSE(framer.next().has_value());
    EXPECT_EQ(framer.pending().buffered_bytes, 3u);  // "PaV" may start a header
    EXPECT_EQ(framer.stats().bytes_skipped, 4u);
    framer.push(pkt);  // "PaV" + "PaVE..." -> the first "PaV" is garbage after all
    FramerRun run;
    test::drain(framer, run);
    ASSERT_EQ(run.frames.size(), 1u);
    ASSERT_EQ(run.resyncs.size(), 1u);
    EXPECT_EQ(run.resyncs[0].stream_offset, 0u);
    EXPECT_EQ(run.resyncs[0].bytes_skipped, 7u);
    EXPECT_EQ(run.frames[0].stream_offset, 7u);
}

TEST(PaveFramer, OversizePayloadIsRefusedWithoutAllocation) {
    // A header announcing 4 GiB - 1, then a normal frame.
    auto huge = make_frame(10, 0);
    huge[8] = huge[9] = huge[10] = huge[11] = 0xFF;
    const auto data = concat({huge, make_frame(11, 40)});
    PaveFramer framer;
    FramerRun run;
    for (std::size_t i = 0; i < data.size(); ++i) {  // byte by byte: nothing may be preallocated
        framer.push(std::span(data).subspan(i, 1));
        test::drain(framer, run);
    }
    EXPECT_LT(framer.buffer_capacity(), 1024u);
    EXPECT_EQ(framer.stats().oversize_rejections, 1u);
    ASSERT_EQ(run.frames.size(), 1u);
    EXPECT_EQ(run.frames[0].header.frame_number, 11u);
    ASSERT_EQ(run.resyncs.size(), 1u);
    EXPECT_EQ(run.resyncs[0].reason, PaveError::PayloadTooLarge);
    EXPECT_EQ(run.resyncs[0].bytes_skipped, huge.size());
}

TEST(PaveFramer, PayloadCapIsAParameter) {
    const auto data = concat({make_frame(12, 1001), make_frame(13, 1000)});
    const FramerRun run = run_framer(data, 0, PaveFramerConfig{1000});
    ASSERT_EQ(run.frames.size(), 1u);
    EXPECT_EQ(run.frames[0].header.frame_number, 13u);
    EXPECT_EQ(run.stats.oversize_rejections, 1u);
    EXPECT_EQ(run.stats.resyncs, 1u);
    EXPECT_EQ(run.resyncs[0].bytes_skipped, 64u + 1001u);
}

TEST(PaveFramer, RandomGarbageNeverCrashesAndEveryByteIsAccounted) {
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> byte(0, 255);
    for (int iter = 0; iter < 200; ++iter) {
        std::vector<std::uint8_t> data;
        for (int part = 0; part < 6; ++part) {
            const auto f = make_frame(static_cast<std::uint32_t>(part), 200, part % 2 ? 68 : 64);
            data.insert(data.end(), f.begin(), f.end());
        }
        for (int k = 0; k < 5; ++k) {  // corrupt random bytes, headers included
            data[static_cast<std::size_t>(rng() % data.size())] =
                static_cast<std::uint8_t>(byte(rng));
        }
        const FramerRun a = run_framer(data, -50, PaveFramerConfig{4096});
        const FramerRun b = run_framer(data, 0, PaveFramerConfig{4096});
        EXPECT_EQ(a.frames, b.frames);
        EXPECT_EQ(a.resyncs, b.resyncs);
        std::uint64_t framed = 0;
        for (const auto& f : a.frames) framed += f.header.header_size + f.payload.size();
        EXPECT_EQ(framed + a.stats.bytes_skipped + a.pending.buffered_bytes, data.size());
    }
}

TEST(PaveFramer, ResetDropsBufferedBytesKeepsCounters) {
    const auto pkt = make_frame(14, 100);
    PaveFramer framer;
    framer.push(std::span(pkt).first(80));
    EXPECT_FALSE(framer.next().has_value());
    framer.reset();
    EXPECT_EQ(framer.pending().buffered_bytes, 0u);
    framer.push(pkt);
    auto ev = framer.next();
    ASSERT_TRUE(ev.has_value());
    const auto& f = std::get<PaveFrame>(*ev);
    EXPECT_EQ(f.stream_offset, 80u);  // offsets count every byte pushed
    EXPECT_EQ(framer.stats().bytes_in, 80u + pkt.size());
}

}  // namespace
}  // namespace gs
