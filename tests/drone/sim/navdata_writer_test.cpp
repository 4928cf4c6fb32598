// write_navdata: byte-exact re-encoding of the real captures, field-by-field round trips of every
// option, and the §7.4 bootstrap datagram.
#include "drone/sim/navdata_writer.hpp"

#include "drone/protocol/navdata_layout.hpp"
#include "support/navdata_fixtures.hpp"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace gs::protocol::navdata {
using namespace gs::sim::navdata;  // the writer under test
namespace {

using test::read_fixture;

// Parsing then writing a real capture reproduces it byte for byte: proves the encoder mirrors the
// decoder, and both match the wire layout, on real data (every option of §3.5 except tag 27's
// opaque 480-byte form, which the writer cannot produce).
TEST(NavdataWriter, ReencodesRealCapturesByteForByte) {
    for (const char* name : {test::kNavdataFull, test::kNavdata2012, test::kNavdataDemo}) {
        const auto bytes = read_fixture(name);
        const auto nd = parse_navdata(bytes);
        ASSERT_TRUE(nd) << name << ": " << to_string(nd.error());
        std::vector<std::uint8_t> out;
        write_navdata(*nd, out);
        EXPECT_EQ(out, bytes) << name;
        EXPECT_EQ(navdata_size(*nd), bytes.size()) << name;
    }
}

TEST(NavdataWriter, BootstrapEqualsForumBytes) {
    const std::vector<std::uint8_t> expected = {0x88, 0x77, 0x66, 0x55, 0x10, 0x0C, 0x80, 0x4F,
                                                0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
                                                0xFF, 0xFF, 0x08, 0x00, 0xA6, 0x02, 0x00, 0x00};
    Header h;
    h.drone_state.raw = 0x4F800C10;
    h.sequence = 1;
    h.vision_defined = 0;
    std::vector<std::uint8_t> out;
    write_bootstrap(h, out);
    EXPECT_EQ(out, expected);

    std::array<std::uint8_t, kBootstrapSize> buf{};
    const auto n = write_bootstrap(h, buf);
    ASSERT_TRUE(n);
    EXPECT_EQ(*n, 24U);
    EXPECT_TRUE(std::equal(buf.begin(), buf.end(), expected.begin()));
    std::array<std::uint8_t, 23> small{};
    const auto e = write_bootstrap(h, small);
    ASSERT_FALSE(e);
    EXPECT_EQ(e.error(), WriteErrc::BufferTooSmall);
}

// Gives every field of `opt` a distinct pseudo-random value (any bit pattern, NaN included).
template <class T>
void randomise(T& opt, std::mt19937& rng) {
    layout::Spec<T>::fields(opt, [&](std::size_t, std::string_view, std::string_view, auto& fld) {
        std::array<std::uint8_t, layout::wire_size_v<std::remove_reference_t<decltype(fld)>>> raw;
        for (auto& x : raw) x = static_cast<std::uint8_t>(rng());
        layout::load(raw.data(), fld);
    });
}

// Field values as wire bytes (bitwise comparison, so NaN payloads count too).
template <class T>
std::vector<std::uint8_t> field_bytes(const T& opt) {
    std::vector<std::uint8_t> out;
    layout::Spec<T>::fields(
        opt, [&](std::size_t, std::string_view, std::string_view, const auto& fld) {
            const std::size_t n = layout::wire_size_v<std::remove_cvref_t<decltype(fld)>>;
            out.resize(out.size() + n);
            layout::store(out.data() + out.size() - n, fld);
        });
    return out;
}

TEST(NavdataWriter, EveryOptionRoundTripsFieldByField) {
    std::mt19937 rng(7);
    Navdata in;
    in.header.drone_state.raw = 0x0F8004F5;
    in.header.sequence = 4242;
    in.header.vision_defined = 1;
    layout::for_each_option_type([&]<class T>(std::type_identity<T>) {
        if constexpr (!std::is_same_v<T, Zimmu3000>) {  // one tag-27 form per datagram
            randomise((in.*layout::Spec<T>::member).emplace(), rng);
        }
    });
    std::vector<std::uint8_t> bytes;
    write_navdata(in, bytes);
    EXPECT_EQ(bytes.size(), 2120U);  // every option once, gps form of tag 27: the capture size
    const auto out = parse_navdata(bytes);
    ASSERT_TRUE(out) << to_string(out.error());
    EXPECT_EQ(out->header.drone_state.raw, in.header.drone_state.raw);
    EXPECT_EQ(out->header.sequence, 4242U);
    EXPECT_EQ(out->header.vision_defined, 1U);
    EXPECT_TRUE(out->skipped.empty());
    layout::for_each_option_type([&]<class T>(std::type_identity<T>) {
        const auto& a = in.*layout::Spec<T>::member;
        const auto& b = out.value().*layout::Spec<T>::member;
        ASSERT_EQ(a.has_value(), b.has_value()) << layout::Spec<T>::name;
        if (a) {
            EXPECT_EQ(field_bytes(*a), field_bytes(*b)) << layout::Spec<T>::name;
        }
    });

    // The zimmu form of tag 27 on its own.
    Navdata z;
    z.zimmu_3000.emplace();
    z.zimmu_3000->vzimmuLSB = -17;
    z.zimmu_3000->vzfind = 2.5f;
    write_navdata(z, bytes);
    const auto zo = parse_navdata(bytes);
    ASSERT_TRUE(zo);
    ASSERT_TRUE(zo->zimmu_3000.has_value());
    EXPECT_EQ(zo->zimmu_3000->vzimmuLSB, -17);
    EXPECT_EQ(zo->zimmu_3000->vzfind, 2.5f);
    EXPECT_FALSE(zo->gps.has_value());
}

TEST(NavdataWriter, DemoModeDatagramLikeTheDrone) {
    Navdata nd;
    nd.header.drone_state.set(DroneStateBit::NavdataDemo, true);
    nd.header.drone_state.set(DroneStateBit::Fly, true);
    nd.header.sequence = 7;
    auto& d = nd.demo.emplace();
    d.ctrl_state = CtrlState::make(CtrlMajor::Hovering, 0);
    d.vbat_flying_percentage = 64;
    d.theta_mdeg = -1500;
    d.altitude_mm = 1200;
    d.vz_mm_s = 100;
    nd.vision_detect.emplace();
    nd.time.emplace().time = DroneTime::make(12, 345678);
    std::vector<std::uint8_t> bytes;
    write_navdata(nd, bytes);
    EXPECT_EQ(bytes.size(), 16U + 148U + 8U + 328U + 8U);
    const auto r = parse_navdata(bytes);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->options[0].tag, 0);  // tag order
    EXPECT_EQ(r->options[1].tag, 1);
    EXPECT_EQ(r->options[2].tag, 16);
    EXPECT_EQ(r->time->time.seconds(), 12U);
    EXPECT_EQ(r->time->time.microseconds(), 345678U);
    const NavState s = to_nav_state(*r, 99);
    EXPECT_DOUBLE_EQ(s.pitch_deg, -1.5);
    EXPECT_DOUBLE_EQ(s.altitude_m, 1.2);
    EXPECT_DOUBLE_EQ(s.vz_mps, -0.1);  // 100 mm/s down = -0.1 m/s up
    EXPECT_EQ(s.ctrl_state, 0x00040000U);
}

TEST(NavdataWriter, SpanOverloadChecksSizeAndVectorReusesCapacity) {
    const auto bytes = read_fixture(test::kNavdataFull);
    const Navdata nd = parse_navdata(bytes).value();
    std::vector<std::uint8_t> small(2119);
    const auto e = write_navdata(nd, std::span<std::uint8_t>(small));
    ASSERT_FALSE(e);
    EXPECT_EQ(e.error(), WriteErrc::BufferTooSmall);
    std::vector<std::uint8_t> big(4096, 0xEE);
    const auto n = write_navdata(nd, std::span<std::uint8_t>(big));
    ASSERT_TRUE(n);
    EXPECT_EQ(*n, 2120U);
    EXPECT_TRUE(std::equal(bytes.begin(), bytes.end(), big.begin()));
    EXPECT_EQ(big[2120], 0xEE);  // nothing written past the datagram

    std::vector<std::uint8_t> out;
    write_navdata(nd, out);
    const auto* data = out.data();
    for (int i = 0; i < 10; ++i) write_navdata(nd, out);
    EXPECT_EQ(out.data(), data);  // steady state: no reallocation
}

}  // namespace
}  // namespace gs::protocol::navdata
