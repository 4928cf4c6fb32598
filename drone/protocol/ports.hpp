#pragma once
// The AR.Drone 2's four ports (docs/protocol.md): navdata UDP 5554, video TCP 5555, AT UDP 5556,
// configuration TCP 5559. One definition for the link's defaults, the virtual drone's, and the
// same layout moved to another base (`sim --port-base`, `record --drone ... --port-base`: several
// virtual drones on one host).

#include <cstdint>

namespace gs::protocol {

struct DronePorts {
    std::uint16_t navdata = 5554;
    std::uint16_t video = 5555;
    std::uint16_t at = 5556;
    std::uint16_t control = 5559;

    // The standard layout with navdata at `base`: video base + 1, AT base + 2, control base + 5.
    static constexpr DronePorts from_base(int base) {
        constexpr DronePorts s{};
        auto at_offset = [base](std::uint16_t standard) {
            return static_cast<std::uint16_t>(base + (standard - s.navdata));
        };
        return {at_offset(s.navdata), at_offset(s.video), at_offset(s.at), at_offset(s.control)};
    }
    // Into a configuration with the four `*_port` fields (link::LinkConfig,
    // sim::VirtualDroneOptions).
    template <class Config>
    void apply_to(Config& c) const {
        c.navdata_port = navdata;
        c.video_port = video;
        c.at_port = at;
        c.control_port = control;
    }
};

}  // namespace gs::protocol
