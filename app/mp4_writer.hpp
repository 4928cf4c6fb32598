#pragma once
// Writes BGR frames as an H.264 MP4 file (libx264 through H264Encoder, muxed by libavformat), for
// `replay --video`: the flight with the classifier's overlay drawn, playable anywhere.

#include "drone/core/expected.hpp"

#include <opencv2/core.hpp>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

namespace gs {

struct Mp4WriterConfig {
    int width = 640;
    int height = 360;
    double fps = 30;
    int bitrate_bps = 3'000'000;
    int gop = 30;
};

class Mp4Writer {
public:
    // Creates (truncates) `path`. Errors say what failed.
    [[nodiscard]] static Expected<std::unique_ptr<Mp4Writer>, std::string> create(
        const std::filesystem::path& path, const Mp4WriterConfig& config);
    ~Mp4Writer();
    Mp4Writer(const Mp4Writer&) = delete;
    Mp4Writer& operator=(const Mp4Writer&) = delete;

    // One frame (CV_8UC3 of the configured size).
    [[nodiscard]] std::optional<std::string> write(const cv::Mat& bgr);
    // Writes the index (moov) and closes the file; idempotent, the destructor calls it.
    [[nodiscard]] std::optional<std::string> close();
    std::int64_t frames() const;

private:
    struct Impl;
    explicit Mp4Writer(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace gs
