#pragma once
// Splitting an H.264 Annex-B elementary stream into access units (one per frame) without
// decoding: the boundary rules of H.264 §7.4.1.2.3 (AUD/SPS/PPS/SEI after a slice, or a slice with
// first_mb_in_slice == 0 after a slice). Pure over bytes; a streaming scanner for large files.

#include "drone/core/expected.hpp"
#include "drone/core/file_error.hpp"

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

namespace gs::dataset {

struct AccessUnitSpan {
    std::uint64_t offset = 0;  // of its first start code
    std::uint64_t size = 0;
    bool idr = false;  // holds an IDR slice (NAL type 5)
};

// Feed bytes in order (any chunking); finish() closes the last access unit.
class AnnexBScanner {
public:
    void feed(std::span<const std::uint8_t> bytes);
    void finish();
    const std::vector<AccessUnitSpan>& units() const { return units_; }
    std::vector<AccessUnitSpan>& units() { return units_; }
    std::uint64_t bytes_seen() const { return pos_; }
    // Bytes before the first start code (junk a reader may warn about).
    std::uint64_t leading_junk() const { return first_start_ == kNone ? pos_ : first_start_; }

private:
    static constexpr std::uint64_t kNone = ~std::uint64_t{0};
    void on_nal(std::uint64_t nal_start, int type, bool first_mb_zero);
    std::vector<AccessUnitSpan> units_;
    std::uint64_t pos_ = 0;
    int zeros_ = 0;
    int need_ = 0;  // bytes still needed after a start code (header, first slice byte)
    int pending_type_ = 0;
    std::uint64_t pending_start_ = 0;
    std::uint64_t first_start_ = kNone;
    std::uint64_t au_start_ = kNone;
    bool seen_vcl_ = false;
    bool au_idr_ = false;
};

std::vector<AccessUnitSpan> split_access_units(std::span<const std::uint8_t> annexb);

// True when the bytes hold an IDR slice (NAL type 5).
bool annexb_has_idr(std::span<const std::uint8_t> annexb);

// Indexes a video.h264 file in bounded memory. `name` is what errors call the file. An access
// unit larger than `max_unit_bytes` is an OutOfRange error.
Expected<std::vector<AccessUnitSpan>, FileError> index_annexb_file(
    const std::filesystem::path& path, const std::string& name,
    std::uint64_t max_unit_bytes = 8u << 20);

}  // namespace gs::dataset
