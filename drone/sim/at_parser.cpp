#include "drone/sim/at_parser.hpp"

#include <array>
#include <bit>
#include <charconv>
#include <limits>

namespace gs::sim::at {

std::string_view to_string(SkipReason r) {
    switch (r) {
        case SkipReason::NotAtCommand:
            return "not an AT*NAME= command";
        case SkipReason::UnknownCommand:
            return "unknown command";
        case SkipReason::BadSequence:
            return "bad sequence number";
        case SkipReason::BadNumber:
            return "bad integer argument";
        case SkipReason::BadString:
            return "bad quoted argument";
        case SkipReason::WrongArgCount:
            return "wrong number of arguments";
        case SkipReason::Unterminated:
            return "command not terminated by CR or LF";
    }
    return "unknown skip reason";
}

std::string_view to_string(DatagramError e) {
    switch (e) {
        case DatagramError::TooLong:
            return "AT datagram longer than 1024 bytes";
    }
    return "unknown datagram error";
}

namespace {

struct Field {
    std::string_view text;  // without the quotes when quoted
    bool quoted = false;
};

// The arguments of one command. 7 (PCMD_MAG) is the most any modelled command takes; one more
// slot lets "too many arguments" be told apart from "exactly enough".
constexpr std::size_t kMaxFields = 8;

struct Fields {
    std::array<Field, kMaxFields> f{};
    std::size_t n = 0;
    bool overflow = false;
};

bool is_control(char c) {
    const auto u = static_cast<unsigned char>(c);
    return u < 0x20 || u == 0x7f;
}

// Splits "a,"b,c",d" into fields. Quoted fields run to the next '"' (no escapes) and must be
// followed by ',' or the end. Returns false with the reason on a malformed quoted field.
bool split_fields(std::string_view s, Fields& out, SkipReason& why) {
    std::size_t i = 0;
    while (true) {
        Field fld;
        if (i < s.size() && s[i] == '"') {
            const auto close = s.find('"', i + 1);
            if (close == s.npos) {
                why = SkipReason::BadString;
                return false;
            }
            fld = {s.substr(i + 1, close - i - 1), true};
            i = close + 1;
            if (i < s.size() && s[i] != ',') {
                why = SkipReason::BadString;
                return false;
            }
        } else {
            const auto comma = s.find(',', i);
            const auto end = comma == s.npos ? s.size() : comma;
            fld = {s.substr(i, end - i), false};
            i = end;
        }
        if (out.n < kMaxFields) {
            out.f[out.n++] = fld;
        } else {
            out.overflow = true;
        }
        if (i >= s.size()) return true;
        ++i;  // skip ','
    }
}

bool parse_i32(const Field& fld, std::int32_t& v) {
    if (fld.quoted || fld.text.empty()) return false;
    const char* b = fld.text.data();
    const char* e = b + fld.text.size();
    const auto r = std::from_chars(b, e, v);
    return r.ec == std::errc{} && r.ptr == e;
}

bool parse_seq(const Field& fld, Seq& seq) {
    std::int32_t v = 0;
    if (!parse_i32(fld, v) || v < 0) return false;
    seq = static_cast<Seq>(v);
    return true;
}

// Parses the argument fields of one command into a typed body by a per-command signature:
// 'i' int32, 'f' float as int32 bits, 's' quoted string.
class ArgReader {
public:
    ArgReader(const Fields& f, std::size_t first) : f_(f), i_(first) {}

    bool i(std::int32_t& v) {
        if (!have()) return false;
        if (!parse_i32(f_.f[i_], v)) return fail(SkipReason::BadNumber);
        ++i_;
        return true;
    }
    bool u(std::uint32_t& v) {
        std::int32_t s = 0;
        if (!i(s)) return false;
        v = std::bit_cast<std::uint32_t>(s);
        return true;
    }
    bool f(float& v) {
        std::int32_t bits = 0;
        if (!i(bits)) return false;
        v = int_to_float(bits);
        return true;
    }
    bool s(std::string& v) {
        if (!have()) return false;
        const Field& fld = f_.f[i_];
        if (!fld.quoted) return fail(SkipReason::BadString);
        for (char c : fld.text) {
            if (is_control(c)) return fail(SkipReason::BadString);
        }
        v.assign(fld.text);
        ++i_;
        return true;
    }
    // True when every field was consumed.
    bool end() {
        if (f_.overflow || i_ != f_.n) return fail(SkipReason::WrongArgCount);
        return true;
    }
    SkipReason reason() const { return why_; }

private:
    bool have() {
        if (i_ >= f_.n) return fail(SkipReason::WrongArgCount);
        return true;
    }
    bool fail(SkipReason r) {
        why_ = r;
        return false;
    }
    const Fields& f_;
    std::size_t i_;
    SkipReason why_ = SkipReason::WrongArgCount;
};

// Parses the arguments for `name`; false with `why` set when the command is skipped.
bool parse_body(std::string_view name, ArgReader& a, CommandBody& body, SkipReason& why) {
    bool ok = false;
    if (name == "REF") {
        Ref r;
        ok = a.u(r.input) && a.end();
        body = r;
    } else if (name == "PCMD") {
        Pcmd p;
        ok = a.i(p.flags) && a.f(p.roll) && a.f(p.pitch) && a.f(p.gaz) && a.f(p.yaw) && a.end();
        body = p;
    } else if (name == "PCMD_MAG") {
        PcmdMag p;
        ok = a.i(p.flags) && a.f(p.roll) && a.f(p.pitch) && a.f(p.gaz) && a.f(p.yaw) &&
             a.f(p.psi) && a.f(p.psi_accuracy) && a.end();
        body = p;
    } else if (name == "FTRIM") {
        ok = a.end();
        body = Ftrim{};
    } else if (name == "CALIB") {
        Calib c;
        ok = a.i(c.device) && a.end();
        body = c;
    } else if (name == "CONFIG") {
        Config c;
        ok = a.s(c.key) && a.s(c.value) && a.end();
        body = std::move(c);
    } else if (name == "CONFIG_IDS") {
        ConfigIds c;
        ok = a.s(c.session_id) && a.s(c.user_id) && a.s(c.application_id) && a.end();
        body = std::move(c);
    } else if (name == "COMWDG") {
        ok = a.end();
        body = Comwdg{};
    } else if (name == "CTRL") {
        Ctrl c;
        ok = a.i(c.mode) && a.i(c.arg) && a.end();
        body = c;
    } else if (name == "LED") {
        Led l;
        ok = a.i(l.anim_id) && a.f(l.freq_hz) && a.i(l.duration_s) && a.end();
        body = l;
    } else if (name == "ANIM") {
        Anim an;
        ok = a.i(an.anim_id) && a.i(an.duration_ms) && a.end();
        body = an;
    } else {
        why = SkipReason::UnknownCommand;
        return false;
    }
    if (!ok) why = a.reason();
    return ok;
}

// One command line without its terminator.
void parse_line(std::string_view line, std::size_t offset, ParsedDatagram& out) {
    auto skip = [&](SkipReason r) { out.skipped.push_back({r, offset}); };
    constexpr std::string_view kPrefix = "AT*";
    if (line.substr(0, kPrefix.size()) != kPrefix) return skip(SkipReason::NotAtCommand);
    const auto eq = line.find('=');
    if (eq == line.npos) return skip(SkipReason::NotAtCommand);
    const std::string_view name = line.substr(kPrefix.size(), eq - kPrefix.size());
    if (!valid_command_name(name)) return skip(SkipReason::NotAtCommand);

    Fields fields;
    SkipReason why = SkipReason::NotAtCommand;
    if (!split_fields(line.substr(eq + 1), fields, why)) return skip(why);
    Seq seq = 0;
    if (!parse_seq(fields.f[0], seq)) return skip(SkipReason::BadSequence);
    // "AT*FTRIM=5,": a single empty trailing field means "no arguments" (CVD, HEIDI).
    if (fields.n == 2 && !fields.overflow && !fields.f[1].quoted && fields.f[1].text.empty()) {
        fields.n = 1;
    }
    ArgReader reader(fields, 1);
    CommandBody body;
    if (!parse_body(name, reader, body, why)) return skip(why);
    out.commands.push_back({seq, std::move(body)});
}

}  // namespace

Expected<std::size_t, DatagramError> parse_datagram_into(std::span<const std::uint8_t> bytes,
                                                         ParsedDatagram& out) {
    out.commands.clear();
    out.skipped.clear();
    if (bytes.size() > kMaxDatagramBytes) return Unexpected{DatagramError::TooLong};
    const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    std::size_t start = 0;
    while (start < text.size()) {
        const auto end = text.find_first_of("\r\n", start);
        if (end == text.npos) {
            out.skipped.push_back({SkipReason::Unterminated, start});
            break;
        }
        if (end > start) parse_line(text.substr(start, end - start), start, out);
        start = end + 1;
    }
    return out.commands.size();
}

Expected<ParsedDatagram, DatagramError> parse_datagram(std::span<const std::uint8_t> bytes) {
    ParsedDatagram out;
    GS_TRY(parse_datagram_into(bytes, out));
    return out;
}

Expected<ParsedDatagram, DatagramError> parse_datagram(std::string_view text) {
    return parse_datagram(std::span<const std::uint8_t>(
        reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

bool SeqFilter::accept(const transport::Endpoint& client, Seq seq) {
    if (!has_client_ || client != client_) {
        if (has_client_) ++restarts_;
        has_client_ = true;
        client_ = client;
        last_ = 0;
    }
    if (seq == 1) {
        if (last_ != 0) ++restarts_;
    } else if (seq <= last_) {
        ++rejected_;
        return false;
    }
    last_ = seq;
    ++accepted_;
    return true;
}

}  // namespace gs::sim::at
