// AT command datagrams as the virtual drone reads them (UDP 5556): any bytes, any length.
#include "drone/sim/at_parser.hpp"
#include "fuzz_util.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    auto d = gs::sim::at::parse_datagram(std::span(data, size));
    gs::sim::at::ParsedDatagram reused;
    auto n = gs::sim::at::parse_datagram_into(std::span(data, size), reused);
    GS_FUZZ_CHECK(static_cast<bool>(d) == static_cast<bool>(n));
    return 0;
}
