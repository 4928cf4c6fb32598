// The video receiver and the H.264 decoder wrapper on any bytes: the input is a PaVE stream when
// it starts with "PaVE", else an Annex-B stream split into access units. Every picture is BGR8;
// no crash, no read past the input in libavcodec (its padding). Seeds: the PaVE captures and the
// real clip in ../shared/fixtures (cut). Opening a libavcodec decoder costs far more than a small
// input's decoding, so one receiver and one decoder serve every input, reset before each (a new
// connection for the receiver: the decoder waits for an IDR, nothing of the last input remains).
#include "drone/video/h264_decoder.hpp"
#include "drone/video/receiver.hpp"
#include "fuzz_util.hpp"

#include <cstring>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static gs::video::VideoReceiver rx(gs::video::ReceiverOptions{2, true});
    static gs::video::H264Decoder decoder;
    static cv::Mat out;
    const std::span<const std::uint8_t> bytes(data, size);
    if (size >= 4 && std::memcmp(data, "PaVE", 4) == 0) {
        rx.begin_connection(0);
        rx.push(bytes, 0);
        while (auto u = rx.next()) {
            if (!gs::video::has_picture(u->fate)) continue;
            GS_FUZZ_CHECK(!u->image.empty() && u->image.type() == CV_8UC3);
        }
        return 0;
    }
    decoder.reset();
    std::uint32_t n = 0;
    for (std::span<const std::uint8_t> rest = bytes; !rest.empty() && n < 64; ++n) {
        const std::size_t k = gs::video::access_unit_size(rest);
        auto r = decoder.decode(gs::video::AccessUnit{rest.first(k), n, 0, 0, std::nullopt}, out);
        if (r && *r == gs::video::DecodeStatus::Frame)
            GS_FUZZ_CHECK(!out.empty() && out.type() == CV_8UC3);
        rest = rest.subspan(k);
    }
    return 0;
}
