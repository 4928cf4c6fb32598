#pragma once
// drone_state masks the link and virtual-drone tests build packets and expectations from, named
// after drone/navdata.hpp's DroneStateBit (docs/protocol.md §3.2).

#include "drone/protocol/navdata.hpp"

#include <cstdint>

namespace gs::test {

using protocol::navdata::DroneStateBit;

constexpr std::uint32_t state_bit(DroneStateBit b) {
    return 1u << static_cast<unsigned>(b);
}

inline constexpr std::uint32_t kFly = state_bit(DroneStateBit::Fly);
inline constexpr std::uint32_t kAck = state_bit(DroneStateBit::Command);  // bit 6: config ACK
inline constexpr std::uint32_t kDemo = state_bit(DroneStateBit::NavdataDemo);
inline constexpr std::uint32_t kBootstrap = state_bit(DroneStateBit::NavdataBootstrap);
inline constexpr std::uint32_t kComLost = state_bit(DroneStateBit::ComLost);
inline constexpr std::uint32_t kVbatLow = state_bit(DroneStateBit::VbatLow);
inline constexpr std::uint32_t kComWdg = state_bit(DroneStateBit::ComWatchdog);
inline constexpr std::uint32_t kEmergency = state_bit(DroneStateBit::Emergency);
// What a landed drone with its firmware running reports: the PIC version and the four threads.
inline constexpr std::uint32_t kThreads =
    state_bit(DroneStateBit::PicVersion) | state_bit(DroneStateBit::AtcodecThreadOn) |
    state_bit(DroneStateBit::NavdataThreadOn) | state_bit(DroneStateBit::VideoThreadOn) |
    state_bit(DroneStateBit::AcqThreadOn);

static_assert(kAck == 1u << 6 && kDemo == 1u << 10 && kBootstrap == 1u << 11 &&
              kComLost == 1u << 13 && kVbatLow == 1u << 15 && kComWdg == 1u << 30 &&
              kEmergency == 1u << 31 && kThreads == 0x0F800000u);

}  // namespace gs::test
