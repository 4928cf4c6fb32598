#pragma once
// A dataset's pixels from video.h264: access units located by the Annex-B index built at open,
// decoded with H264Decoder (drone/h264_decoder.hpp). Random access decodes forward from the
// nearest IDR at or before the frame; sequential reads decode one access unit each.

#include "drone/dataset/frame_store.hpp"

namespace gs::dataset {

// Frames decoded from the dataset's video.h264 (Missing when it has none).
Expected<std::unique_ptr<FrameStore>, FileError> open_video_frames(const Dataset& d);
// video.h264 when present (the source of truth), else the frames/ images.
Expected<std::unique_ptr<FrameStore>, FileError> open_frames(const Dataset& d);

}  // namespace gs::dataset
