#pragma once
// An IPv4 address and port as a plain value: what the sockets in net.hpp bind and send to, and what
// the virtual drone's AT sequence filter compares to notice a new client. No sockets here.

#include "drone/core/expected.hpp"

#include <compare>
#include <cstdint>
#include <string>
#include <string_view>

namespace gs::transport {

enum class EndpointError {
    MissingPort,  // no ':' separating address and port
    BadAddress,   // not four dotted decimal octets 0..255
    BadPort,      // not a decimal number 0..65535
};
[[nodiscard]] std::string_view to_string(EndpointError e);

struct Endpoint {
    std::uint32_t address = 0;  // IPv4 in host byte order: 127.0.0.1 = 0x7F000001
    std::uint16_t port = 0;

    static constexpr Endpoint loopback(std::uint16_t p) { return {0x7F000001u, p}; }
    static constexpr Endpoint any(std::uint16_t p) { return {0u, p}; }
    static constexpr Endpoint from_octets(std::uint8_t a, std::uint8_t b, std::uint8_t c,
                                          std::uint8_t d, std::uint16_t p) {
        return {(std::uint32_t{a} << 24) | (std::uint32_t{b} << 16) | (std::uint32_t{c} << 8) |
                    std::uint32_t{d},
                p};
    }
    // Strict "a.b.c.d:port" (no names, no leading zeros in octets, port 0..65535).
    [[nodiscard]] static Expected<Endpoint, EndpointError> parse(std::string_view text);

    [[nodiscard]] std::string address_string() const;  // "a.b.c.d"
    [[nodiscard]] std::string to_string() const;       // "a.b.c.d:port"

    friend constexpr auto operator<=>(const Endpoint&, const Endpoint&) = default;
};

}  // namespace gs::transport
