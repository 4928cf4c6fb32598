#pragma once
// Rebuilding frames.csv from raw/ (docs/dataset.md: "Replaying raw/ through the protocol parsers
// must reproduce frames.csv"): navdata datagrams and video chunks are fed in receive-time order to
// the parsers, and each frame gets its attitude by the same NavAligner the recorder uses.
//
// The parsers are passed in (tests use stand-ins); make_protocol_replay_decoders() binds the real
// ones: navdata::parse_navdata, and the one video receiver (video::VideoReceiver: PaVE framer ->
// H.264 decoder) as the live link runs it.

#include "drone/dataset/dataset.hpp"

#include <functional>
#include <map>
#include <optional>
#include <span>
#include <vector>

namespace gs::dataset {

// A PaVE frame's capture time as the recording's live receiver gave it (raw/capture_times.csv).
struct RecordedCapture {
    std::uint32_t frame_number = 0;
    std::uint32_t pave_timestamp_ms = 0;
    TimeNs t_ns = 0;  // stream time
};

struct RawReplayDecoders {
    // One navdata datagram -> its state when the link would have accepted it (nullopt when it
    // does not parse, or is a duplicate or a late packet: it is then skipped, as navdata.csv
    // holds only what the link accepted).
    // `recv_ns` is its receive time (stream ns).
    std::function<std::optional<NavState>(std::span<const std::uint8_t>, TimeNs recv_ns)> navdata;
    // A chunk of the video stream received at stream time `recv_ns`; appends the capture time
    // (stream ns) of every frame the chunk completed that the recorder would have written.
    std::function<void(std::span<const std::uint8_t>, TimeNs recv_ns, std::vector<TimeNs>&)> video;
    // A new video connection begins with the next chunk (raw/video_connections.csv).
    std::function<void(TimeNs opened_ns)> begin_connection;
    // The capture times the recording used (raw/capture_times.csv), when it has them.
    std::function<void(std::vector<RecordedCapture>)> capture_times;
};

// The real protocol parsers, mirroring what a recording keeps: every navdata datagram that
// parses (navdata_state below), and every frame the link's decoder produces from the recorded
// stream, from the first IDR on, captured when the chunk completing it arrived. Stateful: one
// set per replay.
RawReplayDecoders make_protocol_replay_decoders();

// One navdata datagram as the recorder stores it in navdata.csv (nullopt when it does not parse).
std::optional<NavState> navdata_state(std::span<const std::uint8_t> datagram);

// raw/video_connections.csv: the byte offsets in raw/video.pave where each connection begins and
// when it opened (docs/dataset.md 1.1). Absent: one connection (offset 0). A cut last line (no
// newline) is left out with a warning in `warnings`.
struct VideoConnection {
    std::uint64_t offset = 0;
    std::int64_t t_us = 0;
};
Expected<std::vector<VideoConnection>, FileError> parse_video_connections(
    std::string text, std::vector<std::string>* warnings = nullptr);
// raw/capture_times.csv (an extension of this recorder); a cut last line is left out with a
// warning in `warnings`.
Expected<std::vector<RecordedCapture>, FileError> parse_capture_times(
    std::string text, std::vector<std::string>* warnings = nullptr);
// Reads and parses `raw_dir`/capture_times.csv; nullopt when the recording has none.
Expected<std::optional<std::vector<RecordedCapture>>, FileError> read_capture_times(
    const std::filesystem::path& raw_dir, std::vector<std::string>* warnings = nullptr);

// PaVE frame number -> the dataset frame (frames.csv row) captured at the same time, to the
// microsecond. Frames the recording did not keep map to nothing.
std::map<std::uint32_t, std::int64_t> frames_of_pave_numbers(
    const std::vector<FrameRow>& frames, const std::vector<RecordedCapture>& captures);

// Replays `raw_dir` (raw/navdata.bin, raw/video.pave, raw/video_chunks.bin, and when present
// raw/video_connections.csv and raw/capture_times.csv) into frames.csv rows. A recording cut
// short (docs/dataset.md 1.1) is replayed up to the cut: a file ending inside its last record or
// line, and raw/video.pave ending before the chunks raw/video_chunks.bin lists, each add one
// warning to `warnings` naming the file; what comes before the cut is replayed.
Expected<std::vector<FrameRow>, FileError> replay_raw(const std::filesystem::path& raw_dir,
                                                      RawReplayDecoders& decoders,
                                                      std::vector<std::string>* warnings = nullptr,
                                                      TimeNs max_nav_wait_ns = 500'000'000);

}  // namespace gs::dataset
