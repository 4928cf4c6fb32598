// Navdata datagrams (UDP 5554): the parser, the conversion to the dataset's units and the JSON of
// `inspect navdata` must take any bytes. Seeds: ../shared/fixtures/ardrone/*navdata*.bin.
#include "drone/protocol/navdata.hpp"
#include "drone/protocol/navdata_json.hpp"
#include "fuzz_util.hpp"

#include <cmath>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    auto nd = gs::protocol::navdata::parse_navdata(std::span(data, size));
    if (!nd) return 0;
    const gs::NavState s = gs::protocol::navdata::to_nav_state(*nd, 0);
    GS_FUZZ_CHECK(s.seq && *s.seq == nd->header.sequence);
    (void)gs::protocol::navdata::to_json(*nd).dump();
    return 0;
}
