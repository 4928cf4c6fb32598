// The raw/ readers of a recording: navdata.bin records, video_chunks.bin records, at.log lines.
// A record cut short is a truncated tail, never a read past the end.
#include "drone/dataset/raw.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto in = gs::fuzz::split(data, size, 3);
    switch (in.choice) {
        case 0:
            if (auto r = gs::dataset::parse_navdata_bin(in.rest)) {
                std::size_t bytes = 0;
                for (const auto& rec : r->records) bytes += 12 + rec.payload.size();
                GS_FUZZ_CHECK(bytes <= in.rest.size());
                GS_FUZZ_CHECK(r->truncated_tail || bytes == in.rest.size());
            }
            break;
        case 1:
            if (auto r = gs::dataset::parse_video_chunks(in.rest))
                GS_FUZZ_CHECK(r->size() * 12 <= in.rest.size());
            break;
        default: {
            const std::string_view t(reinterpret_cast<const char*>(in.rest.data()), in.rest.size());
            (void)gs::dataset::parse_at_log(t);
            break;
        }
    }
    return 0;
}
