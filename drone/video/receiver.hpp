#pragma once
// The one video receive pipeline: bytes of the video port (with their receive time) in, access
// units and decoded frames out. Used by the link's video thread, raw replay of a recording,
// `inspect pave` and the decode benchmark, so all four cut, decode and time frames identically.
//
//   bytes --protocol::PaveFramer--> PaVE frames --codec check--> H.264 access units
//   --H264Decoder--> frames in pooled buffers (FramePool), each timed by the drone's clock
//   (CaptureClock)
//
// Connections: a new TCP connection (a video reset, a drone reboot) is announced with
// begin_connection(); bytes still buffered from the previous one are a frame cut short (counted,
// never joined to the new connection's bytes), and the decoder waits for the next IDR. Every
// access unit comes out once, with its fate: decoded, decoded with concealed damage, skipped
// because its reference was lost (waiting for an IDR), or no picture. A recorder keeps exactly the
// units that produced a picture, so replaying what it kept reproduces every frame.
//
// No sockets, threads or clocks inside: time is an argument. Steady state allocates nothing per
// frame (the framer's buffer, the decoder's and the pool's are reused).

#include "drone/core/clock.hpp"
#include "drone/protocol/pave.hpp"
#include "drone/video/capture_clock.hpp"
#include "drone/video/frame_pool.hpp"
#include "drone/video/h264_decoder.hpp"

#include <opencv2/core.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace gs::video {

enum class UnitFate : std::uint8_t {
    Decoded,     // a picture came out
    Concealed,   // a picture came out; libavcodec concealed damage in it (less to trust)
    WaitingIdr,  // skipped: its reference is lost (stream start, reset, frame gap) until an IDR
    NoPicture,   // the decoder refused it or gave no picture
    NotH264,     // a PaVE frame in another codec: not decoded (counted with the reason)
    NotDecoded,  // the receiver frames and times only (ReceiverOptions::decode false)
};
const char* to_string(UnitFate f);
inline bool has_picture(UnitFate f) {
    return f == UnitFate::Decoded || f == UnitFate::Concealed;
}

// One PaVE frame as received.
struct ReceivedUnit {
    std::int64_t unit = 0;         // 0-based over everything received (every connection)
    std::uint32_t connection = 0;  // which connection it came on (begin_connection() counts)
    std::uint32_t frame_number = 0;
    std::uint32_t pave_timestamp_ms = 0;  // the drone's capture clock
    std::uint16_t stream_id = 0;
    std::uint64_t stream_offset = 0;  // where its PaVE header began, in bytes pushed so far
    protocol::PaveHeader header;      // every field, as received
    protocol::PaveCodec codec = protocol::PaveCodec::H264;
    TimeNs recv_ns = 0;     // when the bytes completing it arrived
    TimeNs capture_ns = 0;  // the drone's timestamp on the receiver's clock (<= recv_ns)
    bool idr = false;       // holds an IDR slice
    UnitFate fate = UnitFate::NoPicture;
    // Decoded: an intra picture that replaced concealed damage (H264DecoderStats::repaired); it
    // jumps where the damage was.
    bool repaired = false;
    std::span<const std::uint8_t> bytes;  // the Annex-B payload; valid until the next push()
    cv::Mat image;                        // the decoded picture (pooled), empty without one
    std::int64_t frame_index = -1;        // 0-based among the pictures produced, else -1
};

struct ReceiverStats {
    std::uint64_t bytes = 0;
    std::uint64_t connections = 0;
    std::uint64_t units = 0;         // PaVE frames out (every fate)
    std::uint64_t pictures = 0;      // Decoded + Concealed
    std::uint64_t concealed = 0;     // pictures with concealed damage
    std::uint64_t repaired = 0;      // intra pictures that replaced concealed damage
    std::uint64_t waiting_idr = 0;   // units skipped for a lost reference
    std::uint64_t no_picture = 0;    // units the decoder refused
    std::uint64_t not_h264 = 0;      // units in another codec
    std::uint64_t cut_by_reset = 0;  // frames begun on a connection that ended inside them
    std::uint64_t resyncs = 0;       // PaVE resynchronisations (garbage skipped)
    std::uint64_t bytes_skipped = 0;
    std::uint64_t pool_exhausted = 0;  // pictures that could not get a pooled buffer
    std::uint64_t clock_anchors = 0;   // capture clock re-anchorings (reboots, jumps)
    std::uint64_t clock_frozen = 0;  // frames timed by their arrival: the drone's clock stood still
    std::string last_error;          // the last unit that did not produce a picture, and why
};

struct ReceiverOptions {
    std::size_t pool_slots = 8;  // frames alive at once before the pool falls back to the heap
    bool decode = true;          // false: framing and timing only (units carry no picture)
};

class VideoReceiver {
public:
    explicit VideoReceiver(ReceiverOptions options = {});

    // A new connection begins (also before the first bytes of a stream, optionally).
    void begin_connection(TimeNs now_ns);
    // Bytes of the current connection, received at `recv_ns`. Invalidates spans handed out.
    void push(std::span<const std::uint8_t> bytes, TimeNs recv_ns);
    // The next unit completed by the bytes pushed so far (decoded here), or nullopt.
    [[nodiscard]] std::optional<ReceivedUnit> next();
    // The resynchronisations next() passed over since the last call (garbage skipped before
    // the unit it returned, or at the end of the data), for a listing; counted in stats().
    std::span<const protocol::PaveResync> resyncs() const { return resyncs_; }
    void clear_resyncs() { resyncs_.clear(); }

    const ReceiverStats& stats() const { return stats_; }
    const protocol::PaveFramerStats& framer_stats() const { return framer_.stats(); }
    const H264DecoderStats& decoder_stats() const { return decoder_.stats(); }
    protocol::PavePending pending() const { return framer_.pending(); }
    const CaptureClock& capture_clock() const { return clock_; }
    std::uint64_t bytes_pushed() const { return stats_.bytes; }  // the next byte's stream offset
    std::size_t frames_in_use() const { return pool_->in_use(); }

private:
    ReceiverOptions options_;
    protocol::PaveFramer framer_;
    H264Decoder decoder_;
    CaptureClock clock_;  // kept across connections: the drone's clock goes on
    std::shared_ptr<FramePool> pool_;
    ReceiverStats stats_;
    TimeNs recv_ns_ = 0;
    std::uint32_t connection_ = 0;
    bool any_connection_ = false;
    std::int64_t next_unit_ = 0;
    std::int64_t next_frame_ = 0;
    std::vector<protocol::PaveResync> resyncs_;
};

}  // namespace gs::video
