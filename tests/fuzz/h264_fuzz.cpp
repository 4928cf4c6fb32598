// The video receiver and the H.264 decoder wrapper on any bytes: the input is a PaVE stream when
// it starts with "PaVE", else an Annex-B stream split into access units. Every picture has the
// display size it claims; no crash, no read out of bounds in libavcodec's input (padding).
// Seeds: the PaVE captures and the real clip in ../shared/fixtures (cut).
#include "drone/h264_decoder.hpp"
#include "drone/video/receiver.hpp"
#include "fuzz_util.hpp"

#include <cstring>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::span<const std::uint8_t> bytes(data, size);
    if (size >= 4 && std::memcmp(data, "PaVE", 4) == 0) {
        gs::video::VideoReceiver rx(gs::video::ReceiverOptions{2, true});
        rx.push(bytes, 0);
        while (auto u = rx.next()) {
            if (!gs::video::has_picture(u->fate)) continue;
            GS_FUZZ_CHECK(!u->image.empty() && u->image.type() == CV_8UC3);
        }
        return 0;
    }
    gs::H264Decoder decoder;
    cv::Mat out;
    std::uint32_t n = 0;
    for (std::span<const std::uint8_t> rest = bytes; !rest.empty() && n < 64; ++n) {
        const std::size_t k = gs::access_unit_size(rest);
        auto r = decoder.decode(gs::AccessUnit{rest.first(k), n, 0, 0, std::nullopt}, out);
        if (r && *r == gs::DecodeStatus::Frame)
            GS_FUZZ_CHECK(!out.empty() && out.type() == CV_8UC3);
        rest = rest.subspan(k);
    }
    return 0;
}
