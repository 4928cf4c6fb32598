#include "drone/sim/navdata_writer.hpp"

#include "drone/protocol/navdata_layout.hpp"

#include <algorithm>

namespace gs::sim::navdata {

namespace {

template <class T>
void store_at(std::span<std::uint8_t> out, std::size_t off, const T& v) {
    layout::store(out.data() + off, v);
}

template <class T>
void encode_option(const T& opt, std::span<std::uint8_t> block) {
    using S = layout::Spec<T>;
    std::fill(block.begin(), block.end(), std::uint8_t{0});
    store_at(block, 0, S::tag);
    store_at(block, 2, S::size);
    S::fields(opt, [&](std::size_t off, std::string_view, std::string_view, const auto& field) {
        store_at(block, off, field);
    });
}

void write_header(const Header& h, std::span<std::uint8_t> out) {
    store_at(out, 0, h.magic);
    store_at(out, 4, h.drone_state.raw);
    store_at(out, 8, h.sequence);
    store_at(out, 12, h.vision_defined);
}

std::size_t write_unchecked(const Navdata& nd, std::span<std::uint8_t> out) {
    write_header(nd.header, out);
    std::size_t off = kHeaderSize;
    layout::for_each_option_type([&]<class T>(std::type_identity<T>) {
        using S = layout::Spec<T>;
        if (const auto& opt = nd.*S::member) {
            encode_option(*opt, out.subspan(off, S::size));
            off += S::size;
        }
    });
    const std::uint32_t sum = navdata_checksum(out.first(off));
    store_at(out, off, kChecksumTag);
    store_at(out, off + 2, kChecksumSize);
    store_at(out, off + 4, sum);
    return off + kChecksumSize;
}
}  // namespace

std::string_view to_string(WriteErrc e) {
    switch (e) {
        case WriteErrc::BufferTooSmall:
            return "output buffer too small";
    }
    return "?";
}

std::size_t navdata_size(const Navdata& nd) {
    std::size_t n = kHeaderSize + kChecksumSize;
    layout::for_each_option_type([&]<class T>(std::type_identity<T>) {
        if ((nd.*layout::Spec<T>::member).has_value()) n += layout::Spec<T>::size;
    });
    return n;
}

Expected<std::size_t, WriteErrc> write_navdata(const Navdata& nd, std::span<std::uint8_t> out) {
    const std::size_t n = navdata_size(nd);
    if (out.size() < n) return Unexpected{WriteErrc::BufferTooSmall};
    return write_unchecked(nd, out.first(n));
}

void write_navdata(const Navdata& nd, std::vector<std::uint8_t>& out) {
    out.resize(navdata_size(nd));
    (void)write_unchecked(nd, out);
}

Expected<std::size_t, WriteErrc> write_bootstrap(const Header& h, std::span<std::uint8_t> out) {
    if (out.size() < kBootstrapSize) return Unexpected{WriteErrc::BufferTooSmall};
    Navdata nd;
    nd.header = h;
    return write_unchecked(nd, out.first(kBootstrapSize));
}

void write_bootstrap(const Header& h, std::vector<std::uint8_t>& out) {
    out.resize(kBootstrapSize);
    (void)write_bootstrap(h, std::span<std::uint8_t>(out));
}

}  // namespace gs::sim::navdata
