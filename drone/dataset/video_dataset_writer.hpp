#pragma once
// Writes a dataset of H.264 video (docs/dataset.md: video.h264, frames.csv, flight.json) in one
// pass, synchronously, for a producer that holds each frame's values when it writes the frame: an
// imported video, a rendered flight, a closed-loop evaluation. (A live recording, whose navdata
// arrives after the frames it describes, goes through DatasetWriter.) Access units go to
// video.h264 as they come; frames.csv and any extra files are written whole by finish(), each
// through a temporary file, and flight.json last: a folder a run left half-written has no
// flight.json, so no reader takes it for a flight.

#include "drone/core/expected.hpp"
#include "drone/dataset/dataset.hpp"

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace gs::dataset {

class VideoDatasetWriter {
public:
    // Creates `dir`, which must not exist or be empty, and its video.h264.
    static Expected<VideoDatasetWriter, std::string> create(const std::filesystem::path& dir);

    // Appends one access unit and its frames.csv row; the row's frame number is set to the
    // frame's index (0, 1, ...), the order of the access units in video.h264.
    void add(std::span<const std::uint8_t> access_unit, FrameRow row);
    std::int64_t frames() const { return frames_; }
    std::uint64_t video_bytes() const { return video_bytes_; }
    const std::filesystem::path& dir() const { return dir_; }

    // Other files of the dataset (labels.csv, labels.json, ...): name in the folder, content.
    using ExtraFiles = std::vector<std::pair<std::string, std::string>>;
    // Closes video.h264 and writes frames.csv, the extra files, then flight.json from `info`
    // (its frame count set to frames()). An error names the file.
    [[nodiscard]] std::optional<std::string> finish(DatasetInfo info, const ExtraFiles& extra = {});
    // The same with flight.json's text given (flight_json_text() of the info, with keys added).
    [[nodiscard]] std::optional<std::string> finish_with(const std::string& flight_json,
                                                         const ExtraFiles& extra = {});

private:
    explicit VideoDatasetWriter(std::filesystem::path dir);

    std::filesystem::path dir_;
    std::ofstream video_;
    std::string frames_csv_;
    std::int64_t frames_ = 0;
    std::uint64_t video_bytes_ = 0;
};

}  // namespace gs::dataset
