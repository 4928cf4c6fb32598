// The raw/ readers of a recording: navdata.bin records, video_chunks.bin records, at.log lines.
// A record cut short is a truncated tail with exactly one warning, never a read past the end.
#include "drone/dataset/raw.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const auto in = gs::fuzz::split(data, size, 3);
    switch (in.choice) {
        case 0: {
            std::vector<std::string> warnings;
            if (auto r = gs::dataset::parse_navdata_bin(in.rest, "raw/navdata.bin", &warnings)) {
                std::size_t bytes = 0;
                for (const auto& rec : r->records) bytes += 12 + rec.payload.size();
                GS_FUZZ_CHECK(bytes <= in.rest.size());
                GS_FUZZ_CHECK(r->truncated_tail || bytes == in.rest.size());
                GS_FUZZ_CHECK(warnings.size() == (r->truncated_tail ? 1u : 0u));
            }
            break;
        }
        case 1: {
            std::vector<std::string> warnings;
            if (auto r =
                    gs::dataset::parse_video_chunks(in.rest, "raw/video_chunks.bin", &warnings)) {
                GS_FUZZ_CHECK(r->size() * 12 <= in.rest.size());
                GS_FUZZ_CHECK(warnings.size() == (r->size() * 12 < in.rest.size() ? 1u : 0u));
            }
            break;
        }
        default: {
            const std::string_view t(reinterpret_cast<const char*>(in.rest.data()), in.rest.size());
            std::vector<std::string> warnings;
            if (gs::dataset::parse_at_log(t, "raw/at.log", &warnings))
                GS_FUZZ_CHECK(warnings.size() == (t.empty() || t.back() == '\n' ? 0u : 1u));
            break;
        }
    }
    return 0;
}
