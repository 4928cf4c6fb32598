#pragma once
// Any video file libavformat opens (MP4, AVI, MKV, raw H.264 ...) turned into a dataset
// (docs/dataset.md) with no navdata: flight.json, video.h264 and a frames.csv whose attitude,
// velocity and altitude cells are empty (unknown). Footage filmed with something other than this
// ground station (a phone, an old recording, another tool's capture) can then be replayed,
// evaluated once labelled, and looked at frame by frame like any flight.
//
// An H.264 stream without reordered frames (the AR.Drone's Baseline stream among them) is copied
// access unit by access unit, bit for bit (MP4's length-prefixed NAL units rewritten as Annex-B);
// anything else is decoded and encoded again as the drone's H.264 (Baseline, an IDR every 15
// frames) at a high bitrate so the import adds little damage of its own. Frame times come from
// the container (each frame's presentation time) or from --fps.

#include "drone/core/camera_calibration.hpp"
#include "drone/core/expected.hpp"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

namespace gs::dataset {

enum class VideoImportMode {
    Auto,    // copy when the stream is H.264 without reordering, else encode
    Copy,    // copy the H.264 access units (refused for other codecs or B-frames)
    Encode,  // decode and encode again
};

struct VideoImportOptions {
    VideoImportMode mode = VideoImportMode::Auto;
    double fps = 0;  // > 0: frame n at n / fps; 0: the container's presentation times
    CameraId camera = CameraId::Front;
    std::optional<CameraCalibration> calibration;       // written to flight.json when given
    int bitrate_bps = 6'000'000;                        // when encoding
    std::int64_t max_frames = -1;                       // < 0: all
    std::function<void(std::int64_t frames)> progress;  // after each frame written
};

struct VideoImportSummary {
    std::int64_t frames = 0;
    int width = 0, height = 0;
    double fps = 0;                            // flight.json's: --fps, or the stream's average rate
    std::string codec;                         // the input's codec name (libavcodec)
    bool copied = false;                       // access units copied (true) or encoded again
    std::int64_t skipped_before_keyframe = 0;  // copy: access units before the first IDR
    std::int64_t decode_errors = 0;            // encode: packets the decoder refused
    std::int64_t timestamp_repairs = 0;        // frames with no or non-increasing time, given one
    bool untimed = false;  // the file has no frame times (raw H.264): frame n at n / fps
};

// Imports `input` into `out_dir` (created; must not exist or be empty). The error names the file
// and what went wrong.
[[nodiscard]] Expected<VideoImportSummary, std::string> import_video(
    const std::filesystem::path& input, const std::filesystem::path& out_dir,
    const VideoImportOptions& options);

}  // namespace gs::dataset
