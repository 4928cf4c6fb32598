// PaVE framing + H.264 decoding throughput on the real captures.
// Usage: bench_decode_bench [REPEATS=20]
// Prints, per capture, framer throughput and per-frame decode time percentiles (decode +
// colour conversion to BGR, what the live pipeline pays per frame).
#include "drone/protocol/pave.hpp"
#include "drone/video/h264_decoder.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

std::vector<std::uint8_t> read_bytes(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

double pct(std::vector<double> v, double p) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    const auto i = static_cast<std::size_t>(p / 100.0 * static_cast<double>(v.size() - 1) + 0.5);
    return v[std::min(i, v.size() - 1)];
}

struct Result {
    std::uint64_t frames = 0;
    double framer_s = 0;
    std::uint64_t bytes = 0;
    std::vector<double> decode_ms;
};

void report(const std::string& name, const Result& r) {
    double total_ms = 0;
    for (double ms : r.decode_ms) total_ms += ms;
    std::printf("%-48s %5zu decoded  %7.0f frames/s  p50 %.2f  p90 %.2f  p99 %.2f  max %.2f ms",
                name.c_str(), r.decode_ms.size(),
                total_ms > 0 ? 1000.0 * static_cast<double>(r.decode_ms.size()) / total_ms : 0.0,
                pct(r.decode_ms, 50), pct(r.decode_ms, 90), pct(r.decode_ms, 99),
                pct(r.decode_ms, 100));
    if (r.framer_s > 0) {
        std::printf("  | framer %.0f MB/s", static_cast<double>(r.bytes) / r.framer_s / 1e6);
    }
    std::printf("\n");
}

Result bench_pave(const std::vector<std::uint8_t>& bytes, int repeats, std::size_t chunk) {
    Result r;
    cv::Mat img;
    for (int rep = 0; rep < repeats; ++rep) {
        gs::protocol::PaveFramer framer;
        gs::video::H264Decoder decoder;
        for (std::size_t pos = 0; pos < bytes.size(); pos += chunk) {
            const std::size_t n = std::min(chunk, bytes.size() - pos);
            auto t0 = Clock::now();
            framer.push(std::span<const std::uint8_t>(bytes.data() + pos, n));
            r.bytes += n;
            for (;;) {
                auto ev = framer.next();
                r.framer_s += std::chrono::duration<double>(Clock::now() - t0).count();
                if (!ev) break;
                if (const auto* f = std::get_if<gs::protocol::PaveFrame>(&*ev)) {
                    ++r.frames;
                    gs::video::AccessUnit au{f->payload, f->header.frame_number,
                                             f->header.display_width, f->header.display_height,
                                             f->header.stream_id};
                    const auto d0 = Clock::now();
                    auto res = decoder.decode(au, img);
                    const auto d1 = Clock::now();
                    if (res && *res == gs::video::DecodeStatus::Frame) {
                        r.decode_ms.push_back(
                            std::chrono::duration<double, std::milli>(d1 - d0).count());
                    }
                }
                t0 = Clock::now();
            }
        }
    }
    return r;
}

Result bench_annexb(const std::vector<std::uint8_t>& bytes, int repeats) {
    Result r;
    cv::Mat img;
    for (int rep = 0; rep < repeats; ++rep) {
        gs::video::H264Decoder decoder;
        std::span<const std::uint8_t> rest(bytes);
        while (!rest.empty()) {
            const std::size_t n = gs::video::access_unit_size(rest);
            const auto d0 = Clock::now();
            auto res = decoder.decode(
                gs::video::AccessUnit{rest.first(n), std::nullopt, 0, 0, std::nullopt}, img);
            const auto d1 = Clock::now();
            if (res && *res == gs::video::DecodeStatus::Frame) {
                r.decode_ms.push_back(std::chrono::duration<double, std::milli>(d1 - d0).count());
            }
            rest = rest.subspan(n);
        }
    }
    return r;
}

}  // namespace

int main(int argc, char** argv) {
    const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 20;
    const std::string dir = std::string(GS_FIXTURES_DIR);
    std::printf("decode_bench: %d repeats, TCP-sized 1460-byte pushes, times per emitted frame\n",
                repeats);
    Result all;
    for (const char* name : {"node-ar-drone_pave.bin", "node-ar-drone_pave-68.bin",
                             "uav-pilot_ardrone_video_stream_dump.bin",
                             "uav-pilot_ardrone_video_stream_dump_bad_pave.bin"}) {
        const auto bytes = read_bytes(dir + "/ardrone/" + name);
        if (bytes.empty()) {
            std::fprintf(stderr, "decode_bench: cannot read %s\n", name);
            return 1;
        }
        const Result r = bench_pave(bytes, repeats, 1460);
        report(name, r);
        all.decode_ms.insert(all.decode_ms.end(), r.decode_ms.begin(), r.decode_ms.end());
    }
    const auto clip = read_bytes(dir + "/real/video/ardrone2_front_office_person.h264");
    if (!clip.empty()) {
        const Result r = bench_annexb(clip, repeats);
        report("ardrone2_front_office_person.h264 (Annex-B)", r);
        all.decode_ms.insert(all.decode_ms.end(), r.decode_ms.begin(), r.decode_ms.end());
    }
    report("all", all);
    return 0;
}
