#include "drone/dataset/raw.hpp"

#include "drone/dataset/dataset.hpp"

#include <charconv>
#include <cstdio>

namespace gs::dataset {
namespace {

void put_le(std::string& out, std::uint64_t v, int bytes) {
    for (int i = 0; i < bytes; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}
std::uint64_t get_le(const std::uint8_t* p, int bytes) {
    std::uint64_t v = 0;
    for (int i = 0; i < bytes; ++i) v |= std::uint64_t{p[i]} << (8 * i);
    return v;
}

Expected<std::vector<std::uint8_t>, FileError> read_binary(const std::filesystem::path& path,
                                                           const std::string& name,
                                                           std::uintmax_t max_bytes) {
    GS_TRY_ASSIGN(auto text, read_text_file(path, name, max_bytes));
    return std::vector<std::uint8_t>(text.begin(), text.end());
}

// The warning for a binary file of records that ends inside record `index` (at byte `at`: `have`
// of its `need` bytes are there).
std::string cut_record_warning(const std::string& name, std::size_t index, std::size_t at,
                               std::size_t have, std::size_t need) {
    return name + ": incomplete last record (record " + std::to_string(index) + " at byte " +
           std::to_string(at) + ": " + std::to_string(have) + " of " + std::to_string(need) +
           " bytes) ignored: the recording was cut short";
}

}  // namespace

void append_raw_record(std::string& out, std::int64_t t_us, std::span<const std::uint8_t> payload) {
    put_le(out, static_cast<std::uint64_t>(t_us), 8);
    put_le(out, payload.size(), 4);
    out.append(reinterpret_cast<const char*>(payload.data()), payload.size());
}

void append_chunk_record(std::string& out, std::int64_t t_us, std::uint32_t length) {
    put_le(out, static_cast<std::uint64_t>(t_us), 8);
    put_le(out, length, 4);
}

void append_at_line(std::string& out, std::int64_t t_us, std::string_view datagram) {
    out += std::to_string(t_us);
    out += ' ';
    for (char ch : datagram) {
        const auto u = static_cast<unsigned char>(ch);
        if (ch == '\\') {
            out += "\\\\";
        } else if (ch == '\r') {
            out += "\\r";
        } else if (ch == '\n') {
            out += "\\n";
        } else if (u < 0x20 || u == 0x7F) {
            char b[8];
            std::snprintf(b, sizeof b, "\\x%02X", u);
            out += b;
        } else {
            out += ch;
        }
    }
    out += '\n';
}

Expected<RawReadResult, FileError> parse_navdata_bin(std::span<const std::uint8_t> bytes,
                                                     const std::string& name,
                                                     std::vector<std::string>* warnings) {
    RawReadResult r;
    std::size_t pos = 0;
    std::int64_t prev = 0;
    // The file ends inside the record at `pos` (docs/dataset.md 1.1: a cut recording).
    auto cut = [&](std::size_t record_bytes) {
        r.truncated_tail = true;
        if (warnings)
            warnings->push_back(
                cut_record_warning(name, r.records.size(), pos, bytes.size() - pos, record_bytes));
    };
    while (pos < bytes.size()) {
        if (bytes.size() - pos < 12) {
            cut(12);
            break;
        }
        const auto t = static_cast<std::int64_t>(get_le(bytes.data() + pos, 8));
        const auto len = static_cast<std::uint32_t>(get_le(bytes.data() + pos + 8, 4));
        if (len > kMaxRawDatagram)
            return Unexpected(FileError{FileErrorCode::OutOfRange, name, 0, 0,
                                        "record " + std::to_string(r.records.size()) + " at byte " +
                                            std::to_string(pos) + " claims " + std::to_string(len) +
                                            " bytes (limit " + std::to_string(kMaxRawDatagram) +
                                            ")"});
        if (t < prev)
            return Unexpected(FileError{FileErrorCode::Inconsistent, name, 0, 0,
                                        "record " + std::to_string(r.records.size()) + " at byte " +
                                            std::to_string(pos) + ": time goes backwards"});
        if (bytes.size() - pos - 12 < len) {
            cut(12 + std::size_t{len});
            break;
        }
        prev = t;
        r.records.push_back({t, std::vector<std::uint8_t>(
                                    bytes.begin() + static_cast<std::ptrdiff_t>(pos + 12),
                                    bytes.begin() + static_cast<std::ptrdiff_t>(pos + 12 + len))});
        pos += 12 + len;
    }
    return r;
}

Expected<std::vector<RawChunk>, FileError> parse_video_chunks(std::span<const std::uint8_t> bytes,
                                                              const std::string& name,
                                                              std::vector<std::string>* warnings) {
    std::vector<RawChunk> out;
    std::uint64_t offset = 0;
    std::size_t pos = 0;
    for (; pos + 12 <= bytes.size(); pos += 12) {
        RawChunk c;
        c.t_us = static_cast<std::int64_t>(get_le(bytes.data() + pos, 8));
        c.length = static_cast<std::uint32_t>(get_le(bytes.data() + pos + 8, 4));
        c.offset = offset;
        if (!out.empty() && c.t_us < out.back().t_us)
            return Unexpected(
                FileError{FileErrorCode::Inconsistent, name, 0, 0,
                          "record " + std::to_string(out.size()) + ": time goes backwards"});
        offset += c.length;
        out.push_back(c);
    }
    if (pos < bytes.size() && warnings)
        warnings->push_back(cut_record_warning(name, out.size(), pos, bytes.size() - pos, 12));
    return out;
}

Expected<std::vector<AtRecord>, FileError> parse_at_log(std::string_view text,
                                                        const std::string& name,
                                                        std::vector<std::string>* warnings) {
    std::vector<AtRecord> out;
    int line_no = 0;
    std::size_t pos = 0;
    while (pos < text.size()) {
        const std::size_t nl = text.find('\n', pos);
        if (nl == std::string_view::npos) {  // partial last line of a killed recording
            if (warnings)
                warnings->push_back(name + ":" + std::to_string(line_no + 1) +
                                    ": incomplete last line (" + std::to_string(text.size() - pos) +
                                    " bytes, no newline) ignored: the recording was cut short");
            break;
        }
        std::string_view line = text.substr(pos, nl - pos);
        pos = nl + 1;
        ++line_no;
        auto bad = [&](int col, const std::string& msg) {
            return Unexpected(FileError{FileErrorCode::Malformed, name, line_no, col, msg});
        };
        const std::size_t sp = line.find(' ');
        if (sp == std::string_view::npos) return bad(1, "expected '<t_us> <datagram>'");
        AtRecord rec;
        auto [p, ec] = std::from_chars(line.data(), line.data() + sp, rec.t_us);
        if (ec != std::errc() || p != line.data() + sp || rec.t_us < 0)
            return bad(1, "expected a time in microseconds");
        for (std::size_t i = sp + 1; i < line.size(); ++i) {
            const char ch = line[i];
            if (ch != '\\') {
                rec.datagram += ch;
                continue;
            }
            const int col = static_cast<int>(i + 1);
            if (i + 1 >= line.size()) return bad(col, "dangling backslash");
            const char e = line[++i];
            if (e == '\\') {
                rec.datagram += '\\';
            } else if (e == 'r') {
                rec.datagram += '\r';
            } else if (e == 'n') {
                rec.datagram += '\n';
            } else if (e == 'x' && i + 2 < line.size()) {
                unsigned v = 0;
                auto [q, ec2] = std::from_chars(line.data() + i + 1, line.data() + i + 3, v, 16);
                if (ec2 != std::errc() || q != line.data() + i + 3)
                    return bad(col, "bad \\x escape");
                rec.datagram += static_cast<char>(v);
                i += 2;
            } else {
                return bad(col, std::string("unknown escape \\") + e);
            }
        }
        out.push_back(std::move(rec));
    }
    return out;
}

Expected<std::filesystem::path, FileError> raw_file_path(const std::filesystem::path& raw_dir,
                                                         const std::string& name) {
    const std::filesystem::path dataset = raw_dir.parent_path();
    return resolve_fixed(dataset, (raw_dir.filename() / name).generic_string());
}

Expected<RawReadResult, FileError> read_navdata_bin(const std::filesystem::path& raw_dir,
                                                    std::vector<std::string>* warnings,
                                                    std::uintmax_t max_bytes) {
    GS_TRY_ASSIGN(auto p, raw_file_path(raw_dir, "navdata.bin"));
    GS_TRY_ASSIGN(auto b, read_binary(p, "raw/navdata.bin", max_bytes));
    return parse_navdata_bin(b, "raw/navdata.bin", warnings);
}

Expected<std::vector<AtRecord>, FileError> read_at_log(const std::filesystem::path& raw_dir,
                                                       std::vector<std::string>* warnings,
                                                       std::uintmax_t max_bytes) {
    GS_TRY_ASSIGN(auto p, raw_file_path(raw_dir, "at.log"));
    GS_TRY_ASSIGN(auto t, read_text_file(p, "raw/at.log", max_bytes));
    return parse_at_log(t, "raw/at.log", warnings);
}

Expected<std::vector<RawChunk>, FileError> read_video_chunks(const std::filesystem::path& raw_dir,
                                                             std::vector<std::string>* warnings,
                                                             std::uintmax_t max_bytes) {
    GS_TRY_ASSIGN(auto p, raw_file_path(raw_dir, "video_chunks.bin"));
    GS_TRY_ASSIGN(auto b, read_binary(p, "raw/video_chunks.bin", max_bytes));
    return parse_video_chunks(b, "raw/video_chunks.bin", warnings);
}

}  // namespace gs::dataset
