// `ardrone-gs inspect navdata FILE [--json]`: decodes one saved navdata datagram and prints every
// field (grouped by option, units shown), the drone_state bits by name and any skipped options.
#include "app/cli_options.hpp"
#include "app/command.hpp"
#include "drone/protocol/navdata.hpp"
#include "drone/protocol/navdata_json.hpp"
#include "drone/protocol/navdata_layout.hpp"

#include <charconv>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <iterator>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace gs::app::cmd_inspect_navdata {
namespace {

using namespace gs::protocol::navdata;

struct Opts {
    std::string file;
    bool json = false;
};

// A datagram is < 64 KiB; refuse anything absurd instead of reading it all.
constexpr std::size_t kMaxFileBytes = 1 << 20;

std::vector<std::uint8_t> read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw fail("cannot open " + path);
    in.seekg(0, std::ios::end);
    const std::streamoff end = in.tellg();
    if (end < 0) throw fail("cannot read " + path);
    const auto size = static_cast<std::size_t>(end);
    if (size > kMaxFileBytes) {
        throw fail(path + ": " + std::to_string(size) +
                   " bytes is too large for one navdata datagram");
    }
    in.seekg(0);
    std::vector<std::uint8_t> bytes(size);
    in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size));
    if (!in) throw fail("cannot read " + path);
    return bytes;
}

template <class T>
void put_value(std::ostream& os, const T& v) {
    if constexpr (std::is_floating_point_v<T>) {
        char buf[64];
        const auto r = std::to_chars(buf, buf + sizeof buf, v);  // shortest round-trip form
        os.write(buf, r.ptr - buf);
    } else if constexpr (std::is_arithmetic_v<T>) {
        os << +v;  // + so u8/i8 print as numbers
    } else if constexpr (std::is_same_v<T, GpsChannel>) {
        os << '(' << +v.sat << ',' << +v.cn0 << ')';
    } else {
        os << '(';
        for (std::size_t i = 0; i < v.size(); ++i) {
            if (i != 0) os << ", ";
            put_value(os, v[i]);
        }
        os << ')';
    }
}

std::string hex32(std::uint32_t v) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "0x%08X", v);
    return buf;
}

template <class T>
void print_option(std::ostream& os, const T& opt, const OptionEntry* where) {
    using S = layout::Spec<T>;
    os << "\n[" << S::name << "] tag " << S::tag;
    if (where != nullptr) os << ", offset " << where->offset << ", " << where->size << " bytes";
    os << '\n';
    S::fields(opt,
              [&](std::size_t, std::string_view name, std::string_view unit, const auto& field) {
                  std::ostringstream line;
                  line << "  " << name;
                  const std::string pad(line.str().size() < 28 ? 28 - line.str().size() : 1, ' ');
                  line << pad;
                  put_value(line, field);
                  if (!unit.empty()) line << ' ' << unit;
                  os << line.str() << '\n';
              });
    if constexpr (std::is_same_v<T, Demo>) {
        const CtrlState c = opt.ctrl_state;
        os << "  ctrl_state -> " << hex32(c.raw) << ": major " << c.major() << ' '
           << ctrl_major_name(c.major()).value_or("(unknown)") << ", minor " << c.minor() << ' '
           << ctrl_minor_name(c.major(), c.minor()).value_or("(no name)") << '\n';
    }
    if constexpr (std::is_same_v<T, Time>) {
        os << "  time -> " << opt.time.seconds() << " s + " << opt.time.microseconds() << " us = ";
        put_value(os, opt.time.total_s());
        os << " s\n";
    }
}

void print_human(std::ostream& os, const std::string& path, std::size_t size, const Navdata& nd) {
    os << "file            " << path << " (" << size << " bytes)\n";
    os << "header          " << hex32(nd.header.magic) << '\n';
    os << "drone_state     " << hex32(nd.header.drone_state.raw) << '\n';
    for (unsigned i = 0; i < 32; ++i) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "  bit %2u %-20s %d  ", i,
                      std::string(kDroneStateBits[i].name).c_str(),
                      nd.header.drone_state.bit(i) ? 1 : 0);
        os << buf << kDroneStateBits[i].meaning << '\n';
    }
    os << "  set: " << set_bit_names(nd.header.drone_state) << '\n';
    os << "sequence        " << nd.header.sequence << '\n';
    os << "vision_defined  " << nd.header.vision_defined << '\n';
    os << "checksum        " << nd.checksum << " (verified, cks block at offset "
       << nd.checksum_offset << ")\n";
    if (nd.trailing_bytes != 0) {
        os << "trailing bytes  " << nd.trailing_bytes << " after the cks block (not checked)\n";
    }
    os << "options         " << nd.options.size() << '\n';
    for (const OptionEntry& e : nd.options) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "  offset %5u  tag %5u  size %4u  ", e.offset, e.tag,
                      e.size);
        os << buf << option_name(e.tag, e.size).value_or("(unknown)") << '\n';
    }
    if (nd.options.overflow() != 0) os << "  ... " << nd.options.overflow() << " more\n";
    if (nd.skipped.empty()) {
        os << "skipped         none\n";
    } else {
        os << "skipped         " << nd.skipped.size() + nd.skipped.overflow() << '\n';
        for (const SkippedOption& s : nd.skipped) {
            os << "  tag " << s.option.tag << " at offset " << s.option.offset << ", "
               << s.option.size << " bytes: " << to_string(s.reason) << '\n';
        }
    }
    layout::for_each_option_type([&]<class T>(std::type_identity<T>) {
        using S = layout::Spec<T>;
        const auto& opt = nd.*S::member;
        if (!opt) return;
        const OptionEntry* where = nullptr;
        for (const OptionEntry& e : nd.options) {
            if (e.tag == S::tag && option_name(e.tag, e.size) == S::name) {
                where = &e;
                break;
            }
        }
        print_option(os, *opt, where);
    });
}

void run(const Opts& o) {
    const std::vector<std::uint8_t> bytes = read_file(o.file);
    const auto nd = parse_navdata(bytes);
    if (!nd) throw fail(o.file + ": " + to_string(nd.error()), 2);
    if (o.json) {
        nlohmann::json j = to_json(*nd);
        j["file"] = o.file;
        j["file_size"] = bytes.size();
        std::cout << j.dump(2) << '\n';
    } else {
        print_human(std::cout, o.file, bytes.size(), *nd);
    }
}

const CommandRegistration reg(
    10, "inspect", "Inspect real drone captures (navdata datagrams, PaVE video streams)",
    [](CLI::App& inspect) {
        auto opts = std::make_shared<Opts>();
        CLI::App* cmd = inspect.add_subcommand(
            "navdata", "Decode one navdata datagram (a UDP 5554 payload saved to a file)");
        cmd->add_option("file", opts->file, "File holding exactly one datagram")
            ->required()
            ->check(regular_file());
        cmd->add_flag("--json", opts->json,
                      "Print JSON (docs/protocol.md field names) instead of text");
        set_action(*cmd, [opts] { run(*opts); });
    });

}  // namespace
}  // namespace gs::app::cmd_inspect_navdata
