// Configuration dumps (TCP 5559): the streaming reader over any chunking and the dump parser.
#include "drone/protocol/config.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    auto whole = gs::protocol::parse_config_dump(text);
    if (whole) (void)gs::protocol::format_config_dump(*whole);
    gs::protocol::ConfigDumpReader reader(4096);
    std::size_t dumps = 0;
    for (std::size_t pos = 0; pos < size; pos += 97) {
        auto r = reader.push(std::span(data + pos, std::min<std::size_t>(97, size - pos)));
        if (r) ++dumps;
        GS_FUZZ_CHECK(reader.buffered() <= 4096 + 97);
    }
    (void)dumps;
    return 0;
}
