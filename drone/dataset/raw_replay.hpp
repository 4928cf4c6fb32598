#pragma once
// Rebuilding frames.csv from raw/ (DATASET.md: "Replaying raw/ through the protocol parsers must
// reproduce frames.csv"): navdata datagrams and video chunks are fed in receive-time order to
// the parsers, and each frame gets its attitude by the same NavAligner the recorder uses.
//
// The parsers are passed in (tests use stand-ins); make_protocol_replay_decoders() binds the real
// ones: navdata::parse_navdata, and PaveFramer -> H264Decoder as the live link runs them.

#include "drone/dataset/dataset.hpp"

#include <functional>
#include <span>
#include <vector>

namespace gs::dataset {

struct RawReplayDecoders {
    // One navdata datagram -> its state (nullopt when it does not parse; it is then skipped).
    std::function<std::optional<NavState>(std::span<const std::uint8_t>)> navdata;
    // A chunk of the video stream received at stream time `recv_ns`; appends the capture time
    // (stream ns) of every frame the chunk completed that the recorder would have written.
    std::function<void(std::span<const std::uint8_t>, TimeNs recv_ns, std::vector<TimeNs>&)> video;
};

// The real protocol parsers, mirroring what a recording keeps: every navdata datagram that
// parses (navdata_state below), and every frame the link's decoder produces from the recorded
// stream, from the first IDR on, captured when the chunk completing it arrived. Stateful: one
// set per replay.
RawReplayDecoders make_protocol_replay_decoders();

// One navdata datagram as the recorder stores it in navdata.csv (nullopt when it does not parse).
std::optional<NavState> navdata_state(std::span<const std::uint8_t> datagram);

// Replays `raw_dir` (raw/navdata.bin, raw/video.pave, raw/video_chunks.bin) into frames.csv rows.
Expected<std::vector<FrameRow>, FileError> replay_raw(const std::filesystem::path& raw_dir,
                                                      RawReplayDecoders& decoders,
                                                      TimeNs max_nav_wait_ns = 500'000'000);

}  // namespace gs::dataset
