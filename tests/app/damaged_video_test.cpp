// Issue 14 point 8: damaged video plays. A real AR.Drone 2 clip is damaged at test time (bytes
// flipped inside P and IDR slices, as a poor Wi-Fi link leaves them) and replayed: every frame
// ffmpeg's decoding gives a picture for is a picture here too (libavcodec conceals as ffmpeg
// does by default), concealed frames are counted and kept, and so are the intra frames that
// repaired them; replay exits 0, --strict refuses.
// The reference count comes from libavcodec's own H.264 parser and decoder with default options,
// the pipeline the ffmpeg command runs, independent of the project's splitter and decoder.
#include "cli_test_util.hpp"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavutil/log.h>
}

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

namespace gs::test::damaged_video {  // named: the app tests are one unity build
namespace {
namespace fs = std::filesystem;

const fs::path kClip =
    fs::path(GS_FIXTURES_DIR) / "real" / "video" / "ardrone2_front_office_person.h264";

std::vector<std::uint8_t> read_all(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

struct Reference {
    int frames = 0, corrupt = 0;
    int repaired = 0;  // intra pictures after a corrupt one (since the last intra picture)
};

// As `ffmpeg -i clip.h264 -f null -` decodes: the h264 parser cuts the stream, the decoder runs
// with libavcodec's defaults.
Reference ffmpeg_count(const std::vector<std::uint8_t>& data) {
    av_log_set_level(AV_LOG_QUIET);
    Reference r;
    const AVCodec* codec = avcodec_find_decoder(AV_CODEC_ID_H264);
    AVCodecParserContext* parser = av_parser_init(AV_CODEC_ID_H264);
    AVCodecContext* ctx = avcodec_alloc_context3(codec);
    avcodec_open2(ctx, codec, nullptr);
    AVPacket* pkt = av_packet_alloc();
    AVFrame* frame = av_frame_alloc();
    std::vector<std::uint8_t> buf(data.size() + AV_INPUT_BUFFER_PADDING_SIZE, 0);
    std::memcpy(buf.data(), data.data(), data.size());
    bool damage = false;
    auto drain = [&] {
        while (avcodec_receive_frame(ctx, frame) == 0) {
            ++r.frames;
            if (frame->decode_error_flags != 0 || (frame->flags & AV_FRAME_FLAG_CORRUPT) != 0) {
                ++r.corrupt;
                damage = true;
            } else if (damage && frame->pict_type == AV_PICTURE_TYPE_I) {
                ++r.repaired;
                damage = false;
            }
            av_frame_unref(frame);
        }
    };
    std::size_t pos = 0;
    for (bool flushing = false;;) {
        std::uint8_t* out = nullptr;
        int size = 0;
        const int used = av_parser_parse2(
            parser, ctx, &out, &size, flushing ? nullptr : buf.data() + pos,
            flushing ? 0 : static_cast<int>(data.size() - pos), AV_NOPTS_VALUE, AV_NOPTS_VALUE, 0);
        if (!flushing) pos += static_cast<std::size_t>(used);
        if (size > 0) {
            pkt->data = out;
            pkt->size = size;
            (void)avcodec_send_packet(ctx, pkt);
            drain();
        }
        if (flushing) break;
        if (pos >= data.size()) flushing = true;
    }
    avcodec_send_packet(ctx, nullptr);
    drain();
    av_frame_free(&frame);
    av_packet_free(&pkt);
    avcodec_free_context(&ctx);
    av_parser_close(parser);
    return r;
}

// Flips `flips` bytes inside the slice data (past the slice header) of every `every`-th slice,
// P and IDR alike; returns how many slices were damaged.
int damage_slices(std::vector<std::uint8_t>& data, int every, int flips, unsigned seed) {
    std::vector<std::size_t> starts;
    for (std::size_t i = 0; i + 3 < data.size(); ++i)
        if (data[i] == 0 && data[i + 1] == 0 && data[i + 2] == 1) starts.push_back(i + 3);
    std::mt19937 rng(seed);
    int n = 0, hit = 0, idr = 0;
    for (std::size_t k = 0; k < starts.size(); ++k) {
        const std::size_t s = starts[k];
        const std::size_t e = k + 1 < starts.size() ? starts[k + 1] - 3 : data.size();
        const int type = data[s] & 0x1F;
        if (type != 1 && type != 5) continue;
        if (n++ % every != 0 || e - s < 64) continue;
        for (int f = 0; f < flips; ++f) data[s + 16 + rng() % (e - s - 24)] ^= 0xFF;
        ++hit;
        idr += type == 5;
    }
    EXPECT_GT(idr, 0) << "an IDR slice among the damaged";
    return hit;
}

// A dataset around an Annex-B stream of `frames` access units (25 fps, no navdata).
fs::path make_dataset(const fs::path& dir, const std::vector<std::uint8_t>& video, int frames) {
    fs::create_directories(dir);
    std::ofstream(dir / "flight.json") << R"({"format": "ardrone-dataset", "version": 1,
        "camera": "front", "width": 640, "height": 360, "fps": 25, "source": "damaged copy"})";
    std::ofstream csv(dir / "frames.csv");
    csv << "frame,t_ms,roll_deg\n";
    for (int i = 0; i < frames; ++i) csv << i << ',' << i * 40 << ",0\n";
    std::ofstream(dir / "video.h264", std::ios::binary)
        .write(reinterpret_cast<const char*>(video.data()),
               static_cast<std::streamsize>(video.size()));
    return dir;
}

TEST(DamagedVideo, EveryFrameFfmpegDecodesIsAPictureConcealedFramesAreCountedAndKept) {
    const auto clean = read_all(kClip);
    ASSERT_FALSE(clean.empty()) << kClip;
    const Reference ref_clean = ffmpeg_count(clean);
    ASSERT_EQ(ref_clean.frames, 82);  // SOURCES.md: 82 frames
    const auto dir = scratch_dir("damaged_video", "slices");
    for (unsigned seed : {1u, 2u}) {
        auto bad = clean;
        const int hit = damage_slices(bad, 3, 6, seed);
        ASSERT_GT(hit, 10);
        const Reference ref = ffmpeg_count(bad);
        ASSERT_EQ(ref.frames, 82) << "ffmpeg conceals every damaged frame of this copy";
        ASSERT_GT(ref.corrupt, 0);
        const auto ds = make_dataset(dir / ("ds" + std::to_string(seed)), bad, 82);
        const auto out = dir / ("out" + std::to_string(seed));
        const auto r = run_cli("replay -q " + ds.string() + " --out " + out.string());
        EXPECT_EQ(r.exit_code, 0) << r.out;
        const auto j = nlohmann::json::parse(read_text(out / "summary.json"));
        EXPECT_EQ(j["processed"], ref.frames);
        EXPECT_EQ(j["decode_errors"], 0);
        EXPECT_EQ(j["concealed_frames"], ref.corrupt);
        // (Every intra frame is among the damaged here, so none repairs; the decoder's tests
        // damage one P-frame and see the next intra frame repair it.)
        EXPECT_EQ(j["repaired_frames"], ref.repaired);
        // --strict turns any damage into a failure.
        const auto s = run_cli("replay -q --strict " + ds.string() + " --out " +
                               (dir / ("strict" + std::to_string(seed))).string());
        EXPECT_NE(s.exit_code, 0) << s.out;
        EXPECT_NE(s.out.find("concealed damage (--strict)"), std::string::npos) << s.out;
    }
    // The clean clip is not "damaged": --strict passes.
    const auto ds = make_dataset(dir / "clean", clean, 82);
    const auto r = run_cli("replay -q --strict " + ds.string() + " --out " + (dir / "oc").string());
    EXPECT_EQ(r.exit_code, 0) << r.out;
}

}  // namespace
}  // namespace gs::test::damaged_video
