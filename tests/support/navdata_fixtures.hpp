#pragma once
// Shared by the navdata tests: reading the real captures in GS_FIXTURES_DIR/ardrone.

#include <cstdint>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>

namespace gs::test {

inline std::vector<std::uint8_t> read_fixture(const std::string& name) {
    const std::string path = std::string(GS_FIXTURES_DIR) + "/ardrone/" + name;
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("cannot open fixture " + path);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline const char* const kNavdataFull = "node-ar-drone_navdata.bin";       // GPS 216 B
inline const char* const kNavdata2012 = "node-ar-drone_navdata_2012.bin";  // zimmu 12 B
inline const char* const kNavdata2013 = "node-ar-drone_navdata_2013.bin";  // tag 27 480 B
inline const char* const kNavdataDemo = "uav-pilot_navdata_demo_inflight.bin";

}  // namespace gs::test
