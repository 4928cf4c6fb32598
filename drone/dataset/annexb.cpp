#include "drone/dataset/annexb.hpp"

#include <fstream>

namespace gs::dataset {

void AnnexBScanner::on_nal(std::uint64_t nal_start, int type, bool first_mb_zero) {
    if (first_start_ == kNone) first_start_ = nal_start;
    if (au_start_ == kNone) au_start_ = nal_start;
    const bool vcl = type == 1 || type == 5;
    const bool starts_au =
        type == 6 || type == 7 || type == 8 || type == 9 || (type >= 14 && type <= 18);
    if (seen_vcl_ && (starts_au || (vcl && first_mb_zero))) {
        units_.push_back({au_start_, nal_start - au_start_, au_idr_});
        au_start_ = nal_start;
        seen_vcl_ = false;
        au_idr_ = false;
    }
    if (vcl) seen_vcl_ = true;
    if (type == 5) au_idr_ = true;
}

void AnnexBScanner::feed(std::span<const std::uint8_t> bytes) {
    for (std::uint8_t b : bytes) {
        if (need_ == 2) {
            pending_type_ = b & 0x1F;
            const bool vcl = pending_type_ == 1 || pending_type_ == 5;
            if (vcl) {
                need_ = 1;
            } else {
                need_ = 0;
                on_nal(pending_start_, pending_type_, false);
            }
        } else if (need_ == 1) {
            need_ = 0;
            // first_mb_in_slice is ue(v); it is 0 exactly when the first bit is 1.
            on_nal(pending_start_, pending_type_, (b & 0x80) != 0);
        }
        if (b == 0) {
            if (zeros_ < 3) ++zeros_;
        } else {
            if (b == 1 && zeros_ >= 2) {
                pending_start_ = pos_ - static_cast<std::uint64_t>(zeros_);
                need_ = 2;
            }
            zeros_ = 0;
        }
        ++pos_;
    }
}

void AnnexBScanner::finish() {
    if (need_ == 1) on_nal(pending_start_, pending_type_, true);  // slice cut after its header
    need_ = 0;
    if (au_start_ != kNone && seen_vcl_) units_.push_back({au_start_, pos_ - au_start_, au_idr_});
    au_start_ = kNone;
    seen_vcl_ = false;
}

std::vector<AccessUnitSpan> split_access_units(std::span<const std::uint8_t> annexb) {
    AnnexBScanner s;
    s.feed(annexb);
    s.finish();
    return std::move(s.units());
}

bool annexb_has_idr(std::span<const std::uint8_t> annexb) {
    int zeros = 0;
    for (std::size_t i = 0; i < annexb.size(); ++i) {
        const std::uint8_t b = annexb[i];
        if (b == 0) {
            ++zeros;
            continue;
        }
        if (b == 1 && zeros >= 2 && i + 1 < annexb.size() && (annexb[i + 1] & 0x1F) == 5)
            return true;
        zeros = 0;
    }
    return false;
}

Expected<std::vector<AccessUnitSpan>, FileError> index_annexb_file(
    const std::filesystem::path& path, const std::string& name, std::uint64_t max_unit_bytes) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        return Unexpected(FileError{FileErrorCode::Io, name, 0, 0, "cannot open for reading"});
    }
    AnnexBScanner s;
    std::vector<std::uint8_t> buf(1u << 20);
    std::size_t checked = 0;
    while (in) {
        in.read(reinterpret_cast<char*>(buf.data()), static_cast<std::streamsize>(buf.size()));
        const auto n = static_cast<std::size_t>(in.gcount());
        if (n == 0) break;
        s.feed(std::span<const std::uint8_t>(buf.data(), n));
        for (; checked < s.units().size(); ++checked) {
            if (s.units()[checked].size > max_unit_bytes) break;
        }
        if (checked < s.units().size()) break;
    }
    if (in.bad()) return Unexpected(FileError{FileErrorCode::Io, name, 0, 0, "read failed"});
    s.finish();
    for (std::size_t i = 0; i < s.units().size(); ++i) {
        if (s.units()[i].size > max_unit_bytes) {
            return Unexpected(FileError{FileErrorCode::OutOfRange, name, 0, 0,
                                        "access unit " + std::to_string(i) + " is " +
                                            std::to_string(s.units()[i].size) + " bytes (limit " +
                                            std::to_string(max_unit_bytes) + ")"});
        }
    }
    return std::move(s.units());
}

}  // namespace gs::dataset
