#include "drone/protocol/at.hpp"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <limits>

namespace gs::protocol::at {

std::string_view to_string(AtError e) {
    switch (e) {
        case AtError::ForbiddenCharacter:
            return "string argument contains '\"' or a control character";
        case AtError::BadName:
            return "command name is not [A-Z0-9_]+";
        case AtError::BadConfigId:
            return "configuration id is not 8 hex digits";
        case AtError::CommandTooLong:
            return "command longer than one AT datagram (1024 bytes)";
        case AtError::Unterminated:
            return "not exactly one CR-terminated AT command";
    }
    return "unknown AT error";
}

std::int32_t float_to_int(float v) {
    if (v == 0.0f) return 0;  // also -0
    return std::bit_cast<std::int32_t>(v);
}

float int_to_float(std::int32_t bits) {
    return std::bit_cast<float>(bits);
}

Seq SeqCounter::next() {
    const Seq s = next_;
    next_ = next_ >= kMaxSeq ? 1 : next_ + 1;
    return s;
}

namespace {

// Builds one command: "AT*" NAME "=" seq {"," arg} "\r".
class Builder {
public:
    Builder(std::string_view name, Seq seq) {
        s_.reserve(48);
        s_ += "AT*";
        s_ += name;
        s_ += '=';
        append_number(seq);
    }
    Builder& i(std::int64_t v) {
        s_ += ',';
        append_number(v);
        return *this;
    }
    Builder& f(float v) { return i(float_to_int(v)); }
    Builder& raw(std::string_view text) {
        s_ += ',';
        s_ += text;
        return *this;
    }
    Builder& quoted(std::string_view text) {
        s_ += ",\"";
        s_ += text;
        s_ += '"';
        return *this;
    }
    std::string done() {
        s_ += '\r';
        return std::move(s_);
    }

private:
    template <class Int>
    void append_number(Int v) {
        char buf[24];
        const auto r = std::to_chars(buf, buf + sizeof buf, v);
        s_.append(buf, r.ptr);
    }
    std::string s_;
};

float motion(float v) {
    if (std::isnan(v)) return 0.0f;
    return std::clamp(v, -1.0f, 1.0f);
}

bool forbidden(char c) {
    const auto u = static_cast<unsigned char>(c);
    return c == '"' || u < 0x20 || u == 0x7f;
}

bool clean_string(std::string_view s) {
    return std::none_of(s.begin(), s.end(), forbidden);
}

bool clean_raw(std::string_view s) {
    return clean_string(s) && s.find(',') == s.npos;
}

bool valid_config_id(std::string_view s) {
    return s.size() == 8 && std::all_of(s.begin(), s.end(), [](char c) {
               return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F');
           });
}

Expected<std::string, AtError> bounded(std::string cmd) {
    if (cmd.size() > kMaxDatagramBytes) return Unexpected{AtError::CommandTooLong};
    return cmd;
}

}  // namespace

std::string ref(Seq seq, std::uint32_t input) {
    return Builder("REF", seq).i(std::bit_cast<std::int32_t>(input)).done();  // drone reads %d
}

std::string pcmd(Seq seq, std::int32_t flags, float roll, float pitch, float gaz, float yaw) {
    return Builder("PCMD", seq)
        .i(flags)
        .f(motion(roll))
        .f(motion(pitch))
        .f(motion(gaz))
        .f(motion(yaw))
        .done();
}

std::string hover(Seq seq) {
    return pcmd(seq, 0, 0.0f, 0.0f, 0.0f, 0.0f);
}

std::string pcmd_mag(Seq seq, std::int32_t flags, float roll, float pitch, float gaz, float yaw,
                     float psi, float psi_accuracy) {
    return Builder("PCMD_MAG", seq)
        .i(flags)
        .f(motion(roll))
        .f(motion(pitch))
        .f(motion(gaz))
        .f(motion(yaw))
        .f(motion(psi))
        .f(motion(psi_accuracy))
        .done();
}

std::string ftrim(Seq seq) {
    return Builder("FTRIM", seq).done();
}

std::string calib(Seq seq, std::int32_t device) {
    return Builder("CALIB", seq).i(device).done();
}

std::string comwdg(Seq seq) {
    return Builder("COMWDG", seq).done();
}

std::string ctrl(Seq seq, CtrlMode mode, std::int32_t arg) {
    return ctrl(seq, static_cast<std::int32_t>(mode), arg);
}

std::string ctrl(Seq seq, std::int32_t mode, std::int32_t arg) {
    return Builder("CTRL", seq).i(mode).i(arg).done();
}

std::string led(Seq seq, std::int32_t anim_id, float freq_hz, std::int32_t duration_s) {
    return Builder("LED", seq).i(anim_id).f(freq_hz).i(duration_s).done();
}

std::string anim(Seq seq, std::int32_t anim_id, std::int32_t duration_ms) {
    return Builder("ANIM", seq).i(anim_id).i(duration_ms).done();
}

Expected<std::string, AtError> config(Seq seq, std::string_view key, std::string_view value) {
    if (!clean_string(key) || !clean_string(value)) return Unexpected{AtError::ForbiddenCharacter};
    return bounded(Builder("CONFIG", seq).quoted(key).quoted(value).done());
}

Expected<std::string, AtError> config_ids(Seq seq, std::string_view session_id,
                                          std::string_view user_id,
                                          std::string_view application_id) {
    for (const auto id : {session_id, user_id, application_id}) {
        if (!clean_string(id)) return Unexpected{AtError::ForbiddenCharacter};
        if (!valid_config_id(id)) return Unexpected{AtError::BadConfigId};
    }
    return Builder("CONFIG_IDS", seq)
        .quoted(session_id)
        .quoted(user_id)
        .quoted(application_id)
        .done();
}

std::string leds_anim_value(std::int32_t anim_id, float freq_hz, std::int32_t duration_s) {
    return std::to_string(anim_id) + ',' + std::to_string(float_to_int(freq_hz)) + ',' +
           std::to_string(duration_s);
}

std::string flight_anim_value(std::int32_t anim_id, std::int32_t duration_ms) {
    return std::to_string(anim_id) + ',' + std::to_string(duration_ms);
}

Expected<std::string, AtError> command(Seq seq, std::string_view name, std::span<const Arg> args) {
    if (!valid_command_name(name)) return Unexpected{AtError::BadName};
    Builder b(name, seq);
    for (const Arg& a : args) {
        if (const auto* v = std::get_if<std::int32_t>(&a)) {
            b.i(*v);
        } else if (const auto* f = std::get_if<float>(&a)) {
            b.f(*f);
        } else if (const auto* r = std::get_if<RawArg>(&a)) {
            if (!clean_raw(r->text)) return Unexpected{AtError::ForbiddenCharacter};
            b.raw(r->text);
        } else if (const auto* q = std::get_if<QuotedArg>(&a)) {
            if (!clean_string(q->text)) return Unexpected{AtError::ForbiddenCharacter};
            b.quoted(q->text);
        }
    }
    return bounded(b.done());
}

Expected<std::size_t, AtError> pack_into(std::span<const std::string> commands,
                                         std::vector<std::string>& out, std::size_t max_bytes) {
    max_bytes = std::min(max_bytes, kMaxDatagramBytes);
    // Validate first so a bad command never leaves half-written output behind.
    for (const std::string& c : commands) {
        if (c.size() < 2 || c.back() != '\r' || c.find_first_of("\r\n") != c.size() - 1) {
            return Unexpected{AtError::Unterminated};
        }
        if (c.size() > max_bytes) return Unexpected{AtError::CommandTooLong};
    }
    std::size_t n = 0;
    auto start_datagram = [&] {
        if (out.size() <= n) out.emplace_back();
        out[n].clear();
        ++n;
    };
    for (const std::string& c : commands) {
        if (n == 0 || out[n - 1].size() + c.size() > max_bytes) start_datagram();
        out[n - 1] += c;
    }
    return n;
}

Expected<std::vector<std::string>, AtError> pack(std::span<const std::string> commands,
                                                 std::size_t max_bytes) {
    std::vector<std::string> out;
    GS_TRY_ASSIGN(auto n, pack_into(commands, out, max_bytes));
    out.resize(n);
    return out;
}

bool valid_command_name(std::string_view s) {
    return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
        return (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
    });
}

}  // namespace gs::protocol::at
