#pragma once
// PaVE (Parrot Video Encapsulation): the header the AR.Drone 2 puts before every video frame on
// TCP 5555/5553 (docs/protocol.md §4), a parser/writer for it, and a streaming framer that cuts an
// arbitrarily chunked TCP byte stream into frames and resynchronises on corruption (§4.4).
// Pure code over bytes: no sockets, clocks or logging.

#include "drone/core/expected.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

namespace gs::protocol {

inline constexpr std::array<std::uint8_t, 4> kPaveSignature = {'P', 'a', 'V', 'E'};
inline constexpr std::uint8_t kPaveCurrentVersion = 2;  // PAVE_CURRENT_VERSION
inline constexpr std::size_t kPaveBaseHeaderSize = 64;  // sizeof(parrot_video_encapsulation_t)
// Firmware sends 64 or 68; anything up to this is accepted (docs/protocol.md §4.4 step 5).
inline constexpr std::size_t kPaveMaxHeaderSize = 128;
// Bytes needed to validate signature, version, codec, header_size and payload_size.
inline constexpr std::size_t kPavePrefixSize = 12;
// Default cap on payload_size: the SDK's socket buffer is 1 MiB; real frames are < 20 kB.
inline constexpr std::uint32_t kPaveDefaultMaxPayload = 1u << 20;

// video_codec (SDK parrot_video_encapsulation_codecs_t). Values outside the list are kept as is.
enum class PaveCodec : std::uint8_t { Unknown = 0, Vlib = 1, P264 = 2, Mpeg4Visual = 3, H264 = 4 };
// frame_type (SDK parrot_video_encapsulation_frametypes_t).
enum class PaveFrameType : std::uint8_t { Unknown = 0, Idr = 1, I = 2, P = 3, Headers = 4 };
// control bits (SDK PAVE_CTRL_*).
inline constexpr std::uint8_t kPaveCtrlFrameAdvertisement = 1u << 0;
inline constexpr std::uint8_t kPaveCtrlLastFrameInStream = 1u << 1;

std::string to_string(PaveCodec c);      // "H264", ..., "unknown(7)"
std::string to_string(PaveFrameType t);  // "IDR", "I", "P", "headers", ..., "unknown(9)"

// One header, field names as in the SDK's parrot_video_encapsulation_t (typos included), so the
// JSON output and docs/protocol.md use the same words. All integers little-endian on the wire.
struct PaveHeader {
    std::array<std::uint8_t, 4> signature = kPaveSignature;
    std::uint8_t version = kPaveCurrentVersion;
    PaveCodec video_codec = PaveCodec::H264;
    std::uint16_t header_size = kPaveBaseHeaderSize;  // bytes from the signature to the payload
    std::uint32_t payload_size = 0;
    std::uint16_t encoded_stream_width = 0;  // macroblock-aligned (640x368)
    std::uint16_t encoded_stream_height = 0;
    std::uint16_t display_width = 0;  // what to show (640x360)
    std::uint16_t display_height = 0;
    std::uint32_t frame_number = 0;  // +1 per frame within a stream
    std::uint32_t timestamp = 0;     // milliseconds, arbitrary origin
    std::uint8_t total_chuncks = 1;
    std::uint8_t chunck_index = 0;
    PaveFrameType frame_type = PaveFrameType::Unknown;
    std::uint8_t control = 0;  // kPaveCtrl* bits
    std::uint32_t stream_byte_position_lw = 0;
    std::uint32_t stream_byte_position_uw = 0;
    std::uint16_t stream_id = 0;
    std::uint8_t total_slices = 1;
    std::uint8_t slice_index = 0;
    std::uint8_t header1_size = 0;  // H.264: SPS size incl. start code at payload start, 0 = none
    std::uint8_t header2_size = 0;  // H.264: PPS size incl. start code
    std::array<std::uint8_t, 2> reserved2{};
    std::uint32_t advertised_size = 0;
    std::array<std::uint8_t, 12> reserved3{};
    // Bytes 64..67 when header_size >= 68 (undocumented firmware extension, kept for round trips).
    std::array<std::uint8_t, 4> extension{};

    std::uint64_t stream_byte_position() const {
        return (std::uint64_t{stream_byte_position_uw} << 32) | stream_byte_position_lw;
    }
    bool is_key_frame() const {  // docs/protocol.md §10 item 18: IDR or I
        return frame_type == PaveFrameType::Idr || frame_type == PaveFrameType::I;
    }
    bool operator==(const PaveHeader&) const = default;
};

enum class PaveError {
    TooShort,         // fewer bytes than the header needs
    BadSignature,     // not "PaVE"
    BadVersion,       // version not 1..kPaveCurrentVersion
    BadCodec,         // video_codec not 1..4
    BadHeaderSize,    // header_size not in [64, 128]
    PayloadTooLarge,  // payload_size above the cap
    BufferTooSmall,   // write: output span smaller than header_size
};
std::string to_string(PaveError e);

// Parses and validates the header at the start of `bytes` (which needs >= header_size bytes;
// the payload need not be present). Sizes are bounded before anything trusts them.
[[nodiscard]] Expected<PaveHeader, PaveError> parse_pave_header(
    std::span<const std::uint8_t> bytes, std::uint32_t max_payload_size = kPaveDefaultMaxPayload);

// Writes exactly h.header_size bytes (64..128; bytes past 68 are zero) into `out`; returns the
// count. Validates like the parser, so whatever it writes parses back to `h`.
[[nodiscard]] Expected<std::size_t, PaveError> write_pave_header(
    const PaveHeader& h, std::span<std::uint8_t> out,
    std::uint32_t max_payload_size = kPaveDefaultMaxPayload);

// ---- Streaming framer ---------------------------------------------------------------------

struct PaveFramerConfig {
    std::uint32_t max_payload_size = kPaveDefaultMaxPayload;  // larger claims are corruption
};

struct PaveFrame {
    std::uint64_t index = 0;          // 0-based, in stream order
    std::uint64_t stream_offset = 0;  // byte offset of the header's signature in the stream
    PaveHeader header;
    std::span<const std::uint8_t> payload;  // valid until the next push()
};

// Bytes that were thrown away to find the next valid header.
struct PaveResync {
    std::uint64_t stream_offset = 0;  // offset of the first skipped byte
    std::uint64_t bytes_skipped = 0;  // the next frame starts at stream_offset + bytes_skipped
    PaveError reason = PaveError::BadSignature;  // why the first skipped byte was rejected
    bool operator==(const PaveResync&) const = default;
};

using PaveEvent = std::variant<PaveFrame, PaveResync>;

struct PaveFramerStats {
    std::uint64_t bytes_in = 0;             // bytes pushed
    std::uint64_t frames = 0;               // complete frames handed out
    std::uint64_t payload_bytes = 0;        // sum of their payload sizes
    std::uint64_t resyncs = 0;              // PaveResync events reported
    std::uint64_t bytes_skipped = 0;        // bytes discarded (reported or still pending)
    std::uint64_t oversize_rejections = 0;  // headers refused for payload_size > cap
};

// What is held back at the end of the data pushed so far.
struct PavePending {
    std::size_t buffered_bytes = 0;     // unconsumed bytes kept for the next push
    std::optional<PaveHeader> header;   // a validated header whose payload is incomplete
    std::uint64_t header_offset = 0;    // its stream offset
    std::uint64_t unreported_skip = 0;  // bytes skipped since the last event (no header yet)
};

// Cuts a TCP byte stream into PaVE frames. Any chunking of the same bytes (1 byte at a time up
// to the whole stream at once) yields the same events, counters and pending state.
//
//     framer.push(bytes);
//     while (auto ev = framer.next()) { if (auto* f = std::get_if<PaveFrame>(&*ev)) ... }
//
// One internal buffer is reused, so steady state does no allocation; its size is bounded by
// max header + max_payload_size + the largest push. Payload sizes are never trusted for
// allocation: a frame is only buffered as its bytes arrive.
class PaveFramer {
public:
    explicit PaveFramer(PaveFramerConfig config = {});

    // Appends bytes. Invalidates spans handed out by earlier next() calls.
    void push(std::span<const std::uint8_t> bytes);
    // The next frame or resync event, or nullopt when more bytes are needed.
    [[nodiscard]] std::optional<PaveEvent> next();

    [[nodiscard]] const PaveFramerStats& stats() const { return stats_; }
    [[nodiscard]] PavePending pending() const;
    void reset();  // forget buffered bytes (e.g. after a reconnect); counters are kept
    // Bytes reserved by the internal buffer: grows with real data only, never with a claimed size.
    [[nodiscard]] std::size_t buffer_capacity() const { return buf_.capacity(); }

private:
    std::size_t unread() const { return buf_.size() - pos_; }
    void skip(std::size_t n, PaveError reason);

    PaveFramerConfig config_;
    std::vector<std::uint8_t> buf_;
    std::size_t pos_ = 0;           // first unconsumed byte in buf_
    std::uint64_t pos_offset_ = 0;  // stream offset of buf_[pos_]
    std::uint64_t skip_start_ = 0;  // stream offset where the current skip run began
    std::uint64_t skip_run_ = 0;    // bytes in the current skip run (0 = none)
    PaveError skip_reason_ = PaveError::BadSignature;
    PaveFramerStats stats_;
};

}  // namespace gs::protocol
