#include "drone/dataset/annexb.hpp"
#include "drone/dataset/dataset.hpp"
#include "drone/dataset/raw.hpp"

#include <gtest/gtest.h>

#include <random>

namespace gs {
namespace {

using namespace dataset;

// Every prefix and a few thousand random mutations of valid files: the parsers return a value or
// an error, never crash or read out of bounds (run under ASan/UBSan in the sanitizer build).
TEST(DatasetFuzz, ParsersSurviveTruncationAndGarbage) {
    const std::string flight =
        R"({"format": "ardrone-dataset", "version": 1, "camera": "front", "width": 640,
            "height": 360, "fps": 30, "frames": 2, "video": "video.h264",
            "calibration": {"fx": 1, "fy": 2, "cx": 3, "cy": 4, "dist": [0, 0, 0, 0, 0]}})";
    const std::string frames = "frame,t_ms,roll_deg,gt_x_m\n0,0,1.5,\"2\"\n1,33.3,-2e3,\n";
    const std::string nav = "t_ms,state,ctrl_state,seq\n0,0x1,0x2,3\n5,0xFFFFFFFF,4,5\n";
    const std::string at = "1 AT*REF=1,290717696\\r\n2 AT\\x01\\\\\n";
    std::string bin;
    const std::vector<std::uint8_t> payload = {0, 0, 0, 1, 0x65, 0x88, 1, 2};
    append_raw_record(bin, 5, payload);
    append_raw_record(bin, 9, payload);

    std::mt19937 rng(1234);
    auto mutate = [&](std::string s) {
        if (s.empty()) return s;
        const int n = 1 + static_cast<int>(rng() % 4);
        for (int i = 0; i < n; ++i) s[rng() % s.size()] = static_cast<char>(rng() & 0xFF);
        return s;
    };
    auto run_all = [&](const std::string& a, const std::string& b, const std::string& c,
                       const std::string& d, const std::string& e) {
        (void)parse_flight_json(a);
        (void)parse_frames_csv(b);
        (void)parse_navdata_csv(c);
        (void)parse_labels_csv(b);
        (void)parse_labels_json(a);
        (void)parse_at_log(d);
        const auto* p = reinterpret_cast<const std::uint8_t*>(e.data());
        (void)parse_navdata_bin(std::span(p, e.size()));
        (void)parse_video_chunks(std::span(p, e.size()));
        (void)split_access_units(std::span(p, e.size()));
    };
    for (std::size_t n = 0; n <= 200; ++n)
        run_all(flight.substr(0, n), frames.substr(0, n), nav.substr(0, n), at.substr(0, n),
                bin.substr(0, std::min(n, bin.size())));
    for (int i = 0; i < 3000; ++i)
        run_all(mutate(flight), mutate(frames), mutate(nav), mutate(at), mutate(bin));
    // sanity: the unmutated inputs are valid
    EXPECT_TRUE(parse_flight_json(flight));
    EXPECT_TRUE(parse_frames_csv(frames));
    EXPECT_TRUE(parse_navdata_csv(nav));
    auto a = parse_at_log(at);
    ASSERT_TRUE(a);
    EXPECT_EQ((*a)[1].datagram, std::string("AT\x01\\"));
}

}  // namespace
}  // namespace gs
