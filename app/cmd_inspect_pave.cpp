// `ardrone-gs inspect pave FILE [--json] [--decode DIR]`: runs a saved PaVE/H.264 TCP stream
// (bytes as read from port 5555/5553) through the framer and lists every frame, every resync and
// the trailing partial frame; --decode also decodes the H.264 and writes DIR/NNNNNN.png.
#include "app/cli_options.hpp"
#include "app/command.hpp"
#include "drone/protocol/pave.hpp"
#include "drone/protocol/pave_json.hpp"
#include "drone/video/h264_decoder.hpp"
#include "drone/video/receiver.hpp"

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace gs::app::cmd_inspect_pave {
namespace {

struct Opts {
    std::string file;
    bool json = false;
    std::string decode_dir;
};

nlohmann::json decoder_json(const video::H264DecoderStats& s) {
    return {{"access_units", s.access_units},
            {"decoded", s.decoded},
            {"skipped_waiting_idr", s.skipped_waiting_idr},
            {"decode_errors", s.decode_errors},
            {"concealed", s.concealed},
            {"frame_gaps", s.frame_gaps},
            {"reinits", s.reinits}};
}

std::string image_name(std::uint64_t n) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%06llu.png", static_cast<unsigned long long>(n));
    return buf;
}

void print_frame_line(std::ostream& os, const protocol::PaveFrame& f,
                      const std::optional<std::string>& img) {
    const protocol::PaveHeader& h = f.header;
    char line[256];
    std::snprintf(line, sizeof line,
                  "%6llu %9llu %4u %8u %12u %11u  %-7s %-5s %4ux%-4u %4ux%-4u %6u %3u/%-3u %4u",
                  static_cast<unsigned long long>(f.index),
                  static_cast<unsigned long long>(f.stream_offset), unsigned{h.header_size},
                  h.payload_size, h.frame_number, h.timestamp, to_string(h.frame_type).c_str(),
                  to_string(h.video_codec).c_str(), unsigned{h.encoded_stream_width},
                  unsigned{h.encoded_stream_height}, unsigned{h.display_width},
                  unsigned{h.display_height}, unsigned{h.stream_id}, unsigned{h.header1_size},
                  unsigned{h.header2_size}, unsigned{h.control});
    os << line;
    if (img) os << "  -> " << *img;
    os << '\n';
}

void run(const Opts& o) {
    std::ifstream in(o.file, std::ios::binary);
    if (!in) throw fail("cannot open " + o.file);

    const bool decode = !o.decode_dir.empty();
    if (decode) {
        std::error_code ec;
        std::filesystem::create_directories(o.decode_dir, ec);
        if (ec || !std::filesystem::is_directory(o.decode_dir)) {
            throw fail("cannot create directory " + o.decode_dir +
                       (ec ? ": " + ec.message() : std::string()));
        }
    }

    // The receive pipeline the link runs (drone/video/receiver.hpp): the same cutting, codec
    // check, decoding and IDR waits.
    video::VideoReceiver rx(video::ReceiverOptions{4, decode});
    std::uint64_t images = 0;
    nlohmann::json frames = nlohmann::json::array();
    nlohmann::json resyncs = nlohmann::json::array();
    std::ostream& os = std::cout;
    if (!o.json) {
        os << o.file << '\n'
           << " index    offset  hdr  payload frame_number   timestamp  type    codec encoded   "
              "display   stream h1/h2  ctrl\n";
    }
    auto list_resyncs = [&] {
        for (const protocol::PaveResync& r : rx.resyncs()) {
            if (o.json) {
                resyncs.push_back(to_json(r));
            } else {
                os << "resync at " << r.stream_offset << ": skipped " << r.bytes_skipped
                   << " bytes (" << to_string(r.reason) << "), next frame at "
                   << r.stream_offset + r.bytes_skipped << '\n';
            }
        }
        rx.clear_resyncs();
    };

    std::vector<char> chunk(64 * 1024);
    while (in) {
        in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
        const auto got = static_cast<std::size_t>(in.gcount());
        if (got == 0) break;
        rx.push(std::span(reinterpret_cast<const std::uint8_t*>(chunk.data()), got), 0);
        while (auto u = rx.next()) {
            list_resyncs();
            protocol::PaveFrame f;
            f.index = static_cast<std::uint64_t>(u->unit);
            f.stream_offset = u->stream_offset;
            f.header = u->header;
            std::optional<std::string> img;
            if (decode && video::has_picture(u->fate)) {
                img = image_name(images);
                const auto path = std::filesystem::path(o.decode_dir) / *img;
                if (!cv::imwrite(path.string(), u->image)) {
                    throw fail("cannot write " + path.string());
                }
                ++images;
            }
            if (o.json) {
                nlohmann::json j = {{"index", f.index}, {"offset", f.stream_offset}};
                j.update(to_json(f.header));
                if (decode) j["image"] = img ? nlohmann::json(*img) : nlohmann::json(nullptr);
                frames.push_back(std::move(j));
            } else {
                print_frame_line(os, f, img);
            }
        }
        list_resyncs();
    }
    if (in.bad()) throw fail("cannot read " + o.file);

    const protocol::PavePending pending = rx.pending();
    const protocol::PaveFramerStats& stats = rx.framer_stats();
    nlohmann::json trailing = nullptr;
    if (pending.buffered_bytes > 0 || pending.unreported_skip > 0) {
        trailing = {{"buffered_bytes", pending.buffered_bytes},
                    {"skipped_bytes", pending.unreported_skip}};
        if (pending.header) {
            nlohmann::json h = to_json(*pending.header);
            trailing["offset"] = pending.header_offset;
            trailing["payload_bytes_present"] =
                pending.buffered_bytes - pending.header->header_size;
            trailing["header"] = std::move(h);
        }
    }

    // An empty file, or one with no PaVE frame at all, is not a video capture: say so and fail
    // (after printing what was found, so the resyncs can still be read).
    const auto no_video = [&] {
        if (stats.frames > 0) return;
        throw fail(o.file + ": no PaVE frame in " + std::to_string(stats.bytes_in) +
                   " bytes: not a video capture (docs/protocol.md §4.1)");
    };
    if (o.json) {
        nlohmann::json j = {{"file", o.file},       {"file_size", stats.bytes_in},
                            {"frames", frames},     {"resyncs", resyncs},
                            {"trailing", trailing}, {"stats", to_json(stats)}};
        if (decode) {
            j["decode"] = {{"dir", o.decode_dir},
                           {"images", images},
                           {"stats", decoder_json(rx.decoder_stats())}};
        }
        os << j.dump(2) << '\n';
        no_video();
        return;
    }
    if (pending.header) {
        os << "trailing partial frame " << pending.header->frame_number << " at "
           << pending.header_offset << ": " << pending.buffered_bytes - pending.header->header_size
           << " of " << pending.header->payload_size << " payload bytes present\n";
    } else if (pending.buffered_bytes > 0) {
        os << "trailing " << pending.buffered_bytes << " bytes (incomplete header)\n";
    }
    if (pending.unreported_skip > 0) {
        os << "trailing garbage: " << pending.unreported_skip << " bytes skipped at the end\n";
    }
    os << stats.bytes_in << " bytes: " << stats.frames << " frames (" << stats.payload_bytes
       << " payload bytes), " << stats.resyncs << " resyncs, " << stats.bytes_skipped
       << " bytes skipped, " << stats.oversize_rejections << " oversize headers refused\n";
    if (decode) {
        const video::H264DecoderStats& d = rx.decoder_stats();
        os << "decoded " << d.decoded << " of " << d.access_units << " access units into "
           << o.decode_dir << " (" << d.skipped_waiting_idr << " skipped waiting for an IDR, "
           << d.frame_gaps << " frame-number gaps, " << d.decode_errors << " errors, "
           << d.concealed << " concealed, " << d.reinits << " re-initialisations)\n";
    }
    no_video();
}

const CommandRegistration reg(
    20, "inspect", "Inspect real drone captures (navdata datagrams, PaVE video streams)",
    [](CLI::App& inspect) {
        auto opts = std::make_shared<Opts>();
        CLI::App* cmd = inspect.add_subcommand(
            "pave", "List the PaVE frames of a saved video stream (TCP 5555 bytes in a file)");
        cmd->add_option("file", opts->file, "File holding the raw TCP byte stream")
            ->required()
            ->check(regular_file());
        cmd->add_flag("--json", opts->json,
                      "Print JSON (docs/protocol.md field names) instead of text");
        cmd->add_option("--decode", opts->decode_dir,
                        "Decode the H.264 and write DIR/NNNNNN.png (0-based, decode order)")
            ->check(output_directory());
        set_action(*cmd, [opts] { run(*opts); });
    });

}  // namespace
}  // namespace gs::app::cmd_inspect_pave
