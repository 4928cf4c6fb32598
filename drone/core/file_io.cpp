#include "drone/core/file_io.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>

namespace gs::inline core {
namespace fs = std::filesystem;

namespace {

FileError err(FileErrorCode code, const std::string& file, std::string msg) {
    return FileError{code, file, 0, 0, std::move(msg)};
}

FileError io_error(const std::string& name, const std::string& what) {
    return FileError{FileErrorCode::Io, name, 0, 0, what};
}

}  // namespace

Expected<std::string, FileError> read_text_file(const fs::path& path, const std::string& name,
                                                std::uintmax_t max_bytes) {
    std::error_code ec;
    const auto st = fs::status(path, ec);
    if (ec || !fs::exists(st))
        return Unexpected(err(FileErrorCode::Missing, name, "file not found"));
    if (!fs::is_regular_file(st))
        return Unexpected(err(FileErrorCode::Malformed, name, "not a regular file"));
    const auto size = fs::file_size(path, ec);
    if (ec) return Unexpected(err(FileErrorCode::Io, name, "cannot stat: " + ec.message()));
    if (size > max_bytes)
        return Unexpected(err(FileErrorCode::OutOfRange, name,
                              "file is " + std::to_string(size) + " bytes (limit " +
                                  std::to_string(max_bytes) + ")"));
    std::ifstream in(path, std::ios::binary);
    if (!in) return Unexpected(err(FileErrorCode::Io, name, "cannot open for reading"));
    std::string text(static_cast<std::size_t>(size), '\0');
    in.read(text.data(), static_cast<std::streamsize>(size));
    text.resize(static_cast<std::size_t>(in.gcount()));
    if (in.bad()) return Unexpected(err(FileErrorCode::Io, name, "read failed"));
    return text;
}

std::optional<FileError> write_file_atomic(const fs::path& path, std::string_view text,
                                           const std::string& name) {
    const fs::path tmp = path.string() + ".tmp";
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) return io_error(name, std::string("cannot create: ") + std::strerror(errno));
    std::size_t done = 0;
    while (done < text.size()) {
        const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            const int e = errno;
            ::close(fd);
            ::unlink(tmp.c_str());
            return io_error(name, std::string("write failed: ") + std::strerror(e));
        }
        done += static_cast<std::size_t>(n);
    }
    ::close(fd);
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        const int e = errno;
        ::unlink(tmp.c_str());
        return io_error(name, std::string("rename failed: ") + std::strerror(e));
    }
    return std::nullopt;
}

}  // namespace gs::inline core
