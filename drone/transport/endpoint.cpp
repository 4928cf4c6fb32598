#include "drone/transport/endpoint.hpp"

#include <charconv>

namespace gs::transport {

std::string_view to_string(EndpointError e) {
    switch (e) {
        case EndpointError::MissingPort:
            return "expected a.b.c.d:port (no ':port')";
        case EndpointError::BadAddress:
            return "address is not four dotted decimals 0..255";
        case EndpointError::BadPort:
            return "port is not a number 0..65535";
    }
    return "unknown endpoint error";
}

namespace {

// Parses a decimal in [0, max] that uses the whole of `s`, without sign or leading zeros.
bool parse_decimal(std::string_view s, std::uint32_t max, std::uint32_t& out) {
    if (s.empty() || s.size() > 5 || (s.size() > 1 && s[0] == '0')) return false;
    std::uint32_t v = 0;
    const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
    if (r.ec != std::errc{} || r.ptr != s.data() + s.size() || v > max) return false;
    out = v;
    return true;
}

}  // namespace

Expected<Endpoint, EndpointError> Endpoint::parse(std::string_view text) {
    const auto colon = text.rfind(':');
    if (colon == text.npos) return Unexpected{EndpointError::MissingPort};
    std::uint32_t port = 0;
    if (!parse_decimal(text.substr(colon + 1), 65535, port))
        return Unexpected{EndpointError::BadPort};
    std::string_view addr = text.substr(0, colon);
    std::uint32_t address = 0;
    for (int i = 0; i < 4; ++i) {
        const auto dot = addr.find('.');
        if ((i < 3) == (dot == addr.npos)) return Unexpected{EndpointError::BadAddress};
        std::uint32_t octet = 0;
        if (!parse_decimal(addr.substr(0, dot), 255, octet)) {
            return Unexpected{EndpointError::BadAddress};
        }
        address = (address << 8) | octet;
        addr = dot == addr.npos ? std::string_view{} : addr.substr(dot + 1);
    }
    return Endpoint{address, static_cast<std::uint16_t>(port)};
}

std::string Endpoint::address_string() const {
    std::string s;
    for (int shift = 24; shift >= 0; shift -= 8) {
        if (shift != 24) s += '.';
        s += std::to_string((address >> shift) & 0xFFu);
    }
    return s;
}

std::string Endpoint::to_string() const {
    return address_string() + ':' + std::to_string(port);
}

}  // namespace gs::transport
