#pragma once
// H.264 (Annex-B) decoding with libavcodec into BGR images at the display size.
// Contract shared by the link, the dataset reader and the inspect command.

#include "drone/core/expected.hpp"

#include <opencv2/core.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>

namespace gs::video {

struct H264DecoderStats {
    std::uint64_t access_units = 0;         // access units fed
    std::uint64_t decoded = 0;              // frames emitted
    std::uint64_t skipped_waiting_idr = 0;  // access units dropped while waiting for an IDR
    std::uint64_t decode_errors = 0;  // access units libavcodec rejected (send/receive failed)
    std::uint64_t concealed = 0;      // frames emitted with damage libavcodec concealed
    // Intra pictures emitted while concealed damage was on show (in a concealed picture or the
    // ones predicted from it): the picture is whole again, and jumps where the damage was.
    std::uint64_t repaired = 0;
    std::uint64_t frame_gaps = 0;  // frame-number gaps seen (each forces an IDR wait)
    std::uint64_t reinits = 0;     // re-initialisations (stream_id, display or coded size change)
};

// The largest picture the decoder accepts (bigger SPS sizes are decode errors): 1080p, above the
// AR.Drone 2's 1280x720 and below what a corrupt SPS could make libavcodec allocate.
inline constexpr int kMaxPictureWidth = 1920;
inline constexpr int kMaxPictureHeight = 1088;

enum class DecodeStatus {
    Frame,    // `out` holds a new BGR frame
    NoFrame,  // accepted, no picture out yet (or skipped waiting for an IDR)
};

enum class DecodeError { CodecUnavailable, InvalidInput, DecodeFailed };
std::string to_string(DecodeError e);

struct AccessUnit {
    std::span<const std::uint8_t> data;         // Annex-B bytes of one frame
    std::optional<std::uint32_t> frame_number;  // PaVE frame_number; a gap forces an IDR wait
    int display_width = 0;                      // PaVE display size; 0 = take the SPS cropping
    int display_height = 0;
    std::optional<std::uint16_t> stream_id;  // PaVE stream_id; a change re-initialises the decoder
};

class H264Decoder {
public:
    H264Decoder();
    ~H264Decoder();
    H264Decoder(const H264Decoder&) = delete;
    H264Decoder& operator=(const H264Decoder&) = delete;

    // Decodes one access unit. Emits nothing until the first IDR after construction, reset() or a
    // frame-number gap. `out` is reused between calls (no per-frame allocation once sized): its
    // pixels are overwritten in place when the size is unchanged, so hand a Mat that nobody else
    // still reads. Output is BGR8 at the display size: the PaVE display size when given (clamped
    // to the decoded picture), else the SPS cropping (640x360 for the 640x368 coded AR.Drone 2).
    // Errors are counted in stats() and returned; the decoder stays usable.
    Expected<DecodeStatus, DecodeError> decode(const AccessUnit& au, cv::Mat& out);

    void reset();  // forget the stream: wait for the next IDR
    const H264DecoderStats& stats() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// True when the Annex-B buffer contains an IDR slice (NAL type 5).
[[nodiscard]] bool contains_idr(std::span<const std::uint8_t> annexb);

// Size of the access unit at the start of an Annex-B buffer: up to the start code of the next
// one (a non-VCL NAL or a slice with first_mb_in_slice 0 after a slice), else the whole buffer.
// Splits raw .h264 files into decoder inputs; PaVE payloads are already one access unit each.
[[nodiscard]] std::size_t access_unit_size(std::span<const std::uint8_t> annexb);

}  // namespace gs::video
