// The PaVE framer (TCP 5555 bytes): any chunking of the same bytes must give the same frames,
// resyncs, counters and pending state as one push, and every byte must be accounted for.
// Seeds: ../shared/fixtures/ardrone/*pave*.bin and the video stream dumps.
#include "drone/protocol/pave.hpp"
#include "fuzz_util.hpp"

#include <vector>

namespace {

struct Event {
    bool frame;
    std::uint64_t offset, size;
    gs::protocol::PaveHeader header;
    std::vector<std::uint8_t> payload;
    bool operator==(const Event&) const = default;
};

std::vector<Event> run(std::span<const std::uint8_t> bytes, std::span<const std::uint8_t> sizes,
                       gs::protocol::PaveFramerStats& stats, gs::protocol::PavePending& pending) {
    gs::protocol::PaveFramer framer;
    std::vector<Event> out;
    std::size_t pos = 0, k = 0;
    while (pos < bytes.size()) {
        std::size_t n = bytes.size() - pos;
        if (!sizes.empty()) n = std::min<std::size_t>(n, 1 + sizes[k++ % sizes.size()] * 7);
        framer.push(bytes.subspan(pos, n));
        pos += n;
        while (auto ev = framer.next()) {
            if (const auto* f = std::get_if<gs::protocol::PaveFrame>(&*ev)) {
                out.push_back({true,
                               f->stream_offset,
                               f->payload.size(),
                               f->header,
                               {f->payload.begin(), f->payload.end()}});
            } else {
                const auto& r = std::get<gs::protocol::PaveResync>(*ev);
                out.push_back({false, r.stream_offset, r.bytes_skipped, {}, {}});
            }
        }
    }
    stats = framer.stats();
    pending = framer.pending();
    return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    // The first 8 bytes choose the chunk sizes; the rest is the stream.
    const std::size_t k = std::min<std::size_t>(size, 8);
    const std::span<const std::uint8_t> sizes(data, k), bytes(data + k, size - k);
    gs::protocol::PaveFramerStats s1, s2;
    gs::protocol::PavePending p1, p2;
    const auto whole = run(bytes, {}, s1, p1);
    const auto chunked = run(bytes, sizes, s2, p2);
    GS_FUZZ_CHECK(whole == chunked);
    GS_FUZZ_CHECK(s1.frames == s2.frames && s1.resyncs == s2.resyncs &&
                  s1.bytes_skipped == s2.bytes_skipped && s1.payload_bytes == s2.payload_bytes);
    GS_FUZZ_CHECK(p1.buffered_bytes == p2.buffered_bytes && p1.header == p2.header);
    // Every byte is in a frame, was skipped, or is still pending.
    std::uint64_t framed = 0;
    for (const auto& e : whole)
        if (e.frame) framed += e.header.header_size + e.size;
    GS_FUZZ_CHECK(framed + s1.bytes_skipped + p1.buffered_bytes == bytes.size());
    return 0;
}
