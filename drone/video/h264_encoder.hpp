#pragma once
// H.264 encoding for the virtual drone's video (libavcodec + libx264): Baseline profile, the
// AR.Drone 2's 640x360 at 30 fps, an IDR every 15 frames with SPS/PPS repeated before each IDR so a
// client joining mid-stream can decode, no B-frames and no lookahead: one Annex-B access unit out
// per frame in. Buffers are reused between frames.

#include "drone/core/expected.hpp"

#include <opencv2/core.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace gs::video {

struct H264EncoderConfig {
    int width = 640;
    int height = 360;
    int fps = 30;
    int gop = 15;                 // IDR period in frames
    int bitrate_bps = 1'500'000;  // average; VBV capped at the same rate over one second
    std::string preset = "veryfast";
};

enum class H264EncodeError {
    CodecUnavailable,  // libx264 not built into libavcodec
    OpenFailed,        // avcodec_open2 rejected the settings
    BadInput,          // image is not CV_8UC3 of the configured size
    EncodeFailed,      // libavcodec returned an error
    NoOutput,          // the encoder held the frame back (would break one-in-one-out)
};
std::string to_string(H264EncodeError e);

class H264Encoder {
public:
    [[nodiscard]] static Expected<std::unique_ptr<H264Encoder>, H264EncodeError> create(
        const H264EncoderConfig& config);
    ~H264Encoder();
    H264Encoder(const H264Encoder&) = delete;
    H264Encoder& operator=(const H264Encoder&) = delete;

    // Encodes one BGR frame into one Annex-B access unit (replacing `access_unit_out`'s content,
    // capacity kept). `is_idr` tells whether it is an IDR (then it starts with SPS and PPS).
    // Returns the access unit's size in bytes.
    [[nodiscard]] Expected<std::size_t, H264EncodeError> encode(
        const cv::Mat& bgr, std::vector<std::uint8_t>& access_unit_out, bool& is_idr);

    const H264EncoderConfig& config() const;
    std::int64_t frames_encoded() const;

private:
    struct Impl;
    explicit H264Encoder(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace gs::video
