// The Annex-B splitter that indexes video.h264 and splits raw .h264 clips: units tile the input,
// in order, within bounds. Seeds: ../shared/fixtures/real/video/*.h264 (cut).
#include "drone/dataset/annexb.hpp"
#include "drone/video/h264_decoder.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::span<const std::uint8_t> bytes(data, size);
    const auto units = gs::dataset::split_access_units(bytes);
    std::uint64_t end = 0;
    for (const auto& u : units) {
        GS_FUZZ_CHECK(u.offset >= end && u.size > 0 && u.offset + u.size <= size);
        GS_FUZZ_CHECK(u.idr == gs::dataset::annexb_has_idr(bytes.subspan(u.offset, u.size)));
        end = u.offset + u.size;
    }
    for (std::span<const std::uint8_t> rest = bytes; !rest.empty();) {
        const std::size_t n = gs::video::access_unit_size(rest);
        GS_FUZZ_CHECK(n > 0 && n <= rest.size());
        rest = rest.subspan(n);
    }
    return 0;
}
