#include "drone/protocol/pave.hpp"

#include <algorithm>
#include <cstring>

namespace gs::protocol {

std::string to_string(PaveCodec c) {
    switch (c) {
        case PaveCodec::Unknown:
            return "unknown";
        case PaveCodec::Vlib:
            return "VLIB";
        case PaveCodec::P264:
            return "P264";
        case PaveCodec::Mpeg4Visual:
            return "MPEG4";
        case PaveCodec::H264:
            return "H264";
    }
    return "unknown(" + std::to_string(static_cast<unsigned>(c)) + ")";
}

std::string to_string(PaveFrameType t) {
    switch (t) {
        case PaveFrameType::Unknown:
            return "unknown";
        case PaveFrameType::Idr:
            return "IDR";
        case PaveFrameType::I:
            return "I";
        case PaveFrameType::P:
            return "P";
        case PaveFrameType::Headers:
            return "headers";
    }
    return "unknown(" + std::to_string(static_cast<unsigned>(t)) + ")";
}

std::string to_string(PaveError e) {
    switch (e) {
        case PaveError::TooShort:
            return "too short for a PaVE header";
        case PaveError::BadSignature:
            return "bad PaVE signature";
        case PaveError::BadVersion:
            return "unsupported PaVE version";
        case PaveError::BadCodec:
            return "unknown PaVE video codec";
        case PaveError::BadHeaderSize:
            return "PaVE header_size out of range";
        case PaveError::PayloadTooLarge:
            return "PaVE payload_size above the cap";
        case PaveError::BufferTooSmall:
            return "output buffer smaller than header_size";
    }
    return "unknown PaVE error";
}

namespace {

std::uint16_t rd16(const std::uint8_t* p) {
    return static_cast<std::uint16_t>(p[0] | (p[1] << 8));
}
std::uint32_t rd32(const std::uint8_t* p) {
    return std::uint32_t{p[0]} | (std::uint32_t{p[1]} << 8) | (std::uint32_t{p[2]} << 16) |
           (std::uint32_t{p[3]} << 24);
}
void wr16(std::uint8_t* p, std::uint16_t v) {
    p[0] = static_cast<std::uint8_t>(v);
    p[1] = static_cast<std::uint8_t>(v >> 8);
}
void wr32(std::uint8_t* p, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}

enum class Check { Ok, NeedMore, Bad };
struct CheckResult {
    Check check;
    PaveError error = PaveError::TooShort;
};

bool valid_version(std::uint8_t v) {
    return v >= 1 && v <= kPaveCurrentVersion;
}
bool valid_codec(std::uint8_t c) {
    return c >= 1 && c <= 4;
}
bool valid_header_size(std::size_t hs) {
    return hs >= kPaveBaseHeaderSize && hs <= kPaveMaxHeaderSize;
}

// Validates as much of a header as `n` bytes allow, field by field in wire order, so a decision
// taken on a short prefix is the one the full header would give (chunking invariance).
CheckResult check_prefix(const std::uint8_t* p, std::size_t n, std::uint32_t max_payload) {
    if (n == 0) return {Check::NeedMore};  // p may be null: memcmp must not see it
    if (n < 4) {
        return {std::memcmp(p, kPaveSignature.data(), n) == 0 ? Check::NeedMore : Check::Bad,
                PaveError::BadSignature};
    }
    if (std::memcmp(p, kPaveSignature.data(), 4) != 0) return {Check::Bad, PaveError::BadSignature};
    if (n < 5) return {Check::NeedMore};
    if (!valid_version(p[4])) return {Check::Bad, PaveError::BadVersion};
    if (n < 6) return {Check::NeedMore};
    if (!valid_codec(p[5])) return {Check::Bad, PaveError::BadCodec};
    if (n < 8) return {Check::NeedMore};
    const std::size_t hs = rd16(p + 6);
    if (!valid_header_size(hs)) return {Check::Bad, PaveError::BadHeaderSize};
    if (n < kPavePrefixSize) return {Check::NeedMore};
    if (rd32(p + 8) > max_payload) return {Check::Bad, PaveError::PayloadTooLarge};
    if (n < hs) return {Check::NeedMore};
    return {Check::Ok};
}

// Decodes a header already validated by check_prefix.
PaveHeader decode(const std::uint8_t* p) {
    PaveHeader h;
    std::memcpy(h.signature.data(), p, 4);
    h.version = p[4];
    h.video_codec = static_cast<PaveCodec>(p[5]);
    h.header_size = rd16(p + 6);
    h.payload_size = rd32(p + 8);
    h.encoded_stream_width = rd16(p + 12);
    h.encoded_stream_height = rd16(p + 14);
    h.display_width = rd16(p + 16);
    h.display_height = rd16(p + 18);
    h.frame_number = rd32(p + 20);
    h.timestamp = rd32(p + 24);
    h.total_chuncks = p[28];
    h.chunck_index = p[29];
    h.frame_type = static_cast<PaveFrameType>(p[30]);
    h.control = p[31];
    h.stream_byte_position_lw = rd32(p + 32);
    h.stream_byte_position_uw = rd32(p + 36);
    h.stream_id = rd16(p + 40);
    h.total_slices = p[42];
    h.slice_index = p[43];
    h.header1_size = p[44];
    h.header2_size = p[45];
    std::memcpy(h.reserved2.data(), p + 46, 2);
    h.advertised_size = rd32(p + 48);
    std::memcpy(h.reserved3.data(), p + 52, 12);
    if (h.header_size >= kPaveBaseHeaderSize + 4) std::memcpy(h.extension.data(), p + 64, 4);
    return h;
}

// Offset of the first full signature in p[0, n); failing that, of the start of a trailing
// partial signature that more bytes could complete; failing that, n.
std::size_t find_signature(const std::uint8_t* p, std::size_t n) {
    std::size_t i = 0;
    while (i < n) {
        const void* hit = std::memchr(p + i, kPaveSignature[0], n - i);
        if (hit == nullptr) return n;
        i = static_cast<std::size_t>(static_cast<const std::uint8_t*>(hit) - p);
        const std::size_t m = std::min<std::size_t>(4, n - i);
        if (std::memcmp(p + i, kPaveSignature.data(), m) == 0) return i;
        ++i;
    }
    return n;
}

}  // namespace

Expected<PaveHeader, PaveError> parse_pave_header(std::span<const std::uint8_t> bytes,
                                                  std::uint32_t max_payload_size) {
    const CheckResult r = check_prefix(bytes.data(), bytes.size(), max_payload_size);
    if (r.check == Check::NeedMore) return Unexpected{PaveError::TooShort};
    if (r.check == Check::Bad) return Unexpected{r.error};
    return decode(bytes.data());
}

Expected<std::size_t, PaveError> write_pave_header(const PaveHeader& h, std::span<std::uint8_t> out,
                                                   std::uint32_t max_payload_size) {
    if (h.signature != kPaveSignature) return Unexpected{PaveError::BadSignature};
    if (!valid_version(h.version)) return Unexpected{PaveError::BadVersion};
    if (!valid_codec(static_cast<std::uint8_t>(h.video_codec))) {
        return Unexpected{PaveError::BadCodec};
    }
    if (!valid_header_size(h.header_size)) return Unexpected{PaveError::BadHeaderSize};
    if (h.payload_size > max_payload_size) return Unexpected{PaveError::PayloadTooLarge};
    if (out.size() < h.header_size) return Unexpected{PaveError::BufferTooSmall};

    std::uint8_t* p = out.data();
    std::memset(p, 0, h.header_size);
    std::memcpy(p, h.signature.data(), 4);
    p[4] = h.version;
    p[5] = static_cast<std::uint8_t>(h.video_codec);
    wr16(p + 6, h.header_size);
    wr32(p + 8, h.payload_size);
    wr16(p + 12, h.encoded_stream_width);
    wr16(p + 14, h.encoded_stream_height);
    wr16(p + 16, h.display_width);
    wr16(p + 18, h.display_height);
    wr32(p + 20, h.frame_number);
    wr32(p + 24, h.timestamp);
    p[28] = h.total_chuncks;
    p[29] = h.chunck_index;
    p[30] = static_cast<std::uint8_t>(h.frame_type);
    p[31] = h.control;
    wr32(p + 32, h.stream_byte_position_lw);
    wr32(p + 36, h.stream_byte_position_uw);
    wr16(p + 40, h.stream_id);
    p[42] = h.total_slices;
    p[43] = h.slice_index;
    p[44] = h.header1_size;
    p[45] = h.header2_size;
    std::memcpy(p + 46, h.reserved2.data(), 2);
    wr32(p + 48, h.advertised_size);
    std::memcpy(p + 52, h.reserved3.data(), 12);
    if (h.header_size >= kPaveBaseHeaderSize + 4) std::memcpy(p + 64, h.extension.data(), 4);
    return std::size_t{h.header_size};
}

// ---- PaveFramer -----------------------------------------------------------------------------

PaveFramer::PaveFramer(PaveFramerConfig config) : config_(config) {}

void PaveFramer::push(std::span<const std::uint8_t> bytes) {
    stats_.bytes_in += bytes.size();
    if (pos_ == buf_.size()) {
        buf_.clear();
        pos_ = 0;
    } else if (pos_ > 0 && buf_.size() + bytes.size() > buf_.capacity()) {
        // Compact only when the buffer would grow: keeps 1-byte pushes linear overall.
        buf_.erase(buf_.begin(), buf_.begin() + static_cast<std::ptrdiff_t>(pos_));
        pos_ = 0;
    }
    buf_.insert(buf_.end(), bytes.begin(), bytes.end());
}

void PaveFramer::skip(std::size_t n, PaveError reason) {
    if (skip_run_ == 0) {
        skip_start_ = pos_offset_;
        skip_reason_ = reason;
    }
    skip_run_ += n;
    stats_.bytes_skipped += n;
    pos_ += n;
    pos_offset_ += n;
}

std::optional<PaveEvent> PaveFramer::next() {
    for (;;) {
        const std::size_t n = unread();
        if (n == 0) return std::nullopt;
        const std::uint8_t* p = buf_.data() + pos_;

        const std::size_t sig = find_signature(p, n);
        if (sig > 0) {
            skip(sig, PaveError::BadSignature);
            continue;
        }
        const CheckResult r = check_prefix(p, n, config_.max_payload_size);
        if (r.check == Check::NeedMore) return std::nullopt;
        if (r.check == Check::Bad) {
            // A signature followed by nonsense: corruption or "PaVE" inside payload bytes.
            if (r.error == PaveError::PayloadTooLarge) ++stats_.oversize_rejections;
            skip(1, r.error);
            continue;
        }
        if (skip_run_ > 0) {  // a valid header ends the skip run: report it before the frame
            PaveResync ev{skip_start_, skip_run_, skip_reason_};
            skip_run_ = 0;
            ++stats_.resyncs;
            return ev;
        }
        PaveHeader h = decode(p);
        const std::size_t total = std::size_t{h.header_size} + h.payload_size;
        if (n < total) return std::nullopt;

        PaveFrame f;
        f.index = stats_.frames;
        f.stream_offset = pos_offset_;
        f.payload = std::span<const std::uint8_t>(p + h.header_size, h.payload_size);
        f.header = h;
        ++stats_.frames;
        stats_.payload_bytes += h.payload_size;
        pos_ += total;
        pos_offset_ += total;
        return f;
    }
}

PavePending PaveFramer::pending() const {
    PavePending out;
    out.buffered_bytes = unread();
    out.unreported_skip = skip_run_;
    const std::uint8_t* p = buf_.data() + pos_;
    if (out.buffered_bytes > 0 &&
        check_prefix(p, out.buffered_bytes, config_.max_payload_size).check == Check::Ok) {
        out.header = decode(p);
        out.header_offset = pos_offset_;
    }
    return out;
}

void PaveFramer::reset() {
    buf_.clear();
    pos_ = 0;
    pos_offset_ = stats_.bytes_in;
    skip_run_ = 0;
}

}  // namespace gs::protocol
