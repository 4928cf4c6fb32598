#include "drone/dataset/video_frames.hpp"

#include "drone/video/h264_decoder.hpp"

#include <fstream>

namespace gs::dataset {
namespace {

class VideoFrames final : public FrameStore {
public:
    explicit VideoFrames(const Dataset& d)
        : path_(*d.video_path()),
          name_(d.info().video),
          units_(d.video_units()),
          width_(d.info().width),
          height_(d.info().height),
          in_(path_, std::ios::binary) {}

    bool ok() const { return static_cast<bool>(in_); }
    std::int64_t count() const override { return static_cast<std::int64_t>(units_.size()); }
    bool last_concealed() const override { return concealed_; }
    bool last_repaired() const override { return repaired_; }

    std::optional<FileError> read(std::int64_t index, cv::Mat& out) override {
        if (index < 0 || index >= count())
            return err(FileErrorCode::OutOfRange, "no access unit " + std::to_string(index));
        std::int64_t from = index;
        if (index != last_ + 1 || last_ < 0) {
            // Random access: restart at the last IDR at or before `index`.
            while (from >= 0 && !units_[static_cast<std::size_t>(from)].idr) --from;
            if (from < 0)
                return err(FileErrorCode::Malformed,
                           "no IDR at or before access unit " + std::to_string(index));
            decoder_.reset();
        }
        for (std::int64_t i = from; i <= index; ++i) {
            last_ = -1;
            const auto& u = units_[static_cast<std::size_t>(i)];
            buf_.resize(static_cast<std::size_t>(u.size));
            in_.clear();
            in_.seekg(static_cast<std::streamoff>(u.offset));
            in_.read(reinterpret_cast<char*>(buf_.data()), static_cast<std::streamsize>(u.size));
            if (!in_)
                return err(FileErrorCode::Io, "read failed at access unit " + std::to_string(i));
            video::AccessUnit au;
            au.data = buf_;
            au.frame_number = static_cast<std::uint32_t>(i);
            au.display_width = width_;
            au.display_height = height_;
            const video::H264DecoderStats before = decoder_.stats();
            auto r = decoder_.decode(au, out);
            concealed_ = decoder_.stats().concealed > before.concealed;
            repaired_ = decoder_.stats().repaired > before.repaired;
            // The decoder has taken this unit whatever came out: the next frame in order goes on
            // from here, so one damaged unit costs its own frame, not the rest of its GOP. A
            // damaged unit before the one asked for is concealed by the decoder.
            last_ = i;
            if (i < index) continue;
            if (!r)
                return err(FileErrorCode::Malformed,
                           "access unit " + std::to_string(i) + ": " + to_string(r.error()));
            if (*r != video::DecodeStatus::Frame)
                return err(FileErrorCode::Malformed,
                           "access unit " + std::to_string(i) + " produced no picture");
        }
        if (out.cols != width_ || out.rows != height_)
            return err(FileErrorCode::Inconsistent,
                       "decoded " + std::to_string(out.cols) + "x" + std::to_string(out.rows) +
                           ", flight.json says " + std::to_string(width_) + "x" +
                           std::to_string(height_));
        last_ = index;
        return std::nullopt;
    }

private:
    FileError err(FileErrorCode c, std::string msg) const {
        return FileError{c, name_, 0, 0, std::move(msg)};
    }
    std::filesystem::path path_;
    std::string name_;
    std::vector<AccessUnitSpan> units_;
    int width_, height_;
    std::ifstream in_;
    video::H264Decoder decoder_;
    std::vector<std::uint8_t> buf_;
    std::int64_t last_ = -1;
    bool concealed_ = false;
    bool repaired_ = false;
};

}  // namespace

Expected<std::unique_ptr<FrameStore>, FileError> open_video_frames(const Dataset& d) {
    if (!d.video_path())
        return Unexpected(
            FileError{FileErrorCode::Missing, d.info().video, 0, 0, "the dataset has no video"});
    auto v = std::make_unique<VideoFrames>(d);
    if (!v->ok())
        return Unexpected(
            FileError{FileErrorCode::Io, d.info().video, 0, 0, "cannot open for reading"});
    return std::unique_ptr<FrameStore>(std::move(v));
}

Expected<std::unique_ptr<FrameStore>, FileError> open_frames(const Dataset& d) {
    if (d.video_path()) return open_video_frames(d);
    return open_image_frames(d);
}

}  // namespace gs::dataset
