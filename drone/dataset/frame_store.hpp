#pragma once
// Random access to a dataset's pixels: frame n as a BGR8 image of the dataset's size. Two
// implementations: an image folder (frames/, here) and video.h264 (video_frames.hpp, decoded).

#include "drone/dataset/dataset.hpp"

#include <opencv2/core.hpp>

#include <memory>
#include <optional>

namespace gs::dataset {

class FrameStore {
public:
    virtual ~FrameStore() = default;
    virtual std::int64_t count() const = 0;
    // Frame `index` into `out` (reused when the size matches). nullopt on success.
    [[nodiscard]] virtual std::optional<FileError> read(std::int64_t index, cv::Mat& out) = 0;
    // The frame read last was decoded with concealed damage (video only).
    virtual bool last_concealed() const { return false; }
    // ... was an intra picture that replaced concealed damage (video only).
    virtual bool last_repaired() const { return false; }
};

// Frames from the dataset's image files (frames/ or a thesis folder). Each image must decode and
// have the dataset's width and height; files larger than `max_file_bytes` are refused.
Expected<std::unique_ptr<FrameStore>, FileError> open_image_frames(
    const Dataset& d, std::uintmax_t max_file_bytes = 64u << 20);

}  // namespace gs::dataset
