#include "drone/dataset/frame_store.hpp"

#include <opencv2/imgcodecs.hpp>

#include <fstream>

namespace gs::dataset {
namespace {

class ImageFrames final : public FrameStore {
public:
    ImageFrames(const Dataset& d, std::uintmax_t max_bytes)
        : dir_(d.dir()),
          files_(d.image_files()),
          width_(d.info().width),
          height_(d.info().height),
          max_bytes_(max_bytes) {}

    std::int64_t count() const override { return static_cast<std::int64_t>(files_.size()); }

    std::optional<FileError> read(std::int64_t index, cv::Mat& out) override {
        if (index < 0 || index >= count())
            return FileError{FileErrorCode::OutOfRange, "frames/", 0, 0,
                             "no frame " + std::to_string(index)};
        const auto& path = files_[static_cast<std::size_t>(index)];
        std::error_code ec;
        std::string name = std::filesystem::relative(path, dir_, ec).generic_string();
        if (ec || name.empty()) name = path.filename().string();
        const auto size = std::filesystem::file_size(path, ec);
        if (ec) return FileError{FileErrorCode::Io, name, 0, 0, ec.message()};
        if (size > max_bytes_)
            return FileError{FileErrorCode::OutOfRange, name, 0, 0,
                             "image file is " + std::to_string(size) + " bytes (limit " +
                                 std::to_string(max_bytes_) + ")"};
        buf_.resize(static_cast<std::size_t>(size));
        std::ifstream in(path, std::ios::binary);
        in.read(reinterpret_cast<char*>(buf_.data()), static_cast<std::streamsize>(size));
        if (!in) return FileError{FileErrorCode::Io, name, 0, 0, "read failed"};
        // Refuse a PNG whose header announces another size before decoding it (pixel bombs).
        if (buf_.size() >= 24 && buf_[0] == 0x89 && buf_[1] == 'P' && buf_[2] == 'N' &&
            buf_[3] == 'G') {
            auto be32 = [&](std::size_t o) {
                return (std::uint32_t{buf_[o]} << 24) | (std::uint32_t{buf_[o + 1]} << 16) |
                       (std::uint32_t{buf_[o + 2]} << 8) | std::uint32_t{buf_[o + 3]};
            };
            const std::uint32_t w = be32(16), h = be32(20);
            if (w != static_cast<std::uint32_t>(width_) || h != static_cast<std::uint32_t>(height_))
                return FileError{FileErrorCode::Inconsistent, name, 0, 0,
                                 "image is " + std::to_string(w) + "x" + std::to_string(h) +
                                     ", flight.json says " + std::to_string(width_) + "x" +
                                     std::to_string(height_)};
        }
        cv::Mat img;
        try {
            img = cv::imdecode(buf_, cv::IMREAD_COLOR);
        } catch (const cv::Exception&) {
            img.release();
        }
        if (img.empty())
            return FileError{FileErrorCode::Malformed, name, 0, 0,
                             "not a decodable PNG/JPEG image"};
        if (img.cols != width_ || img.rows != height_)
            return FileError{FileErrorCode::Inconsistent, name, 0, 0,
                             "image is " + std::to_string(img.cols) + "x" +
                                 std::to_string(img.rows) + ", flight.json says " +
                                 std::to_string(width_) + "x" + std::to_string(height_)};
        out = img;
        return std::nullopt;
    }

private:
    std::filesystem::path dir_;
    std::vector<std::filesystem::path> files_;
    int width_, height_;
    std::uintmax_t max_bytes_;
    std::vector<std::uint8_t> buf_;
};

}  // namespace

Expected<std::unique_ptr<FrameStore>, FileError> open_image_frames(const Dataset& d,
                                                                   std::uintmax_t max_bytes) {
    if (static_cast<std::int64_t>(d.image_files().size()) != d.frame_count())
        return Unexpected(FileError{FileErrorCode::Missing, d.info().images + "/", 0, 0,
                                    "no image folder with one image per frame"});
    return std::unique_ptr<FrameStore>(std::make_unique<ImageFrames>(d, max_bytes));
}

}  // namespace gs::dataset
