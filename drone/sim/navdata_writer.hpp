#pragma once
// Navdata encoder for the virtual drone: the mirror of parse_navdata. Writes the header, every
// option present in a Navdata (in tag order, at its layout size, from the same field table the
// decoder uses) and the checksum block. No allocation when given a span; the vector overloads
// reuse the vector's capacity, so a long-lived vector makes steady-state encoding allocation-free.

#include "drone/core/expected.hpp"
#include "drone/protocol/navdata.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

namespace gs::sim::navdata {

// The drone side of protocol::navdata: it writes the decoder's types from the same layout table.
using namespace gs::protocol::navdata;  // NOLINT(google-build-using-namespace)

enum class WriteErrc : std::uint8_t {
    BufferTooSmall,  // `out` is smaller than navdata_size() (at most ~2.4 kB with every option)
};
std::string_view to_string(WriteErrc e);

// Bytes write_navdata will produce for `nd`: 16 + layout size of each present option + 8.
[[nodiscard]] std::size_t navdata_size(const Navdata& nd);

// Writes nd.header, then every engaged option of nd in tag order (zimmu_3000 before gps if both
// are set), then the cks block = byte sum of everything before it. nd.options / nd.skipped /
// nd.checksum* (parser outputs) are ignored. Returns the number of bytes written.
[[nodiscard]] Expected<std::size_t, WriteErrc> write_navdata(const Navdata& nd,
                                                             std::span<std::uint8_t> out);
// Same, into `out` (resized to exactly the datagram; capacity reused).
void write_navdata(const Navdata& nd, std::vector<std::uint8_t>& out);

// The bootstrap datagram (§1.3, §7.4): header + cks only, 24 bytes.
inline constexpr std::size_t kBootstrapSize = kHeaderSize + kChecksumSize;
[[nodiscard]] Expected<std::size_t, WriteErrc> write_bootstrap(const Header& h,
                                                               std::span<std::uint8_t> out);
void write_bootstrap(const Header& h, std::vector<std::uint8_t>& out);

}  // namespace gs::sim::navdata
