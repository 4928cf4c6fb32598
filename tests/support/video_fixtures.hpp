#pragma once
// Shared by the PaVE and H.264 tests: loading the real captures and running them through the
// framer with a given chunking.

#include "drone/protocol/pave.hpp"
#include "drone/video/h264_decoder.hpp"  // access_unit_size
#include "support/navdata_fixtures.hpp"  // read_fixture

#include <cstdint>
#include <fstream>
#include <iterator>
#include <random>
#include <span>
#include <string>
#include <variant>
#include <vector>

namespace gs::test {

inline std::string fixture_path(const std::string& name) {
    return std::string(GS_FIXTURES_DIR) + "/ardrone/" + name;
}

inline std::vector<std::uint8_t> read_bytes(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

// An Annex-B stream cut into its access units (views into `bytes`).
inline std::vector<std::span<const std::uint8_t>> split_annexb(
    const std::vector<std::uint8_t>& bytes) {
    std::vector<std::span<const std::uint8_t>> aus;
    std::span<const std::uint8_t> rest(bytes);
    while (!rest.empty()) {
        const std::size_t n = video::access_unit_size(rest);
        aus.push_back(rest.first(n));
        rest = rest.subspan(n);
    }
    return aus;
}

// The real AR.Drone 2 office clip (82 frames, an intra picture every 15: 0, 15, 30, ...) with a
// run of 24 bytes flipped a third of the way into frame `frame`'s slice data, as a lost or
// corrupt stretch of a Wi-Fi packet leaves it: libavcodec conceals that frame.
inline std::vector<std::uint8_t> office_clip_damaged_at(std::size_t frame) {
    auto clip =
        read_bytes(std::string(GS_FIXTURES_DIR) + "/real/video/ardrone2_front_office_person.h264");
    const auto aus = split_annexb(clip);
    if (frame >= aus.size()) return {};
    const auto at =
        static_cast<std::size_t>(aus[frame].data() - clip.data()) + aus[frame].size() / 3;
    for (std::size_t i = 0; i < 24; ++i) clip[at + i] ^= 0xA5;
    return clip;
}

// A frame copied out of the framer (its span dies at the next push).
struct OwnedFrame {
    std::uint64_t index = 0;
    std::uint64_t stream_offset = 0;
    protocol::PaveHeader header;
    std::vector<std::uint8_t> payload;
    bool operator==(const OwnedFrame&) const = default;
};

struct FramerRun {
    std::vector<OwnedFrame> frames;
    std::vector<protocol::PaveResync> resyncs;
    std::vector<int> order;  // 0 = frame, 1 = resync, in event order
    protocol::PaveFramerStats stats;
    protocol::PavePending pending;
};

inline void drain(protocol::PaveFramer& framer, FramerRun& run) {
    while (auto ev = framer.next()) {
        if (const auto* f = std::get_if<protocol::PaveFrame>(&*ev)) {
            run.frames.push_back(OwnedFrame{
                f->index, f->stream_offset, f->header, {f->payload.begin(), f->payload.end()}});
            run.order.push_back(0);
        } else {
            run.resyncs.push_back(std::get<protocol::PaveResync>(*ev));
            run.order.push_back(1);
        }
    }
}

// Pushes `bytes` in chunks of `chunk` bytes (0 = all at once; negative = random sizes 1..-chunk
// from a fixed seed) and collects everything the framer reports.
inline FramerRun run_framer(const std::vector<std::uint8_t>& bytes, int chunk,
                            protocol::PaveFramerConfig config = {}) {
    protocol::PaveFramer framer(config);
    FramerRun run;
    std::mt19937 rng(12345);
    std::size_t pos = 0;
    while (pos < bytes.size()) {
        std::size_t n = bytes.size() - pos;
        if (chunk > 0) {
            n = std::min<std::size_t>(n, static_cast<std::size_t>(chunk));
        } else if (chunk < 0) {
            std::uniform_int_distribution<int> dist(1, -chunk);
            n = std::min<std::size_t>(n, static_cast<std::size_t>(dist(rng)));
        }
        framer.push(std::span<const std::uint8_t>(bytes.data() + pos, n));
        pos += n;
        drain(framer, run);
    }
    run.stats = framer.stats();
    run.pending = framer.pending();
    return run;
}

}  // namespace gs::test
