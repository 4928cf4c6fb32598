#pragma once
// The raw/ captures of a recording (docs/dataset.md "raw/"), for bit-exact replay:
//   raw/navdata.bin   records {u64 t_us LE, u32 length LE, payload[length]}, one per UDP datagram
//   raw/at.log        one line per AT datagram sent: "<t_us> <datagram>", the datagram escaped
//                     (\\ \r \n and \xHH for other control bytes) so each stays on one line
//   raw/video.pave    the TCP byte stream of the video port, as received
//   raw/video_chunks.bin  (extension) records {u64 t_us LE, u32 length LE}: when each received
//                     chunk of video.pave arrived, so replay knows frame receive times
// t_us is microseconds since the start of the recording on the receiver's monotonic clock.
// A recording killed mid-write (power loss, a full disk) may end in a partial record or line:
// readers leave it out and report it in `warnings` (docs/dataset.md 1.1: "read with a warning"),
// naming the file, rather than fail on it.

#include "drone/core/expected.hpp"
#include "drone/core/file_error.hpp"

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace gs::dataset {

struct RawRecord {
    std::int64_t t_us = 0;
    std::vector<std::uint8_t> payload;
};

struct RawChunk {
    std::int64_t t_us = 0;
    std::uint64_t offset = 0;  // in video.pave
    std::uint32_t length = 0;
};

struct AtRecord {
    std::int64_t t_us = 0;
    std::string datagram;
};

// Largest navdata datagram accepted (a UDP payload cannot be larger).
inline constexpr std::uint32_t kMaxRawDatagram = 65507;

void append_raw_record(std::string& out, std::int64_t t_us, std::span<const std::uint8_t> payload);
void append_chunk_record(std::string& out, std::int64_t t_us, std::uint32_t length);
void append_at_line(std::string& out, std::int64_t t_us, std::string_view datagram);

struct RawReadResult {
    std::vector<RawRecord> records;
    bool truncated_tail = false;  // the file ends inside a record (killed recording)
};

// `name` is what errors and warnings call the file ("raw/navdata.bin"). A file that ends inside
// its last record or line gives everything before it, and one warning in `warnings` (when given)
// naming the file and where it was cut.
Expected<RawReadResult, FileError> parse_navdata_bin(std::span<const std::uint8_t> bytes,
                                                     const std::string& name = "raw/navdata.bin",
                                                     std::vector<std::string>* warnings = nullptr);
Expected<std::vector<RawChunk>, FileError> parse_video_chunks(
    std::span<const std::uint8_t> bytes, const std::string& name = "raw/video_chunks.bin",
    std::vector<std::string>* warnings = nullptr);
Expected<std::vector<AtRecord>, FileError> parse_at_log(
    std::string_view text, const std::string& name = "raw/at.log",
    std::vector<std::string>* warnings = nullptr);

// File readers (bounded by `max_bytes`).
// `name` inside `raw_dir` (a dataset's raw/), or UnsafePath when it, or raw/ itself, leads out of
// the dataset directory (raw_dir's parent) through symlinks.
Expected<std::filesystem::path, FileError> raw_file_path(const std::filesystem::path& raw_dir,
                                                         const std::string& name);

Expected<RawReadResult, FileError> read_navdata_bin(const std::filesystem::path& raw_dir,
                                                    std::vector<std::string>* warnings = nullptr,
                                                    std::uintmax_t max_bytes = 2ull << 30);
Expected<std::vector<AtRecord>, FileError> read_at_log(const std::filesystem::path& raw_dir,
                                                       std::vector<std::string>* warnings = nullptr,
                                                       std::uintmax_t max_bytes = 1ull << 30);
Expected<std::vector<RawChunk>, FileError> read_video_chunks(
    const std::filesystem::path& raw_dir, std::vector<std::string>* warnings = nullptr,
    std::uintmax_t max_bytes = 1ull << 30);

}  // namespace gs::dataset
