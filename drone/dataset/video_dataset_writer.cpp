#include "drone/dataset/video_dataset_writer.hpp"

#include "drone/core/file_io.hpp"
#include "drone/dataset/writer.hpp"

namespace gs::dataset {

namespace fs = std::filesystem;

VideoDatasetWriter::VideoDatasetWriter(fs::path dir)
    : dir_(std::move(dir)), frames_csv_(frames_csv_header()) {}

Expected<VideoDatasetWriter, std::string> VideoDatasetWriter::create(const fs::path& dir) {
    std::error_code ec;
    if (fs::exists(dir, ec) && (!fs::is_directory(dir, ec) || !fs::is_empty(dir, ec)))
        return Unexpected(dir.string() + " exists and is not an empty directory");
    fs::create_directories(dir, ec);
    if (ec) return Unexpected("cannot create " + dir.string() + ": " + ec.message());
    VideoDatasetWriter w(dir);
    w.video_.open(dir / "video.h264", std::ios::binary);
    if (!w.video_) return Unexpected("cannot create " + (dir / "video.h264").string());
    return w;
}

void VideoDatasetWriter::add(std::span<const std::uint8_t> access_unit, FrameRow row) {
    video_.write(reinterpret_cast<const char*>(access_unit.data()),
                 static_cast<std::streamsize>(access_unit.size()));
    video_bytes_ += access_unit.size();
    row.frame = frames_++;
    frames_csv_ += frames_csv_row(row);
}

std::optional<std::string> VideoDatasetWriter::finish(DatasetInfo info, const ExtraFiles& extra) {
    info.frames = frames_;
    return finish_with(flight_json_text(info), extra);
}

std::optional<std::string> VideoDatasetWriter::finish_with(const std::string& flight_json,
                                                           const ExtraFiles& extra) {
    video_.close();
    if (!video_) return "cannot write " + (dir_ / "video.h264").string();
    if (auto e = write_file_atomic(dir_ / "frames.csv", frames_csv_, "frames.csv"))
        return to_string(*e);
    for (const auto& [name, text] : extra)
        if (auto e = write_file_atomic(dir_ / name, text, name)) return to_string(*e);
    // flight.json last: a half-written flight is not a dataset.
    if (auto e = write_file_atomic(dir_ / "flight.json", flight_json, "flight.json"))
        return to_string(*e);
    return std::nullopt;
}

}  // namespace gs::dataset
